/* Power for temporal MIS (issue 26, "powered to see a 0.2 % bias"; docs/statistics.md, power
 * table): Talbot and pairwise-defensive temporal MIS against no temporal reuse (all three
 * unbiased for the same frame) on a camera panning 12.5 units a frame over cornell-glossy,
 * direct light only, per channel, on the same seeds.
 *
 * Design for power (evidence_temporal_mis_paired_pan: 24², 1 candidate, frame 8, K = 48:
 * 0.28-0.36 % detectable):
 *   - 8 initial candidates instead of 1: the pixel's own estimate (B, and A's canonical
 *     domain) is quieter, and most of the paired difference is that noise (24², K = 24:
 *     0.50 % with 1 candidate, 0.31 % with 4; 32², K = 32: 0.10 % with 8). The planted
 *     temporal-mis-current-target stays as large (+0.38 % in R at frame 4 with 8
 *     candidates, +0.33 % with 4; with 1 candidate it is invisible at frame 4 and +0.4-0.7 %
 *     at frame 8: the bias depends on where the highlights sit in that frame);
 *   - frame 4 instead of 8: the history already weighs c = 4 against the current frame's 1,
 *     at half the frames per run; the saved time buys pixels (32² instead of 24²). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "restir/frame/pipeline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

static void power_pan_options(restir_options *o, int temporal, int mis, int max_depth, int candidates)
{
    restir_options_default(o);
    o->temporal.enabled = temporal;
    o->temporal.mis = mis;
    o->spatial.mis = MIS_TALBOT;
    o->spatial_passes = 0;
    o->candidates = candidates;
    o->max_depth = max_depth;
    o->shift = RESTIR_SHIFT_HYBRID;
    o->temporal.mcap = 20;
    o->threads = 2;
}

/* Talbot and pairwise-defensive temporal MIS vs none at frame `frame`, K = runs. */
static void power_temporal(int res, int runs, int frame, int max_depth, int candidates)
{
    scene s;
    restir_options talbot, pairwise, none;
    bench_paired pt, pp;
    int k;
    uint32_t seed0 = test_seed() * 2246822519u + 1013u;
    if (rt_load_glossy_pan(&s, res, 200)) return;
    power_pan_options(&talbot, 1, MIS_TALBOT, max_depth, candidates);
    power_pan_options(&pairwise, 1, MIS_PAIRWISE_DEFENSIVE, max_depth, candidates);
    power_pan_options(&none, 0, MIS_TALBOT, max_depth, candidates);
    bench_paired_init(&pt, "temporal Talbot vs none, glossy pan, 8 candidates");
    bench_paired_init(&pp, "temporal pairwise-defensive vs none, glossy pan, 8 candidates");
    for (k = 0; k < runs; ++k) {
        double a[3], b[3], c[3];
        talbot.seed = pairwise.seed = none.seed = seed0 + 7919u * (uint32_t)k;
        if (bench_sequence_mean(&s, &none, frame, b) || bench_sequence_mean(&s, &talbot, frame, a) ||
            bench_sequence_mean(&s, &pairwise, frame, c))
            break;
        bench_paired_add(&pt, a, b);
        bench_paired_add(&pp, c, b);
    }
    scene_free(&s);
    if (test_has_failed()) return;
    bench_paired_finish(&pt);
    bench_paired_finish(&pp);
    if (bench_paired_expect_consistent(&pt, BENCH_Z_CONSISTENT)) return;
    bench_paired_expect_consistent(&pp, BENCH_Z_CONSISTENT);
}

/* Direct light only (paths of 2 segments), 32², frame 4, 8 candidates, K = 28. */
TEST(power_temporal_pan)
{
    power_temporal(32, 28, 4, 2, 8);
}

/* Paths up to 3 segments (indirect light too), 32², frame 4, 8 candidates, K = 192. Not
 * larger images: at 64² (K = 96: 0.15-0.21 % detectable) temporal-mis-current-target moved
 * the image by only +0.05 %: the finer the pixels, the closer the reprojected primary hit
 * and the smaller |p̂_t(y_1) - p̂_{t-1}(X_1)/J_1|, the bias of that mutant. */
TEST_LONG(power_temporal_pan_long)
{
    power_temporal(32, 192, 4, 3, 8);
}
