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
 * variate removes nothing here (tried: identical numbers). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "restir/restir/mutate.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

static void power_mutate(int res, int runs, int strategy, const char *name)
{
    scene s;
    bench_sequence_config on, off;
    bench_paired p;
    if (rt_load_scene("scenes/cornell-glossy.scene", res, &s)) return;
    restir_options_default(&on.o);
    on.s = off.s = &s;
    on.frame = off.frame = 0;
    on.o.shift = RESTIR_SHIFT_HYBRID;
    on.o.spatial_passes = 0;
    on.o.temporal.enabled = 0;
    on.o.candidates = 2;
    on.o.max_depth = 4;
    on.o.threads = 2;
    on.o.mutation.count = 20;
    on.o.mutation.strategy = strategy;
    on.o.mutation.stages = MUTATE_AFTER_INITIAL;
    off.o = on.o;
    off.o.mutation.count = 0;
    bench_paired_init(&p, name);
    if (!bench_paired_run(&p, runs, test_seed() * 40503u + 99u + 1000u * (uint32_t)strategy, bench_sequence_run, &on,
                          bench_sequence_run, &off))
        bench_paired_expect_consistent(&p, BENCH_Z_CONSISTENT);
    scene_free(&s);
}

/* fp x20 after the initial stage, 24², K = 64. */
TEST(power_mutate_fp)
{
    power_mutate(24, 64, MUTATE_FP, "mutations fp x20 vs none after initial, cornell-glossy 24^2");
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
