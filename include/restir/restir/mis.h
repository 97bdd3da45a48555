/* Resampling MIS weights of GRIS with confidence weights (docs/mis-derivations.md).
 *
 * SETTING. A GRIS step resamples from M domains (pixels, frames) i = 0..M-1 into the
 * target domain Omega of one pixel. Domains 0..R-1 (R = n_canonical >= 1) are CANONICAL
 * (GRIS Def. 5.2): identity shift, target p̂ (usually R = 1: domain 0 is the pixel's own
 * reservoir). Candidate j's sample X_j is shifted to y_j = T_j(X_j) in Omega.
 *
 * INPUT. The M x M matrix of "p̂ from i" (GRIS Eq. 35; Stochastic MIS Eq. 10)
 *     ptarget[i*M + j] = p̂_{<-i}(y_j) = p̂_i(T_i^{-1}(y_j)) |dT_i^{-1}/dy|(y_j)
 * i.e. row i = the target of domain i, column j = at candidate j's shifted sample:
 *   - canonical rows i < R:       p̂(y_j) (the destination target; the forward shift gives it);
 *   - diagonal (i = j >= R):      p̂_j(X_j) / |dT_j/dX_j|   (stored target / forward Jacobian);
 *   - other entries i >= R, i!=j: shift y_j back into domain i: ONE SHIFT EVALUATION each;
 *   - a failed shift (y_j not in the image of T_i) is 0, like a zero target (Eq. 35).
 * Entries must be finite and >= 0. Confidences c_i >= 0 (GRIS §6.2, Stochastic MIS §2.5).
 * A function reads only the entries its formula needs, so a caller may leave the others
 * unset (e.g. pairwise MIS never needs an off-diagonal non-canonical column entry).
 *
 * OUTPUT. m_i(y_j), the MIS weight of domain i at the point y_j; the resampling weight of
 * candidate j is w_j = m_j(y_j) p̂(y_j) W_j |dT_j/dX_j| (GRIS Eq. 19, reservoir.h).
 *
 * CONVENTIONS (docs/mis-derivations.md §5-§6), which make sum_i m_i(y_j) = 1 hold exactly
 * for every input, even outside supp p̂ where the value is irrelevant (w_j = 0 there):
 *   - a normalising denominator that is 0 (all relevant targets are 0) gives all weight to
 *     the canonical domains, split by confidence c_r / c_R (equally if c_R = 0);
 *   - a pairwise pair (canonical vs j) whose two terms are both 0 goes to the canonical side.
 *
 * SHIFT COUNTS. Each function adds to *shifts (if not NULL) the number of entries it read
 * that cost a shift evaluation (i >= R and i != j). Summed over m_j(y_j), j = 0..M-1 (the
 * resampling use) this equals mis_shift_count(); the M - R forward shifts T_j(X_j) that
 * every family needs come on top. */
#ifndef RESTIR_MIS_H
#define RESTIR_MIS_H

#include "restir/core/vec.h"

typedef enum {
    MIS_CONSTANT = 0,          /* m_i = c_i / sum c: cheap, biased if supports differ (GRIS §5.6) */
    MIS_TALBOT = 1,            /* generalized Talbot / balance heuristic (GRIS Eq. 36), O(M^2) */
    MIS_PAIRWISE_UNIFORM = 2,  /* generalized pairwise, uniform variant (GRIS Eq. 37), O(M) */
    MIS_PAIRWISE_DEFENSIVE = 3, /* generalized pairwise, defensive (GRIS Eq. 38), O(M) */
    /* Defensive pairwise in the confidence form of the authors' Falcor code (not a --mis
     * name: --mis pairwise-defensive --pairwise-confidence falcor; options.h): */
    MIS_PAIRWISE_DEFENSIVE_FALCOR = 8
} mis_family;
#define MIS_FAMILY_COUNT 4

typedef struct {
    int m;                  /* M >= 1 domains */
    int n_canonical;        /* R, 1 <= R <= M: domains 0..R-1 are canonical */
    const real *confidence; /* c_i, length M */
    const real *ptarget;    /* M x M, row-major: ptarget[i*M + j] = p̂_{<-i}(y_j) */
} mis_input;

static inline real mis_ptarget(const mis_input *in, int i, int j) { return in->ptarget[i * in->m + j]; }

/* m_i(y_j) = c_i / sum_k c_k: the constant weights (GRIS §5.6; GRIS §6.2 reservoir merge). */
real mis_constant(const mis_input *in, int i, int j, long *shifts);
/* GRIS Eq. 36 with confidences (Stochastic MIS Eq. 9):
 *     m_i(y) = c_i p̂_{<-i}(y) / sum_k c_k p̂_{<-k}(y). */
