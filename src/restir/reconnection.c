/* Reconnection to x_k and the recording of a selected path (include/restir/restir/reconnection.h). */
#include "restir/restir/reconnection.h"

#include "restir/render/light_ris.h"
#include "restir/scene/scene_trace.h"
#include "restir/scene/sky.h"

#include <math.h>
#include <string.h>

static int rgb_finite(rgb c) { return isfinite(c.r) && isfinite(c.g) && isfinite(c.b); }

/* Can vertex v sample through `lobe` at all? (GRIS §7.6: the offset copies the base lobe.) */
static enum shift_failure lobe_usable(const path_vertex *v, unsigned lobe)
{
    real p[BSDF_MAX_LOBES];
    if ((int)lobe >= bsdf_lobe_count(&v->b)) return SHIFT_FAIL_LOBE_UNAVAILABLE;
    if (bsdf_lobe_is_delta(&v->b, (int)lobe)) return SHIFT_FAIL_DELTA_LOBE; /* a Dirac cannot reach x_k */
    bsdf_lobe_probabilities(&v->b, v->wo_local, p);
    return p[lobe] > 0 ? SHIFT_OK : SHIFT_FAIL_LOBE_UNAVAILABLE;
}

/* The one-lobe bounce at v towards w: f_l|cos| / (P(l|wo) pdf_l(w)), with the pdf. */
static enum shift_failure lobe_bounce(const path_vertex *v, unsigned lobe, vec3 w, rgb *weight, real *pdf)
{
    rgb f;
    enum shift_failure why = lobe_usable(v, lobe);
    if (why != SHIFT_OK) return why;
    if (!path_vertex_eval_lobe(v, (int)lobe, w, &f, pdf)) return SHIFT_FAIL_BSDF_ZERO;
    *weight = rgb_scale(f, 1 / *pdf);
    return SHIFT_OK;
}

/* The light pdf of the last vertex after the shift moved x_{d-1} to y_{d-1}: it depends
 * on y_{d-1}, so it is recomputed (pitfall 6, docs/restir-pt.md §11). The light-pdf ablation keeps the base
 * path's stale value instead, everywhere the offset path needs it (the NEE estimate's
 * 1/p_light and the NEE/BSDF MIS weight). The Jacobian keeps the true pdf: the ablation
 * models a stale cache, not a wrong reconnection. */
static real last_light_pdf(const restir_context *c, const path_sample *x, real recomputed)
{
    return c->ablation == RESTIR_ABLATE_LIGHT_PDF ? x->light_pdf : recomputed;
}

/* The NEE pdf of the light point y (triangle tri, normal ny) seen from x_{d-1} = from: the
 * light sampler's p_light, or with light RIS p̃(y; Z) from the sample's own candidates at
 * vertex d-1. Under RIS that is M p_0(y) P_s, the PSS density of selecting y given the
 * candidates (the selection number's interval has length P_s), so in the Jacobian its
 * ratio is P'_s/P_s: the analogue of Enhanced Eq. 2's light-density ratio (docs/enhanced.md §6). */
static real nee_pdf(const path_context *pc, const path_vertex *from, const path_sample *x, uint32_t tri, vec3 y,
                    vec3 ny)
{
    if (pc->light_ris > 0) return light_ris_pdf_nee(pc, from, path_sample_key(x), (uint32_t)(x->length - 1), tri, y, ny);
    return path_light_pdf(pc, tri, from->position, y, ny);
}

/* x_k = x_d is an NEE light vertex sampled from y_{k-1} = y_{d-1}: the NEE estimate
 * f_all|cos| Le / p_light times w_nee (GRIS Eq. 49) with the light pdf from y_{d-1}. */
