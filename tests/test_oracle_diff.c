/* diff-dump cannot say "ok" wrongly (issue 31; docs/oracle.md §3): every false "ok" the GPU
 * trial found is a test here, each failing on the diff before issue 31 (it exited 0):
 *   - B with W = +inf or confidence = +inf at one pixel (NaN comparisons pass);
 *   - an A that holds only its manifest, an A without a frame, a run cut short;
 *   - a B that differs only in a reconnection field (rc_triangle, rc_position,
 *     rc_radiance, rc_pdf) or in F.
 * Also: per-field tolerances, --max-outlier-fraction, --images, --first beyond 32, region
 * dumps (--dump-region) and the restart that refuses zero reconnection data. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/pfm.h"
#include "restir/oracle/dump_diff.h"
#include "restir/oracle/stage_dump.h"
#include "dump_util.h"
#include "test.h"

static char out[262144];

#define DIFF_COMMON "scenes/pillars.scene --method restir --preset gris-realtime --spatial-passes 2 --size 40x28 " \
                    "--sequence 0..2 --quiet --no-png --threads 2"
#define DIFF_W 40

static const char *diff_dir(const char *name) { return dump_scratch("diff_", name); }

/* The reference run, every stage dumped (once per test run). */
static const char *reference(void) { return dump_once(DIFF_COMMON, test_tmp_path("da.pfm"), diff_dir("A")); }

/* A fresh copy of the reference dump called name. */
static const char *copy_of_reference(const char *name)
{
    const char *d = diff_dir(name);
    dump_copy(reference(), d);
    return d;
}

/* The record edits a test plants in one pixel of a copy. */
enum edit {
    EDIT_W_INF, EDIT_CONF_INF, EDIT_RC_TRIANGLE, EDIT_RC_POSITION, EDIT_RC_RADIANCE, EDIT_RC_PDF, EDIT_F,
    EDIT_F_TINY, EDIT_N_INVALID, EDIT_W_SCALE, EDIT_ZERO_RC
};

static void apply_edit(reservoir *r, enum edit what)
{
    path_sample *s = &r->y;
    switch (what) {
    case EDIT_W_INF: r->W = (real)INFINITY; break;
    case EDIT_CONF_INF: r->confidence = (real)INFINITY; break;
    case EDIT_RC_TRIANGLE: s->rc_triangle += 1; break;
    case EDIT_RC_POSITION: s->rc_position.y += 1e-3f; break;
    case EDIT_RC_RADIANCE: s->rc_radiance.b *= (real)1.001; break;
    case EDIT_RC_PDF: s->rc_pdf *= (real)1.001; break;
    case EDIT_F: s->F.r *= (real)1.001; break;
    case EDIT_F_TINY: s->F.g *= (real)(1 + (sizeof(real) == 4 ? 1e-6 : 1e-9)); break; /* a few ulps of real */
    case EDIT_N_INVALID: r->n_invalid += 1; break;
    case EDIT_W_SCALE: r->W *= (real)1.5; break;
    case EDIT_ZERO_RC: /* what a GPU build that leaves the x_k fields 0 writes */
        s->rc_k = PATH_RC_NONE;
        s->rc_flags = 0;
        s->rc_triangle = 0;
        s->rc_bary[0] = s->rc_bary[1] = 0;
        memset(&s->rc_position, 0, sizeof s->rc_position);
        memset(&s->rc_normal, 0, sizeof s->rc_normal);
        memset(&s->rc_wo, 0, sizeof s->rc_wo);
        s->rc_pdf_prev = s->rc_geom = s->rc_pdf = 0;
        memset(&s->rc_radiance, 0, sizeof s->rc_radiance);
        break;
    }
}

/* Applies `what` to record p of dir/frame/stage (p = -1: every record; p = -2: the first
 * record with a reconnection vertex); returns the record edited (p = -1: the count), -1 on
 * failure. */
typedef struct {
    long p; /* the record to edit; -1: every record; -2: the first with a reconnection vertex */
    enum edit what;
} record_edit;

static void edit_one(void *user, long i, reservoir *r)
{
    record_edit *t = user;
    if (t->p == -2 && r->y.rc_k != PATH_RC_NONE) t->p = i;
    if (t->p == -1 || i == t->p) apply_edit(r, t->what);
}

static long edit_record(const char *dir, int frame, const char *stage, long p, enum edit what)
{
    char path[1200];
    record_edit t;
    long n;
    t.p = p;
    t.what = what;
    stage_dump_path(path, sizeof path, dir, (uint32_t)frame, stage, "resv");
    n = dump_edit(path, path, edit_one, &t);
    return n < 0 ? -1 : t.p < 0 ? n : t.p;
}

