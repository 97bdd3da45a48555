/* Stochastic resampling MIS weights (include/restir/restir/stochastic_mis.h;
 * docs/stochastic-mis.md has the derivations). */
#include "restir/restir/stochastic_mis.h"
#include "restir/restir/mis.h"

#include <math.h>
#include <string.h>

/* The index whose CDF interval holds u; entries with P = 0 have empty intervals and are
 * skipped, and a u past the rounded total falls on the last positive entry. */
static int invert_cdf(const real *P, int m, real u)
{
    real acc = 0;
    int i, last = -1;
    for (i = 0; i < m; ++i) {
        if (!(P[i] > 0)) continue;
        acc += P[i];
        last = i;
        if (u < acc) return i;
    }
    return last;
}

/* Stochastic MIS §3.1: a multiset of Ñ picks with replacement, multiplicities K: the
 * K_S̄(i) and P(i) of Stochastic MIS Eq. 15. */
int stochastic_pick(const real *P, int m, int n_picks, const real *u, int *K)
{
    int k, distinct = 0;
    memset(K, 0, (size_t)m * sizeof *K);
    for (k = 0; k < n_picks; ++k) {
        int i = invert_cdf(P, m, u[k]);
        if (i < 0) return 0; /* P = 0 everywhere: nothing can be picked */
        if (K[i]++ == 0) distinct++;
    }
    return distinct;
}

/* Stochastic MIS Eq. 15. */
real stochastic_mis_weight(int K, int n_picks, real P, real m)
{
    if (K == 0 || !(P > 0) || n_picks <= 0) return 0;
    return (real)K / ((real)n_picks * P) * m;
}

/* Stochastic MIS Eq. 17 (normalised). */
real stochastic_selection_p(const real *a, int m, real *P)
{
    real sum = 0;
    int i;
    for (i = 0; i < m; ++i) {
        real v = a[i] > 0 && isfinite((double)a[i]) ? a[i] : 0;
        P[i] = v;
        sum += v;
    }
    for (i = 0; i < m; ++i) P[i] = sum > 0 ? P[i] / sum : 0;
    return sum;
}

/* Stochastic MIS Eq. 11a (Eq. 16 without the K / (Ñ P) factor). */
real stochastic_pairwise_m(real c_c, real c_S, real c_i, real q_i, real p)
{
    real C = c_S + c_c, ratio = mis_product_ratio(c_i, q_i, c_S, q_i, c_c, p);
    if (!(C > 0) || ratio < 0) return 0;
    return c_S / C * ratio;
}

/* Stochastic MIS Eq. 19: the term of the canonical weight Eq. 11b that pair i holds. */
real stochastic_pairwise_b(real c_c, real c_S, real c_i, real q_i, real p)
{
    real C = c_S + c_c, ratio = mis_product_ratio(c_c, p, c_S, q_i, c_c, p);
    if (!(C > 0)) return 0;
    if (ratio < 0) return c_i / C; /* empty pair: the canonical side (mis.c convention) */
    return c_i / C * ratio;
}

/* Stochastic MIS §4.3: c_i <- c_i Ñ / M for the non-canonical domains. */
real stochastic_confidence_scale(int n_picks, int m_noncanonical)
{
    if (m_noncanonical <= 0 || n_picks >= m_noncanonical) return 1;
    return (real)n_picks / (real)m_noncanonical;
}

/* Stochastic MIS Eq. 18: the multiplicities K'(i) of the Ñ_c uniform picks (P_c = 1/M)
 * of the canonical weight. */
void stochastic_canonical_picks(int n, int n_picks, const real *uc, int *Kc)
{
    int k;
    for (k = 0; k < n; ++k) Kc[k] = 0;
    for (k = 0; k < n_picks; ++k) {
        int j = (int)(uc[k] * (real)n);
        Kc[j < n ? j : n - 1]++;
    }
}

/* Stochastic MIS Eq. 18: K'(i) / (Ñ_c P_c) b_i(Y_c) */
real stochastic_canonical_term(int kc, int n_picks, int n, real c_c, real c_S, real c_i, real q_i, real p)
{
    real Pc = (real)1 / (real)n;
    return (real)kc / ((real)n_picks * Pc) * stochastic_pairwise_b(c_c, c_S, c_i, q_i, p);
}