static enum shift_failure reconnect_nee_light(const restir_context *c, const path_vertex *prev,
                                              const path_vertex *xk, const path_sample *x, rc_terms *t)
{
    const path_context *pc = &c->path;
    rgb f_cos, le;
    real p_bsdf;
    if (!prev->can_nee) return SHIFT_FAIL_BSDF_ZERO;
    f_cos = path_vertex_eval(prev, t->direction);
    le = path_vertex_emitted(pc, xk);
    t->pdf_prev = nee_pdf(pc, prev, x, x->rc_triangle, xk->position, xk->ng);
    t->light_pdf = last_light_pdf(c, x, t->pdf_prev);
    t->radiance = le;
    if (rgb_is_black(f_cos)) return SHIFT_FAIL_BSDF_ZERO;
    if (rgb_is_black(le) || !(t->light_pdf > 0) || !(t->pdf_prev > 0)) return SHIFT_FAIL_ZERO;
    p_bsdf = path_vertex_pdf(prev, t->direction);
    t->factor = rgb_scale(rgb_scale(rgb_mul(f_cos, le), 1 / t->light_pdf), path_mis_weight_nee(pc, t->light_pdf, p_bsdf));
    return SHIFT_OK;
}

/* x_k = x_d is an emitter hit by the bounce at y_{k-1}: Le times w_bsdf, whose light pdf
 * is recomputed from y_{d-1}. */
static rgb emitter_from_prev(const restir_context *c, const path_vertex *prev, const path_vertex *xk,
                             const path_sample *x, real pdf_lobe, rc_terms *t)
{
    const path_context *pc = &c->path;
    bsdf_bounce b;
    rgb le = path_vertex_emitted(pc, xk);
    memset(&b, 0, sizeof b);
    b.pdf_lobe = pdf_lobe;
    b.pdf_all = path_vertex_pdf(prev, t->direction);
    t->light_pdf = last_light_pdf(c, x, path_light_pdf_hit(pc, prev, xk, path_sample_key(x), (uint32_t)(x->length - 1)));
    t->radiance = le;
    return rgb_scale(le, path_mis_weight_bsdf_hit(pc, &b, t->light_pdf));
}

/* Light RIS at x_k = x_{d-1} seen from the new incoming direction (its target p̂ holds the
 * BSDF, so the candidates' weights move with w'_{k-1}). NEE: the selected candidate is the
 * one along w_k; its p̃ is the new NEE pdf and, as M p_0 P_s, the Jacobian's p_k (the
 * selection number's interval maps linearly: P'_s/P_s). BSDF: the emitter hit along w_k,
 * found again by the path sampler's ray, and its p̃ from the sample's fresh candidates. */
static enum shift_failure ris_at_last_vertex(const restir_context *c, const path_vertex *xk, const path_sample *x,
                                             real *light_pdf)
{
    const path_context *pc = &c->path;
    rng_key key = path_sample_key(x);
    uint32_t k = x->rc_k;
    if (x->lobe[k] == PATH_LOBE_NEE) {
        light_sample z;
        if (!light_ris_candidate_towards(pc, xk, key, k, x->rc_wo, &z)) return SHIFT_FAIL_NEE;
        *light_pdf = light_ris_pdf_nee(pc, xk, key, k, z.triangle, v3_from_f(z.position), v3_from_f(z.normal));
    } else {
        ray r = scene_spawn_ray(xk->hit.position, xk->hit.ng, v3f_from(x->rc_wo), v3f_from(xk->wo));
        surface_hit h;
        path_vertex hit;
        if (scene_intersect(pc->scene, &r, &h)) path_vertex_make(&hit, pc->scene, &h, v3_from_f(r.dir));
        else if (light_set_has_sky(pc->lights)) path_vertex_make_distant(&hit, x->rc_wo); /* x_d at infinity */
        else return SHIFT_FAIL_REPLAY_MISS;
        *light_pdf = path_light_pdf_hit(pc, xk, &hit, key, k);
    }
    return *light_pdf > 0 || x->lobe[k] != PATH_LOBE_NEE ? SHIFT_OK : SHIFT_FAIL_ZERO;
}

/* The part of the path from x_k on, seen from the new incoming direction -w'_{k-1}:
 * the BSDF at x_k is re-evaluated (pitfall 5, docs/restir-pt.md §11), and when x_k = x_{d-1} so is the
 * final MIS weight (x_{d-1} stays, so its light pdf is still the stored one, except under
 * light RIS: ris_at_last_vertex). */
