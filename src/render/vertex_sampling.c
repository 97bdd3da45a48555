/* One vertex of unidirectional path sampling: NEE, one-lobe BSDF sampling, and the
 * balance-heuristic MIS weights of GRIS Eq. 49 (include/restir/render/vertex_sampling.h). */
#include "restir/render/vertex_sampling.h"

#include "restir/render/light_ris.h"
#include "restir/scene/scene_trace.h"
#include "restir/scene/sky.h"
#include "restir/scene/surface_maps.h"

#include <math.h>
#include <string.h>

void path_vertex_make(path_vertex *v, const scene *s, const surface_hit *h, vec3 ray_dir)
{
    int l, n;
    v->hit = *h;
    v->position = v3_from_f(h->position);
    v->ng = v3_from_f(h->ng);
    v->ns = v3_from_f(h->ns);
    v->wo = v3_normalize(v3_neg(ray_dir)); /* float ray directions are unit only to ~1e-7 */
    v->frame = shading_frame_make(v->ns);
    v->wo_local = shading_frame_to_local(&v->frame, v->wo);
    v->b = scene_bsdf_at(s, h); /* textured: looked up at this hit's own triangle and barycentrics */
    /* P(l|wo), once: NEE, lobe selection, sampling and the all-lobe pdf all need it. */
    bsdf_lobe_probabilities(&v->b, v->wo_local, v->lobe_p);
    /* NEE can only reach the non-Dirac lobes; skip it where there are none. */
    n = bsdf_lobe_count(&v->b);
    v->can_nee = 0;
    for (l = 0; l < n; ++l)
        if (v->lobe_p[l] > 0 && !bsdf_lobe_is_delta(&v->b, l)) v->can_nee = 1;
}

void path_vertex_make_distant(path_vertex *v, vec3 w) { path_vertex_make_distant_stored(v, v3f_from(w)); }

void path_vertex_make_distant_stored(path_vertex *v, vec3f p)
{
    vec3 w = light_distant_direction(p);
    memset(v, 0, sizeof *v);
    v->hit.position = p;
    v->hit.ng = v->hit.ns = v3f_from(v3_neg(w));
    v->hit.t = INFINITY;
    v->hit.triangle = LIGHT_TRIANGLE_DISTANT;
    v->position = w;
    v->ng = v->ns = v->wo = v3_neg(w);
    v->can_nee = 0;
}

rgb path_vertex_emitted(const path_context *c, const path_vertex *v)
{
    uint32_t tri = v->hit.triangle;
    /* Only triangles in the light set emit, so that what BSDF sampling can hit is exactly
     * what NEE can sample (lights_build drops zero-area emitters). */
    if (tri >= c->lights->triangle_count || c->lights->light_of_triangle[tri] == LIGHT_NONE)
        return tri == LIGHT_TRIANGLE_DISTANT ? light_distant_radiance(c->lights, v->position) : rgb_gray(0);
    return light_emitted(light_emission_at(c->lights, c->lights->light_of_triangle[tri], v->hit.b1, v->hit.b2), v->ng,
                         v->wo);
}

/* Shading normals may disagree with the true surface about which side a direction is
 * on. Reflection must stay on wo's geometric side and transmission cross it; where the
 * shading frame says otherwise, f is taken as 0 (for NEE and BSDF sampling alike). */
static int sides_consistent(const path_vertex *v, vec3 wi, vec3 wi_local)
{
    real go = v3_dot(v->wo, v->ng), gi = v3_dot(wi, v->ng);
    if (go == 0 || gi == 0) return 0;
    return (go * gi > 0) == (v->wo_local.z * wi_local.z > 0);
}

rgb path_vertex_eval(const path_vertex *v, vec3 wi)
{
    vec3 wl = shading_frame_to_local(&v->frame, wi);
    if (!sides_consistent(v, wi, wl)) return rgb_gray(0);
    return bsdf_eval(&v->b, v->wo_local, wl);
}

real path_vertex_pdf(const path_vertex *v, vec3 wi)
{
    vec3 wl = shading_frame_to_local(&v->frame, wi);
    return bsdf_pdf_given(&v->b, v->wo_local, v->lobe_p, wl, -1, 0);
}

void path_vertex_eval_pdf(const path_vertex *v, vec3 wi, rgb *f_cos, real *pdf)
{
    vec3 wl = shading_frame_to_local(&v->frame, wi);
    bsdf_eval_pdf_given(&v->b, v->wo_local, v->lobe_p, wl, f_cos, pdf);
    if (!sides_consistent(v, wi, wl)) *f_cos = rgb_gray(0); /* the pdf ignores the side rule, as path_vertex_pdf */
}

