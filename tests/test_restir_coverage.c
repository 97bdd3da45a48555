/* Coverage of offline ReSTIR PT where it was thin (issue 9), under the K-run statistics of
 * `restir check` against the path tracer:
 *   - the mirror corridor (generate_corridor): hybrid shifts that replay 3+ glossy bounces
 *     and reconnect at k >= 5, rough transmission through the glass block, 3 spatial
 *     passes (so shifted samples are shifted again);
 *   - the gris-offline preset itself (32 path trees, 3 passes, 6 neighbours in radius
 *     10, defensive pairwise MIS: GRIS §8.3), and the same check rejecting the preset
 *     with --ablate jacobian (on the spot scene of restir_util.h, where E[J] is far
 *     from 1). */
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"

#define ALPHA 1e-3

typedef struct {
    scene s;
    check_side pt;
    int block, runs;
} coverage_bench;

/* path NULL: the spot scene. */
static int bench_open(coverage_bench *b, const char *path, int res, int runs, uint32_t spp, int max_depth)
{
    rerror e;
    memset(b, 0, sizeof *b);
    b->block = 4;
    b->runs = runs;
    if (!path) {
        if (rt_make_spot(&b->s, res)) return -1;
        if (scene_prepare(&b->s, &e)) {
            test_fail(__FILE__, __LINE__, "%s", e.msg);
            scene_free(&b->s);
            return -1;
        }
    } else if (rt_load_scene(path, res, &b->s))
        return -1;
    if (rt_pt_side(&b->s, test_seed() * 7919u + 11, runs, spp, max_depth, 0, b->block, &b->pt)) {
        scene_free(&b->s);
        return -1;
    }
    return 0;
}

static void bench_close(coverage_bench *b)
{
    check_side_free(&b->pt);
    scene_free(&b->s);
}

/* K runs of ReSTIR with options o against the bench's path tracer; `biased` is the
 * expected verdict. Returns the mean z (0 on error). */
static double expect(coverage_bench *b, const char *what, const restir_options *o, int biased)
{
    check_side a;
    check_result c;
    check_options opt;
    rerror e;
    int status;
    double z;
    if (rt_restir_side(&b->s, o, b->runs, b->block, &a)) return 0;
    check_options_default(&opt);
    opt.alpha = ALPHA;
    opt.block_size = b->block;
    status = check_compare(&a, &b->pt, &opt, &c, &e);
    check_side_free(&a);
    CHECKF(status == 0, "check_compare: %s", e.msg);
    if (status) return 0;
    z = rt_mean_z(&c);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what, z,
                c.lum_a.mean, c.lum_b.mean, c.rejected, c.tests, c.worst.z);
    if (biased)
        CHECKF(c.different, "%s: the biased estimator was not detected (mean z %.2f, worst block z %.2f)", what, z,
               c.worst.z);
    else
        CHECKF(!c.different, "%s: differs from the path tracer: mean z %.2f (p %.3g), %ld of %ld blocks rejected, worst z %.2f",
               what, z, c.global.p, c.rejected, c.tests, c.worst.z);
    check_result_free(&c);
    return z;
}

static void corridor_options(restir_options *o, int shift, int mis)
{
    restir_options_default(o);
    o->seed = test_seed() * 1181u + 17u * (uint32_t)shift + (uint32_t)mis;
    o->shift = shift;
    o->mis = mis;
    o->spatial_passes = 3;
    o->neighbors = 4;
    o->radius = 4;
    o->frames = 16; /* light through the rough glass block is heavy-tailed: 4 frames gave false block rejections */
    o->candidates = 2;
    o->max_depth = 8;
    o->threads = 2;
}

/* The corridor with the hybrid shift (long replay, late reconnection, rough glass), 3
 * passes; the reconnection shift and Talbot MIS in the TEST_LONG version. */
static void corridor(int res, int runs, int all)
{
    coverage_bench b;
    restir_options o;
    if (bench_open(&b, RT_CORRIDOR, res, runs, 64, 8)) return;
    corridor_options(&o, RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE);
    expect(&b, "corridor hybrid pairwise-defensive 3 passes", &o, 0);
    if (all && !test_has_failed()) {
        corridor_options(&o, RESTIR_SHIFT_HYBRID, MIS_TALBOT);
        expect(&b, "corridor hybrid talbot 3 passes", &o, 0);
    }
    if (all && !test_has_failed()) {
        corridor_options(&o, RESTIR_SHIFT_RECONNECTION, MIS_PAIRWISE_DEFENSIVE);
        expect(&b, "corridor reconnection pairwise-defensive 3 passes", &o, 0);
    }
    if (all && !test_has_failed()) {
        corridor_options(&o, RESTIR_SHIFT_REPLAY, MIS_PAIRWISE_DEFENSIVE);
        expect(&b, "corridor replay pairwise-defensive 3 passes", &o, 0);
    }
    bench_close(&b);
}

TEST(restir_corridor_unbiased) { corridor(12, 16, 0); }
TEST_LONG(restir_corridor_unbiased_long) { corridor(16, 24, 1); }

/* The preset as `render --preset gris-offline` sets it (the image size and the frame
 * count are the test's). */
static void preset_options(restir_options *o, int ablation)
{
    restir_options_default(o);
    restir_options_preset_gris_offline(o);
    o->seed = test_seed() * 1181u + 5u + (uint32_t)ablation;
    o->max_depth = 3;
    o->frames = 2;
    o->ablation = ablation;
    o->threads = 2;
}

TEST(restir_preset_gris_offline_unbiased_and_jacobian_ablation_detected)
{
    coverage_bench b;
    restir_options o;
    preset_options(&o, RESTIR_ABLATE_NONE);
    CHECK(o.mis == MIS_PAIRWISE_DEFENSIVE && o.candidates == 32 && o.spatial_passes == 3 && o.neighbors == 6 &&
          o.radius == 10);
    if (bench_open(&b, NULL, 16, 16, 256, 3)) return;
    expect(&b, "spot gris-offline", &o, 0);
    preset_options(&o, RESTIR_ABLATE_JACOBIAN);
    if (!test_has_failed()) expect(&b, "spot gris-offline --ablate jacobian", &o, 1);
    bench_close(&b);
}
