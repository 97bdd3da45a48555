/* The RTXDI boiling filter (the baseline of Enhanced Fig. 9, §7.4; notes §2.6; issue 12;
 * docs/correlation.md): per group of g x g pixels, the average w̄ of the non-zero
 * reservoir weights w = p̂(Y) W_Y, and every reservoir with w > a w̄ is cleared, where
 *     a = 10 / s - 9   for the strength s in (0, 1]   (Enhanced §7.4: a = -9 + 10/s)
 * (s = 1: a = 1, the strongest; s -> 0: a -> infinity, off). Clearing samples by their
 * own weight removes energy: BIASED (dark), by design. RTXDI runs it after temporal
 * resampling on 16 x 16 thread groups; so does our pipeline (groups = our 16 x 16 tiles). */
#ifndef RESTIR_BOILING_FILTER_H
#define RESTIR_BOILING_FILTER_H

#include <stdint.h>
#include "restir/restir/reservoir.h"

#define BOILING_GROUP 16

/* a = 10 / s - 9 (s clamped to [1e-6, 1] as RTXDI does). */
double boiling_multiplier(double strength);

/* 1 iff weight w is cleared in a group whose non-zero weights average `mean` (> 0). */
int boiling_rejects(double w, double mean, double strength);

/* The filter over a w x h image of reservoirs, groups of g x g pixels aligned at (0,0).
 * Returns the number of reservoirs cleared (reservoir_init; the confidence goes too, as
 * in RTXDI). */
uint64_t boiling_filter(reservoir *rs, int w, int h, int g, double strength);

#endif
