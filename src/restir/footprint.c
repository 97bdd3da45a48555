/* The footprint reconnection criterion, Enhanced §4 Eq. 5 (include/restir/restir/footprint.h,
 * docs/enhanced.md §1). */
#include "restir/restir/footprint.h"
#include "restir/scene/scene_trace.h"

#include <math.h>

/* Enhanced Eq. 5 RHS without c/100 (Müller et al. 2021 primary-ray footprint R_pri^2). */
real rc_primary_footprint(const path_vertex *x1)
{
    real dist = (real)x1->hit.t, cosine = (real)fabs(v3_dot(x1->ng, x1->wo));
    if (!(cosine > 0)) return (real)INFINITY;
    return dist * dist / (cosine / (4 * PI_R));
}

/* P(ell|wo) pdf_ell(wi) at v for world directions wo (towards the previous vertex) and wi:
 * the lobe-extended sampling density of Enhanced Eq. 2. */
static real lobe_density(const path_vertex *v, unsigned lobe, vec3 wo, vec3 wi)
{
    real p[BSDF_MAX_LOBES];
    vec3 wo_local = shading_frame_to_local(&v->frame, wo), wi_local = shading_frame_to_local(&v->frame, wi);
    if ((int)lobe >= bsdf_lobe_count(&v->b)) return 0;
    bsdf_lobe_probabilities(&v->b, wo_local, p);
    return p[lobe] * bsdf_lobe_pdf(&v->b, (int)lobe, wo_local, wi_local);
}

/* Footnote 6: the inverse footprint is skipped where the reconnection cannot change p_k. */
static int inverse_skipped(const rc_vertex *cur)
{
    if (!cur->surface || cur->lobe == PATH_LOBE_NONE || cur->lobe == PATH_LOBE_NEE) return 1;
    return (int)cur->lobe < bsdf_lobe_count(&cur->surface->b) &&
           bsdf_lobe_kind_of(&cur->surface->b, (int)cur->lobe) == BSDF_LOBE_DIFFUSE;
}

/* Enhanced Eq. 5, both footprints of the pair. */
void rc_footprints(const rc_vertex *prev, const rc_vertex *cur, real *forward, real *inverse)
{
    vec3 to = v3_sub(cur->position, prev->position);
    real dist2 = v3_dot(to, to), density;
    vec3 w;
    *forward = *inverse = (real)INFINITY;
    /* x_k at infinity: the area per sample of x_k traced from x_{k-1} is 1/(p G) with G -> 0,
     * and the inverse footprint of a light vertex is skipped (docs/environment.md). */
    if (cur->at_infinity) return;
    if (!(dist2 > 0)) {
        *forward = *inverse = 0;
        return;
    }
    w = v3_scale(to, 1 / (real)sqrt(dist2));
    /* (p_{k-1}(w_{k-1}) G(x_{k-1} -> x_k))^-1: the area per sample of x_k traced from x_{k-1}. */
    if (prev->lobe != PATH_LOBE_NEE && prev->surface) {
        density = lobe_density(prev->surface, prev->lobe, prev->surface->wo, w) * (real)fabs(v3_dot(cur->ng, w)) / dist2;
        *forward = density > 0 ? 1 / density : (real)INFINITY;
    }
    /* (p_k(w_k) G(x_k -> x_{k-1}))^-1: the area per sample of x_{k-1} traced back from x_k. */
    if (!inverse_skipped(cur)) {
        if (bsdf_lobe_is_delta(&cur->surface->b, (int)cur->lobe)) {
            *inverse = 0;
            return;
        }
        density = lobe_density(cur->surface, cur->lobe, v3_neg(w), cur->wi) * (real)fabs(v3_dot(prev->ng, w)) / dist2;
        *inverse = density > 0 ? 1 / density : (real)INFINITY;
    }
}

/* Enhanced Eq. 5 with the single-vertex roughness threshold at x_{k-1} (§4.2). */
enum shift_failure rc_footprint_test(const rc_criterion *c, const rc_vertex *prev, const rc_vertex *cur,
                                     real primary_footprint)
{
    real forward, inverse, threshold = c->footprint_c / 100 * primary_footprint;
    if (!prev->rough) return SHIFT_FAIL_RC_ROUGHNESS;
    rc_footprints(prev, cur, &forward, &inverse);
    return (forward < inverse ? forward : inverse) >= threshold ? SHIFT_OK : SHIFT_FAIL_RC_FOOTPRINT;
}

int rc_vertex_of_xk(const scene *s, const path_sample *x, real roughness_threshold, path_vertex *storage,
                    rc_vertex *v)
{
    int k = x->rc_k;
    surface_hit h;
    v->position = v3_from_f(x->rc_position);
    v->ng = v3_from_f(x->rc_normal);
    v->wi = x->rc_wo;
    v->at_infinity = (x->rc_flags & PATH_RC_FLAG_DISTANT) != 0;
    if (v->at_infinity) v->position = light_distant_direction(x->rc_position);
    if (k == x->length) { /* the light vertex x_d: emissive, no lobe */
        v->surface = NULL;
        v->lobe = PATH_LOBE_NONE;
        v->rough = rc_vertex_is_rough(NULL, PATH_LOBE_NONE, roughness_threshold);
        return 1;
    }
    if (!scene_surface_point(s, x->rc_triangle, x->rc_bary[0], x->rc_bary[1], &h)) return 0;
    h.position = x->rc_position; /* as the base path found it (reconnection.c, make_xk) */
    h.ng = x->rc_normal;
    path_vertex_make(storage, s, &h, v3_neg(x->rc_wo)); /* wo is not read: the test uses x_{k-1} */
    v->surface = storage;
    v->lobe = x->lobe[k];
    v->rough = rc_vertex_is_rough(&storage->b, x->lobe[k], roughness_threshold);
    return 1;
}
