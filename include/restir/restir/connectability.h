/* Choosing the reconnection vertex x_k of a path (GRIS §7.4-7.6, §8.3; Enhanced §2.3).
 *
 * The base path precomputes ONE reconnection index k (GRIS §7.4): the first k >= 2 such
 * that the pair (x_{k-1}, x_k) is connectable:
 *   - x_{k-1} and x_k are rough for the lobes the path actually used (GRIS §7.6):
 *       a BSDF-sampled vertex x_j: its lobe ell_j is not a Dirac and has linear
 *       roughness > threshold (0.2, GRIS §8.3);
 *       an NEE-sampled vertex (ell_j = NEE): rough if ANY lobe of its material is;
 *       a light vertex x_d: always rough;
 *   - ||x_k - x_{k-1}|| >= d_min (GRIS §7.5 distance condition).
 * A shift must reconnect exactly there, and the offset path must select the same k
 * under the same test, or the shift is not invertible (GRIS §7.4; pitfall 3, docs/restir-pt.md §11).
 *
 * Everything the criterion reads is a function of the vertex positions, materials and
 * lobes, never of the direction a vertex is seen from, so base and offset paths evaluate
 * it identically. The whole decision is behind rc_pair_test (one pair) and rc_select
 * (the index).
 *
 * --rc-criterion footprint (Enhanced §4, Eq. 5; include/restir/restir/footprint.h) replaces the
 * pair test by: x_{k-1} rough for its lobe (alpha_min, §4.2) and the dual ray footprint
 * threshold. That test DOES depend on the direction x_{k-1} is seen from (its BSDF pdf)
 * and on the pixel (the primary-ray footprint of x_0 x_1), so it differs between a base
 * path and its offset: the shift tests it on the offset path as well (shift.c,
 * hybrid_same_reconnection), which is what keeps T bijective. */
#ifndef RESTIR_CONNECTABILITY_H
#define RESTIR_CONNECTABILITY_H

#include "restir/restir/path_sample.h"
#include "restir/restir/restir_context.h"

/* What the criterion knows about vertex x_j of a path. */
typedef struct {
    vec3 position; /* x_j */
    int rough;     /* x_j is rough for the lobe it used (rc_vertex_is_rough) */
    int at_infinity; /* 1: x_j is a vertex at infinity (the last, x_d); position = its unit
                      * direction; the distance condition holds and its footprint is
                      * infinite (docs/environment.md, "Connectability") */
    /* for the footprint criterion (Enhanced Eq. 5): */
    vec3 ng;                     /* geometric normal at x_j (G uses it, as GRIS Eq. 52) */
    const path_vertex *surface;  /* x_j as the path sampler built it (BSDF, shading frame; for
                                    v[1] also hit.t = ||x_0 - x_1||); NULL: the light vertex x_d */
    unsigned lobe;               /* ell_j: lobe index, PATH_LOBE_NEE, PATH_LOBE_NONE (x_d) */
    vec3 wi;                     /* w_j: unit direction x_j -> x_{j+1} (j < d) */
} rc_vertex;

/* GRIS §7.6 roughness of a vertex: `lobe` is its lobe index ell_j, PATH_LOBE_NEE for an
 * NEE-sampled vertex, or PATH_LOBE_NONE for a light vertex x_d (then b may be NULL). */
int rc_vertex_is_rough(const bsdf *b, unsigned lobe, real roughness_threshold);

/* The pair (x_{k-1}, x_k): SHIFT_OK if connectable, else SHIFT_FAIL_RC_ROUGHNESS (one of
 * them is not rough) or SHIFT_FAIL_RC_DISTANCE (||x_k - x_{k-1}|| < d_min); with the
 * footprint criterion SHIFT_FAIL_RC_ROUGHNESS (x_{k-1} only) or SHIFT_FAIL_RC_FOOTPRINT.
 * primary_footprint: rc_primary_footprint of the path's x_1 (footprint criterion only). */
enum shift_failure rc_pair_test(const rc_criterion *c, const rc_vertex *prev, const rc_vertex *cur,
                                real primary_footprint);

/* Enhanced §6.2.3: with c->force_nee, the pair (x_{d-1}, x_d) of an NEE path (v[d-1].lobe =
 * PATH_LOBE_NEE) is taken when no earlier pair passes; 1 if k = d is such a forced pair. */
int rc_forced_nee(const rc_criterion *c, const rc_vertex *v, int k, int d);

/* The reconnection index of a length-d path with vertices v[1..d] (v[0] unused):
 *   reconnection shift: 2 (y_2 = x_2, unconditionally: GRIS §7.4);
 *   random replay:      PATH_RC_NONE;
 *   hybrid:             the first k in [2, d] whose pair passes rc_pair_test, else d for an
 *                       NEE path with force_nee (rc_forced_nee), else NONE.
 * The footprint criterion reads the primary footprint from v[1].surface. */
int rc_select(const restir_context *c, const rc_vertex *v, int d);

/* The distance threshold d_min for a scene: `fraction` of its bounding-box diagonal. */
real rc_min_distance_for_scene(const scene *s, real fraction);

#endif
