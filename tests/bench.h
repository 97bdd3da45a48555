/* The paired bench (issue 26; docs/statistics.md "Paired bench"): a configuration A and
 * its baseline B rendered on the SAME K seeds, compared per colour channel (R, G, B, never
 * luminance alone: a chromatic bias can hide in a luminance target).
 *
 * Per run k both sides give their image mean per channel, a_k and b_k; the test is on the
 * paired differences d_k = a_k - b_k (most of the noise is shared and cancels):
 *     mean(d) = (1/K) sum d_k,  se = sd(d) / sqrt(K)  (sd with K - 1 in the denominator),
 *     t = mean(d) / se  with K - 1 dof,  z = the normal-equivalent of t (stats_t_to_z),
 *     detectable relative bias = (t_{1-alpha/2} + t_{0.8}) se / |mean(b)| at alpha = 1e-4:
 *     the relative bias this K finds with 80 % power at |z| >= the alpha = 1e-4 threshold.
 * A and B must both be unbiased for the same image (an alternative configuration of the
 * same stage, e.g. stochastic MIS against its deterministic comparator): then mean(d) = 0.
 *
 * Use: either drive it with two run functions (bench_paired_run), or render the runs
 * yourself and add them (bench_paired_add; several comparisons may then share a baseline),
 * then bench_paired_finish, bench_paired_expect_consistent / _expect_detected. Every
 * finished comparison prints one line with RESTIR_TEST_VERBOSE set (name, K, means, z,
 * detectable bias) and appends it to the file RESTIR_BENCH_LOG names, if set. */
#ifndef RESTIR_TESTS_BENCH_H
#define RESTIR_TESTS_BENCH_H

#include <stdint.h>
#include "restir/core/image.h"
#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"

/* The runs K of a power test (tests/test_power_*.c): K in the default build; a quarter of K
 * (at least 8) where the Makefile sets RESTIR_TEST_REDUCED (the float, sanitizer and debug
 * builds, which CI also runs: the same code paths at a fraction of the time; the verdict
 * stays the same |z| test, so it is weaker, not looser). The power table is the default
 * build's. */
#ifdef RESTIR_TEST_REDUCED
#define BENCH_RUNS(k) ((k) / 4 < 8 ? 8 : (k) / 4)
#else
#define BENCH_RUNS(k) (k)
#endif

#define BENCH_ALPHA 1e-4
/* |z| of a consistent pair must stay below this (two-sided p ~ 7e-6 per channel); a planted
 * bug counts as caught at |z| >= 6 (tests/mutants/README.md). */
#define BENCH_Z_CONSISTENT 4.5

typedef struct bench_paired_s {
    const char *name;
    int runs;                    /* K pairs added */
    double sum_a[3], sum_b[3], sum_d[3], sum_dd[3]; /* accumulators (d: shifted by the first d) */
    double first_d[3];
    /* bench_paired_finish: */
    double mean_a[3], mean_b[3]; /* means over the runs of the per-run image means (R, G, B) */
    double diff[3], se[3];       /* mean(d) and its standard error */
    double z[3];                 /* normal-equivalent z of t = diff / se (K - 1 dof); +-40 if se = 0 != diff */
    double rel[3];               /* diff / mean_b (0 if mean_b = 0) */
    double detectable[3];        /* relative bias found with 80 % power at alpha = 1e-4 */
} bench_paired;

void bench_paired_init(bench_paired *p, const char *name);
/* One pair: the image means (R, G, B) of run k of A and of run k of B (same seed). */
void bench_paired_add(bench_paired *p, const double a[3], const double b[3]);
/* Computes the statistics (needs >= 2 runs) and reports them (verbose / RESTIR_BENCH_LOG). */
void bench_paired_finish(bench_paired *p);
/* max over the channels of |z|; *channel (may be NULL) receives its index. */
double bench_paired_max_abs_z(const bench_paired *p, int *channel);
/* The smallest detectable relative bias over the channels (the test's power). */
double bench_paired_detectable(const bench_paired *p);

/* Test verdicts (record a failure with the numbers and the margin for the mutation score,
 * return 0 if the expectation holds): consistent = every |z| < zmax; detected = some
 * channel |z| >= zmin. */
int bench_paired_expect_consistent(const bench_paired *p, double zmax);
int bench_paired_expect_detected(const bench_paired *p, double zmin);

/* One run of a configuration: the image means (R, G, B) for `seed`; 0 on success, else
 * nonzero after recording a test failure. */
typedef int (*bench_run_fn)(void *user, uint32_t seed, double mean[3]);
/* K runs of A and of B, run k of both with seed seed0 + 7919 k, added and finished. 0 on
 * success. */
int bench_paired_run(bench_paired *p, int runs, uint32_t seed0, bench_run_fn a, void *ua, bench_run_fn b, void *ub);

/* Helpers for run functions. */
void bench_image_mean(const image *img, double mean[3]);
/* restir_render(s, o) (o->seed set by the caller): its image means. */
int bench_restir_mean(const scene *s, const restir_options *o, double mean[3]);
/* restir_render_sequence over frames 0..frame: the image means of frame `frame`. */
int bench_sequence_mean(const scene *s, const restir_options *o, int frame, double mean[3]);

/* A bench_run_fn for bench_paired_run: user is a bench_sequence_config; the sequence run
 * with o.seed = seed, the image means of frame `frame` (frame BENCH_OFFLINE: one
 * restir_render, the offline driver, instead of a sequence). */
#define BENCH_OFFLINE (-1)
typedef struct {
    const scene *s;
    restir_options o;
    int frame;
} bench_sequence_config;
int bench_sequence_run(void *user, uint32_t seed, double mean[3]);

#endif