/* W = +inf or c = +inf in one pixel of B is a difference, whatever the tolerances. */
TEST(oracle_diff_nonfinite_is_a_difference)
{
    const char *a = reference(), *b = copy_of_reference("inf");
    CHECK(edit_record(b, 1, "spatial1", 7 * DIFF_W + 9, EDIT_W_INF) >= 0);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", a, b) == 1, "%s", out);
    CHECKF(strstr(out, "pixel 9,7: NON-FINITE in B") && strstr(out, "first difference: frame 1, stage spatial1"), "%s",
           out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-rel all=1e300 --max-outlier-fraction 1 --min-same 0", a,
                    b) == 1,
           "a tolerance admitted W = +inf:\n%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", a, b) == 1, "--stat admitted W = +inf:\n%s", out);
    b = copy_of_reference("cinf");
    CHECK(edit_record(b, 2, "temporal", 3, EDIT_CONF_INF) >= 0);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --json", a, b) == 1, "%s", out);
    CHECKF(strstr(out, "\"kind\": \"nonfinite\", \"nonfinite_in\": \"B\"") != NULL, "%s", out);
}

/* A that holds only its manifest, lacks a frame, or was cut short; B that lacks a stage,
 * is truncated or holds another frame's file: exit 2, never 0. */
TEST(oracle_diff_incomplete_input_is_an_error)
{
    /* Each case damages a fresh copy of the reference by a shell command run inside it and
     * diffs the copy as A and/or as B against the reference. */
    static const struct {
        const char *name, *damage;
        int as_a, as_b;
        const char *expect; /* in the message; NULL: exit 2 is the whole check */
    } cases[] = {
        {"manifest_only", "find . -mindepth 1 -maxdepth 1 ! -name manifest.json -exec rm -rf {} +", 1, 0, "missing"},
        {"no_frame", "rm -rf frame_0001", 1, 1, NULL},
        /* a run cut short: its manifest says 2 of 3 frames (what an interrupted run leaves) */
        {"cut", "sed -i 's/\"written\": 3/\"written\": 2/' manifest.json && rm -rf frame_0002", 1, 0, "cut short"},
        /* B: a stage missing, a truncated file, another frame's file */
        {"no_stage", "rm frame_0002/spatial2.resv", 0, 1, NULL},
        {"short", "truncate -s -100 frame_0001/temporal.resv", 0, 1, NULL},
        {"swapped", "cp frame_0000/temporal.resv frame_0001/temporal.resv", 0, 1, "holds frame 0, stage 'temporal'"},
    };
    const char *a = reference(), *d;
    char cmd[4000];
    size_t i;
    int b;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        d = copy_of_reference(cases[i].name);
        snprintf(cmd, sizeof cmd, "cd '%s' && %s", d, cases[i].damage);
        CHECKF(system(cmd) == 0, "%s failed", cmd);
        for (b = 0; b < 2; ++b) {
            if (!(b ? cases[i].as_b : cases[i].as_a)) continue;
            CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", b ? a : d, b ? d : a) == 2, "%s as %s:\n%s",
                   cases[i].name, b ? "B" : "A", out);
            CHECKF(!cases[i].expect || strstr(out, cases[i].expect), "%s as %s: no '%s' in\n%s", cases[i].name,
                   b ? "B" : "A", cases[i].expect, out);
        }
    }
}

/* Every documented field is compared: one pixel's reconnection field or F changed alone is
 * found and named; per-field tolerances and --ignore. */
TEST(oracle_diff_compares_every_field)
{
    static const struct {
        enum edit what;
        const char *field;
    } cases[] = {{EDIT_RC_TRIANGLE, "rc_triangle"}, {EDIT_RC_POSITION, "rc_position"},
                 {EDIT_RC_RADIANCE, "rc_radiance"}, {EDIT_RC_PDF, "rc_pdf"}, {EDIT_F, "F"}};
    const char *a = reference(), *b;
    char want[200];
    size_t i;
    long p;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        b = copy_of_reference("field");
        p = edit_record(b, 1, "temporal", -2, cases[i].what);
        CHECK(p >= 0);
        CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", a, b) == 1, "%s changed, diff says ok:\n%s",
               cases[i].field, out);
        snprintf(want, sizeof want, "pixel %ld,%ld: beyond tolerance (%s rel err", p % DIFF_W, p / DIFF_W, cases[i].field);
        CHECKF(strstr(out, want) != NULL, "want '%s':\n%s", want, out);
    }
    /* a tolerance per field: F changed by 1e-9 relative (1e-6 in float) passes with F=1e-8 (1e-5),
     * not with W=1e-8 (1e-5) */
    b = copy_of_reference("tiny");
    CHECK(edit_record(b, 0, "spatial2", -2, EDIT_F_TINY) >= 0);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-rel W=%s", a, b, sizeof(real) == 4 ? "1e-5" : "1e-8") == 1,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-rel F=%s", a, b, sizeof(real) == 4 ? "1e-5" : "1e-8") == 0,
           "%s", out);
    /* integer fields compare exactly, --ignore skips one */
    b = copy_of_reference("ninv");
    CHECK(edit_record(b, 0, "initial", -2, EDIT_N_INVALID) >= 0);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-rel all=1", a, b) == 1, "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --ignore n_invalid", a, b) == 0, "%s", out);
    CHECK(test_cli(out, sizeof out, "diff-dump %s %s --max-rel n_invalid=1", a, b) == 2);
    CHECK(test_cli(out, sizeof out, "diff-dump %s %s --max-rel Wx=1", a, b) == 2);
}

