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
 * under the same test, or the shift is not invertible (GRIS §7.4; notes pitfall 3).
 *
 * Everything the criterion reads is a function of the vertex positions, materials and
 * lobes, never of the direction a vertex is seen from, so base and offset paths evaluate
 * it identically. The whole decision is behind rc_pair_test (one pair) and rc_select
 * (the index): the Enhanced footprint criterion (equation 5 of that paper, not implemented
 * yet) replaces rc_pair_test. */
#ifndef RESTIR_CONNECTABILITY_H
#define RESTIR_CONNECTABILITY_H

#include "restir/path_sample.h"
#include "restir/restir_context.h"

/* What the criterion knows about vertex x_j of a path. */
typedef struct {
    vec3 position; /* x_j */
    int rough;     /* x_j is rough for the lobe it used (rc_vertex_is_rough) */
} rc_vertex;

/* GRIS §7.6 roughness of a vertex: `lobe` is its lobe index ell_j, PATH_LOBE_NEE for an
 * NEE-sampled vertex, or PATH_LOBE_NONE for a light vertex x_d (then b may be NULL). */
int rc_vertex_is_rough(const bsdf *b, unsigned lobe, real roughness_threshold);

/* The pair (x_{k-1}, x_k): SHIFT_OK if connectable, else SHIFT_FAIL_RC_ROUGHNESS (one of
 * them is not rough) or SHIFT_FAIL_RC_DISTANCE (||x_k - x_{k-1}|| < d_min). */
enum shift_failure rc_pair_test(const rc_criterion *c, const rc_vertex *prev, const rc_vertex *cur);

/* The reconnection index of a length-d path with vertices v[1..d] (v[0] unused):
 *   reconnection shift: 2 (y_2 = x_2, unconditionally: GRIS §7.4);
 *   random replay:      PATH_RC_NONE;
 *   hybrid:             the first k in [2, d] whose pair passes rc_pair_test, else NONE. */
int rc_select(const restir_context *c, const rc_vertex *v, int d);

/* The distance threshold d_min for a scene: `fraction` of its bounding-box diagonal. */
real rc_min_distance_for_scene(const scene *s, real fraction);

#endif
