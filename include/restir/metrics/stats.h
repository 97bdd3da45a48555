/* Statistics for deciding whether two renderers estimate the same image
 * (docs/statistics.md): normal and Student t distributions, Welch's t-test with the
 * Welch-Satterthwaite degrees of freedom, multiple-comparison corrections (Sidak,
 * Benjamini-Hochberg), TOST equivalence on a ratio of means, confidence intervals.
 *
 * All arithmetic is double, independent of PRECISION: these are decisions about
 * estimators, not estimators. */
#ifndef RESTIR_STATS_H
#define RESTIR_STATS_H

#include "restir/core/error.h"

/* ---- distributions ---- */

/* Standard normal CDF Phi(z) and upper tail 1 - Phi(z), both accurate in the tails. */
double stats_normal_cdf(double z);
double stats_normal_sf(double z);
/* Phi^-1(p) for p in (0,1); -inf at 0, +inf at 1, NaN outside. */
double stats_normal_quantile(double p);

/* Regularized incomplete beta function I_x(a, b) for a, b > 0, x in [0,1]. */
double stats_incomplete_beta(double a, double b, double x);

/* Student t with `dof` > 0 degrees of freedom (non-integer allowed, +inf = normal):
 * CDF P(T <= t), upper tail P(T > t) (accurate far into the tail: relative error
 * ~1e-13 at 1e-12), two-sided p-value P(|T| >= |t|), and the quantile. */
double stats_t_cdf(double t, double dof);
double stats_t_sf(double t, double dof);
double stats_t_two_sided_p(double t, double dof);
double stats_t_quantile(double p, double dof);

/* The normal-equivalent z of a t statistic: the z with the same CDF value,
 * Phi^-1(T_dof(t)), computed from the nearer tail. Maps of these are comparable
 * across pixels with different degrees of freedom. */
double stats_t_to_z(double t, double dof);

/* ---- estimates and tests ---- */

/* An estimate of a mean: its value, the variance of the estimate (the squared standard
 * error), and the degrees of freedom of that variance estimate. var_of_mean = 0 means
 * exact (a reference taken as ground truth; dof is then ignored). */
typedef struct {
    double mean;
    double var_of_mean;
    double dof;
} stats_estimate;

/* From K samples summarised as mean and unbiased sample variance: var_of_mean = var/K,
 * dof = K - 1. */
stats_estimate stats_estimate_from_samples(double mean, double sample_var, double count);
/* Mean, unbiased sample variance of n values (two-pass, in double). */
void stats_mean_var(const double *x, long n, double *mean, double *sample_var);

/* Welch-Satterthwaite degrees of freedom of a sum of independent variance estimates
 * s_i with dof_i each: (sum s_i)^2 / sum(s_i^2 / dof_i). Terms with s_i = 0 drop out;
 * returns +inf if all are exact, 0 if count is 0. */
double stats_satterthwaite(const double *s, const double *dof, int count);

typedef struct {
    double diff;  /* mean_a - mean_b */
    double se;    /* standard error of diff */
    double t;     /* diff / se (+-inf if se = 0 and diff != 0, 0 if both are 0) */
    double dof;   /* Welch-Satterthwaite */
    double p;     /* two-sided p-value: 1 if se = diff = 0, 0 if se = 0 != diff */
} stats_welch;

/* Welch's unequal-variance t-test of H0: mean_a = mean_b (Welch 1947). */
stats_welch stats_welch_test(stats_estimate a, stats_estimate b);

/* Sidak per-test level for m tests at family-wise level alpha: 1 - (1 - alpha)^(1/m). */
double stats_sidak_level(double alpha, long m);
/* Sidak-adjusted p-value 1 - (1 - p)^m. */
double stats_sidak_adjust(double p, long m);
/* Benjamini-Hochberg step-up at false-discovery rate q over p[0..m-1]: returns the
 * number of rejections R (p-values <= q R / m are rejected); *threshold receives
 * q R / m (0 if none). reject (may be NULL) gets 1 per rejected test. -1 on
 * allocation failure. */
long stats_benjamini_hochberg(const double *p, long m, double q, unsigned char *reject,
                              double *threshold, rerror *e);

/* Two one-sided tests (Schuirmann 1987) for the ratio rho = mean_a / mean_b being
 * within [1 - margin, 1 + margin] (mean_b > 0). Each side is a Welch test of the
 * linear combination mean_a - c mean_b (Fieller's construction), c = 1 -+ margin. */
typedef struct {
    double margin;
    double p_lower;     /* H0: rho <= 1 - margin */
    double p_upper;     /* H0: rho >= 1 + margin */
    double p;           /* max of the two */
    int equivalent;     /* p < alpha */
} stats_tost;

stats_tost stats_tost_ratio(stats_estimate a, stats_estimate b, double margin, double alpha);

/* Fieller confidence interval at `level` (e.g. 0.99) for the ratio mean_a / mean_b.
 * Returns 1 and a bounded [lo, hi] if mean_b is significantly nonzero at that level,
 * else 0 with lo = -inf, hi = +inf. */
int stats_ratio_ci(stats_estimate a, stats_estimate b, double level, double *lo, double *hi);
/* t confidence interval at `level` for a mean: mean -+ t_{(1+level)/2, dof} se. */
void stats_mean_ci(stats_estimate a, double level, double *lo, double *hi);

#endif
