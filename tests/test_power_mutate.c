/* Power for the MCMC mutations (issue 26, "powered to see a 0.2 % bias"; docs/statistics.md,
 * power table): N mutations against none on the same seeds, per channel, cornell-glossy.
 *
 * Design for power (evidence_mutate_paired_per_channel: a 5-frame sequence, 16², 2 path
 * trees, pp after the temporal step, K = 32: 0.34 / 0.15 / 0.14 % detectable in 4.2 s):
 *   - one frame, the mutations right after the initial stage, no temporal or spatial pass:
 *     frame 0 of a sequence costs a fifth of frame 4, and the pixels that time buys (24²)
 *     lower the noise more than the extra passes added signal;
 *   - fp (full path-space perturbations: every vertex moves), where the planted
 *     mh-no-target-ratio shifts the colour most (at 24², K = 32: blue z -6.0 for fp, -5.2
 *     for pp, red +4.5 / +3.0).
 * Mutations keep each pixel's luminance F W exactly (the acceptance and W keep p̂ W; the
 * target is luminance), so the paired difference is all colour: a luminance control
 * variate removes nothing here (tried: identical numbers).
 * The rv / pp kernel ratio of Mutations Eq. 20 is 1 on every path of cornell-glossy that
 * power_mutate_fp sees (fp is symmetric); power_mutate_eq20 runs rv on a scene made for it
 * (below). Runs: BENCH_RUNS (bench.h): a quarter in the float, sanitizer and debug builds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "pt_util.h"
#include "restir/restir/mutate.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

/* N mutations (strategy, right after the initial stage; frame 0, 2 path trees, no temporal
 * or spatial pass) against none on the scene s, K = runs, run k on seed seed0 + 7919 k. */
static void power_mutate_paired(const scene *s, int runs, int strategy, int count, int max_depth,
                                enum restir_paths paths, uint32_t seed0, const char *name)
{
    bench_sequence_config on, off;
    bench_paired p;
    restir_options_default(&on.o);
    on.s = off.s = s;
    on.frame = off.frame = 0;
    on.o.shift = RESTIR_SHIFT_HYBRID;
    on.o.spatial_passes = 0;
    on.o.temporal.enabled = 0;
    on.o.candidates = 2;
    on.o.max_depth = max_depth;
    on.o.paths = paths;
    on.o.threads = 2;
    on.o.mutation.count = count;
    on.o.mutation.strategy = strategy;
    on.o.mutation.stages = MUTATE_AFTER_INITIAL;
    off.o = on.o;
    off.o.mutation.count = 0;
    bench_paired_init(&p, name);
    if (!bench_paired_run(&p, runs, seed0, bench_sequence_run, &on, bench_sequence_run, &off))
        bench_paired_expect_consistent(&p, BENCH_Z_CONSISTENT);
}

/* x20 on cornell-glossy, all light, paths up to 4 segments. */
static void power_mutate(int res, int runs, int strategy, const char *name)
{
    scene s;
    if (rt_load_scene("scenes/cornell-glossy.scene", res, &s)) return;
    power_mutate_paired(&s, runs, strategy, 20, 4, RESTIR_PATHS_ALL,
                        test_seed() * 40503u + 99u + 1000u * (uint32_t)strategy, name);
    scene_free(&s);
}

/* fp x20 after the initial stage, 24², K = 64. */
TEST(power_mutate_fp)
{
    power_mutate(24, BENCH_RUNS(64), MUTATE_FP, "mutations fp x20 vs none after initial, cornell-glossy 24^2");
}

/* rv and pp x20 after the initial stage, 24², K = 64 (session 14: every strategy in make test). */
TEST(power_mutate_rv)
{
    power_mutate(24, BENCH_RUNS(64), MUTATE_RV, "mutations rv x20 vs none after initial, cornell-glossy 24^2");
}

TEST(power_mutate_pp)
{
    power_mutate(24, BENCH_RUNS(64), MUTATE_PP, "mutations pp x20 vs none after initial, cornell-glossy 24^2");
}

/* Every strategy at 32², K = 64. */
TEST_LONG(power_mutate_long)
{
    int strategy;
    char name[128];
    for (strategy = 0; strategy < MUTATE_STRATEGY_COUNT && !test_has_failed(); ++strategy) {
        snprintf(name, sizeof name, "mutations %s x20 vs none after initial, cornell-glossy 32^2",
                 mutate_strategy_names[strategy]);
        power_mutate(32, 64, strategy, name);
    }
}