static enum shift_failure suffix_at_xk(const restir_context *c, const path_vertex *xk, const path_sample *x,
                                       rc_terms *t, rgb *suffix)
{
    const path_context *pc = &c->path;
    int k = x->rc_k, d = x->length;
    unsigned lobe = x->lobe[k];
    t->light_pdf = x->light_pdf;
    t->radiance = x->rc_radiance;
    if (k == d - 1 && c->path.light_ris > 0) {
        enum shift_failure why = ris_at_last_vertex(c, xk, x, &t->light_pdf);
        if (why != SHIFT_OK) return why;
    }
    if (lobe == PATH_LOBE_NEE) { /* k = d-1: NEE from x_k to the stored light point */
        rgb f_cos;
        real p_bsdf;
        t->pdf_k = c->path.light_ris > 0 ? t->light_pdf : 1;
        if (!(t->light_pdf > 0)) return SHIFT_FAIL_ZERO;
        if (!xk->can_nee) return SHIFT_FAIL_BSDF_ZERO;
        f_cos = path_vertex_eval(xk, x->rc_wo);
        if (rgb_is_black(f_cos)) return SHIFT_FAIL_BSDF_ZERO;
        p_bsdf = path_vertex_pdf(xk, x->rc_wo);
        *suffix = rgb_scale(rgb_scale(rgb_mul(f_cos, x->rc_radiance), 1 / t->light_pdf),
                            path_mis_weight_nee(pc, t->light_pdf, p_bsdf));
    } else {
        rgb w;
        enum shift_failure why = lobe_bounce(xk, lobe, x->rc_wo, &w, &t->pdf_k);
        if (why != SHIFT_OK) return why;
        if (k == d - 1) { /* x_{k+1} = x_d is the emitter hit along w_k */
            bsdf_bounce b;
            memset(&b, 0, sizeof b);
            b.pdf_lobe = t->pdf_k;
            b.pdf_all = path_vertex_pdf(xk, x->rc_wo);
            *suffix = rgb_mul(w, rgb_scale(x->rc_radiance, path_mis_weight_bsdf_hit(pc, &b, t->light_pdf)));
        } else {
            *suffix = rgb_mul(w, x->rc_radiance);
        }
    }
    return SHIFT_OK;
}

/* Where the segment y_{k-1} -> x_k starts, exactly as the path sampler starts it:
 * a BSDF-sampled ray leaves from the robustly offset origin (scene_spawn_ray), so the
 * base path's x_k lies on the ray from that origin along the sampled direction, and the
 * direction (and distance) of a reconnection is measured from there too; with the
 * vertex itself the base direction would be off by |offset| / distance (~1e-4 rad in
 * the Cornell box), enough to change a glossy F by a percent. NEE measures from the
 * vertex itself (vertex_sample_light). */
static vec3 segment_origin(const path_vertex *prev, vec3f xk, unsigned lobe_prev)
{
    if (lobe_prev == PATH_LOBE_NEE) return prev->position;
    return v3_from_f(
        scene_spawn_ray(prev->hit.position, prev->hit.ng, v3f_sub(xk, prev->hit.position), v3f_from(prev->wo)).origin);
}

/* Rebuilds x_k as the path sampler would see it arriving along w'_{k-1}. */
static int make_xk(const restir_context *c, const path_sample *x, vec3 direction, path_vertex *xk)
{
    surface_hit h;
    if (!scene_surface_point(c->path.scene, x->rc_triangle, x->rc_bary[0], x->rc_bary[1], &h)) return 0;
    /* Position and geometric normal exactly as the base path found them (an NEE light
     * point comes from the light sampler, not from a ray hit). */
    h.position = x->rc_position;
    h.ng = x->rc_normal;
    path_vertex_make(xk, c->path.scene, &h, direction);
    return 1;
}

/* The reconnection to x_k = x_d at infinity (docs/environment.md): the offset keeps the
 * direction w, so y_{d-1} -> x_d leaves along w; the area measure at x_k is replaced by
 * solid angle, in which the reconnected vertex is w itself: G = 1 on both sides, and
 * Enhanced Eq. 2 becomes p^y_{d-1}(w) / p^x_{d-1}(w) (J = 1 for an NEE light vertex: the
 * light pdf of a direction does not depend on the receiver). */
