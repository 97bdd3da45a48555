/* Distributions, Welch's t-test, multiple-comparison corrections, TOST and confidence
 * intervals (docs/statistics.md). Everything in double. */
#include "restir/metrics/stats.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

#define SQRT1_2 0.70710678118654752440
#define SQRT_2PI 2.50662827463100050242

/* ---- normal distribution ---- */

/* erfc keeps full relative accuracy in the far tail, where 1 - erf would cancel. */
double stats_normal_cdf(double z) { return 0.5 * erfc(-z * SQRT1_2); }
double stats_normal_sf(double z) { return 0.5 * erfc(z * SQRT1_2); }

/* Lower-tail quantile for p <= 0.5: Acklam's rational approximation (relative error
 * < 1.2e-9), then one Halley step on Phi(x) - p, which brings it to about full double
 * precision because erfc is accurate in the tail. */
static double normal_lower_quantile(double p)
{
    static const double a[6] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[5] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                6.680131188771972e+01,  -1.328068155288572e+01};
    static const double c[6] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[4] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                3.754408661907416e+00};
    double x, err, u;
    if (p < 0.02425) {
        double q = sqrt(-2.0 * log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    } else {
        double q = p - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
    }
    /* Halley: u = (Phi(x) - p) / phi(x). */
    err = stats_normal_cdf(x) - p;
    u = err * SQRT_2PI * exp(0.5 * x * x);
    return x - u / (1.0 + 0.5 * x * u);
}

double stats_normal_quantile(double p)
{
    if (!(p >= 0.0 && p <= 1.0)) return NAN;
    if (p == 0.0) return -INFINITY;
    if (p == 1.0) return INFINITY;
    /* 1 - p is exact for p > 0.5 (Sterbenz), so the upper half mirrors the lower. */
    return p <= 0.5 ? normal_lower_quantile(p) : -normal_lower_quantile(1.0 - p);
}

/* ---- incomplete beta and Student t ---- */

/* Continued fraction of I_x(a,b) (Abramowitz & Stegun 26.5.8), evaluated with the
 * modified Lentz method; converges quickly for x < (a+1)/(a+b+2). `y` = 1 - x is passed
 * separately so callers that know it exactly (t distribution) lose nothing to rounding. */
static double incomplete_beta_cf(double a, double b, double x, double y)
{
    const double tiny = 1e-300, eps = 1e-16;
    double log_front = a * log(x) + b * log(y) - (lgamma(a) + lgamma(b) - lgamma(a + b));
    double f, cc, dd;
    int m;
    /* f = 1 / (1 + d1 / (1 + d2 / (1 + ...))), started as b0 = tiny, a1 = 1, b1 = 1. */
    f = tiny;
    cc = f;
    dd = 0.0;
    for (m = 0; m < 10000; ++m) {
        int step;
        for (step = 0; step < 2; ++step) {
            double num, delta;
            if (m == 0 && step == 0)
                num = 1.0;
            else if (step == 1) /* d_{2m+1} */
                num = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
            else /* d_{2m} */
                num = m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
            dd = 1.0 + num * dd;
            if (fabs(dd) < tiny) dd = tiny;
            cc = 1.0 + num / cc;
            if (fabs(cc) < tiny) cc = tiny;
            dd = 1.0 / dd;
            delta = cc * dd;
            f *= delta;
            if (m > 0 && fabs(delta - 1.0) < eps) return exp(log_front) * f / a;
        }
    }
    return exp(log_front) * f / a; /* not reached for sane inputs */
}

/* I_x(a,b) with both x and y = 1 - x given. */
static double incomplete_beta_xy(double a, double b, double x, double y)
{
    if (x <= 0.0) return 0.0;
    if (y <= 0.0) return 1.0;
    if (x < (a + 1.0) / (a + b + 2.0)) return incomplete_beta_cf(a, b, x, y);
    return 1.0 - incomplete_beta_cf(b, a, y, x);
}

double stats_incomplete_beta(double a, double b, double x)
{
    if (!(a > 0.0 && b > 0.0 && x >= 0.0 && x <= 1.0)) return NAN;
    return incomplete_beta_xy(a, b, x, 1.0 - x);
}

/* P(T > |t|) = I_x(dof/2, 1/2) / 2 with x = dof / (dof + t^2). */
static double t_tail(double t, double dof)
{
    double t2 = t * t, x, y;
    if (isinf(t)) return 0.0;
    if (isinf(dof) || dof > 1e10) return stats_normal_sf(fabs(t));
    x = dof / (dof + t2);
    y = t2 / (dof + t2);
    return 0.5 * incomplete_beta_xy(0.5 * dof, 0.5, x, y);
}