/* --max-outlier-fraction admits floor(F x pixels) same-sample pixels beyond tolerance;
 * --images writes the mask (the planted pixel is class 1) and F W; --first lists more than 32. */
TEST(oracle_diff_outliers_images_first)
{
    const char *a = reference(), *b = copy_of_reference("outlier");
    char path[1200];
    image img;
    rerror e;
    const char *p;
    int n = 0;
    CHECK(edit_record(b, 1, "spatial1", 11 * DIFF_W + 23, EDIT_W_SCALE) >= 0);
    /* 40 x 28 = 1120 pixels: 0.001 admits one, 0.0008 none */
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-outlier-fraction 0.001", a, b) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-outlier-fraction 0.0008", a, b) == 1, "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --images %s/img", a, b, test_tmpdir()) == 1, "%s", out);
    snprintf(path, sizeof path, "%s/img/frame_0001_spatial1_mask.pfm", test_tmpdir());
    CHECKF(pfm_read(path, &img, NULL, &e) == 0, "%s", e.msg);
    CHECK(img.width == 40 && img.height == 28 && img.px[3 * (11 * DIFF_W + 23)] == 1 && img.px[0] == 0);
    image_free(&img);
    snprintf(path, sizeof path, "%s/img/frame_0001_spatial1_B_FW.pfm", test_tmpdir());
    CHECK(test_file_exists(path));
    snprintf(path, sizeof path, "%s/img/frame_0002_spatial2_mask.png", test_tmpdir());
    CHECK(test_file_exists(path));
    /* --first: another seed differs almost everywhere; 40 pixels are listed */
    CHECKF(test_cli(out, sizeof out, "render " DIFF_COMMON " --seed 2 -o %s/s2.pfm --dump-dir %s --dump-stages initial",
                    test_tmpdir(), diff_dir("S2")) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --first 40", diff_dir("S2"), a) == 1, "%s", out);
    for (p = out; (p = strstr(p, "reproduce: ")) != NULL; ++p) ++n;
    CHECKF(n == 3 * 40, "%d pixels listed (want 40 per frame)", n);
}

/* --dump-region: only the rectangle's records (equal to the full dump's), the manifest says
 * the region, diff-dump compares a region with a full dump in image coordinates, and a
 * restart from a region dump is refused. */