static enum shift_failure rc_evaluate_distant(const restir_context *c, const path_vertex *prev, const path_sample *x,
                                              rc_terms *t)
{
    unsigned lobe_prev = x->lobe[x->rc_k - 1];
    path_vertex xk;
    rgb w_prev;
    enum shift_failure why;
    path_vertex_make_distant_stored(&xk, x->rc_position);
    t->direction = xk.position;
    t->geom = 1; /* dw'/dw = 1: the reconnected "point" is the direction itself */
    if (lobe_prev == PATH_LOBE_NEE) {
        why = reconnect_nee_light(c, prev, &xk, x, t);
    } else {
        why = lobe_bounce(prev, lobe_prev, t->direction, &w_prev, &t->pdf_prev);
        if (why == SHIFT_OK) t->factor = rgb_mul(w_prev, emitter_from_prev(c, prev, &xk, x, t->pdf_prev, t));
    }
    if (why != SHIFT_OK) return why;
    if (rgb_is_black(t->factor)) return SHIFT_FAIL_ZERO;
    if (!rgb_finite(t->factor) || !isfinite(t->pdf_prev * t->geom * t->pdf_k)) return SHIFT_FAIL_NONFINITE;
    if (!sky_visible(c->path.scene, prev->hit.position, prev->hit.ng, t->direction)) return SHIFT_FAIL_OCCLUDED;
    return SHIFT_OK;
}

enum shift_failure rc_evaluate(const restir_context *c, const path_vertex *prev, const path_sample *x, rc_terms *t)
{
    int k = x->rc_k, d = x->length;
    unsigned lobe_prev;
    path_vertex xk;
    vec3 to;
    real dist2;
    rgb w_prev, suffix;
    enum shift_failure why;
    memset(t, 0, sizeof *t);
    t->pdf_k = 1;
    if (k < 2 || k > d) return SHIFT_FAIL_EMPTY;
    if (x->rc_flags & PATH_RC_FLAG_DISTANT) return rc_evaluate_distant(c, prev, x, t);
    lobe_prev = x->lobe[k - 1];
    to = v3_sub(v3_from_f(x->rc_position), segment_origin(prev, x->rc_position, lobe_prev));
    dist2 = v3_dot(to, to);
    if (!(dist2 > 0)) return SHIFT_FAIL_ZERO;
    t->direction = v3_scale(to, 1 / (real)sqrt(dist2));
    if (!make_xk(c, x, t->direction, &xk)) return SHIFT_FAIL_ZERO;
    /* GRIS Eq. 52 / Enhanced Eq. 2: G(y_{k-1} -> x_k) with the geometric normal at x_k. */
    t->geom = (real)fabs(v3_dot(xk.ng, t->direction)) / dist2;
    if (!(t->geom > 0)) return SHIFT_FAIL_ZERO;
    if (lobe_prev == PATH_LOBE_NEE) {
        why = reconnect_nee_light(c, prev, &xk, x, t);
    } else {
        why = lobe_bounce(prev, lobe_prev, t->direction, &w_prev, &t->pdf_prev);
        if (why == SHIFT_OK && k == d) {
            t->factor = rgb_mul(w_prev, emitter_from_prev(c, prev, &xk, x, t->pdf_prev, t));
            if (rgb_is_black(t->factor)) why = SHIFT_FAIL_ZERO;
        } else if (why == SHIFT_OK) {
            suffix = rgb_gray(0);
            why = suffix_at_xk(c, &xk, x, t, &suffix);
            t->factor = rgb_mul(w_prev, suffix);
        }
    }
    if (why != SHIFT_OK) return why;
    if (rgb_is_black(t->factor)) return SHIFT_FAIL_ZERO;
    if (!rgb_finite(t->factor) || !isfinite(t->pdf_prev * t->geom * t->pdf_k)) return SHIFT_FAIL_NONFINITE;
    /* Visibility of every reconnection segment, forward and inverse alike (docs/design.md, Conventions). */
    if (!scene_visible(c->path.scene, prev->hit.position, prev->hit.ng, x->rc_position, &x->rc_normal))
        return SHIFT_FAIL_OCCLUDED;
    return SHIFT_OK;
}

