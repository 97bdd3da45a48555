/* Region dumps as inputs (issue 31; docs/oracle.md §6 "From a region dump"): `restir
 * inspect --from-dump` and `restir replay` on a `--dump-region ... --dump-halo N` dump give
 * the whole-image dump's output bit for bit for pixels whose every input was dumped, and
 * refuse (exit 2, naming the pixel and the missing input) a pixel at the rectangle's edge. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/oracle/stage_dump.h"
#include "test.h"

static char out[262144], other[262144];

#define REGION_COMMON "scenes/pillars.scene --method restir --preset gris-realtime --spatial-passes 2 --size 40x28 " \
                      "--radius 6 --sequence 0..2 --quiet --no-png --threads 2"
#define REGION_ARGS "--dump-region 14,10,10,8 --dump-halo 7" /* files: 7,3,24,22 */

static const char *dir_of(const char *name)
{
    static char buf[4][1100];
    static int slot;
    char *b = buf[slot++ % 4];
    snprintf(b, 1100, "%s/region_%s", test_tmpdir(), name);
    return b;
}

/* A dump made once per test process (`extra`: more render arguments). */
static const char *dump_of(const char *name, const char *extra)
{
    static char made[8][32];
    static int n_made;
    const char *dir = dir_of(name);
    char cmd[1400];
    int i;
    for (i = 0; i < n_made; ++i)
        if (!strcmp(made[i], name)) return dir;
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) test_fail(__FILE__, __LINE__, "%s failed", cmd);
    if (test_cli(out, sizeof out, "render %s -o %s/%s.pfm --dump-dir %s %s", REGION_COMMON, test_tmpdir(), name, dir,
                 extra) != 0)
        test_fail(__FILE__, __LINE__, "the reference run failed: %s", out);
    else if (n_made < 8)
        snprintf(made[n_made++], sizeof made[0], "%s", name);
    return dir;
}

/* s with every occurrence of word removed (the dump's directory in printed file names). */
static void strip(char *s, const char *word)
{
    size_t n = strlen(word);
    char *p;
    while ((p = strstr(s, word)) != NULL) memmove(p, p + n, strlen(p + n) + 1);
}

/* The bytes of a stage file's records (after the 64-byte header), NULL if unreadable. */
static unsigned char *records(const char *dir, int frame, const char *stage, long *size)
{
    char path[1200];
    unsigned char *buf;
    FILE *fp;
    stage_dump_path(path, sizeof path, dir, (uint32_t)frame, stage, "resv");
    if (!(fp = fopen(path, "rb"))) return NULL;
    fseek(fp, 0, SEEK_END);
    *size = ftell(fp) - 64;
    fseek(fp, 64, SEEK_SET);
    buf = malloc((size_t)*size);
    if (buf && fread(buf, 1, (size_t)*size, fp) != (size_t)*size) {
        free(buf);
        buf = NULL;
    }
    fclose(fp);
    return buf;
}

/* inspect of one pixel on the region dump prints what it prints on the whole-image dump
 * (the file names aside), at every reuse stage of frame 2, history included. */
TEST(oracle_region_dump_inspect_equals_whole)
{
    const char *whole = dump_of("whole", ""), *region = dump_of("rect", REGION_ARGS);
    const char *stages[] = {"temporal", "spatial1", "spatial2"};
    int s, a, b;
    for (s = 0; s < 3; ++s) {
        a = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage %s --pixel 18,13 --json", whole,
                     stages[s]);
        b = test_cli(other, sizeof other, "inspect --from-dump %s --frame 2 --stage %s --pixel 18,13 --json", region,
                     stages[s]);
        CHECKF(a == 0 && b == 0 && strstr(other, "\"differs\": []"), "%s: exit %d / %d\n%s", stages[s], a, b, other);
        strip(out, whole);
        strip(other, region);
        CHECKF(!strcmp(out, other), "%s: the region dump's inspect differs:\n%s\n---\n%s", stages[s], out, other);
    }
}

/* replay of the region's core writes records byte-identical to the whole-image dump's. */
TEST(oracle_region_dump_replay_equals_whole)
{
    const char *whole = dump_of("whole", ""), *region = dump_of("rect", REGION_ARGS);
    const char *stages[] = {"temporal", "spatial2"};
    int s, status;
    for (s = 0; s < 2; ++s) {
        const char *o = dir_of(stages[s]);
        unsigned char *got, *want;
        long n_got = 0, n_want = 0, y;
        char cmd[1200];
        snprintf(cmd, sizeof cmd, "rm -rf %s", o);
        if (system(cmd) != 0) test_fail(__FILE__, __LINE__, "%s failed", cmd);
        status = test_cli(out, sizeof out, "replay %s --frame 2 --stage %s --dump-dir %s", region, stages[s], o);
        CHECKF(status == 0 && strstr(out, "region 14,10,10,8"), "%s: exit %d\n%s", stages[s], status, out);
        got = records(o, 2, stages[s], &n_got);
        want = records(whole, 2, stages[s], &n_want);
        CHECKF(got && want && n_got == 80 * 216 && n_want == 40 * 28 * 216, "%s: sizes %ld, %ld", stages[s], n_got,
               n_want);
        for (y = 0; got && want && n_got == 80 * 216 && y < 8; ++y)
            CHECKF(!memcmp(got + y * 10 * 216, want + ((10 + y) * 40 + 14) * 216, 10 * 216),
                   "%s: row %ld of the core differs from the whole-image dump", stages[s], 10 + y);
        free(got);
        free(want);
    }
}

/* A pixel whose stage reads outside the dumped rectangle is refused, naming the pixel and
 * the missing input; so is a pixel outside the rectangle, and a replay of the whole
 * rectangle (its edge pixels' neighbours were not dumped) leaves nothing behind. */
TEST(oracle_region_dump_refuses_edge_pixels)
{
    const char *region = dump_of("rect", REGION_ARGS), *o = dir_of("edge");
    char cmd[1200];
    FILE *fp;
    int status;
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage spatial1 --pixel 10,6", region);
    CHECKF(status == 2 && strstr(out, "pixel (10, 6): missing input") && strstr(out, "previous stage's reservoir at pixel (4, 0)"),
           "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage spatial2 --pixel 2,2", region);
    CHECKF(status == 2 && strstr(out, "not all in the dumped rectangle"), "exit %d\n%s", status, out);
    snprintf(cmd, sizeof cmd, "rm -rf %s", o);
    if (system(cmd) != 0) test_fail(__FILE__, __LINE__, "%s failed", cmd);
    status = test_cli(out, sizeof out, "replay %s --frame 2 --stage spatial1 --dump-dir %s --region 7,3,24,22", region, o);
    CHECKF(status == 2 && strstr(out, "stage spatial1, pixel (") && strstr(out, "missing input"), "exit %d\n%s", status, out);
    fp = fopen(o, "r");
    CHECKF(!fp, "%s was left behind", o);
    if (fp) fclose(fp);
}
