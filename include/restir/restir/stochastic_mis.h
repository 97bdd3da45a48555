/* Stochastic resampling MIS weights (Stochastic MIS §3-§4, Eqs. 13-19; derivations and
 * the unbiasedness proof: docs/stochastic-mis.md).
 *
 * A GRIS step over M domains needs, for every candidate i, a weight m_i(Y_i) with
 * sum_i m_i(y) = 1 (Stochastic MIS Eq. 8). The stochastic weights replace m_i by an
 * estimate m̃_i with E[m̃_i | X̄, W̄] = m_i(Y_i) (Eq. 13): the GRIS estimator is linear in
 * the weights, so its expectation is unchanged (docs/stochastic-mis.md §3).
 *
 * This file holds the pure, shift-free parts: the multiset of picks, the general weight
 * (Eq. 15), the selection probabilities (Eq. 17) and the pairwise forms (Eqs. 16, 18-19).
 * The GRIS step that uses them (shifts, reservoir) is stochastic_spatial.h. */
#ifndef RESTIR_STOCHASTIC_MIS_H
#define RESTIR_STOCHASTIC_MIS_H

#include "restir/core/vec.h"

#define STOCHASTIC_MAX_PICKS 256 /* Ñ, Ñ_c <= this (addressed RNG slots) */

/* Ñ picks with replacement from the distribution P[0..m) (P >= 0, sum 1 or all 0), the
 * k-th pick by inverting the CDF at u[k] in [0,1); K[i] = multiplicity of i
 * (K_S̄(i), Stochastic MIS §3.1). An entry with P = 0 is never picked. If all P are 0,
 * K = 0. Returns the number of distinct picks. */
int stochastic_pick(const real *P, int m, int n_picks, const real *u, int *K);

/* Stochastic MIS Eq. 15: m̃_i = K(i) / (Ñ P(i)) m_i, and 0 where P(i) = 0 (then K = 0). */
real stochastic_mis_weight(int K, int n_picks, real P, real m);

/* Stochastic MIS Eq. 17: P(i) proportional to c_i p̂(X_i) W_{X_i}, from the inputs only
 * (no shift): a[i] = c_i p̂_i(X_i) W_i (a[i] >= 0; negative or non-finite counts as 0),
 * normalised into P[0..m). Returns the sum before normalising (0: P = 0 everywhere). */
real stochastic_selection_p(const real *a, int m, real *P);

/* The pairwise weights of one non-canonical domain i against the canonical domain c
 * (Stochastic MIS Eq. 11 / GRIS Eq. 38 defensive, R = 1), with c_S the sum of the
 * non-canonical confidences used in the formulas (after any §4.3 scaling):
 *   Eq. 11a: m_i(y)  = (c_S / C) c_i q_i / (c_S q_i + c_c p)       C = c_S + c_c
 *   Eq. 19:  b_i(y)  = (c_i / C) c_c p / (c_S q_i + c_c p)
 * with q_i = p̂_{<-i}(y), p = p̂(y). An empty pair (c_S q_i + c_c p = 0) belongs to the
 * canonical side: m_i = 0, b_i = c_i / C (the mis.c convention, so that
 * c_c / C + sum_i b_i(y) + sum_i m_i(y) = 1 for every y). C = 0 gives m_i = b_i = 0. */
real stochastic_pairwise_m(real c_c, real c_S, real c_i, real q_i, real p);
real stochastic_pairwise_b(real c_c, real c_S, real c_i, real q_i, real p);

/* Stochastic MIS §4.3: the factor applied to every non-canonical confidence, Ñ/M with
 * M the number of non-canonical domains, capped at 1 so that Ñ >= M is deterministic
 * pairwise MIS (the paper: "naturally degrading to deterministic pairwise MIS"). */
real stochastic_confidence_scale(int n_picks, int m_noncanonical);

/* Stochastic MIS §4.2: the Ñ_c uniform picks (P_c = 1/n) among the n non-canonical domains
 * for the canonical weight, the k-th at floor(uc[k] n); Kc[i] = multiplicity of i. */
void stochastic_canonical_picks(int n, int n_picks, const real *uc, int *Kc);

/* Stochastic MIS Eq. 18, one term of the sum over the picked domains i:
 *     K'(i) / (Ñ_c P_c) b_i(Y_c),   P_c = 1/n,   b_i of Eq. 19 with q_i = p̂_{<-i}(Y_c);
 * m̃_c = c_c / C + the sum of these terms (C = c_c + c_S > 0, n >= 1). */
real stochastic_canonical_term(int kc, int n_picks, int n, real c_c, real c_S, real c_i, real q_i, real p);

#endif