/* Enhanced Eq. 2 (= GRIS Eq. 52 converted by GRIS Eq. 54). */
real rc_jacobian(const rc_terms *t, const path_sample *x)
{
    real numerator = t->pdf_prev * t->geom * t->pdf_k;
    real denominator = x->rc_pdf_prev * x->rc_geom * x->rc_pdf;
    return denominator > 0 ? numerator / denominator : 0;
}

/* ---- recording ---------------------------------------------------------------------- */

/* Radiance leaving x_d towards x_{d-1} times the final vertex's MIS weight: the last
 * factor of the path contribution (GRIS Eq. 49). */
static rgb final_vertex_factor(const restir_context *c, const path_trunk *t, const path_sample *s,
                               const path_end *end)
{
    const path_context *pc = &c->path;
    int d = s->length;
    if (s->technique == PATH_TECH_NEE)
        return rgb_scale(end->nee.contribution, path_mis_weight_nee(pc, end->nee.pdf_light, end->nee.pdf_bsdf));
    return rgb_mul(t->b[d - 1].weight,
                   rgb_scale(path_vertex_emitted(pc, &t->v[d]), path_mis_weight_bsdf_hit(pc, &t->b[d - 1], end->light_pdf)));
}

/* L_k for k <= d-2 (path_sample.h): the bounce weights at x_{k+1}..x_{d-2}, then the
 * last bounce or NEE estimate at x_{d-1} with Le and the final MIS weight; none of them
 * depends on x_{k-1}. For k >= d-1: Le(x_d -> x_{d-1}) alone. */
static rgb suffix_radiance(const restir_context *c, const path_trunk *t, const path_sample *s,
                           const path_end *end, int k)
{
    int d = s->length, j;
    rgb L;
    if (k >= d - 1)
        return s->technique == PATH_TECH_NEE ? end->nee.emitted : path_vertex_emitted(&c->path, &t->v[d]);
    L = final_vertex_factor(c, t, s, end);
    for (j = d - 2; j > k; --j) L = rgb_mul(t->b[j].weight, L);
    return L;
}

/* Copies x_k (a trunk vertex, or the NEE light point) and w_k into s. */
static void store_xk(const path_trunk *t, const path_end *end, int k, path_sample *s)
{
    int d = s->length;
    if (k == d && s->technique == PATH_TECH_NEE) {
        const light_sample *y = &end->nee.y;
        s->rc_triangle = y->triangle;
        /* light_sample barycentrics are (b0, b1); path_sample stores (b1, b2). */
        s->rc_bary[0] = (float)y->barycentric.y;
        s->rc_bary[1] = (float)(1 - y->barycentric.x - y->barycentric.y);
        s->rc_position = y->position;
        s->rc_normal = y->normal;
        s->rc_wo = v3(0, 0, 0);
        if (y->triangle == LIGHT_TRIANGLE_DISTANT) { /* the vertex at infinity: its direction */
            s->rc_bary[0] = s->rc_bary[1] = 0;
            s->rc_flags |= PATH_RC_FLAG_DISTANT;
        }
        return;
    }
    s->rc_triangle = t->v[k].hit.triangle;
    s->rc_bary[0] = t->v[k].hit.b1;
    s->rc_bary[1] = t->v[k].hit.b2;
    s->rc_position = t->v[k].hit.position;
    s->rc_normal = t->v[k].hit.ng;
    if (k == d && path_vertex_is_distant(&t->v[k])) s->rc_flags |= PATH_RC_FLAG_DISTANT;
    if (k == d) s->rc_wo = v3(0, 0, 0);
    else if (k == d - 1 && s->technique == PATH_TECH_NEE) s->rc_wo = end->nee.wi;
    else s->rc_wo = t->b[k].wi;
}

