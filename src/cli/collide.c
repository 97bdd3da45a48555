/* Output collisions (collide.h). Two spellings of one file ("a.pfm", "./a.pfm",
 * "out/../a.pfm") must collide too, and an output usually does not exist yet, so the
 * comparison resolves the directory (which does exist once output_path_check passed, or
 * is one missing level below one that does) and compares the last component. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "collide.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

/* "dir/name" -> the resolved directory + "/" + name, or the path as given if the
 * directory cannot be resolved. */
static void resolved(const char *path, char *out, size_t size)
{
    char dir[PATH_MAX], real[PATH_MAX];
    const char *slash = strrchr(path, '/'), *name = slash ? slash + 1 : path;
    if (!slash) snprintf(dir, sizeof dir, ".");
    else if (slash == path) snprintf(dir, sizeof dir, "/");
    else snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    if (realpath(dir, real)) snprintf(out, size, "%s/%s", real, name);
    else snprintf(out, size, "%s", path);
}

int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    char ra[2 * PATH_MAX], rb[2 * PATH_MAX];
    if (!strcmp(a, b)) return 1;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    resolved(a, ra, sizeof ra);
    resolved(b, rb, sizeof rb);
    return !strcmp(ra, rb);
}

/* The path with its longest existing ancestor resolved (symlinks, "..") and the rest as
 * written: "d/x/../m.json" with no d yet -> "/cwd/d/x/../m.json". Enough to see one path
 * below another when neither exists yet (render's --dump-dir is made later). */
static void resolved_loosely(const char *path, char *out, size_t size)
{
    char head[PATH_MAX], real[PATH_MAX];
    size_t cut;
    snprintf(head, sizeof head, "%s", path);
    for (;;) {
        char *slash = strrchr(head, '/');
        if (realpath(head, real)) break;
        if (!slash) {
            if (!realpath(".", real)) real[0] = '\0';
            snprintf(out, size, "%s/%s", real, path);
            return;
        }
        if (slash == head) { /* "/x": the root exists */
            snprintf(out, size, "%s", path);
            return;
        }
        *slash = '\0';
    }
    cut = strlen(head);
    snprintf(out, size, "%s%s", strcmp(real, "/") ? real : "", path + cut);
}

int path_within(const char *path, const char *dir)
{
    char rp[2 * PATH_MAX], rd[2 * PATH_MAX];
    size_t n;
    if (same_file(path, dir)) return 1;
    resolved_loosely(dir, rd, sizeof rd);
    resolved_loosely(path, rp, sizeof rp);
    n = strlen(rd);
    while (n > 1 && rd[n - 1] == '/') rd[--n] = '\0';
    return !strncmp(rp, rd, n) && (rp[n] == '/' || rp[n] == '\0');
}

static int given(const named_file *f) { return f->path && f->path[0]; }

int outputs_distinct(const char *command, const named_file *outs, int n_out, const named_file *ins, int n_in,
                     const char *allow_in_out)
{
    int i, j;
    for (i = 0; i < n_out; ++i) {
        if (!given(&outs[i])) continue;
        for (j = i + 1; j < n_out; ++j)
            if (given(&outs[j]) && same_file(outs[i].path, outs[j].path)) {
                fprintf(stderr, "restir %s: %s %s is also %s %s: one would overwrite the other\n", command,
                        outs[j].role, outs[j].path, outs[i].role, outs[i].path);
                return 2;
            }
        for (j = 0; j < n_in; ++j)
            if (given(&ins[j]) && same_file(outs[i].path, ins[j].path) &&
                !(allow_in_out && ins[j].path == allow_in_out && same_file(outs[i].path, allow_in_out))) {
                fprintf(stderr, "restir %s: %s %s is %s %s: the output would overwrite an input\n", command,
                        outs[i].role, outs[i].path, ins[j].role, ins[j].path);
                return 2;
            }
    }
    return 0;
}
