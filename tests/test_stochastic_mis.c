/* Stochastic resampling MIS weights (stochastic_mis.h; docs/stochastic-mis.md):
 *   - Eq. 13 for the general weight Eq. 15, EXACTLY: the expectation over every ordered
 *     Ñ-tuple of picks (M^Ñ of them, each with probability prod P) equals m_i, on random
 *     inputs with P(i) = 0 entries (where m_i = 0) and duplicates (Ñ > 1);
 *   - the same as a property test on draws from the addressed RNG: a z-test per weight
 *     (Sidak over all weights), Sum E[m̃] = 1, P(i) = 0 never picked; the test is shown
 *     to reject a broken weight (no 1/P(i): the "naive" choice) with its margin;
 *   - the pairwise forms Eqs. 16, 18-19 against mis.c's deterministic defensive pairwise
 *     MIS (GRIS Eq. 38), and E[m̃_c] = m_c exactly by enumeration of the Ñ_c picks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/mis.h"
#include "restir/core/rng.h"
#include "restir/metrics/stats.h"
#include "restir/restir/stochastic_mis.h"
#include "test.h"

#define MAXM 8
/* agreement of two computations in the estimator precision */
#define TOL (sizeof(real) == 4 ? 2e-5 : 1e-9)
#define TOL_FORM (sizeof(real) == 4 ? 2e-6 : 1e-12)

static double uni(rng_key k, uint32_t v, uint32_t s) { return (double)rng_u(k, RNG_TEST, v, s); }

/* A random case: M in 2..6 domains, P with some zeros (sum 1), m a partition of unity
 * with m_i = 0 wherever P(i) = 0 (Eq. 15's requirement P > 0 where m > 0). */
static int random_case(rng_key k, real *P, real *m)
{
    int M = 2 + (int)(uni(k, 0, 0) * 5), i, nz = 0;
    double sp = 0, sm = 0;
    for (i = 0; i < M; ++i) {
        int zero = uni(k, 1, (uint32_t)i) < 0.3;
        P[i] = zero ? 0 : (real)(0.05 + uni(k, 2, (uint32_t)i));
        m[i] = zero ? 0 : (real)(uni(k, 3, (uint32_t)i));
        nz += !zero;
    }
    if (nz == 0) {
        P[0] = 1;
        m[0] = 1;
    }
    for (i = 0; i < M; ++i) sp += P[i], sm += m[i];
    for (i = 0; i < M; ++i) {
        P[i] = (real)(P[i] / sp);
        m[i] = sm > 0 ? (real)(m[i] / sm) : 0;
    }
    return M;
}

/* E[m̃_i] over all M^Ñ ordered tuples (t enumerates them in base M). */
static void exact_expectation(const real *P, const real *m, int M, int N, double *E)
{
    long t, total = 1;
    int i, k, K[MAXM];
    for (k = 0; k < N; ++k) total *= M;
    for (i = 0; i < M; ++i) E[i] = 0;
    for (t = 0; t < total; ++t) {
        long r = t;
        double prob = 1;
        memset(K, 0, sizeof K);
        for (k = 0; k < N; ++k) {
            int pick = (int)(r % M);
            r /= M;
            prob *= (double)P[pick];
            K[pick]++;
        }
        if (prob == 0) continue;
        for (i = 0; i < M; ++i) E[i] += prob * (double)stochastic_mis_weight(K[i], N, P[i], m[i]);
    }
}

TEST(stochastic_mis_eq15_exact_expectation)
{
    static const int picks[] = {1, 2, 3, 5};
    int c, n, i;
    for (c = 0; c < 200 && !test_has_failed(); ++c) {
        real P[MAXM], m[MAXM];
        double E[MAXM], sum;
        rng_key k = rng_key_make(test_seed(), 1400u, (uint32_t)c);
        int M = random_case(k, P, m);
        for (n = 0; n < 4; ++n) {
            exact_expectation(P, m, M, picks[n], E);
            sum = 0;
            for (i = 0; i < M; ++i) {
                CHECKF(fabs(E[i] - (double)m[i]) < TOL, "case %d N~ %d: E[m~_%d] = %.12g, m = %.12g (P %.4g)", c,
                       picks[n], i, E[i], (double)m[i], (double)P[i]);
                sum += E[i];
            }
            CHECKF(fabs(sum - 1) < TOL, "case %d N~ %d: sum E[m~] = %.12g", c, picks[n], sum);
        }
    }
    CHECK(stochastic_mis_weight(0, 4, 0, 1) == 0);  /* P = 0: m~ = 0 */
    CHECK(stochastic_mis_weight(3, 4, (real)0.5, 1) == (real)1.5); /* K / (N P) m */
}