enum shift_failure path_record(const restir_context *c, const path_vertex *x1, path_sample *s)
{
    path_trunk t;
    path_end end;
    rc_vertex v[PATH_MAX_LENGTH + 1];
    path_sample r = *s;
    rc_terms terms;
    int k, d = s->length;
    enum shift_failure why = path_replay(&t, c, x1, s, &end);
    if (why != SHIFT_OK) return why;
    trunk_lobes(&t, d, s->technique, r.lobe);
    trunk_rc_vertices(&t, c, r.lobe, d, &end, s->technique, v);
    r.rc_k = (uint8_t)rc_select(c, v, d);
    r.rc_flags = 0;
    r.light_pdf = end.light_pdf;
    path_sample_set_contribution(&r, end.F);
    k = r.rc_k;
    if (k != PATH_RC_NONE) {
        store_xk(&t, &end, k, &r);
        r.rc_radiance = suffix_radiance(c, &t, &r, &end, k);
        /* The source terms of Enhanced Eq. 2, by the very code every shift runs. */
        if (rc_evaluate(c, &t.v[k - 1], &r, &terms) != SHIFT_OK) r.rc_flags |= PATH_RC_FLAG_UNSHIFTABLE;
        r.rc_pdf_prev = terms.pdf_prev;
        r.rc_geom = terms.geom;
        r.rc_pdf = terms.pdf_k;
    } else {
        r.rc_triangle = 0;
        r.rc_bary[0] = r.rc_bary[1] = 0;
        r.rc_position = r.rc_normal = v3f(0, 0, 0);
        r.rc_wo = v3(0, 0, 0);
        r.rc_pdf_prev = r.rc_geom = r.rc_pdf = 0;
        r.rc_radiance = rgb_gray(0);
    }
    *s = r;
    return SHIFT_OK;
}

int rc_segment_visible(const restir_context *c, const path_vertex *y1, const path_sample *y)
{
    path_trunk t;
    int k = y->rc_k;
    if (k == PATH_RC_NONE) return 1;
    if (trunk_replay(&t, c, y1, y, k - 1) != SHIFT_OK) return 0;
    if (y->rc_flags & PATH_RC_FLAG_DISTANT)
        return sky_visible(c->path.scene, t.v[k - 1].hit.position, t.v[k - 1].hit.ng, light_distant_direction(y->rc_position));
    return scene_visible(c->path.scene, t.v[k - 1].hit.position, t.v[k - 1].hit.ng, y->rc_position, &y->rc_normal);
}

/* ---- the reconnection data in another frame (temporal reuse in animated scenes) ---------- */

/* x_k, w_k and the suffix of x re-expressed in the scene of c: x_k where its triangle is
 * posed in that scene (rot: the rotation that object underwent, NULL if it did not move;
 * then the stored point is kept bit for bit), w_k turned with it, and the suffix
 * x_{k+1}..x_d traced again from x_k along w_k in that scene with the sample's own
 * numbers (vertices k+1..d-1, the numbers that produced the suffix): L_k, the light pdf
 * and the suffix lobes are recomputed. In primary sample space this is the identity on
 * the suffix numbers and a rigid (measure-preserving) motion of x_k and w_k, so the shift
 * that follows keeps its Jacobian (Enhanced Eq. 2) and the source terms stay the base's. */