int path_vertex_eval_lobe(const path_vertex *v, int lobe, vec3 wi, rgb *f_cos, real *pdf)
{
    const real *p = v->lobe_p;
    vec3 wl = shading_frame_to_local(&v->frame, wi);
    *f_cos = rgb_gray(0);
    *pdf = 0;
    if (lobe < 0 || lobe >= bsdf_lobe_count(&v->b) || bsdf_lobe_is_delta(&v->b, lobe)) return 0;
    if (!(p[lobe] > 0) || !sides_consistent(v, wi, wl)) return 0;
    /* The same f and pdf as a sample of this direction (bsdf.c finish_sample). */
    *f_cos = bsdf_lobe_eval(&v->b, lobe, v->wo_local, wl);
    *pdf = p[lobe] * bsdf_lobe_pdf(&v->b, lobe, v->wo_local, wl);
    return *pdf > 0 && !rgb_is_black(*f_cos);
}

/* The light-pdf ablation scales the estimator's light pdf by 1.05. */
static real ablated_light_pdf(const path_context *c, real p)
{
    return (c->ablations & PT_ABLATE_LIGHT_PDF) ? p * (real)1.05 : p;
}

real path_light_pdf(const path_context *c, uint32_t tri, vec3 x, vec3 y, vec3 ny)
{
    return ablated_light_pdf(c, light_pdf_solid_angle(c->lights, tri, x, y, ny));
}

/* path_light_pdf for NEE's own light sample (vertex_sample_light_numbers). */
static real nee_light_pdf(const path_context *c, real pdf_area, vec3 d, real dist2, vec3 ny)
{
    return ablated_light_pdf(c, pdf_area > 0 ? pdf_area_to_solid_angle_d(pdf_area, d, dist2, ny) : 0);
}

int vertex_sample_light(const path_context *c, const path_vertex *v, const rng_key *path, uint32_t vertex_index,
                        nee_sample *out)
{
    real u[4];
    if (c->light_ris > 0) return light_ris_sample(c, v, *path, vertex_index, out);
    rng_u_slots(*path, RNG_NEE, vertex_index, 0, 4, u);
    return vertex_sample_light_numbers(c, v, u, out);
}

#ifdef __GNUC__
#define SKY_COLD __attribute__((noinline, cold)) /* out of the hot NEE path of skyless scenes */
#else
#define SKY_COLD
#endif

/* NEE towards a point at infinity (docs/environment.md): the direction is the sample, its
 * pdf is already in solid angle, and the shadow ray has no end. */
static SKY_COLD int nee_distant(const path_context *c, const path_vertex *v, nee_sample *out)
{
    out->wi = light_distant_direction(out->y.position);
    out->emitted = out->y.emission;
    out->pdf_light = ablated_light_pdf(c, out->y.pdf_area);
    path_vertex_eval_pdf(v, out->wi, &out->f_cos, &out->pdf_bsdf);
    if (rgb_is_black(out->emitted) || rgb_is_black(out->f_cos) || !(out->pdf_light > 0)) return 0;
    out->shadow_ray = 1;
    if (!sky_visible(c->scene, v->hit.position, v->hit.ng, out->wi)) return 0;
    out->contribution = rgb_scale(rgb_mul(out->f_cos, out->emitted), 1 / out->pdf_light);
    return 1;
}

int vertex_sample_light_numbers(const path_context *c, const path_vertex *v, const real u[4], nee_sample *out)
{
    vec3 d;
    real dist2, dist;
    out->contribution = rgb_gray(0);
    out->shadow_ray = 0;
    if (!light_sample_point(c->lights, u, &out->y)) return 0;
    if (out->y.triangle == LIGHT_TRIANGLE_DISTANT) return nee_distant(c, v, out);
    d = v3_sub(v3_from_f(out->y.position), v->position);
    dist2 = v3_dot(d, d);
    dist = (real)sqrt(dist2); /* v3_length(d) */
    if (!(dist > 0)) return 0;
    out->wi = v3_scale(d, 1 / dist);
    out->emitted = light_emitted(out->y.emission, v3_from_f(out->y.normal), v3_neg(out->wi));
    /* path_light_pdf(c, triangle, x, y, ny) from what is at hand: the sample's own P(l)/area_l
     * (light_pdf_area of its triangle) and |y - x|^2; the same bits */
    out->pdf_light = nee_light_pdf(c, out->y.pdf_area, d, dist2, v3_from_f(out->y.normal));
    path_vertex_eval_pdf(v, out->wi, &out->f_cos, &out->pdf_bsdf);
    if (rgb_is_black(out->emitted) || rgb_is_black(out->f_cos) || !(out->pdf_light > 0)) return 0;
    out->shadow_ray = 1;
    if (!scene_visible(c->scene, v->hit.position, v->hit.ng, out->y.position, &out->y.normal)) return 0;
    /* Solid-angle form of the NEE estimator: f|cos| Le / p_light(ω). */
    out->contribution = rgb_scale(rgb_mul(out->f_cos, out->emitted), 1 / out->pdf_light);
    return 1;
}