TEST(oracle_region_dump)
{
    const char *a = reference(), *g = diff_dir("G");
    char path[1200];
    reservoir *full, *part;
    reservoir_dump_info fi, pi;
    rerror e;
    long x, y;
    int same = 1;
    stage_manifest m;
    CHECKF(test_cli(out, sizeof out, "render " DIFF_COMMON " -o %s/g.pfm --dump-dir %s --dump-region 5,6,10,8",
                    test_tmpdir(), g) == 0,
           "%s", out);
    CHECKF(stage_manifest_read(g, &m, &e) == 0, "%s", e.msg);
    CHECK(m.region.x == 5 && m.region.y == 6 && m.region.width == 10 && m.region.height == 8 && m.width == 40);
    stage_dump_path(path, sizeof path, a, 2, "spatial2", "resv");
    CHECKF(reservoir_dump_read(path, &full, &fi, &e) == 0, "%s", e.msg);
    stage_dump_path(path, sizeof path, g, 2, "spatial2", "resv");
    CHECKF(reservoir_dump_read(path, &part, &pi, &e) == 0, "%s", e.msg);
    CHECK(pi.width == 10 && pi.height == 8);
    for (y = 0; y < 8; ++y)
        for (x = 0; x < 10; ++x) {
            const reservoir *f = &full[(y + 6) * 40 + x + 5], *q = &part[y * 10 + x];
            same &= f->W == q->W && f->wsum == q->wsum && dump_same_sample(&f->y, &q->y);
        }
    free(full);
    free(part);
    CHECK(same);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", a, g) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", g, a) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", g, g) == 0, "%s", out);
    /* a plant inside the region, reported in image coordinates (record 3,2 of the region) */
    {
        const char *b = diff_dir("Gp");
        char cmd[4000];
        char want[200];
        long p;
        snprintf(cmd, sizeof cmd, "rm -rf %s && cp -r %s %s", b, g, b);
        CHECK(system(cmd) == 0);
        p = edit_record(b, 1, "spatial1", -2, EDIT_W_SCALE);
        CHECK(p >= 0);
        CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", a, b) == 1, "%s", out);
        snprintf(want, sizeof want, "first difference: frame 1, stage spatial1, pixel %ld,%ld", 5 + p % 10, 6 + p / 10);
        CHECKF(strstr(out, want) != NULL, "want '%s':\n%s", want, out);
    }
    CHECKF(test_cli(out, sizeof out, "render " DIFF_COMMON " -o %s/gr.pfm --from-dump %s --from-stage temporal",
                    test_tmpdir(), g) == 2,
           "%s", out);
    CHECKF(strstr(out, "cannot restart") != NULL, "%s", out);
    CHECK(test_cli(out, sizeof out, "render " DIFF_COMMON " -o %s/gx.pfm --dump-dir %s --dump-region 35,0,10,8",
                   test_tmpdir(), diff_dir("Gx")) == 2);
    CHECKF(strstr(out, "does not lie inside") != NULL, "%s", out);
    CHECK(test_cli(out, sizeof out, "render " DIFF_COMMON " -o %s/gx.pfm --dump-dir %s --dump-region 1,2,3",
                   test_tmpdir(), diff_dir("Gx")) == 2);
}

/* A restart from a dump whose reconnection data is zero (rc_k = 0 and the x_k fields 0)
 * silently stopped spatial reuse (every hybrid shift failed: rc_offset_reconnects). Now
 * refused, exit 2, naming the file and the fields; our own dump still restarts. */
TEST(oracle_restart_refuses_zero_reconnection_data)
{
    const char *b = copy_of_reference("zero_rc");
    int f;
    for (f = 0; f <= 2; ++f) CHECK(edit_record(b, f, "temporal", -1, EDIT_ZERO_RC) > 0);
    CHECKF(test_cli(out, sizeof out, "render " DIFF_COMMON " -o %s/z.pfm --from-dump %s --from-stage temporal",
                    test_tmpdir(), b) == 2,
           "%s", out);
    CHECKF(strstr(out, "temporal.resv") && strstr(out, "no usable reconnection data") &&
               strstr(out, "would silently stop spatial reuse"),
           "%s", out);
    /* W = +inf cannot be restarted from either */
    b = copy_of_reference("inf_restart");
    CHECK(edit_record(b, 1, "temporal", 17, EDIT_W_INF) >= 0);
    CHECKF(test_cli(out, sizeof out, "render " DIFF_COMMON " -o %s/z.pfm --from-dump %s --from-stage temporal",
                    test_tmpdir(), b) == 2,
           "%s", out);
    CHECKF(strstr(out, "must be finite") != NULL, "%s", out);
}

/* --pairwise-confidence falcor: the manifest records it, a run with it agrees with the
 * default to rounding (1e-12) while every confidence is 1 (frame 0, spatial1) and differs once
 * confidences are unequal (frame 0, spatial2: its inputs carry spatial1's summed
 * confidences): the form a Falcor-derived build must be diffed against (docs/oracle.md §3,
 * docs/mis-derivations.md §3.5). */
TEST(oracle_pairwise_confidence_forms_diff)
{
    const char *a = reference(), *f = diff_dir("falcor");
    char path[1200];
    char *text;
    CHECKF(test_cli(out, sizeof out, "render " DIFF_COMMON " --pairwise-confidence falcor -o %s/pf.pfm --dump-dir %s",
                    test_tmpdir(), f) == 0,
           "%s", out);
    snprintf(path, sizeof path, "%s/manifest.json", f);
    text = test_read_text(path);
    CHECKF(text && strstr(text, "\"pairwise_confidence\": \"falcor\""), "%s", text ? text : "no manifest");
    free(text);
    /* rounding of the two weight formulas: 1e-12 in double; binary32 needs 1e-4 */
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-rel all=%s", a, f, sizeof(real) == 4 ? "1e-4" : "1e-12") == 1,
           "%s", out);
    CHECKF(strstr(out, "first difference: frame 0, stage spatial2") != NULL, "%s", out);
    CHECKF(strstr(out, "frame    0 spatial1     same 1.000000") && strstr(out, "frame    1 initial      same 1.000000"),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", f, f) == 0, "%s", out);
}
