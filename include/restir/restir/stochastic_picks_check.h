/* The pick counts of one stochastic pairwise MIS step (stochastic_spatial.h), checked by
 * `make DEBUG=1` after every step (issue 26). stochastic_check_step takes the picks as
 * given; this checks that they are the picks the step was asked to make and that every
 * one of them was used:
 *   - the Ñ picks: sum_i K(i) = Ñ when some non-canonical domain has P(i) > 0 (else 0),
 *     and K(i) > 0 only where P(i) > 0 (Eq. 17 recomputed from c_i p̂(X_i) W_i);
 *   - the Ñ_c canonical picks (when the canonical side ran: its sample is usable, M >= 1,
 *     C > 0): sum_i K'(i) = Ñ_c over ALL M domains (P_c = 1/M, empty ones included), and
 *     the step made exactly one MIS shift per distinct canonical pick (a pick it skipped,
 *     e.g. one landing on an empty pixel, leaves its b_i(Y_c) out of m̃_c: biased);
 *   - every shift the step made is one of those or one forward shift per distinct pick.
 * before/after: the step's spatial_stats before and after it. 0 if all hold, else 1 with
 * the reason in why. */
#ifndef RESTIR_STOCHASTIC_PICKS_CHECK_H
#define RESTIR_STOCHASTIC_PICKS_CHECK_H

#include <stddef.h>
#include "restir/restir/stochastic_spatial.h"

int stochastic_check_pick_counts(const stochastic_options *so, int m, const reservoir *const *in,
                                 const stochastic_workspace *w, const spatial_stats *before, const spatial_stats *after,
                                 char *why, size_t why_size);

#endif
