/* Distributions and tests of src/metrics/stats.c against known values.
 * Reference values: closed forms where they exist (t with 1 and 2 dof, I_x(2,3)),
 * otherwise computed with mpmath 1.3 at 50 significant digits (betainc, ncdf, erfinv). */
#include <math.h>
#include <stdlib.h>
#include "restir/core/rng.h"
#include "restir/metrics/stats.h"
#include "test.h"

/* |a - b| <= rel * |b| */
#define CHECK_REL(a, b, rel) CHECK_NEAR((a), (b), (rel) * fabs((double)(b)))

TEST(stats_normal_cdf_and_quantile)
{
    CHECK_REL(stats_normal_cdf(-1.0), 0.15865525393145705141, 1e-14);
    CHECK_REL(stats_normal_cdf(-3.0), 0.0013498980316300945267, 1e-14);
    CHECK_REL(stats_normal_cdf(-8.0), 6.2209605742717841235e-16, 1e-13);
    CHECK_REL(stats_normal_cdf(-12.0), 1.7764821120776789977e-33, 1e-13);
    CHECK_REL(stats_normal_cdf(0.5), 0.69146246127401310364, 1e-15);
    CHECK_REL(stats_normal_sf(-2.0), 0.9772498680518207928, 1e-15);
    CHECK_REL(stats_normal_sf(8.0), 6.2209605742717841235e-16, 1e-13);

    CHECK_REL(stats_normal_quantile(0.975), 1.9599639845400542355, 1e-14);
    CHECK_REL(stats_normal_quantile(0.995), 2.575829303548900761, 1e-14);
    CHECK_REL(stats_normal_quantile(1e-10), -6.3613409024040562047, 1e-14);
    CHECK_REL(stats_normal_quantile(1e-300), -37.047096299361199237, 1e-13);
    CHECK_REL(stats_normal_quantile(0.3), -0.52440051270804078404, 1e-14);
    CHECK_REL(stats_normal_quantile(0.02425), -1.9729610513118848503, 1e-14);
    CHECK_REL(stats_normal_quantile(0.9999), 3.7190164854556805644, 1e-12);
    CHECK(stats_normal_quantile(0.5) == 0.0);
    CHECK(isinf(stats_normal_quantile(0.0)) && stats_normal_quantile(0.0) < 0);
    CHECK(isnan(stats_normal_quantile(1.5)));
}

TEST(stats_incomplete_beta_known_values)
{
    /* I_0.4(2,3) = 1 - sum_{j<2} C(4,j) 0.4^j 0.6^(4-j) = 0.5248 exactly. */
    CHECK_REL(stats_incomplete_beta(2.0, 3.0, 0.4), 0.5248, 1e-14);
    /* I_x(1/2,1/2) = (2/pi) asin(sqrt(x)). */
    CHECK_REL(stats_incomplete_beta(0.5, 0.5, 0.1), 2.0 / 3.14159265358979323846 * asin(sqrt(0.1)), 1e-14);
    CHECK_REL(stats_incomplete_beta(50.0, 80.0, 0.3), 0.020700287911373362561, 1e-12);
    CHECK(stats_incomplete_beta(2.0, 3.0, 0.0) == 0.0);
    CHECK(stats_incomplete_beta(2.0, 3.0, 1.0) == 1.0);
    CHECK(isnan(stats_incomplete_beta(-1.0, 3.0, 0.5)));
}

TEST(stats_t_cdf_known_values)
{
    static const struct { double t, dof, cdf; } cases[] = {
        {1.0, 1.0, 0.75},
        {2.0, 3.0, 0.93033701572057841158},
        {3.0, 5.0, 0.98495037605126871308},
        {-1.5, 7.5, 0.0872402852932321174},
        {0.3, 1000.0, 0.61788024791637797779},
    };
    static const struct { double t, dof, tail; } tails[] = {
        /* lower tails P(T <= t), down to and below 1e-12 */
        {-10.0, 10.0, 7.9477658779820597717e-7},
        {-40.0, 4.0, 1.1670081613006342976e-6},
        {-200.0, 2.5, 1.2715477190689985999e-6},
        {-8.0, 30.0, 3.1329112378503794717e-9},
        {-6.5, 2000.0, 5.0564938301634618754e-11},
        {-25.0, 7.0, 2.0898485588297168142e-8},
        {-60.0, 7.0, 4.6888003291645084344e-11},
        {-15.0, 15.0, 9.7063796521821949326e-11},
        {-100.0, 5.5, 1.7640916404301142961e-10},
        {-12.0, 40.0, 3.9120856521279863115e-15},
        {-9.0, 200.0, 8.8546914616323939802e-17},
    };
    size_t i;
    double t;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        CHECK_REL(stats_t_cdf(cases[i].t, cases[i].dof), cases[i].cdf, 1e-13);
        CHECK_REL(stats_t_sf(-cases[i].t, cases[i].dof), cases[i].cdf, 1e-13);
    }
    for (i = 0; i < sizeof tails / sizeof tails[0]; ++i) {
        CHECK_REL(stats_t_cdf(tails[i].t, tails[i].dof), tails[i].tail, 1e-11);
        CHECK_REL(stats_t_sf(-tails[i].t, tails[i].dof), tails[i].tail, 1e-11);
        CHECK_REL(stats_t_two_sided_p(tails[i].t, tails[i].dof), 2.0 * tails[i].tail, 1e-11);
    }
    /* Closed forms: dof 1 (Cauchy) P(T > t) = atan(1/t)/pi; dof 2 P(T > t) = 1/(s(s+t)),
     * s = sqrt(2 + t^2), exact in the tail without cancellation. */
    for (t = 0.5; t < 1e7; t *= 3.7) {
        double s = sqrt(2.0 + t * t);
        CHECK_REL(stats_t_sf(t, 1.0), atan(1.0 / t) / 3.14159265358979323846, 1e-13);
        CHECK_REL(stats_t_sf(t, 2.0), 1.0 / (s * (s + t)), 1e-13);
    }
    /* Large dof tends to the normal. */
    CHECK_REL(stats_t_cdf(-3.0, 1e12), stats_normal_cdf(-3.0), 1e-9);
    CHECK_REL(stats_t_cdf(-3.0, INFINITY), stats_normal_cdf(-3.0), 1e-15);
    CHECK(stats_t_cdf(0.0, 3.0) == 0.5);
    CHECK(isnan(stats_t_cdf(1.0, 0.0)));
}

