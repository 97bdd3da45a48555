/* Paired bias tests of spatial reuse (docs/statistics.md "Paired check"): K spatial
 * passes (A) against 0 passes (B: initial resampling alone, validated against the path
 * tracer in test_restir_initial.c) on the SAME seed and frame ranges, so run k of A reuses
 * exactly the initial samples of run k of B. check_compare_paired tests the K per-run
 * differences of the image mean and of every block (one-sample t-tests, Sidak), so the
 * noise the two share cancels. The unpaired tests against the path tracer stay
 * (test_restir_spatial.c); these add power, and cover what those never combine with
 * 2+ passes: Russian roulette, --jitter and --paths indirect. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

#define ALPHA 1e-3

typedef struct {
    int shift, mis, passes;
    int russian_roulette, jitter, indirect;
} paired_case;

typedef struct {
    scene s;
    int runs, frames, max_depth, block;
    uint32_t seed;
} paired_bench;

static int verbose(void) { return getenv("RESTIR_TEST_VERBOSE") != NULL; }

static void options_for(const paired_bench *b, const paired_case *m, int passes, restir_options *o)
{
    restir_options_default(o);
    o->seed = b->seed;
    o->shift = m->shift;
    o->spatial.mis = m->mis;
    o->spatial_passes = passes;
    o->spatial.neighbors = 4;
    o->spatial.radius = 4.0 * b->s.width / 16;
    o->frames = b->frames;
    o->candidates = 2;
    o->max_depth = b->max_depth;
    o->russian_roulette = m->russian_roulette;
    o->jitter = m->jitter;
    o->paths = m->indirect ? RESTIR_PATHS_INDIRECT : RESTIR_PATHS_ALL;
    o->threads = 2;
}

/* The paired verdict of case m (A: m->passes passes, B: 0 passes, same seeds) and, for
 * the record, the unpaired Welch verdict of the same two sides. Returns 0 on success. */
static int paired_compare(const paired_bench *b, const paired_case *m, check_result *paired, double *se_ratio)
{
    restir_options oa, ob;
    check_side a, base;
    check_options opt;
    check_result unpaired;
    rerror e;
    int status;
    options_for(b, m, m->passes, &oa);
    options_for(b, m, 0, &ob);
    if (rt_restir_side(&b->s, &oa, b->runs, b->block, &a)) return -1;
    if (rt_restir_side(&b->s, &ob, b->runs, b->block, &base)) {
        check_side_free(&a);
        return -1;
    }
    check_options_default(&opt);
    opt.alpha = ALPHA;
    opt.block_size = b->block;
    status = check_compare_paired(&a, &base, &opt, paired, &e);
    if (status == 0 && check_compare(&a, &base, &opt, &unpaired, &e) == 0) {
        *se_ratio = paired->global.se > 0 ? unpaired.global.se / paired->global.se : INFINITY;
        check_result_free(&unpaired);
    }
    check_side_free(&a);
    check_side_free(&base);
    if (status) test_fail(__FILE__, __LINE__, "check_compare_paired: %s", e.msg);
    return status;
}

static void case_name(const paired_case *m, char *out, size_t n)
{
    snprintf(out, n, "shift %s mis %s passes %d%s%s%s", restir_shift_names[m->shift], restir_mis_names[m->mis],
             m->passes, m->russian_roulette ? " rr" : "", m->jitter ? " jitter" : "",
             m->indirect ? " indirect" : "");
}

/* Case m must be consistent with its 0-pass baseline. */
static void expect_consistent(const paired_bench *b, const char *scene_name, const paired_case *m)
{
    check_result r;
    double ratio = 0;
    char what[160];
    if (paired_compare(b, m, &r, &ratio)) return;
    case_name(m, what, sizeof what);
    if (verbose())
        fprintf(stderr, "  paired %s %s: mean z %.2f (relative diff %+.4f%% +- %.4f%%), worst block z %.2f; "
                        "se unpaired / paired = %.1f\n",
                scene_name, what, stats_t_to_z(r.global.t, r.global.dof), 100 * r.bias,
                100 * r.global.se / fabs(r.lum_b.mean), r.worst.z, ratio);
    CHECKF(!r.different, "%s %s: differs from its 0-pass baseline on the same seeds: mean z %.2f (p %.3g), %ld of %ld blocks rejected, worst z %.2f",
           scene_name, what, stats_t_to_z(r.global.t, r.global.dof), r.global.p, r.rejected, r.tests, r.worst.z);
    check_result_free(&r);
}

static int bench_open(paired_bench *b, const char *path, int res, int runs, int frames, int max_depth)
{
    memset(b, 0, sizeof *b);
    b->runs = runs;
    b->frames = frames;
    b->max_depth = max_depth;
    b->block = 4;
    b->seed = test_seed() * 2654435761u + 17u;
    return rt_load_scene(path, res, &b->s);
}

/* Every shift x {Talbot, pairwise, defensive} x {1, 3} passes. */
static void paired_matrix(const char *path, int res, int runs, int frames)
{
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    paired_bench b;
    paired_case m;
    int f;
    memset(&m, 0, sizeof m);
    if (bench_open(&b, path, res, runs, frames, 4)) return;
    for (m.shift = 0; m.shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++m.shift)
        for (f = 0; f < 3 && !test_has_failed(); ++f)
            for (m.passes = 1; m.passes <= 3 && !test_has_failed(); m.passes += 2) {
                m.mis = families[f];
                expect_consistent(&b, path, &m);
            }
    scene_free(&b.s);
}

TEST(restir_paired_spatial_matrix)
{
    paired_matrix("scenes/cornell-glossy.scene", 16, 12, 1);
}

/* Russian roulette, --jitter and --paths indirect, each with 2 and 3 passes (hybrid). */
TEST(restir_paired_rr_jitter_indirect)
{
    paired_bench b;
    paired_case cases[] = {
        {RESTIR_SHIFT_HYBRID, MIS_TALBOT, 2, 1, 0, 0},
        {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 3, 1, 0, 0},
        {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_UNIFORM, 2, 0, 1, 0},
        {RESTIR_SHIFT_RECONNECTION, MIS_TALBOT, 3, 0, 1, 0},
        {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 2, 0, 0, 1},
        {RESTIR_SHIFT_REPLAY, MIS_TALBOT, 3, 0, 0, 1},
        {RESTIR_SHIFT_HYBRID, MIS_TALBOT, 2, 1, 1, 1},
    };
    size_t i;
    if (bench_open(&b, "scenes/cornell-glossy.scene", 16, 16, 2, 5)) return; /* heavy tails (RR, indirect): 2 frames per run */
    for (i = 0; i < sizeof cases / sizeof cases[0] && !test_has_failed(); ++i)
        expect_consistent(&b, "cornell-glossy", &cases[i]);
    scene_free(&b.s);
}

TEST_LONG(restir_paired_spatial_matrix_long)
{
    paired_matrix("scenes/cornell.scene", 16, 24, 2);
    if (!test_has_failed()) paired_matrix("scenes/cornell-glossy.scene", 24, 24, 2);
    if (!test_has_failed()) paired_matrix("scenes/glass.scene", 16, 24, 4);
}