real mis_talbot(const mis_input *in, int i, int j, long *shifts);
/* GRIS Eq. 37 with confidences (docs/mis-derivations.md §3), c_R = sum of canonical c,
 * c_S = sum of non-canonical c, q_k = p̂_{<-k}(y), p̂ = p̂(y):
 *     i >= R:  m_i = c_i q_i / (c_S q_i + c_R p̂)
 *     i <  R:  m_i = (c_i / c_R) sum_{k>=R} (c_k / c_S) c_R p̂ / (c_S q_k + c_R p̂) */
real mis_pairwise_uniform(const mis_input *in, int i, int j, long *shifts);
/* GRIS Eq. 38 with confidences (Stochastic MIS Eqs. 11-12 for R = 1), C = c_R + c_S:
 *     i >= R:  m_i = (c_S / C) c_i q_i / (c_S q_i + c_R p̂)
 *     i <  R:  m_i = c_i / C + sum_{k>=R} (c_k / C) c_i p̂ / (c_S q_k + c_R p̂) */
real mis_pairwise_defensive(const mis_input *in, int i, int j, long *shifts);
/* GRIS Eq. 38 with confidences in the form of the authors' Falcor ReSTIR PT code
 * (docs/mis-derivations.md §3.5): every pair holds the share 1/(k+1), k = M - R, whatever
 * its confidence, and inside pair i the canonical side is c_R p̂ / k against c_i q_i:
 *     i >= R:  m_i = 1/(k+1) c_i q_i / (c_i q_i + (c_R/k) p̂)
 *     i <  R:  m_i = (c_i / c_R) 1/(k+1) [1 + sum_{k'>=R} (c_R/k) p̂ / (c_k' q_k' + (c_R/k) p̂)]
 * Equal to mis_pairwise_defensive when all confidences are equal; a partition of unity for
 * any confidences, so unbiased too (same section). */
real mis_pairwise_defensive_falcor(const mis_input *in, int i, int j, long *shifts);

/* Dispatch by family. */
real mis_weight(mis_family f, const mis_input *in, int i, int j, long *shifts);
/* m_i(y_j) for every i = 0..M-1 into out[0..M-1] (reads column j). */
void mis_weights_at(mis_family f, const mis_input *in, int j, real *out, long *shifts);
/* Shift evaluations (beyond the M - R forward shifts) to compute m_j(y_j) for every j:
 * constant 0, Talbot (M-R)(M-1), pairwise (both) R(M-R). */
long mis_shift_count(mis_family f, int m, int n_canonical);

/* Two-domain merge (Mutations App. B; = GRIS Eq. 36 for M = 2 with confidences). Domain c
 * is the canonical one (the current pixel), n the other (e.g. the previous frame).
 * Mutations Eq. 31, at the canonical sample x_c:
 *     m_c(x_c) = c_c p̂_c(x_c) / (c_c p̂_c(x_c) + c_n p̂_n(x_c') |dx_c'/dx_c|)
 *   p_c = p̂_c(x_c), p_n_from_c = p̂_n(x_c') |dx_c'/dx_c| with x_c' = T^{-1}(x_c) in domain n
 *   (0 if that shift fails). A zero denominator gives 1 (Mutations: m = 1 without a shift). */
real mis_pair_canonical(real c_c, real p_c, real c_n, real p_n_from_c);
/* Mutations Eq. 32, at the shifted neighbour sample x_n' = T(x_n):
 *     m_n(x_n') = c_n p̂_n(x_n) |dx_n/dx_n'| / (c_n p̂_n(x_n) |dx_n/dx_n'| + c_c p̂_c(x_n'))
 *   p_n_from_n = p̂_n(x_n) / |dT/dx_n|, p_c_at_n = p̂_c(x_n'). A zero denominator gives 0. */
real mis_pair_neighbor(real c_n, real p_n_from_n, real c_c, real p_c_at_n);

/* index = mis_family: "constant", "talbot", "pairwise", "pairwise-defensive";
 * NULL-terminated. The one name table of these families. (Stochastic pairwise MIS is not a
 * family but a spatial algorithm: spatial_options.h.) */
extern const char *const restir_mis_names[];
/* c_n p_n / (c_a p_a + c_b p_b) for finite c, p >= 0 (the ratio inside every balance
 * weight above), or -1 when the denominator is 0. When a product overflows (the float
 * build: c = 1e30 with p̂ = 1e10) the confidences are divided by their largest and the
 * targets by theirs first, which leaves the ratio unchanged; otherwise the plain
 * expression is returned, bit for bit (docs/precision.md). */
real mis_product_ratio(real c_n, real p_n, real c_a, real p_a, real c_b, real p_b);

/* restir_mis_names[f] for f < MIS_FAMILY_COUNT. */
const char *mis_family_name(mis_family f);
/* Parses a name above; returns 0 on success, -1 if unknown. */
int mis_family_parse(const char *name, mis_family *f);

#endif
