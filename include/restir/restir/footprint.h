/* The footprint reconnection criterion of ReSTIR PT Enhanced (§4, Eq. 5, footnote 6,
 * §4.2), `--rc-criterion footprint`; derivation and conventions in docs/enhanced.md §1.
 *
 * A pair (x_{k-1}, x_k) is connectable if x_{k-1} is rough for the lobe it used
 * (alpha_min: the GRIS roughness test, now at x_{k-1} only) and
 *
 *   min( (p_{k-1}(w_{k-1}) G(x_{k-1} -> x_k))^-1 , (p_k(w_k) G(x_k -> x_{k-1}))^-1 )
 *       >= c/100 * ||x_0 - x_1||^2 / (<n_{x_1}, x_1->x_0> / 4 pi)                 (Eq. 5)
 *
 *   p_{k-1}(w_{k-1}): P(ell_{k-1}|wo) pdf_ell(w) at x_{k-1} towards x_k, wo towards x_{k-2}
 *                     (the lobe-extended sampling pdf that Enhanced Eq. 2 puts in the
 *                     Jacobian); skipped (infinite footprint) if x_k was sampled by NEE:
 *                     then its area density is the light sampler's and does not depend on
 *                     x_{k-1}, so the reconnection does not change it (Jacobian = 1 there);
 *   p_k(w_k):         P(ell_k|wo') pdf_ell(w_k) at x_k with wo' towards x_{k-1}; skipped for
 *                     a diffuse lobe ell_k, an emissive x_k (the light vertex x_d), and an
 *                     NEE direction w_k, where p_k does not depend on x_{k-1} (footnote 6);
 *                     a Dirac ell_k has zero footprint (never connectable);
 *   G(a -> b) = |n_g(b) . w| / ||b - a||^2.
 * The right-hand side uses the path's own x_0 x_1: base and offset paths have their own. */
#ifndef RESTIR_FOOTPRINT_H
#define RESTIR_FOOTPRINT_H

#include "restir/restir/connectability.h"

/* ||x_0 - x_1||^2 / (|<n_g(x_1), w_o>| / 4 pi) for the primary vertex x1 (hit.t = ||x_0 - x_1||,
 * the camera ray direction being unit length); +inf at grazing incidence. */
real rc_primary_footprint(const path_vertex *x1);

/* The two sides of Eq. 5 for the pair (prev, cur): forward (p_{k-1} G)^-1 and inverse
 * (p_k G)^-1, +inf where skipped, 0 for a Dirac ell_k. */
void rc_footprints(const rc_vertex *prev, const rc_vertex *cur, real *forward, real *inverse);

/* Enhanced Eq. 5 and the alpha_min test at x_{k-1}: SHIFT_OK, SHIFT_FAIL_RC_ROUGHNESS or
 * SHIFT_FAIL_RC_FOOTPRINT. */
enum shift_failure rc_footprint_test(const rc_criterion *c, const rc_vertex *prev, const rc_vertex *cur,
                                     real primary_footprint);

/* The rc_vertex of the stored reconnection vertex x_k of sample x (rc_k = k), for the
 * offset path's test; *storage receives x_k as a path vertex (it must outlive *v).
 * Returns 0 if x_k's triangle cannot be rebuilt. */
int rc_vertex_of_xk(const scene *s, const path_sample *x, real roughness_threshold, path_vertex *storage,
                    rc_vertex *v);

#endif
