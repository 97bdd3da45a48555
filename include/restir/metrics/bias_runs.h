/* Bias over K independent runs against a reference (issue 12; docs/statistics.md "Bias
 * over runs"; `restir compare --bias`). Enhanced §5 reports mean(|bias| / ref) over the
 * image (3.25% in its Kitchen); we measure it on blocks of pixels (block means of
 * luminance), with
 *   rel_bias        (mean_k I_k - R) / R of the whole (masked) image, t interval over
 *                   the runs (99% unless bias_options.level says otherwise, as check):
 *                   the signed test "consistent with 0";
 *   mean_abs_rel    mean_j |mean_k b_kj - r_j| / r_j over blocks j with r_j > 0, and its
 *                   basic bootstrap interval (runs resampled with replacement);
 *   corrected       2 mean_abs_rel - mean(bootstrap draws): the bootstrap's estimate of
 *                   mean_abs_rel with the noise's inflation of |.| removed (a resample
 *                   repeats runs, inflating it once more by about as much); the basic
 *                   interval [2v - q97.5, 2v - q2.5] is an interval for this quantity;
 *   noise_floor     the value mean_abs_rel takes in expectation for an UNBIASED estimator
 *                   with the same per-block spread: mean_j sqrt(2/pi) s_j / sqrt(K) / r_j
 *                   (E|N(0, s^2/K)|); an unbiased configuration measures mean_abs_rel close
 *                   to it, a biased one above it. The reference is exact unless its
 *                   noise is given (bias_options: `compare --bias --ref-moments`). */
#ifndef RESTIR_BIAS_RUNS_H
#define RESTIR_BIAS_RUNS_H

#include <stdint.h>
#include "restir/core/error.h"

typedef struct {
    double value, lo, hi; /* estimate and its interval at bias_options.level */
} bias_interval;

/* How the intervals are made and what is known of the reference's own noise. */
typedef struct {
    double level;          /* two-sided interval level: 0.99 by default, the level of `restir check` */
    int resamples;         /* bootstrap draws (>= 10) */
    uint32_t seed;         /* of the addressed RNG that draws them */
    const double *ref_var; /* per block: the variance of the reference's block mean, or NULL: exact */
    double ref_mean_var;   /* the variance of the reference's weighted image mean (0: exact) */
    double ref_dof;        /* its degrees of freedom (the reference's runs - 1; 0: exact) */
} bias_options;

void bias_options_default(bias_options *o);

typedef struct {
    int runs;
    long blocks;            /* blocks with r_j > 0 */
    bias_interval rel_bias;
    bias_interval mean_abs_rel; /* value: raw; lo, hi: basic bootstrap interval (of the corrected value) */
    double corrected;
    double noise_floor;
} bias_result;

/* run_block: K x B per-run block means (run-major), ref_block: B reference block means,
 * weight: B pixel counts (a block's share of the image mean; 0 = not in the mask).
 * With the reference's noise (o->ref_var, o->ref_mean_var): rel_bias's interval adds it
 * (delta method for I/R - 1, Welch-Satterthwaite degrees of freedom) and noise_floor is
 * E|N(0, s_j^2 / K + ref_var_j)| / r_j; the bootstrap resamples the runs only. */
int bias_measure(const double *run_block, const double *ref_block, const double *weight, int runs, long blocks,
                 const bias_options *o, bias_result *r, rerror *e);

#endif
