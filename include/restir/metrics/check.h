/* `restir check`: do two renderers estimate the same image? (docs/statistics.md, "check")
 *
 * Each side is K independent runs (or their moments file set), or a reference image that
 * is exact or carries its own variance. The verdict "different" is a family-wise test at
 * level alpha made of two parts with alpha/2 each:
 *   - a Welch t-test of the luminance image means (exact for correlated pixels when the
 *     per-run image means are known);
 *   - per-block, per-channel Welch t-tests with a Sidak or Benjamini-Hochberg correction.
 * Reported alongside: per-pixel and per-block normal-equivalent z maps, a TOST
 * equivalence verdict on the ratio of image means, and the relative bias with its
 * confidence interval. */
#ifndef RESTIR_CHECK_H
#define RESTIR_CHECK_H

#include "restir/core/error.h"
#include "restir/core/image.h"
#include "restir/metrics/check_tail.h"
#include "restir/metrics/moments.h"
#include "restir/metrics/stats.h"

enum check_correction { CHECK_SIDAK = 0, CHECK_BH = 1 };

typedef struct {
    double alpha;                     /* level of the "different" verdict (default 0.01) */
    enum check_correction correction; /* block family correction (default Sidak) */
    double margin;                    /* relative equivalence margin (default 0.01) */
    int block_size;                   /* block edge in pixels (default 8; 1 = per pixel) */
    int skew_correction;              /* 1 (default): block tests on per-run block means discount
                                         t on the tail opposite the pooled skewness (Hall 1992;
                                         docs/statistics.md "Skewed per-run means"); 0: plain Welch */
} check_options;

void check_options_default(check_options *o);

enum check_side_kind { CHECK_SIDE_RUNS = 0, CHECK_SIDE_MOMENTS = 1, CHECK_SIDE_EXACT = 2 };

/* One side of the comparison. Build it with exactly one of: begin_runs + add_run... +
 * end_runs; from_moments; exact. */
typedef struct {
    enum check_side_kind kind;
    int width, height;
    int block_size, blocks_x, blocks_y;
    long runs;                /* K; 0 for an exact reference */
    image mean, var;          /* per-pixel mean and single-run sample variance (var: not for exact) */
    double *run_means;        /* 3 per run (r, g, b image means), or NULL */
    double *block_run_means;  /* runs only: [run][block][channel] block means */
    moments acc;              /* runs only, while accumulating */
    /* moments only: per-run block means read from the file set (PREFIX.blocks.bin), used
     * for the block tests when one of these sizes is the check's block size */
    int run_block_count;
    int run_block_sizes[MOMENTS_MAX_BLOCK_SIZES];
    double *run_block_means[MOMENTS_MAX_BLOCK_SIZES];
    enum moments_correlation correlation; /* moments only: what the file set says */
} check_side;

/* Runs: block_size must equal the check_options block size used later. */
int check_side_begin_runs(check_side *s, int width, int height, int block_size, rerror *e);
int check_side_add_run(check_side *s, const image *run, const char *name, rerror *e);
int check_side_end_runs(check_side *s, rerror *e); /* needs >= 2 runs */
/* Takes ownership of f's images, run means and per-run block means (f is emptied).
 * Needs f->runs >= 2. */
int check_side_from_moments(check_side *s, moments_file *f, const char *name, rerror *e);
/* A reference taken as exact (zero variance). Takes ownership of ref (emptied). */
int check_side_exact(check_side *s, image *ref, rerror *e);
void check_side_free(check_side *s);
/* Multiplies every run of the side by `factor` (means by factor, variances by factor^2):
 * a planted relative bias factor - 1, for measuring the power of check
 * (`restir check --scale-a`, scripts/power.sh). */
void check_side_scale(check_side *s, double factor);

typedef struct {
    int x, y, channel;  /* block coordinates (in blocks) and channel 0..2 */
    stats_welch test;
    double z;           /* normal-equivalent z */
} check_block;

typedef struct {
    /* image-mean luminance test (level alpha / 2) */
    stats_estimate lum_a, lum_b;
    int lum_a_exact_runs, lum_b_exact_runs; /* 1: from per-run means; 0: independent-pixel bound */
    int blocks_a_from_runs, blocks_b_from_runs; /* 1: block variances from per-run block means (any
                                                   pixel correlation); 0: independent-pixel formula
                                                   (or an exact side) */
    /* 1: the side is a moments file set whose renderer correlates pixels
     * ("correlated_pixels": true) but which lacks the per-run statistics for a part
     * (image mean or blocks at this block size): that part is anti-conservative. */
    int correlated_warning_a, correlated_warning_b;
    stats_welch global;
    int global_reject;
    /* block family (level alpha / 2) */
    int blocks_x, blocks_y;
    long tests;              /* 3 * blocks */
    long rejected;
    double block_threshold;  /* a block test rejects iff its p <= this */
    check_block worst;       /* smallest p */
    double skew_a, skew_b;   /* pooled standardized skewness of the per-run block means (0 without them) */
    image block_z;           /* blocks_x x blocks_y, z per channel */
    /* pixels (diagnostic only, not part of the verdict) */
    image pixel_z;           /* width x height, z per channel, saturated at +-CHECK_Z_MAX */
    long pixel_tests;        /* 3 * pixels */
    long pixels_p_below_alpha; /* uncorrected per-pixel tests with p < alpha */
    /* equivalence and bias of the luminance image mean */
    stats_tost tost;
    double bias, bias_lo, bias_hi; /* mean_a / mean_b - 1 and its (1 - alpha) Fieller interval */
    int bias_ci_bounded;
    /* can the verdict be trusted? (check_tail.h) */
    check_tail tail_a, tail_b;
    int inconclusive;        /* a side's runs are heavy-tailed: `different` is reported but not a verdict */
    long runs_needed;        /* then: the runs per side Cochran's rule asks for (at least) */
    int different;           /* the verdict */
    int paired;              /* 1: from check_compare_paired (tests on per-run differences) */
} check_result;

#define CHECK_Z_MAX 40.0

int check_compare(const check_side *a, const check_side *b, const check_options *o, check_result *r, rerror *e);
/* The paired comparison (docs/statistics.md "Paired check"): run k of A and run k of B
 * were made from the same random numbers (e.g. a reuse feature and its validated baseline
 * on the same seeds and frames), so their shared noise cancels in the differences
 * d_k = A_k - B_k. Both sides need the same K >= 2 runs with per-run image and block means
 * (check_side_begin_runs ...). The verdict has the same two parts at alpha/2 each:
 *   - the image-mean luminance difference: one-sample t-test of the K d_k (K - 1 dof);
 *   - per block and channel, one-sample t-tests of the K block-mean differences, with the
 *     Sidak or Benjamini-Hochberg correction.
 * global / worst hold the paired tests (diff = mean d, se = sd(d)/sqrt(K)); lum_a, lum_b
 * each side's own estimate; pixel_z the unpaired per-pixel Welch z (diagnostic only: the
 * sides keep no per-run pixels); bias = mean d / B's mean with the t interval of mean d
 * divided by B's mean (B's mean taken as fixed); the TOST is the paired one on
 * d against +-margin x B's mean. r->paired = 1. */
int check_compare_paired(const check_side *a, const check_side *b, const check_options *o, check_result *r,
                         rerror *e);
void check_result_free(check_result *r);

#endif
