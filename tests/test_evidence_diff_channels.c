/* `diff-dump --stat` per colour channel (issue 26): the ReSTIR target is luminance, so a bug
 * that moves colour and keeps luminance (an MH acceptance without its target ratio keeps
 * luminance(F) W of every pixel exact, Mutations Eq. 23) is invisible to a luminance test.
 * Planted here in a dump: one stage's F rotated in colour with its luminance kept per pixel
 * (R raised by d min(R, 0.7152 G / 0.2126), G lowered by 0.2126 / 0.7152 of that: F >= 0). The luminance z stays small; the channel
 * z finds the stage, unpaired (another seed, d = 0.5) and paired (the same run, d = 0.003,
 * the size of mh-no-target-ratio's colour shift, which the unpaired mode cannot see). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/oracle/stage_dump.h"
#include "dump_util.h"
#include "test.h"

static char out[262144];

#define DC_COMMON \
    "scenes/cornell-glossy.scene --method restir --preset gris-realtime --size 48x48 --sequence 0..1 --quiet " \
    "--no-png --threads 2"

#define dc_note(...)                                                  \
    do {                                                              \
        if (getenv("RESTIR_TEST_VERBOSE")) {                          \
            fprintf(stderr, "  " __VA_ARGS__);                        \
            fprintf(stderr, "\n");                                    \
        }                                                             \
    } while (0)

static const char *dc_dir(const char *name) { return dump_scratch("dchan_", name); }

/* Rewrites dump `path` in place with every F rotated in colour (see the top; luminance(F)
 * unchanged up to rounding, so p̂ and luminance(F) W stay). */
static void rotate_record(void *user, long i, reservoir *rs)
{
    double d = *(const double *)user, r = (double)rs->y.F.r, g = (double)rs->y.F.g;
    double dr = d * fmin(r, g * 0.7152 / 0.2126); /* G stays >= 0 (the reader refuses F < 0) */
    (void)i;
    rs->y.F.r = (real)(r + dr);
    rs->y.F.g = (real)(g - 0.2126 * dr / 0.7152);
}

static void rotate_colour(const char *path, double d) { dump_edit(path, path, rotate_record, &d); }

/* The luminance z (unpaired "(z ...)" of the row's first line, or "lum" of the paired list)
 * and the three channel z of the row of `frame`, `stage` in diff-dump's text. */
static int row_z(const char *text, int frame, const char *stage, int paired, double *lum, double z[3])
{
    char head[64];
    const char *p, *q;
    snprintf(head, sizeof head, "frame %4d %-12s", frame, stage);
    if (!(p = strstr(text, head))) return 0;
    if (!(q = strstr(p, "(z "))) return 0;
    *lum = atof(q + 3);
    if (!(q = strstr(p, "paired z R "))) return 0;
    if (paired) {
        if (sscanf(q, "paired z R %lf G %lf B %lf lum %lf", &z[0], &z[1], &z[2], lum) != 4) return 0;
        return 1;
    }
    {
        const char *f = strstr(p, "    F*W R ");
        int c;
        if (!f) return 0;
        for (c = 0; c < 3; ++c) {
            if (!(f = strstr(f, "(z "))) return 0;
            z[c] = atof(f + 3);
            f += 3;
        }
    }
    return 1;
}

TEST(evidence_diff_dump_stat_per_channel)
{
    char path[1200];
    double lum, z[3];
    CHECKF(test_cli(out, sizeof out, "render " DC_COMMON " -o %s.pfm --dump-dir %s", dc_dir("a"), dc_dir("A")) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "render " DC_COMMON " --seed 2 -o %s.pfm --dump-dir %s", dc_dir("b"),
                    dc_dir("B")) == 0,
           "%s", out);
    if (test_has_failed()) return;
    /* the same estimator with another seed: every channel agrees */
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", dc_dir("A"), dc_dir("B")) == 0, "%s", out);
    /* unpaired: B's frame 1 spatial1 rotated by d = 0.5 */
    CHECK(dump_copy(dc_dir("B"), dc_dir("Bp")) != NULL);
    stage_dump_path(path, sizeof path, dc_dir("Bp"), 1, "spatial1", "resv");
    rotate_colour(path, 0.5);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", dc_dir("A"), dc_dir("Bp")) == 1, "%s", out);
    CHECKF(strstr(out, "first difference: frame 1, stage spatial1") != NULL, "%s", out);
    CHECKF(row_z(out, 1, "spatial1", 0, &lum, z), "%s", out);
    dc_note("unpaired, d = 0.5: luminance z %+.2f, R %+.2f G %+.2f B %+.2f", lum, z[0], z[1], z[2]);
    CHECKF(fabs(lum) < 4 && fabs(z[0]) > 6, "luminance z %+.2f (must pass), R z %+.2f (must be found)", lum, z[0]);
    /* paired: A's own frame 0 temporal rotated by d = 0.003 */
    CHECK(dump_copy(dc_dir("A"), dc_dir("Ap")) != NULL);
    stage_dump_path(path, sizeof path, dc_dir("Ap"), 0, "temporal", "resv");
    rotate_colour(path, 0.003);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", dc_dir("A"), dc_dir("Ap")) == 0,
           "the unpaired mode should not see 0.3%%:\n%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --paired", dc_dir("A"), dc_dir("Ap")) == 1, "%s", out);
    CHECKF(strstr(out, "first difference: frame 0, stage temporal") != NULL, "%s", out);
    CHECKF(row_z(out, 0, "temporal", 1, &lum, z), "%s", out);
    dc_note("paired, d = 0.003: luminance z %+.2f, R %+.2f G %+.2f B %+.2f", lum, z[0], z[1], z[2]);
    CHECKF(fabs(lum) < 4 && fabs(z[0]) > 6 && fabs(z[1]) > 6, "luminance z %+.2f, R %+.2f, G %+.2f", lum, z[0], z[1]);
}
