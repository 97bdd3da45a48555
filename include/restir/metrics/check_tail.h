/* Does `restir check` know enough to judge? The tail of the per-run statistics
 * (docs/statistics.md, "When check cannot judge: heavy-tailed runs"; issue 27).
 *
 * check's tests are t-tests on K per-run means. They are calibrated when those means are
 * close to normal: a finite variance and a skewness small for K. An estimator whose
 * per-run results are heavy-tailed (a rare run carries a firefly that moves the mean by
 * more than the other runs' spread) breaks both: most run sets miss the firefly (mean low,
 * variance low: a confident "different"), the next one catches it (variance huge:
 * "consistent"). Two measures of each side's runs:
 *   - skewness: the sample skewness of the K per-run luminance image means, and the pooled
 *     skewness of the per-run block means (check.h, skew_a / skew_b);
 *   - a tail index alpha (Hill 1975) of the per-run block means, pooled over blocks and
 *     channels: each block's K values are centred on their median and scaled by their
 *     median absolute deviation, the positive deviations of all blocks are pooled, and
 *     alpha = 1 / mean(ln(y_i / y_(k+1))) over the k = ceil(sqrt(n)) largest of the n.
 *     alpha < 2 means the variance may be infinite (a t-test is then never exact), a
 *     light-tailed (normal-like) side gives about 3 (K = 8) to 7 (K = 32; tools/check_tail).
 * The verdict is inconclusive when a side's alpha is below CHECK_TAIL_ALPHA_MIN by more
 * than its noise (alpha (1 + 1/sqrt(k)) < CHECK_TAIL_ALPHA_MIN, Hill's sd ~ alpha/sqrt(k)); the
 * number of runs it would take is then at least K >= 25 g^2 (Cochran's rule for the t-test
 * of a skewed mean: K > 25 g1^2; Cochran 1977, Sampling Techniques §2.15), g the larger
 * of the two skewness measures, and no K suffices if the variance is infinite. */
#ifndef RESTIR_CHECK_TAIL_H
#define RESTIR_CHECK_TAIL_H

#define CHECK_TAIL_ALPHA_MIN 2.0 /* below: heavy-tailed, the verdict cannot be trusted */
#define CHECK_TAIL_MIN_RUNS 8    /* fewer runs per side: the tail is not measured */
#define CHECK_TAIL_MIN_EXCEEDANCES 200 /* fewer pooled deviations: not measured either (K = 8 on
                                          a 24 x 24 image, 27 block series, gives ~108: there the
                                          estimate flagged 9 of 100 correct ReSTIR/PT pairs) */

typedef struct {
    int measured;          /* 0: no per-run block means, K < CHECK_TAIL_MIN_RUNS, or fewer than
                              CHECK_TAIL_MIN_EXCEEDANCES deviations (exceedances says how many) */
    double skew_image;     /* sample skewness g1 of the K per-run luminance image means (0: none) */
    double skew_blocks;    /* pooled skewness of the per-run block means */
    double tail_index;     /* pooled Hill estimate (HUGE_VAL when nothing is heavy) */
    double tail_upper;     /* tail_index (1 + 1 / sqrt(k)): one standard deviation above it */
    long exceedances;      /* n: positive standardised deviations pooled */
    long tail_count;       /* k: the largest of them that the estimate uses */
    int heavy;             /* tail_upper < CHECK_TAIL_ALPHA_MIN */
} check_tail;

/* The tail of K per-run values at x[0], x[stride], ..., for nseries series starting at
 * x + series_stride * j (the layout of per-run block means: stride 3 * blocks, series
 * stride 1). skew_image_runs: the K per-run luminance image means, or NULL. */
void check_tail_measure(check_tail *t, const double *x, long runs, long stride, long nseries,
                        const double *image_runs, double skew_blocks);

/* The runs the t-test would need on this side: ceil(25 g^2) for the larger |g| (at least
 * K + 1 when the side is heavy). */
long check_tail_runs_needed(const check_tail *t, long runs);

/* Sample skewness g1 = m3 / m2^(3/2) of n values (0 when they are all equal). */
double check_sample_skewness(const double *x, long n, long stride);

#endif