TEST(stats_t_quantile_known_values)
{
    CHECK_REL(stats_t_quantile(0.975, 1.0), 12.706204736174704646, 1e-12);
    CHECK_REL(stats_t_quantile(0.975, 10.0), 2.2281388519862747484, 1e-12);
    CHECK_REL(stats_t_quantile(0.995, 4.0), 4.6040948713499932254, 1e-12);
    CHECK_REL(stats_t_quantile(0.9995, 3.0), 12.923978636687483065, 1e-12);
    CHECK_REL(stats_t_quantile(0.025, 25.0), -2.0595385527532977489, 1e-12);
    /* dof 2 closed form: t_p = (2p - 1) / sqrt(2 p (1 - p)). */
    CHECK_REL(stats_t_quantile(1e-12, 2.0), (2e-12 - 1.0) / sqrt(2e-12 * (1.0 - 1e-12)), 1e-12);
    CHECK(stats_t_quantile(0.5, 7.0) == 0.0);
    /* Round trip. */
    CHECK_REL(stats_t_cdf(stats_t_quantile(3e-9, 6.3), 6.3), 3e-9, 1e-10);
}

TEST(stats_t_to_z_matches_tails)
{
    /* Same tail probability: Phi(z) = T(t). */
    double z = stats_t_to_z(-60.0, 7.0);
    CHECK_REL(stats_normal_cdf(z), 4.6888003291645084344e-11, 1e-10);
    z = stats_t_to_z(60.0, 7.0);
    CHECK_REL(stats_normal_sf(z), 4.6888003291645084344e-11, 1e-10);
    CHECK_REL(stats_t_to_z(1.5, INFINITY), 1.5, 1e-14);
    CHECK(stats_t_to_z(0.0, 3.0) == 0.0);
}

TEST(stats_welch_and_satterthwaite)
{
    /* Two samples {1,2,3,4} and {2,4,6,8,10}: means 2.5, 6; variances 5/3, 10.
     * s_a = 5/12, s_b = 2; t = -3.5/sqrt(29/12); dof = (29/12)^2 / ((5/12)^2/3 + 4/4). */
    static const double xa[] = {1, 2, 3, 4}, xb[] = {2, 4, 6, 8, 10};
    double ma, va, mb, vb, dof;
    stats_welch w;
    stats_mean_var(xa, 4, &ma, &va);
    stats_mean_var(xb, 5, &mb, &vb);
    CHECK_NEAR(va, 5.0 / 3.0, 1e-15);
    CHECK_NEAR(vb, 10.0, 1e-14);
    w = stats_welch_test(stats_estimate_from_samples(ma, va, 4), stats_estimate_from_samples(mb, vb, 5));
    dof = (29.0 / 12.0) * (29.0 / 12.0) / ((5.0 / 12.0) * (5.0 / 12.0) / 3.0 + 1.0);
    CHECK_NEAR(w.diff, -3.5, 1e-15);
    CHECK_NEAR(w.t, -3.5 / sqrt(29.0 / 12.0), 1e-14);
    CHECK_NEAR(w.dof, dof, 1e-12);
    CHECK_REL(w.p, stats_t_two_sided_p(w.t, dof), 1e-14);
    /* Zero variance on both sides: equal -> no evidence, different -> certain. */
    {
        stats_estimate c1 = {0.25, 0.0, 3.0}, c2 = {0.5, 0.0, 3.0};
        w = stats_welch_test(c1, c1);
        CHECK(w.p == 1.0 && w.t == 0.0);
        w = stats_welch_test(c1, c2);
        CHECK(w.p == 0.0 && isinf(w.t));
    }
    /* An exact reference: dof is that of the other side. */
    {
        stats_estimate a = {1.0, 0.01, 9.0}, ref = {0.9, 0.0, 0.0};
        w = stats_welch_test(a, ref);
        CHECK_NEAR(w.dof, 9.0, 1e-12);
        CHECK_NEAR(w.t, 1.0, 1e-12);
    }
}

