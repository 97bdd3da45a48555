/* One GRIS step with stochastic pairwise MIS (Stochastic MIS §4, Eqs. 14, 16-19, §4.3;
 * docs/stochastic-mis.md, where the unbiasedness of the whole step is proven).
 *
 * Domains as in spatial.h: 0 is the pixel's own reservoir (canonical c), 1..M are the
 * M non-canonical domains (the accepted neighbours, or the pixels of a reuse cell). The
 * step is the defensive pairwise GRIS step over all 1 + M domains (mis.h,
 * MIS_PAIRWISE_DEFENSIVE) with its weights replaced by unbiased estimates:
 *   - Ñ picks with replacement among 1..M by P(i) ∝ c_i p̂(X_i) W_i (Eq. 17; no shift);
 *     only the picked domains are shifted in, with m̃_i = K(i)/(Ñ P(i)) m_i (Eq. 16);
 *   - Ñ_c separate uniform picks (P_c = 1/M), each one shift of the canonical sample out,
 *     give m̃_c = c_c/C + sum K'(i)/(Ñ_c P_c) b_i (Eqs. 18-19);
 *   - with confidence scaling (§4.3) every non-canonical c_i is first multiplied by
 *     min(1, Ñ/M), in the weights and in the output confidence.
 * Shifts: at most Ñ forward + Ñ_c MIS shifts, whatever M. The output confidence is
 * c_c + sum_i c_i' (the scaled confidences; deterministic given the inputs). */
#ifndef RESTIR_STOCHASTIC_SPATIAL_H
#define RESTIR_STOCHASTIC_SPATIAL_H

#include "restir/restir/spatial.h"
#include "restir/restir/stochastic_mis.h"

typedef struct {
    int n_picks;            /* Ñ, 1..STOCHASTIC_MAX_PICKS */
    int n_canonical_picks;  /* Ñ_c, 1..STOCHASTIC_MAX_PICKS */
    int confidence_scaling; /* §4.3: c_i <- c_i min(1, Ñ/M) */
    int naive_p;            /* the ablation "stochastic-p" (deliberately biased): picks
                               uniformly among the non-zero samples, but weights as if
                               every one of the M domains had P = 1/M (no P(i) correction) */
} stochastic_options;

/* Ñ = Ñ_c = 1, confidence scaling on, no ablation. */
void stochastic_options_default(stochastic_options *so);
/* 0, or -1 with "stochastic: what is wrong". */
int stochastic_options_validate(const stochastic_options *so, rerror *e);

typedef struct {
    int max_domains;
    real *a, *P;   /* Eq. 17 inputs and probabilities, per non-canonical domain */
    int *K, *Kc;   /* multiplicities of the Ñ and the Ñ_c picks */
    path_sample *shifted;
    real *jacobian; /* |dT/dX| of each picked domain's shift in, 0 where it failed or was not picked */
    /* what the step used, kept for the debug invariants (stochastic_check_step) */
    real *P_used;  /* the P(i) inside m̃_i (Eq. 16) */
    real *m_used;  /* m̃_i of each picked domain whose shift succeeded */
    real *q_back;  /* p̂_{<-i}(Y_c) of each canonical pick (0: the shift out failed) */
    real m_c_used; /* m̃_c (Eqs. 18-19) */
    real *check_conf, *check_ptarget; /* scratch of stochastic_check_step: M and M x M */
    /* optional: domain i's primary vertex on demand (i >= 1), so that only the Ñ_c
     * canonical picks pay for building one (cells hold up to 63 domains); NULL: x1[i] */
    const path_vertex *(*vertex)(void *user, int i);
    void *vertex_user;
} stochastic_workspace;

int stochastic_workspace_alloc(stochastic_workspace *w, int max_domains, rerror *e);
void stochastic_workspace_free(stochastic_workspace *w);

/* The step at one pixel: x1[i], in[i] for i = 0..m-1 as spatial_resample; u[i] the
 * selection number of domain i (RNG_RIS), up[0..Ñ) the numbers of the Ñ picks, uc[0..Ñ_c)
 * those of the canonical picks; all addressed, independent of the reservoirs. */
void stochastic_pairwise_resample(const restir_context *c, const stochastic_options *so, int m,
                                  const path_vertex *const *x1, const reservoir *const *in, const real *u,
                                  const real *up, const real *uc, reservoir *out, stochastic_workspace *w,
                                  spatial_stats *st);

#endif