/* Mean of m̃_i over D draws of the Ñ picks from the addressed RNG, and its z against m_i.
 * broken = 1 replaces P(i) by 1/M in the weight (the naive uniform weight with picks
 * proportional to P). Returns the largest |z| over the weights; *zero_picked counts
 * picks of P = 0 entries. */
static double property_z(const real *P, const real *m, int M, int N, int D, uint32_t tag, int broken,
                         double *sum_mean, int *zero_picked)
{
    double s[MAXM] = {0}, s2[MAXM] = {0}, worst = 0;
    real u[16];
    int K[MAXM], d, i, k;
    *zero_picked = 0;
    for (d = 0; d < D; ++d) {
        rng_key key = rng_key_make(test_seed(), tag, (uint32_t)d);
        for (k = 0; k < N; ++k) u[k] = rng_u(key, RNG_TEST, 7, (uint32_t)k);
        stochastic_pick(P, M, N, u, K);
        for (i = 0; i < M; ++i) {
            double w = (double)stochastic_mis_weight(K[i], N, broken ? (real)1 / (real)M : P[i], m[i]);
            if (P[i] == 0 && K[i]) (*zero_picked)++;
            s[i] += w;
            s2[i] += w * w;
        }
    }
    *sum_mean = 0;
    for (i = 0; i < M; ++i) {
        double mean = s[i] / D, var = s2[i] / D - mean * mean, se = sqrt(var > 0 ? var / (D - 1) : 0), z;
        *sum_mean += mean;
        if (se == 0) z = fabs(mean - (double)m[i]) > 1e-12 ? INFINITY : 0;
        else z = (mean - (double)m[i]) / se;
        if (fabs(z) > worst) worst = fabs(z);
    }
    return worst;
}

TEST(stochastic_mis_eq13_property_ztest)
{
    enum { CASES = 40, D = 4000 };
    static const int picks[] = {1, 4, 9};
    /* Sidak over CASES x 3 x MAXM weights at alpha 1e-3 */
    double zc = stats_normal_quantile(1 - 0.5 * (1 - pow(1 - 1e-3, 1.0 / (CASES * 3 * MAXM))));
    double worst = 0, broken_min = INFINITY;
    int c, n, broken_cases = 0;
    for (c = 0; c < CASES && !test_has_failed(); ++c) {
        real P[MAXM], m[MAXM];
        rng_key k = rng_key_make(test_seed(), 1401u, (uint32_t)c);
        int M = random_case(k, P, m), zp;
        for (n = 0; n < 3; ++n) {
            double sum, z = property_z(P, m, M, picks[n], D, 20000u + (uint32_t)(c * 3 + n), 0, &sum, &zp), zb;
            CHECKF(z < zc, "case %d M %d N~ %d: |z| %.2f >= %.2f", c, M, picks[n], z, zc);
            CHECKF(zp == 0, "case %d: an entry with P = 0 was picked %d times", c, zp);
            CHECKF(fabs(sum - 1) < 0.1, "case %d: sum of mean m~ %.4f", c, sum);
            if (z > worst) worst = z;
            /* the broken weight: must be rejected wherever P is not uniform enough to hide */
            zb = property_z(P, m, M, picks[n], D, 20000u + (uint32_t)(c * 3 + n), 1, &sum, &zp);
            {
                int i, far = 0;
                for (i = 0; i < M; ++i) far |= m[i] > 0.05 && fabs((double)P[i] * M - 1) > 0.3;
                if (far) {
                    broken_cases++;
                    if (zb < broken_min) broken_min = zb;
                }
            }
        }
    }
    CHECKF(broken_cases > 0 && broken_min > zc, "the naive weight (no 1/P) was not rejected: min |z| %.2f (limit %.2f)",
           broken_min, zc);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  E[m~] = m: worst |z| %.2f (limit %.2f); naive weight rejected in %d cases, min |z| %.1f\n",
                worst, zc, broken_cases, broken_min);
}