enum shift_failure rc_retrace_suffix(const restir_context *c, const path_sample *x, const double (*rot)[3],
                                     path_sample *out)
{
    const path_context *pc = &c->path;
    const scene *s = pc->scene;
    int k = x->rc_k, d = x->length;
    surface_hit h;
    vec3 pos;
    *out = *x;
    if (!path_sample_is_valid(x) || k == PATH_RC_NONE || k >= d) return SHIFT_OK; /* k = d: a static light */
    if (!scene_surface_point(s, x->rc_triangle, x->rc_bary[0], x->rc_bary[1], &h)) return SHIFT_FAIL_ZERO;
    if (rot) {
        vec3 w = x->rc_wo;
        out->rc_position = h.position;
        out->rc_normal = h.ng;
        out->rc_wo = v3((real)(rot[0][0] * w.x + rot[0][1] * w.y + rot[0][2] * w.z),
                        (real)(rot[1][0] * w.x + rot[1][1] * w.y + rot[1][2] * w.z),
                        (real)(rot[2][0] * w.x + rot[2][1] * w.y + rot[2][2] * w.z));
    }
    pos = v3_from_f(out->rc_position);
    if (x->lobe[k] == PATH_LOBE_NEE) { /* k = d-1: the light point of the sample's NEE numbers */
        light_sample ls;
        real u[4];
        vec3 y, dv;
        real dist;
        /* the sample's own numbers: a mutated sample keeps its light point numbers in pss[]
         * (path_sample.h), not in its replay identity (issue 26) */
        path_nee_numbers(x, u);
        if (!light_sample_point(pc->lights, u, &ls)) return SHIFT_FAIL_NEE;
        if (ls.triangle == LIGHT_TRIANGLE_DISTANT) { /* x_d at infinity: only visibility can change */
            out->rc_wo = light_distant_direction(ls.position);
            out->rc_radiance = ls.emission;
            out->light_pdf = path_light_pdf(pc, ls.triangle, pos, v3_from_f(ls.position), v3_from_f(ls.normal));
            if (rgb_is_black(out->rc_radiance) || !(out->light_pdf > 0)) return SHIFT_FAIL_NEE;
            return sky_visible(s, out->rc_position, out->rc_normal, out->rc_wo) ? SHIFT_OK : SHIFT_FAIL_NEE;
        }
        y = v3_from_f(ls.position);
        dv = v3_sub(y, pos);
        dist = v3_length(dv);
        if (!(dist > 0)) return SHIFT_FAIL_NEE;
        out->rc_wo = v3_scale(dv, 1 / dist);
        out->rc_radiance = light_emitted(ls.emission, v3_from_f(ls.normal), v3_neg(out->rc_wo));
        out->light_pdf = path_light_pdf(pc, ls.triangle, pos, y, v3_from_f(ls.normal));
        if (rgb_is_black(out->rc_radiance) || !(out->light_pdf > 0)) return SHIFT_FAIL_NEE;
        if (!scene_visible(s, out->rc_position, out->rc_normal, ls.position, &ls.normal)) return SHIFT_FAIL_NEE;
        return SHIFT_OK;
    }
    {
        ray r = scene_spawn_ray(out->rc_position, out->rc_normal, v3f_from(out->rc_wo), v3f(0, 0, 0));
        surface_hit hit;
        path_trunk t;
        path_end end;
        enum shift_failure why;
        int j;
        memset(&t, 0, sizeof t);
        t.n = k + 1;
        if (scene_intersect(s, &r, &hit)) path_vertex_make(&t.v[k + 1], s, &hit, v3_from_f(r.dir));
        else if (k == d - 1 && light_set_has_sky(pc->lights)) path_vertex_make_distant(&t.v[d], out->rc_wo);
        else return SHIFT_FAIL_REPLAY_MISS;
        if (k == d - 1) { /* x_{k+1} = x_d: the emitter hit along w_k */
            out->rc_radiance = path_vertex_emitted(pc, &t.v[d]);
            if (rgb_is_black(out->rc_radiance)) return SHIFT_FAIL_REPLAY_NO_LIGHT;
            out->light_pdf = path_light_pdf(pc, t.v[d].hit.triangle, pos, t.v[d].position, t.v[d].ng);
            return SHIFT_OK;
        }
        t.beta[k + 1] = rgb_gray(1);
        while (t.n < d - 1) {
            real u[3];
            path_bsdf_numbers(x, t.n, u);
            if ((why = trunk_sample(&t, u)) != SHIFT_OK) return why;
            if ((why = trunk_trace(&t, s)) != SHIFT_OK) return why;
        }
        if ((why = trunk_finish(&t, c, x, &end)) != SHIFT_OK) return why;
        out->rc_radiance = suffix_radiance(c, &t, x, &end, k);
        out->light_pdf = end.light_pdf;
        for (j = k + 1; j < d; ++j) out->lobe[j] = (uint8_t)t.b[j].lobe;
        if (x->technique == PATH_TECH_NEE) out->lobe[d - 1] = PATH_LOBE_NEE;
        return SHIFT_OK;
    }
}