real path_light_pdf_hit(const path_context *c, const path_vertex *from, const path_vertex *hit, rng_key path,
                        uint32_t vertex_index)
{
    uint32_t tri = hit->hit.triangle;
    if (c->light_ris > 0 && !(c->ablations & PT_ABLATE_LIGHT_RIS_PDF))
        return light_ris_pdf_hit(c, from, path, vertex_index, tri, hit->position, hit->ng);
    return path_light_pdf(c, tri, from->position, hit->position, hit->ng);
}

/* vertex_sample_bsdf_numbers up to the all-lobe pdf (pdf_all = -1); *s is the lobe's sample. */
static int sample_bsdf(const path_vertex *v, real u_lobe, vec2 u, bsdf_bounce *out, bsdf_sample_record *s)
{
    if (!bsdf_sample_given(&v->b, v->wo_local, v->lobe_p, u_lobe, u, s)) return 0;
    out->wi = shading_frame_to_world(&v->frame, s->wi);
    if (!sides_consistent(v, out->wi, s->wi)) return 0;
    out->lobe = s->lobe;
    out->is_delta = s->is_delta;
    out->weight = s->weight;
    out->pdf_lobe = s->lobe_prob * s->pdf;
    out->pdf_all = -1; /* not computed yet: path_bounce_pdf_all */
    return 1;
}

/* GRIS §7.6: the MIS weight of a BSDF-sampled path uses the pdf summed over all lobes
 * (the sampled lobe's pdf is s.pdf: not evaluated again). */
real path_bounce_pdf_all(const path_vertex *v, const bsdf_sample_record *s)
{
    return s->is_delta ? 0 : bsdf_pdf_given(&v->b, v->wo_local, v->lobe_p, s->wi, s->lobe, s->pdf);
}

int vertex_sample_bsdf(const path_vertex *v, const rng_key *path, uint32_t vertex_index, bsdf_bounce *out,
                       bsdf_sample_record *s)
{
    real u[3];
    rng_u_slots(*path, RNG_BSDF, vertex_index, 0, 3, u);
    return sample_bsdf(v, u[0], v2(u[1], u[2]), out, s);
}

int vertex_sample_bsdf_numbers(const path_vertex *v, real u_lobe, vec2 u, bsdf_bounce *out)
{
    bsdf_sample_record s;
    if (!sample_bsdf(v, u_lobe, u, out, &s)) return 0;
    out->pdf_all = path_bounce_pdf_all(v, &s);
    return 1;
}

/* GRIS Eq. 49: omega_n = p_n / (p_1 + p_2) (balance heuristic, Veach 1997 Eq. 9.4). */
real path_mis_balance(real p_this, real p_other)
{
    real sum = p_this + p_other;
    return sum > 0 ? p_this / sum : 0;
}

/* The power heuristic (Veach 1997 Eq. 9.5, beta = 2): used only by the mis-sum ablation. */
static real mis_power2(real p_this, real p_other)
{
    real a = p_this * p_this, b = p_other * p_other;
    return a + b > 0 ? a / (a + b) : 0;
}

real path_mis_weight_nee(const path_context *c, real p_light, real p_bsdf)
{
    switch (c->strategy) {
    case PT_STRATEGY_NEE: return 1;
    case PT_STRATEGY_BSDF: return 0;
    default: return path_mis_balance(p_light, p_bsdf);
    }
}

real path_mis_weight_bsdf_hit(const path_context *c, const bsdf_bounce *b, real p_light)
{
    real p_bsdf;
    /* NEE cannot produce a direction through a Dirac lobe: BSDF sampling is the only
     * technique for this path, in every strategy. */
    if (b->is_delta) return 1;
    switch (c->strategy) {
    case PT_STRATEGY_NEE: return 0;
    case PT_STRATEGY_BSDF: return 1;
    default: break;
    }
    p_bsdf = (c->ablations & PT_ABLATE_MIS_LOBE) ? b->pdf_lobe : b->pdf_all;
    if (c->ablations & PT_ABLATE_MIS_SUM) return mis_power2(p_bsdf, p_light);
    return path_mis_balance(p_bsdf, p_light);
}
