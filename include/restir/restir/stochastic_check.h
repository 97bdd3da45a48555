/* DEBUG invariants of one stochastic pairwise MIS step (src/restir/stochastic_check.c;
 * Stochastic MIS Eqs. 16-19; docs/statistics.md): the step recomputed from what it used. */
#ifndef RESTIR_RESTIR_STOCHASTIC_CHECK_H
#define RESTIR_RESTIR_STOCHASTIC_CHECK_H

#include "restir/restir/stochastic_spatial.h"

/* The invariants `make DEBUG=1` checks after every stochastic step (docs/statistics.md,
 * "Debug invariants"), recomputed from the inputs and not from the step's own sums:
 * confidences >= 0 and the output confidence c_c + sum min(1, Ñ/M) c_i; a finite W >= 0;
 * Ñ and Ñ_c picks made; each pick has P(i) > 0 by Eq. 17 recomputed from c_i p̂(X_i) W_i,
 * and the P(i) in its weight is that one (skipped for the naive_p ablation, which breaks it
 * on purpose); every m̃_i equals K(i)/(Ñ P(i)) times the deterministic defensive pairwise
 * weight of mis.c (GRIS Eq. 38) over the scaled confidences, and m̃_c equals
 * c_c/C + sum K'(i)/(Ñ_c/M) (c_i/C - m_i(Y_c)) (Eq. 19 via b_i = c_i/C - m_i); a successful
 * reconnection's segment is unoccluded. 0 if all hold, else 1 with the reason in `why`. */
int stochastic_check_step(const restir_context *c, const stochastic_options *so, int m, const path_vertex *const *x1,
                          const reservoir *const *in, const reservoir *out, stochastic_workspace *w, char *why,
                          size_t why_size);

#endif