double stats_t_cdf(double t, double dof)
{
    if (isnan(t) || !(dof > 0.0)) return NAN;
    return t < 0.0 ? t_tail(t, dof) : 1.0 - t_tail(t, dof);
}

double stats_t_sf(double t, double dof)
{
    if (isnan(t) || !(dof > 0.0)) return NAN;
    return t > 0.0 ? t_tail(t, dof) : 1.0 - t_tail(t, dof);
}

double stats_t_two_sided_p(double t, double dof)
{
    double p;
    if (isnan(t) || !(dof > 0.0)) return NAN;
    p = 2.0 * t_tail(t, dof);
    return p > 1.0 ? 1.0 : p;
}

/* Quantile by bisection on the monotone CDF: slow (a few hundred CDF evaluations) but
 * plainly correct at any dof and p; it runs a handful of times per `restir check`. */
double stats_t_quantile(double p, double dof)
{
    double lo, hi;
    int i;
    if (!(p >= 0.0 && p <= 1.0) || !(dof > 0.0)) return NAN;
    if (p == 0.0) return -INFINITY;
    if (p == 1.0) return INFINITY;
    if (isinf(dof) || dof > 1e10) return stats_normal_quantile(p);
    if (p > 0.5) return -stats_t_quantile(1.0 - p, dof);
    if (p == 0.5) return 0.0;
    hi = 0.0;
    lo = -1.0;
    while (stats_t_cdf(lo, dof) > p) {
        hi = lo;
        lo *= 2.0;
        if (isinf(lo)) return -INFINITY;
    }
    for (i = 0; i < 2000; ++i) {
        double mid = 0.5 * (lo + hi);
        if (mid == lo || mid == hi) break;
        if (stats_t_cdf(mid, dof) > p)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

double stats_t_to_z(double t, double dof)
{
    if (isnan(t) || !(dof > 0.0)) return NAN;
    if (t == 0.0) return 0.0;
    if (t < 0.0) return stats_normal_quantile(t_tail(t, dof));
    return -stats_normal_quantile(t_tail(t, dof));
}

/* ---- estimates and tests ---- */

stats_estimate stats_estimate_from_samples(double mean, double sample_var, double count)
{
    stats_estimate s;
    s.mean = mean;
    s.var_of_mean = count > 0 ? sample_var / count : 0.0;
    s.dof = count - 1.0;
    return s;
}

void stats_mean_var(const double *x, long n, double *mean, double *sample_var)
{
    double sum = 0.0, ss = 0.0, m;
    long i;
    for (i = 0; i < n; ++i) sum += x[i];
    m = n > 0 ? sum / (double)n : 0.0;
    for (i = 0; i < n; ++i) ss += (x[i] - m) * (x[i] - m);
    *mean = m;
    *sample_var = n > 1 ? ss / (double)(n - 1) : 0.0;
}

/* Welch (1947), Satterthwaite (1946). */
double stats_satterthwaite(const double *s, const double *dof, int count)
{
    double total = 0.0, denom = 0.0;
    int i, any = 0;
    if (count <= 0) return 0.0;
    for (i = 0; i < count; ++i) {
        if (s[i] <= 0.0) continue;
        any = 1;
        total += s[i];
        denom += s[i] * s[i] / dof[i];
    }
    if (!any) return INFINITY;
    return total * total / denom;
}

/* Welch's t for diff with variance components (s_a, dof_a), (s_b, dof_b). Zero total
 * variance (both sides constant, e.g. a black background) is decided without dividing:
 * equal values give no evidence (p = 1), unequal ones are certain (p = 0). */
static stats_welch welch_from_parts(double diff, double s_a, double dof_a, double s_b, double dof_b)
{
    stats_welch w;
    double s[2], d[2];
    s[0] = s_a;
    s[1] = s_b;
    d[0] = dof_a;
    d[1] = dof_b;
    w.diff = diff;
    w.se = sqrt(s_a + s_b);
    if (w.se == 0.0) {
        w.dof = INFINITY;
        w.t = diff == 0.0 ? 0.0 : (diff > 0.0 ? INFINITY : -INFINITY);
        w.p = diff == 0.0 ? 1.0 : 0.0;
        return w;
    }
    w.dof = stats_satterthwaite(s, d, 2);
    w.t = diff / w.se;
    w.p = stats_t_two_sided_p(w.t, w.dof);
    return w;
}

stats_welch stats_welch_test(stats_estimate a, stats_estimate b)
{
    return welch_from_parts(a.mean - b.mean, a.var_of_mean, a.dof, b.var_of_mean, b.dof);
}

double stats_sidak_level(double alpha, long m)
{
    if (m <= 1) return alpha;
    return -expm1(log1p(-alpha) / (double)m);
}

double stats_sidak_adjust(double p, long m)
{
    if (m <= 1 || p >= 1.0) return p;
    return -expm1((double)m * log1p(-p));
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Benjamini & Hochberg (1995) step-up procedure. */
long stats_benjamini_hochberg(const double *p, long m, double q, unsigned char *reject,
                              double *threshold, rerror *e)
{
    double *sorted, cut = 0.0;
    long i, r = 0;
    if (m <= 0) {
        if (threshold) *threshold = 0.0;
        return 0;
    }
    sorted = rmalloc((size_t)m, sizeof *sorted, e);
    if (!sorted) return -1;
    for (i = 0; i < m; ++i) sorted[i] = isnan(p[i]) ? 1.0 : p[i];
    qsort(sorted, (size_t)m, sizeof *sorted, compare_double);
    for (i = m; i >= 1; --i)
        if (sorted[i - 1] <= q * (double)i / (double)m) {
            r = i;
            break;
        }
    free(sorted);
    if (r > 0) cut = q * (double)r / (double)m;
    /* Rejecting every p <= q R / m rejects exactly the R smallest (ties included). */
    if (reject)
        for (i = 0; i < m; ++i) reject[i] = (unsigned char)(r > 0 && !isnan(p[i]) && p[i] <= cut);
    if (threshold) *threshold = cut;
    return r;
}

/* One side of the TOST: Welch test of L = mean_a - c mean_b against 0. Returns the
 * one-sided p-value of H0: L <= 0 (upper = 0) or H0: L >= 0 (upper = 1). */
static double tost_side(stats_estimate a, stats_estimate b, double c, int upper)
{
    stats_welch w = welch_from_parts(a.mean - c * b.mean, a.var_of_mean, a.dof, c * c * b.var_of_mean, b.dof);
    if (w.se == 0.0) {
        if (upper) return w.diff < 0.0 ? 0.0 : 1.0;
        return w.diff > 0.0 ? 0.0 : 1.0;
    }
    return upper ? stats_t_cdf(w.t, w.dof) : stats_t_sf(w.t, w.dof);
}

/* Schuirmann (1987) two one-sided tests; the ratio hypotheses are linear in the means
 * (Fieller 1954): rho >= c  <=>  mean_a - c mean_b >= 0 for mean_b > 0. */
stats_tost stats_tost_ratio(stats_estimate a, stats_estimate b, double margin, double alpha)
{
    stats_tost r;
    r.margin = margin;
    if (!(b.mean > 0.0) || !(margin > 0.0)) {
        r.p_lower = r.p_upper = r.p = 1.0;
        r.equivalent = 0;
        return r;
    }
    r.p_lower = tost_side(a, b, 1.0 - margin, 0);
    r.p_upper = tost_side(a, b, 1.0 + margin, 1);
    r.p = r.p_lower > r.p_upper ? r.p_lower : r.p_upper;
    r.equivalent = r.p < alpha;
    return r;
}

/* Fieller (1954): {rho : (mean_a - rho mean_b)^2 <= t^2 (v_a + rho^2 v_b)}, with t the
 * two-sided quantile at the Welch-Satterthwaite dof of the point estimate. */
int stats_ratio_ci(stats_estimate a, stats_estimate b, double level, double *lo, double *hi)
{
    double rho, s[2], d[2], dof, t, q2, q1, disc, r1, r2;
    *lo = -INFINITY;
    *hi = INFINITY;
    if (b.mean == 0.0) return 0;
    rho = a.mean / b.mean;
    s[0] = a.var_of_mean;
    s[1] = rho * rho * b.var_of_mean;
    d[0] = a.dof;
    d[1] = b.dof;
    dof = stats_satterthwaite(s, d, 2);
    t = stats_t_quantile(0.5 * (1.0 + level), dof);
    if (isinf(dof) && s[0] == 0.0 && s[1] == 0.0) t = 0.0; /* both exact */
    q2 = b.mean * b.mean - t * t * b.var_of_mean;
    if (!(q2 > 0.0)) return 0;
    q1 = a.mean * b.mean;
    disc = t * t * (a.var_of_mean * q2 + b.var_of_mean * a.mean * a.mean);
    r1 = (q1 - sqrt(disc)) / q2;
    r2 = (q1 + sqrt(disc)) / q2;
    *lo = r1 < r2 ? r1 : r2;
    *hi = r1 < r2 ? r2 : r1;
    return 1;
}

void stats_mean_ci(stats_estimate a, double level, double *lo, double *hi)
{
    double half = 0.0;
    if (a.var_of_mean > 0.0) half = stats_t_quantile(0.5 * (1.0 + level), a.dof) * sqrt(a.var_of_mean);
    *lo = a.mean - half;
    *hi = a.mean + half;
}
