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

void bias_options_default(bias_options *o)
{
    o->level = 0.99;
    o->resamples = 400;
    o->seed = 1;
    o->ref_var = NULL;
    o->ref_mean_var = 0;
    o->ref_dof = 0;
}

/* The two-sided t quantile at `level` for dof degrees of freedom. */
static double t_level(double level, double dof)
{
    return stats_t_quantile(0.5 + 0.5 * level, dof > 0 ? dof : 1);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Signed relative bias of the weighted image mean, t interval over the runs; with a noisy
 * reference R the delta method for I / R - 1 adds (I/R)^2 var(R) / R^2 to the runs'
 * s^2 / K, and the degrees of freedom are Welch-Satterthwaite's. */
static void signed_bias(const double *run_block, const double *ref, const double *weight, int runs, long blocks,
                        const bias_options *o, bias_result *r)
{
    double rm = 0, wsum = 0, s = 0, s2 = 0, mean, var_runs, var_ref = 0, se, dof = runs - 1;
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
    var_runs = fmax(0, (s2 - runs * mean * mean) / (runs - 1)) / runs;
    if (o->ref_mean_var > 0 && o->ref_dof > 0) {
        double v[2], d[2];
        var_ref = (1 + mean) * (1 + mean) * o->ref_mean_var / (rm * rm);
        v[0] = var_runs, v[1] = var_ref, d[0] = runs - 1, d[1] = o->ref_dof;
        dof = stats_satterthwaite(v, d, 2);
    }
    se = sqrt(var_runs + var_ref);
    r->rel_bias.value = mean;
    r->rel_bias.lo = mean - t_level(o->level, dof) * se;
    r->rel_bias.hi = mean + t_level(o->level, dof) * se;
}

static double noise_floor(const double *run_block, const double *ref, const double *weight, int runs, long blocks,
                          const double *ref_var, long *used)
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
        sum += sqrt(2 / 3.14159265358979323846) * sqrt(var / runs + (ref_var ? ref_var[j] : 0)) / ref[j];
        ++*used;
    }
    return *used ? sum / (double)*used : 0;
}

int bias_measure(const double *run_block, const double *ref_block, const double *weight, int runs, long blocks,
                 const bias_options *o, bias_result *r, rerror *e)
{
    int *pick, k, b, resamples = o->resamples, lo_i, hi_i;
    double tail = 0.5 * (1 - o->level);
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
    if (!(o->level > 0 && o->level < 1)) {
        free(pick);
        free(draws);
        return rerror_set(e, "bias: interval level %g outside (0, 1)", o->level);
    }
    signed_bias(run_block, ref_block, weight, runs, blocks, o, r);
    r->noise_floor = noise_floor(run_block, ref_block, weight, runs, blocks, o->ref_var, &r->blocks);
    for (k = 0; k < runs; ++k) pick[k] = k;
    r->mean_abs_rel.value = mean_abs_rel(run_block, ref_block, weight, runs, blocks, pick);
    for (b = 0; b < resamples; ++b) {
        rng_key key = rng_key_make(o->seed, (uint32_t)b, 0);
        for (k = 0; k < runs; ++k) {
            int i = (int)(rng_u(key, 0, 0, (uint32_t)k) * runs);
            pick[k] = i < runs ? i : runs - 1;
        }
        draws[b] = mean_abs_rel(run_block, ref_block, weight, runs, blocks, pick);
    }
    /* The basic (reverse-percentile) bootstrap interval [2v - q(1 - t), 2v - q(t)], t the
     * tail (0.005 at the 99% level): a resample
     * repeats runs, so its block means are noisier and |.| of them is biased upwards; the
     * percentile interval would inherit that shift, the basic interval reflects it away. */
    r->corrected = 0;
    for (b = 0; b < resamples; ++b) r->corrected += draws[b] / resamples;
    r->corrected = 2 * r->mean_abs_rel.value - r->corrected;
    qsort(draws, (size_t)resamples, sizeof *draws, cmp_double);
    hi_i = (int)((1 - tail) * resamples);
    lo_i = (int)(tail * resamples);
    r->mean_abs_rel.lo = 2 * r->mean_abs_rel.value - draws[hi_i < resamples ? hi_i : resamples - 1];
    r->mean_abs_rel.hi = 2 * r->mean_abs_rel.value - draws[lo_i];
    if (r->mean_abs_rel.lo < 0) r->mean_abs_rel.lo = 0;
    free(pick);
    free(draws);
    return 0;
}
