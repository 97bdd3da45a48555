/* The temporal reverse shift's round trip (issue 26): an invariant of the temporal GRIS
 * step (temporal.h) that `make DEBUG=1` checks after every step, and tests drive directly.
 *
 * The history candidate enters the step as y_1 = T_{t-1 -> t}(X_1), and its own MIS term
 * (the diagonal of GRIS Eq. 35) is p̂_{t-1}(X_1) / J_1. Shifting y_1 back into the previous
 * pixel (in the previous frame's scene, GRIS App. B) must reproduce X_1: the reverse
 * shift's p̂_{t-1}(T^{-1}(y_1)) equals the stored target p̂_{t-1}(X_1), and
 * p̂_{t-1}(T^{-1}(y_1)) |dT^{-1}/dy_1| equals the diagonal entry the step used. A step that
 * puts the current frame's p̂_t(y_1) there (a classic port error) passes the partition-of-
 * unity check (Talbot's weights sum to one for any matrix) but not this one. */
#ifndef RESTIR_TEMPORAL_CHECK_H
#define RESTIR_TEMPORAL_CHECK_H

#include <stddef.h>
#include "restir/restir/spatial.h"

/* After a two-domain temporal step whose workspace w still holds it: prev the previous
 * frame's context, rf the refresh into the previous frame (may be NULL), x1_prev domain 1's
 * primary vertex, x the history sample X_1 as it entered the step (refreshed into frame
 * t-1 if rf: the reservoir's sample). Returns 0 if the round trip holds (or there is
 * nothing to check: no valid history candidate, or the reverse shift fails at a grazing
 * configuration), 1 with the reason in why otherwise. Relative tolerance: 1e-3 (double; 5e-2 in
 * animated scenes, whose suffix re-trace moves p̂ by up to 1e-2), float 2e-2 (1e-1). *checked (may be NULL) is incremented when a round trip was compared. */
int temporal_check_round_trip(const restir_context *prev, const domain_refresh *rf, const path_vertex *x1_prev,
                              const path_sample *x, const spatial_workspace *w, char *why, size_t why_size,
                              long *checked);

#endif
