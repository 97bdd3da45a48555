/* Sample identity and duplication maps (Enhanced §5; issue 12; docs/correlation.md).
 *
 * Sample identity: a reservoir's sample is a shifted copy of one initial candidate, and
 * that candidate is named by its replay identity (seed, pixel, sample) (path_sample.h),
 * which every shift keeps. Two reservoirs hold "the same sample" iff both have W > 0 and
 * equal identities (the GPU codes compare the stored replay seed; notes §2.8 writes 0 for
 * W = 0, so empty and zero-weight reservoirs are never duplicates).
 *
 * Duplication map (Enhanced §5 step 1): count(p) = the number of pixels q != p in the
 * (2r+1) x (2r+1) window around p (r = 8: 17 x 17) whose reservoir holds p's sample;
 * D(p) = count(p) / ((2r+1)^2 - 1) in [0, 1] (288 for r = 8).
 *
 * Adaptive confidence cap (Enhanced §5 step 3), looked up at the temporal source pixel:
 *     c_cap = lerp(c_cap_default, c_cap_min, D^alpha)
 * with c_cap_min = 1 and alpha = 0.1 by default. It lowers the MIS confidences by a
 * function of the samples themselves, so the MIS weights no longer sum to 1: BIASED by
 * design (Enhanced §5 last paragraph; measured in docs/results.md "Correlation"). */
#ifndef RESTIR_DUPLICATION_H
#define RESTIR_DUPLICATION_H

#include <stdint.h>
#include "restir/restir/reservoir.h"

#define DUPLICATION_RADIUS 8 /* 17 x 17 window (Enhanced §5) */

/* 1 iff a and b hold copies of the same initial candidate (both W > 0, same identity). */
int duplication_same_sample(const reservoir *a, const reservoir *b);

/* count[p] for every pixel of the w x h reservoir image rs (row-major), window radius
 * 0 <= r <= DUPLICATION_RADIUS; the window is clipped at the image border (clipped pixels
 * count as no copy). In 16 x 16 tiles on `threads` workers (threads.h: the same counts for
 * any thread count). */
void duplication_counts(const reservoir *rs, int w, int h, int r, int threads, uint16_t *count);

/* D = count / ((2r+1)^2 - 1). */
double duplication_score(unsigned count, int r);
/* (2r+1)^2 - 1: 288 for r = 8. */
double duplication_score_denominator(int r);

/* Enhanced §5 step 3: lerp(cap_default, cap_min, D^alpha) (D in [0,1], alpha > 0). */
double duplication_cap(double cap_default, double cap_min, double d, double alpha);

/* Per-frame correlation summary of a duplication map (--stats "correlation"). */
typedef struct {
    uint64_t pixels;      /* pixels counted (all pixels of the image) */
    uint64_t duplicated;  /* pixels with count > 0 */
    uint64_t count_sum;   /* sum of count */
    uint32_t count_max;   /* largest count */
} duplication_summary;

void duplication_summarize(const uint16_t *count, long n, duplication_summary *s);
void duplication_summary_add(duplication_summary *acc, const duplication_summary *add);

/* The false-colour heat map of Enhanced Fig. 5: black at D = 0 to red at D >= d_max
 * (Enhanced: d_max = 0.2), 8-bit sRGB. */
void duplication_heat_colour(double d, double d_max, unsigned char rgb[3]);

#endif