TEST(stats_corrections)
{
    double p[8] = {0.01, 0.04, 0.03, 0.005, 0.5, 0.2, 0.0001, 0.041};
    unsigned char reject[8];
    double thr;
    long r;
    rerror e;
    CHECK_NEAR(stats_sidak_level(0.05, 1), 0.05, 0);
    CHECK_REL(stats_sidak_level(0.05, 10), 1.0 - pow(0.95, 0.1), 1e-13);
    CHECK_REL(stats_sidak_level(0.01, 1000000), 1.0050335802996815969e-8, 1e-12);
    CHECK_REL(stats_sidak_adjust(stats_sidak_level(0.01, 4096), 4096), 0.01, 1e-12);
    /* BH at q = 0.05, m = 8: sorted 0.0001 0.005 0.01 0.03 0.04 0.041 0.2 0.5 against
     * q k/m = 0.00625 k: the largest k with p_(k) <= 0.00625 k is k = 3 (0.01 <= 0.01875);
     * k = 4: 0.03 > 0.025; k = 5: 0.04 > 0.03125; k = 6: 0.041 > 0.0375. */
    r = stats_benjamini_hochberg(p, 8, 0.05, reject, &thr, &e);
    CHECK(r == 3);
    CHECK_NEAR(thr, 0.01875, 1e-15);
    CHECK(reject[6] && reject[3] && reject[0] && !reject[2] && !reject[1] && !reject[4]);
    r = stats_benjamini_hochberg(p, 8, 0.2, reject, &thr, &e); /* 0.025 k: k = 6 (0.041 <= 0.15) */
    CHECK(r == 6);
    CHECK(!reject[4] && !reject[5] && reject[7]);
}

TEST(stats_tost_and_intervals)
{
    /* a: mean 1.002 with se 0.001 (dof 99); exact reference 1.0. */
    stats_estimate a = {1.002, 1e-6, 99.0}, ref = {1.0, 0.0, 0.0};
    stats_tost t = stats_tost_ratio(a, ref, 0.01, 0.01);
    double lo, hi;
    /* lower: (1.002 - 0.99)/0.001 = 12; upper: (1.002 - 1.01)/0.001 = -8 */
    CHECK_REL(t.p_lower, stats_t_sf(12.0, 99.0), 1e-9);
    CHECK_REL(t.p_upper, stats_t_cdf(-8.0, 99.0), 1e-9);
    CHECK(t.equivalent);
    t = stats_tost_ratio(a, ref, 0.003, 0.01); /* upper t = -1: not shown equivalent */
    CHECK(!t.equivalent);
    /* With an exact denominator Fieller reduces to the t interval divided by mean_b. */
    CHECK(stats_ratio_ci(a, ref, 0.99, &lo, &hi));
    CHECK_NEAR(lo, 1.002 - stats_t_quantile(0.995, 99.0) * 0.001, 1e-12);
    CHECK_NEAR(hi, 1.002 + stats_t_quantile(0.995, 99.0) * 0.001, 1e-12);
    stats_mean_ci(a, 0.95, &lo, &hi);
    CHECK_NEAR(hi - lo, 2.0 * stats_t_quantile(0.975, 99.0) * 0.001, 1e-12);
    /* A denominator not significantly nonzero gives an unbounded interval. */
    {
        stats_estimate b = {0.001, 1e-4, 10.0};
        CHECK(!stats_ratio_ci(a, b, 0.99, &lo, &hi));
        CHECK(isinf(lo) && isinf(hi));
    }
}

/* Fieller interval coverage with both sides noisy: simulated Gaussian means. */
TEST(stats_ratio_ci_coverage)
{
    int trial, covered = 0, trials = 4000;
    uint32_t seed = test_seed();
    for (trial = 0; trial < trials; ++trial) {
        double u[4], na, nb;
        int i;
        for (i = 0; i < 4; ++i)
            u[i] = 1.0 - rng_uniform_double(rng_key_at(rng_key_make(seed, (uint32_t)trial, 0), RNG_TEST, 0, (uint32_t)i));
        na = sqrt(-2.0 * log(u[0])) * cos(6.283185307179586 * u[1]);
        nb = sqrt(-2.0 * log(u[2])) * cos(6.283185307179586 * u[3]);
        {
            /* true ratio 1.3; known variances (large dof) */
            stats_estimate a = {1.3 + 0.05 * na, 0.0025, 1e6}, b = {1.0 + 0.04 * nb, 0.0016, 1e6};
            double lo, hi;
            if (stats_ratio_ci(a, b, 0.9, &lo, &hi) && lo <= 1.3 && 1.3 <= hi) covered++;
        }
    }
    /* Binomial(4000, 0.9): sd = 19; allow 4 sd. */
    CHECKF(abs(covered - 3600) < 76, "covered %d of %d (expect 3600)", covered, trials);
}
