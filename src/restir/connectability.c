/* The reconnection criterion (include/restir/restir/connectability.h). */
#include "restir/restir/connectability.h"

#include "restir/restir/footprint.h"

/* GRIS §7.6: "we test if vertex x_j is sufficiently rough by examining the roughness of
 * the lobe ell_j chosen to sample vertex x_{j+1}. We treat NEE-sampled vertices as rough
 * if at least one of their BRDF lobes is sufficiently rough. All light vertices are
 * treated as rough." The NEE rule looks at the material's lobes, not at P(l|wo), so it
 * does not depend on the direction the vertex is seen from (docs/restir-pt.md). */
int rc_vertex_is_rough(const bsdf *b, unsigned lobe, real roughness_threshold)
{
    int l;
    if (lobe == PATH_LOBE_NONE) return 1;
    if (lobe == PATH_LOBE_NEE) {
        for (l = 0; l < bsdf_lobe_count(b); ++l)
            if (bsdf_lobe_is_rough(b, l, roughness_threshold)) return 1;
        return 0;
    }
    return (int)lobe < bsdf_lobe_count(b) && bsdf_lobe_is_rough(b, (int)lobe, roughness_threshold);
}

/* GRIS §7.4-7.5 (Enhanced §2.3): min(alpha_{k-1}, alpha_k) >= alpha_min for the sampled
 * lobes, and ||x_k - x_{k-1}|| >= d_min; or Enhanced Eq. 5 (footprint.c). */
enum shift_failure rc_pair_test(const rc_criterion *c, const rc_vertex *prev, const rc_vertex *cur,
                                real primary_footprint)
{
    if (c->mode == RC_MODE_FOOTPRINT) return rc_footprint_test(c, prev, cur, primary_footprint);
    if (!prev->rough || !cur->rough) return SHIFT_FAIL_RC_ROUGHNESS;
    /* GRIS §7.5 at infinity: ||x_k - x_{k-1}|| = infinity >= d_min (docs/environment.md). */
    if (!cur->at_infinity && !(v3_length(v3_sub(cur->position, prev->position)) >= c->min_distance))
        return SHIFT_FAIL_RC_DISTANCE;
    return SHIFT_OK;
}

/* Enhanced §6.2.3 forced NEE light reconnection: "we force reconnection to such vertices
 * if no earlier reconnection is found" -- the light vertex of an NEE path (x_{d-1} used
 * ell = NEE), whatever the pair test says. Replay then never re-samples the light. */
int rc_forced_nee(const rc_criterion *c, const rc_vertex *v, int k, int d)
{
    return c->force_nee && k == d && d >= 2 && v[d - 1].lobe == PATH_LOBE_NEE;
}

int rc_select(const restir_context *c, const rc_vertex *v, int d)
{
    int k;
    real primary;
    switch (c->shift) {
    case RESTIR_SHIFT_RECONNECTION: return 2;
    case RESTIR_SHIFT_REPLAY: return PATH_RC_NONE;
    default: break;
    }
    primary = c->rc.mode == RC_MODE_FOOTPRINT ? rc_primary_footprint(v[1].surface) : 0;
    for (k = 2; k <= d; ++k)
        if (rc_pair_test(&c->rc, &v[k - 1], &v[k], primary) == SHIFT_OK) return k;
    if (rc_forced_nee(&c->rc, v, d, d)) return d; /* Enhanced §6.2.3 */
    return PATH_RC_NONE;
}

real rc_min_distance_for_scene(const scene *s, real fraction)
{
    vec3 extent = v3_sub(v3_from_f(s->bounds_max), v3_from_f(s->bounds_min));
    return fraction * v3_length(extent);
}
