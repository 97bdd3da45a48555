/* Bias over K runs against a reference (include/restir/metrics/bias_runs.h). */
#include "restir/metrics/bias_runs.h"

#include <math.h>
#include <stdlib.h>
#include "restir/core/rng.h"
#include "restir/metrics/stats.h"

/* mean_j |mean over the chosen runs of b_kj - r_j| / r_j; pick[k] = run used as draw k. */
static double mean_abs_rel(const double *run_block, const double *ref, const double *weight, int runs, long blocks,
                           const int *pick)
{
    double sum = 0;
    long j, n = 0;
    int k;
    for (j = 0; j < blocks; ++j) {
        double m = 0;
        if (!(ref[j] > 0) || !(weight[j] > 0)) continue;
        for (k = 0; k < runs; ++k) m += run_block[(long)pick[k] * blocks + j];
        sum += fabs(m / runs - ref[j]) / ref[j];
        ++n;
    }
    return n ? sum / (double)n : 0;
}

/* The two-sided 95% t quantile for n - 1 degrees of freedom (stats_t_quantile, as every
 * interval of the statistics code and of the results scripts). */
static double t95(int n) { return n >= 2 ? stats_t_quantile(0.975, n - 1.0) : 1.96; }

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Signed relative bias of the weighted image mean, t interval over the runs. */
static void signed_bias(const double *run_block, const double *ref, const double *weight, int runs, long blocks,
                        bias_result *r)
{
    double rm = 0, wsum = 0, s = 0, s2 = 0, mean, sd;
    long j;
    int k;
    for (j = 0; j < blocks; ++j) {
        rm += weight[j] * ref[j];
        wsum += weight[j];
    }
    rm /= wsum;
    for (k = 0; k < runs; ++k) {
        double im = 0;
        for (j = 0; j < blocks; ++j) im += weight[j] * run_block[(long)k * blocks + j];
        im = (im / wsum - rm) / rm;
        s += im;
        s2 += im * im;
    }
    mean = s / runs;
    sd = sqrt(fmax(0, (s2 - runs * mean * mean) / (runs - 1)));
    r->rel_bias.value = mean;
    r->rel_bias.lo = mean - t95(runs) * sd / sqrt((double)runs);
    r->rel_bias.hi = mean + t95(runs) * sd / sqrt((double)runs);
}

static double noise_floor(const double *run_block, const double *ref, const double *weight, int runs, long blocks,
                          long *used)
{
    double sum = 0;
    long j;
    int k;
    *used = 0;
    for (j = 0; j < blocks; ++j) {
        double s = 0, s2 = 0, m, var;
        if (!(ref[j] > 0) || !(weight[j] > 0)) continue;
        for (k = 0; k < runs; ++k) {
            double v = run_block[(long)k * blocks + j];
            s += v;
            s2 += v * v;
        }
        m = s / runs;
        var = fmax(0, (s2 - runs * m * m) / (runs - 1));
        sum += sqrt(2 / 3.14159265358979323846) * sqrt(var / runs) / ref[j];
        ++*used;
    }
    return *used ? sum / (double)*used : 0;
}

int bias_measure(const double *run_block, const double *ref_block, const double *weight, int runs, long blocks,
                 int resamples, uint32_t seed, bias_result *r, rerror *e)
{
    int *pick, k, b;
    double *draws;
    if (runs < 2 || blocks < 1 || resamples < 10) return rerror_set(e, "bias: needs >= 2 runs, >= 1 block, >= 10 resamples");
    pick = malloc((size_t)runs * sizeof *pick);
    draws = malloc((size_t)resamples * sizeof *draws);
    if (!pick || !draws) {
        free(pick);
        free(draws);
        return rerror_set(e, "bias: out of memory");
    }
    r->runs = runs;
    signed_bias(run_block, ref_block, weight, runs, blocks, r);
    r->noise_floor = noise_floor(run_block, ref_block, weight, runs, blocks, &r->blocks);
    for (k = 0; k < runs; ++k) pick[k] = k;
    r->mean_abs_rel.value = mean_abs_rel(run_block, ref_block, weight, runs, blocks, pick);
    for (b = 0; b < resamples; ++b) {
        rng_key key = rng_key_make(seed, (uint32_t)b, 0);
        for (k = 0; k < runs; ++k) {
            int i = (int)(rng_u(key, 0, 0, (uint32_t)k) * runs);
            pick[k] = i < runs ? i : runs - 1;
        }
        draws[b] = mean_abs_rel(run_block, ref_block, weight, runs, blocks, pick);
    }
    /* The basic (reverse-percentile) bootstrap interval [2v - q97.5, 2v - q2.5]: a resample
     * repeats runs, so its block means are noisier and |.| of them is biased upwards; the
     * percentile interval would inherit that shift, the basic interval reflects it away. */
    r->corrected = 0;
    for (b = 0; b < resamples; ++b) r->corrected += draws[b] / resamples;
    r->corrected = 2 * r->mean_abs_rel.value - r->corrected;
    qsort(draws, (size_t)resamples, sizeof *draws, cmp_double);
    r->mean_abs_rel.lo = 2 * r->mean_abs_rel.value -
                         draws[(int)(0.975 * resamples) < resamples ? (int)(0.975 * resamples) : resamples - 1];
    r->mean_abs_rel.hi = 2 * r->mean_abs_rel.value - draws[(int)(0.025 * resamples)];
    if (r->mean_abs_rel.lo < 0) r->mean_abs_rel.lo = 0;
    free(pick);
    free(draws);
    return 0;
}