/* ---- Mutations Eq. 20 (the rv / pp kernel ratio) --------------------------------------- */

/* A scene made for Eq. 20: a white floor seen from above, a back wall in 16 horizontal strips
 * from red at the top to blue at the bottom, and a ceiling light (2 x 0.7 m, facing down)
 * right against the top of the wall. With indirect light only the paths are camera -> x_1
 * (floor) -> x_2 (wall: the reconnection vertex, k = 2) -> x_3 on the light, and where x_3 is
 * a BSDF hit (not NEE-sampled) rv moves x_2 with x_3 kept: the kernel ratio A(z)/A(y) of
 * Eq. 20 holds p(w_2) and G(x_2 -> x_3) = cos / r², which vary steeply with the height of x_2
 * near the light. A chain with a wrong ratio leaves another density than p̂ invariant: x_2
 * drifts up or down the wall, so the colour drifts between red and blue while each pixel's
 * luminance F W stays exact. Every difference is that red-blue trade at a fixed luminance,
 * so R, G and B give the same |z|.
 * Why strips: with a wall only half red, half blue (one colour edge) the colour changes only
 * where x_2 crosses the edge: detectable 1.9-2.4 % in red, eq20-inverted |z| 8.3-8.8 and
 * eq20-cos-at-moved-vertex 0.6-3.7 at seeds 1-3 (K = 96, 100 mutations). With a colour that
 * follows the height every step of the chain shows in it, and the lottery between two far
 * colours becomes one between neighbours (0.91 % at the same K; 32 strips: 0.88 %). Most
 * of the ratio's leverage sits where the wall meets the light (r -> 0): with the light 0.5 m
 * off the wall the two-colour wall's eq20-inverted fell from -8 % to -1.5 %. */
static int make_eq20_wall(scene *s, int res)
{
    enum { STRIPS = 16 };
    uint32_t white, light;
    int i;
    if (test_scene_begin(s, 4 + 2 * STRIPS, 2 + STRIPS)) return -1;
    white = test_scene_material(s, MAT_LAMBERT, rgb_gray((real)0.8), rgb_gray(0));
    light = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_gray(5));
    test_scene_quad(s, v3f(-1, 0, -1), v3f(0, 0, 2), v3f(2, 0, 0), white);     /* y = 0, normal +y */
    for (i = 0; i < STRIPS; ++i) {                                              /* z = 1, normal -z */
        real t = (real)i / (STRIPS - 1);                                        /* 0 bottom, 1 top */
        uint32_t m = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.1 + (real)0.75 * t, (real)0.15,
                                                                  (real)0.85 - (real)0.75 * t), rgb_gray(0));
        test_scene_quad(s, v3f(-1, (float)i / STRIPS, 1), v3f(0, 1.0f / STRIPS, 0), v3f(2, 0, 0), m);
    }
    test_scene_quad(s, v3f(-1, 1, 0.3f), v3f(2, 0, 0), v3f(0, 0, 0.7f), light); /* y = 1, normal -y */
    test_scene_camera(s, v3(0, (real)0.9, (real)-1.6), v3(0, 0, (real)0.2), v3(0, 1, 0), 40, res);
    return test_scene_prepare(s);
}

/* On the Eq. 20 wall, indirect light only. */
static void power_eq20(int res, int runs, int strategy, int count, int max_depth, const char *name)
{
    scene s;
    if (make_eq20_wall(&s, res)) return;
    power_mutate_paired(&s, runs, strategy, count, max_depth, RESTIR_PATHS_INDIRECT,
                        test_seed() * 69069u + 5u + 1000u * (uint32_t)strategy, name);
    scene_free(&s);
}

/* rv x25 right after the initial stage vs none, 24², K = 256. Few mutations and many runs: the
 * more steps, the larger the drift of a wrong chain but the less the mutated sample shares with
 * the initial one (the paired noise). At about the same cost (2.5-4 s): x100, K = 96: 0.91 %
 * detectable in red, eq20-cos-at-moved-vertex z +5.8; x50, K = 192: 0.55 %, z +8.5; x25,
 * K = 256: 0.40 %, z +8.8; x10, K = 384: 0.25 %, z +7.7. */
TEST(power_mutate_eq20)
{
    power_eq20(24, BENCH_RUNS(256), MUTATE_RV, 25, 3, "mutations rv x25 vs none after initial, eq20 wall 24^2");
}