/* Eqs. 11a, 19 against mis.c (GRIS Eq. 38 defensive, R = 1), and E[m̃_c] = m_c (Eq. 18)
 * exactly over the Ñ_c uniform picks. */
TEST(stochastic_mis_pairwise_forms_match_mis_c)
{
    int c, i;
    for (c = 0; c < 300 && !test_has_failed(); ++c) {
        rng_key k = rng_key_make(test_seed(), 1402u, (uint32_t)c);
        int M = 2 + (int)(uni(k, 0, 0) * 5); /* domains incl. the canonical 0 */
        real conf[MAXM], pt[MAXM * MAXM], c_S = 0, mc_det, sum_b = 0, p;
        mis_input in;
        memset(pt, 0, sizeof pt);
        for (i = 0; i < M; ++i) conf[i] = (real)(uni(k, 1, (uint32_t)i) < 0.1 ? 0 : 0.5 + 4 * uni(k, 1, 100u + (uint32_t)i));
        for (i = 0; i < M; ++i) {
            pt[i] = (real)(uni(k, 2, (uint32_t)i) < 0.2 ? 0 : uni(k, 2, 100u + (uint32_t)i));           /* p̂(y_i) */
            pt[i * M + 0] = (real)(uni(k, 3, (uint32_t)i) < 0.2 ? 0 : uni(k, 3, 100u + (uint32_t)i));   /* q_i(y_c) */
            if (i > 0) pt[i * M + i] = (real)(uni(k, 4, (uint32_t)i) < 0.2 ? 0 : uni(k, 4, 100u + (uint32_t)i));
        }
        in.m = M;
        in.n_canonical = 1;
        in.confidence = conf;
        in.ptarget = pt;
        for (i = 1; i < M; ++i) c_S += conf[i];
        p = pt[0];
        mc_det = mis_pairwise_defensive(&in, 0, 0, NULL);
        for (i = 1; i < M; ++i) {
            real det = mis_pairwise_defensive(&in, i, i, NULL);
            real sto = stochastic_pairwise_m(conf[0], c_S, conf[i], pt[i * M + i], pt[i]);
            if (conf[0] + c_S > 0)
                CHECKF(fabs((double)(det - sto)) < TOL_FORM, "case %d: Eq. 11a m_%d %.17g vs mis.c %.17g", c, i,
                       (double)sto, (double)det);
            sum_b += stochastic_pairwise_b(conf[0], c_S, conf[i], pt[i * M + 0], p);
        }
        if (conf[0] + c_S > 0) {
            real mc = conf[0] / (conf[0] + c_S) + sum_b; /* Eq. 11b = c_c / C + sum b_i */
            CHECKF(fabs((double)(mc - mc_det)) < TOL_FORM, "case %d: c_c/C + sum b %.17g vs mis.c %.17g", c, (double)mc,
                   (double)mc_det);
        }
        /* E over Ñ_c = 2 uniform picks among the n = M - 1 (P_c = 1/n) of Eq. 18's sum */
        if (conf[0] + c_S > 0 && M > 1) {
            int n = M - 1, a, b;
            double E = 0;
            for (a = 0; a < n; ++a)
                for (b = 0; b < n; ++b) {
                    int Kc[MAXM] = {0}, j;
                    double est = 0;
                    Kc[a]++, Kc[b]++;
                    for (j = 0; j < n; ++j)
                        if (Kc[j])
                            est += (double)Kc[j] / (2.0 / n) *
                                   (double)stochastic_pairwise_b(conf[0], c_S, conf[j + 1], pt[(j + 1) * M], p);
                    E += est / ((double)n * n);
                }
            CHECKF(fabs(E - (double)sum_b) < TOL, "case %d: E[Eq. 18 sum] %.12g vs %.12g", c, E, (double)sum_b);
        }
    }
    {   /* Eq. 17: proportional to c p̂ W, normalised; negative / NaN count as 0 */
        real a[5] = {1, 3, 0, -2, 0}, P[5];
        CHECK(stochastic_selection_p(a, 5, P) == 4);
        CHECK(P[0] == (real)0.25 && P[1] == (real)0.75 && P[2] == 0 && P[3] == 0 && P[4] == 0);
    }
    CHECK(stochastic_confidence_scale(1, 8) == (real)0.125);
    CHECK(stochastic_confidence_scale(16, 8) == 1);
}
