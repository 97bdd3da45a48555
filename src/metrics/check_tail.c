/* The tail of check's per-run statistics (check_tail.h). */
#include "restir/metrics/check_tail.h"

#include <math.h>
#include <stdlib.h>

double check_sample_skewness(const double *x, long n, long stride)
{
    double mean = 0, m2 = 0, m3 = 0;
    long k;
    if (n < 3) return 0;
    for (k = 0; k < n; ++k) mean += x[k * stride];
    mean /= (double)n;
    for (k = 0; k < n; ++k) {
        double d = x[k * stride] - mean;
        m2 += d * d;
        m3 += d * d * d;
    }
    m2 /= (double)n;
    m3 /= (double)n;
    return m2 > 0 ? m3 / (m2 * sqrt(m2)) : 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int cmp_double_desc(const void *a, const void *b) { return cmp_double(b, a); }

/* Median of n values (v is reordered). */
static double median(double *v, long n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* One series: its positive deviations from the median in units of its median absolute
 * deviation (of its mean absolute deviation when more than half the runs share one value,
 * e.g. 15 black runs and one firefly) appended to y. */
static void standardised_exceedances(const double *x, long runs, long stride, double *work, double *y, long *n)
{
    double med, scale, mean_abs = 0;
    long k;
    for (k = 0; k < runs; ++k) work[k] = x[k * stride];
    med = median(work, runs);
    for (k = 0; k < runs; ++k) {
        work[k] = fabs(x[k * stride] - med);
        mean_abs += work[k];
    }
    scale = median(work, runs);
    if (!(scale > 0)) scale = mean_abs / (double)runs;
    if (!(scale > 0) || !isfinite(scale)) return;
    for (k = 0; k < runs; ++k) {
        double d = (x[k * stride] - med) / scale;
        if (d > 0 && isfinite(d)) y[(*n)++] = d;
    }
}

void check_tail_measure(check_tail *t, const double *x, long runs, long stride, long nseries,
                        const double *image_runs, double skew_blocks)
{
    double *work, *y, h = 0;
    long n = 0, j, i, k;
    t->measured = 0;
    t->skew_image = image_runs ? check_sample_skewness(image_runs, runs, 1) : 0;
    t->skew_blocks = skew_blocks;
    t->tail_index = t->tail_upper = HUGE_VAL;
    t->exceedances = t->tail_count = 0;
    t->heavy = 0;
    if (!x || runs < CHECK_TAIL_MIN_RUNS || nseries < 1) return;
    work = malloc((size_t)runs * sizeof *work);
    y = malloc((size_t)runs * (size_t)nseries * sizeof *y);
    if (!work || !y) {
        free(work);
        free(y);
        return;
    }
    for (j = 0; j < nseries; ++j) standardised_exceedances(x + j, runs, stride, work, y, &n);
    t->exceedances = n;
    t->measured = n >= CHECK_TAIL_MIN_EXCEEDANCES;
    k = (long)ceil(sqrt((double)n));
    if (t->measured && k < n) {
        qsort(y, (size_t)n, sizeof *y, cmp_double_desc);
        /* Hill (1975): alpha = 1 / mean ln(y_(i) / y_(k+1)), i = 1..k. */
        for (i = 0; i < k; ++i) h += log(y[i] / y[k]);
        h /= (double)k;
        t->tail_count = k;
        t->tail_index = h > 0 ? 1.0 / h : HUGE_VAL;
    }
    /* Heavy only when the estimate is below the limit by more than its own noise: Hill's
     * alpha has a standard deviation of about alpha / sqrt(k), so the bound alpha (1 +
     * 1 / sqrt(k)) must be below it (one standard deviation: no normal or exponential run
     * set of 40 flagged wherever it is measured, a Pareto 1.5 tail in 25 to 40 of 40;
     * tools/check_tail, docs/statistics.md). */
    t->tail_upper = t->tail_count > 0 ? t->tail_index * (1.0 + 1.0 / sqrt((double)t->tail_count)) : HUGE_VAL;
    t->heavy = t->tail_upper < CHECK_TAIL_ALPHA_MIN;
    free(work);
    free(y);
}

long check_tail_runs_needed(const check_tail *t, long runs)
{
    double g = fabs(t->skew_image) > fabs(t->skew_blocks) ? fabs(t->skew_image) : fabs(t->skew_blocks);
    double need = ceil(25.0 * g * g);
    if (t->heavy && need <= (double)runs) need = (double)runs + 1;
    return need > 1e9 ? 1000000000L : (long)need;
}
