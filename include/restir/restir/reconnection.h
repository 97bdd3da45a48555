/* Reconnection: the offset path reaches the base path's vertex x_k from its own x_{k-1}
 * (GRIS §7.2 "vertex copy", §8.1; Enhanced §2.3), and the recording of a selected path
 * with the data a reconnection needs (docs/formats.md).
 *
 * The PSS Jacobian of a reconnection from y_{k-1} to x_k (Enhanced Eq. 2, which is the
 * solid-angle Jacobian GRIS Eq. 52 converted to primary sample space by GRIS Eq. 54):
 *
 *   |dT/du| = p^y_{k-1}(w'_{k-1}) G(y_{k-1} -> x_k) p^y_k(w_k)
 *             ------------------------------------------------
 *             p^x_{k-1}(w_{k-1}) G(x_{k-1} -> x_k) p^x_k(w_k)
 *
 *   p_{k-1}: the pdf with which x_{k-1} samples the direction to x_k: P(ell|wo) pdf_ell
 *            (lobe-extended PSS: the lobe-selection number is a dimension), or the NEE
 *            solid-angle pdf when x_k = x_d is an NEE light vertex;
 *   G(a -> b) = |n_g(b) . w| / ||b - a||^2 with the geometric normal at b (GRIS Eq. 52);
 *   p_k:     P(ell_k|wo) pdf_ell_k(w_k) at x_k for the NEW incoming direction; 1 when
 *            k = d (Enhanced Eq. 2) and when w_k is x_k's NEE direction (k = d-1: the
 *            light sample does not depend on the incoming direction, so the NEE numbers
 *            map to themselves with Jacobian 1).
 *
 * rc_evaluate computes the numerator terms and the offset's contribution from any
 * y_{k-1}; path_record calls it with the base path's own x_{k-1} to store the
 * denominator, so that shifting a path to its own pixel gives J = 1 exactly and
 * J(a->b) J(b->a) = 1 up to rounding of one division. */
#ifndef RESTIR_RECONNECTION_H
#define RESTIR_RECONNECTION_H

#include "restir/restir/path_replay.h"

/* The reconnection from y_{k-1} to x_k, evaluated at the destination. */
typedef struct {
    rgb factor;     /* F(y) / beta(y_{k-1}): the bounce at y_{k-1}, the (re-evaluated) BSDF at
                     * x_k, the suffix radiance, and the final vertex's MIS weight */
    real pdf_prev;  /* p^y_{k-1}(w'_{k-1}) */
    real geom;      /* G(y_{k-1} -> x_k) */
    real pdf_k;     /* p^y_k(w_k), or 1 */
    real light_pdf; /* NEE pdf of x_d seen from the offset's x_{d-1} (recomputed when k = d) */
    rgb radiance;   /* suffix radiance the offset sample stores (Le towards y_{k-1} when k = d) */
    vec3 direction; /* w'_{k-1} = (x_k - y_{k-1}) / ||x_k - y_{k-1}|| */
} rc_terms;

/* Reconnects the vertex `prev` (y_{k-1}, built by the path sampler with its incoming
 * direction) to x_k of sample x (rc_k = k). Re-evaluates the BSDF at x_k for the new
 * incoming direction (not frozen: pitfall 5, docs/restir-pt.md §11) and the final vertex's NEE/BSDF MIS
 * weight with the destination pdfs, the light pdf included when x_{d-1} moves (notes
 * pitfall 6; the light-pdf ablation keeps x's stale one), and traces the segment
 * y_{k-1} -> x_k (pitfall 7). Fails with SHIFT_FAIL_LOBE_UNAVAILABLE, _DELTA_LOBE, _ZERO,
 * _NONFINITE or (last, after every term is filled) _OCCLUDED. */
enum shift_failure rc_evaluate(const restir_context *c, const path_vertex *prev, const path_sample *x, rc_terms *t);

/* Enhanced Eq. 2 from the destination terms and the source terms stored in x. */
real rc_jacobian(const rc_terms *t, const path_sample *x);

/* Records a selected path: s holds the replay identity, length and technique; the path
 * is replayed from its own primary hit x1 and s receives its lobes (GRIS §7.6), the
 * reconnection index of the context's shift (connectability.h), the vertex x_k with the
 * source terms of Enhanced Eq. 2 (rc_evaluate from x_{k-1}), w_k, the suffix radiance,
 * the final vertex's light pdf, F and p̂ = luminance(F). If the reconnection from the own
 * x_{k-1} fails, PATH_RC_FLAG_UNSHIFTABLE is set (docs/restir-pt.md). Returns SHIFT_OK or
 * the replay's failure (then s is unchanged). */
enum shift_failure path_record(const restir_context *c, const path_vertex *x1, path_sample *s);

/* The reconnection segment of sample y of the pixel with primary hit y1, traced again:
 * y_1..y_{k-1} replayed with y's numbers, then the shadow ray y_{k-1} -> x_k. 1 if visible
 * (or y has no reconnection vertex), 0 if blocked or the replay fails. For the debug
 * build's invariants (spatial_check_step): every successful shift must
 * pass it. */
int rc_segment_visible(const restir_context *c, const path_vertex *y1, const path_sample *y);

/* Temporal reuse in animated scenes (temporal.h): x with its reconnection vertex posed in
 * c's scene (rot = the 3x3 rotation its object underwent since x was sampled, NULL if it
 * did not move), w_k rotated alike, and the suffix x_{k+1}..x_d traced again in c's scene
 * with x's own numbers (L_k, light pdf, suffix lobes recomputed). Identity for k = d and
 * for samples without k. A failure (suffix ray misses, no light, NEE occluded) means the
 * sample has no counterpart in that scene: the shift that would follow fails. */
enum shift_failure rc_retrace_suffix(const restir_context *c, const path_sample *x, const double (*rot)[3],
                                     path_sample *out);

#endif
