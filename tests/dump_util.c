/* dump_util.h: scratch stage-dump directories for the oracle tests. */
#include "dump_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/reservoir_dump.h"
#include "test.h"

#define DUMP_PATH_MAX 1100
#define DUMPS_MAX 32

const char *dump_scratch(const char *prefix, const char *name)
{
    static char slots[8][DUMP_PATH_MAX];
    static int next;
    char *p = slots[next++ & 7];
    snprintf(p, sizeof slots[0], "%s/%s%s", test_tmpdir(), prefix, name);
    return p;
}

const char *dump_once(const char *args, const char *pfm, const char *dir)
{
    static char made[DUMPS_MAX][DUMP_PATH_MAX];
    static int n_made;
    static char out[262144];
    char cmd[DUMP_PATH_MAX + 16];
    int i;
    for (i = 0; i < n_made; ++i)
        if (!strcmp(made[i], dir)) return made[i];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) test_fail(__FILE__, __LINE__, "%s failed", cmd);
    if (test_cli(out, sizeof out, "render %s -o %s --dump-dir %s", args, pfm, dir) != 0) {
        test_fail(__FILE__, __LINE__, "the reference run failed: %s", out);
        return dir;
    }
    if (n_made == DUMPS_MAX) return dir; /* made again by the next call */
    snprintf(made[n_made], sizeof made[0], "%s", dir);
    return made[n_made++];
}

const char *dump_copy(const char *src, const char *dst)
{
    char cmd[4000];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && cp -r '%s' '%s'", dst, src, dst);
    if (system(cmd) == 0) return dst;
    test_fail(__FILE__, __LINE__, "%s failed", cmd);
    return NULL;
}

long dump_edit(const char *src, const char *dst, dump_edit_fn edit, void *user)
{
    reservoir *rs;
    reservoir_dump_info info;
    rerror e;
    long i, n;
    if (reservoir_dump_read(src, &rs, &info, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    n = (long)info.width * (long)info.height;
    for (i = 0; i < n; ++i) edit(user, i, &rs[i]);
    if (reservoir_dump_write(dst, rs, &info, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        n = -1;
    }
    free(rs);
    return n;
}

/* The factors of record p (p < 0: every record): W and wsum. */
typedef struct {
    long p;
    real w_factor, wsum_factor;
} w_scaling;

static void scale_record(void *user, long i, reservoir *r)
{
    const w_scaling *w = user;
    if (w->p >= 0 && i != w->p) return;
    r->W *= w->w_factor;
    r->wsum *= w->wsum_factor;
}

long dump_scale_w(const char *src, const char *dst, long p, double scale, int with_wsum)
{
    w_scaling w;
    w.p = p;
    w.w_factor = (real)scale;
    w.wsum_factor = with_wsum ? (real)scale : 1;
    return dump_edit(src, dst, scale_record, &w);
}
