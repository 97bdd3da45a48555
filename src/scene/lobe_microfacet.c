/* GGX microfacet lobes: reflection (conductor, plastic coat, rough glass) and
 * transmission (rough glass), both sampled from the visible normals of wo
 * (Heitz 2018) and evaluated with the separable Smith G2 (Walter et al. 2007 Eq. 23).
 * wo.z > 0 always (lobes.h). */
#include "lobes.h"
#include "restir/microfacet.h"

rgb lobe_specular_fresnel(const lobe_view *v, real cos_wo_m)
{
    if (v->b->type == MAT_CONDUCTOR) return fresnel_schlick_rgb(cos_wo_m, v->b->specular);
    return rgb_scale(v->b->specular, fresnel_dielectric(cos_wo_m, v->eta));
}

/* ---- reflection ---- */

/* Walter et al. 2007 Eq. 13: the reflection half vector m = (wo + wi)/|wo + wi|. */
static int reflection_half_vector(vec3 wo, vec3 wi, vec3 *m)
{
    vec3 h = v3_add(wo, wi);
    real len = v3_length(h);
    if (wi.z <= 0 || !(len > 0)) return 0;
    *m = v3_scale(h, 1 / len);
    return 1;
}

/* Walter et al. 2007 Eq. 20 times |wi.z|: f cos = F(wo.m) D(m) G2 / (4 wo.z). */
static rgb glossy_reflection_eval(const lobe_view *v, vec3 wi)
{
    vec3 m;
    real a = v->b->alpha, dg;
    if (!reflection_half_vector(v->wo, wi, &m)) return rgb_gray(0);
    dg = ggx_D(m, a) * ggx_G2_separable(v->wo, wi, m, a) / (4 * v->wo.z);
    return rgb_scale(lobe_specular_fresnel(v, v3_dot(v->wo, m)), dg);
}

/* VNDF density times the reflection Jacobian 1/(4 wo.m) (Walter et al. 2007 Eq. 14). */
static real glossy_reflection_pdf(const lobe_view *v, vec3 wi)
{
    vec3 m;
    real wo_m;
    if (!reflection_half_vector(v->wo, wi, &m)) return 0;
    wo_m = v3_dot(v->wo, m);
    return wo_m > 0 ? ggx_vndf_pdf(v->wo, m, v->b->alpha) / (4 * wo_m) : 0;
}

static int glossy_reflection_sample(const lobe_view *v, vec2 u, vec3 *wi)
{
    vec3 m = ggx_vndf_sample(v->wo, u, v->b->alpha);
    if (v3_dot(v->wo, m) <= 0) return 0;
    *wi = reflect_about(v->wo, m);
    return wi->z > 0;
}

static int glossy_reflection_inverse(const lobe_view *v, vec3 wi, vec2 *u)
{
    vec3 m;
    if (!reflection_half_vector(v->wo, wi, &m)) return 0;
    return ggx_vndf_sample_inverse(v->wo, m, v->b->alpha, u);
}

/* ---- transmission ---- */

/* Walter et al. 2007 Eq. 16: the refraction half vector m ~ -(n_o wo + n_i wi),
 * here with n_o = 1, n_i = eta, oriented to wo's side (m.z > 0). Valid only if wi
 * is below, wo above, and the two lie on opposite sides of the microfacet: then
 * wi is exactly the refraction of wo about m. */
static int transmission_half_vector(const lobe_view *v, vec3 wi, vec3 *m)
{
    vec3 h = v3_add(v->wo, v3_scale(wi, v->eta));
    real len = v3_length(h);
    if (wi.z >= 0 || !(len > 0)) return 0;
    *m = v3_scale(h, (h.z < 0 ? -1 : 1) / len);
    return v3_dot(v->wo, *m) > 0 && v3_dot(wi, *m) < 0;
}

/* Walter et al. 2007 Eq. 21 (radiance; n_o = 1, n_i = eta) times |wi.z|:
 * f cos = Ks (1 - F(wo.m)) D G2 |wi.m| (wo.m) / (wo.z (wo.m + eta wi.m)^2). */
static rgb glossy_transmission_eval(const lobe_view *v, vec3 wi)
{
    vec3 m;
    real a = v->b->alpha, wo_m, wi_m, denom, t;
    if (!transmission_half_vector(v, wi, &m)) return rgb_gray(0);
    wo_m = v3_dot(v->wo, m);
    wi_m = v3_dot(wi, m);
    denom = wo_m + v->eta * wi_m;
    t = (1 - fresnel_dielectric(wo_m, v->eta)) * ggx_D(m, a) * ggx_G2_separable(v->wo, wi, m, a);
    return rgb_scale(v->b->specular, t * (-wi_m) * wo_m / (v->wo.z * denom * denom));
}

/* VNDF density times the refraction Jacobian eta^2 |wi.m| / (wo.m + eta wi.m)^2
 * (Walter et al. 2007 Eq. 17). */
static real glossy_transmission_pdf(const lobe_view *v, vec3 wi)
{
    vec3 m;
    real wi_m, denom;
    if (!transmission_half_vector(v, wi, &m)) return 0;
    wi_m = v3_dot(wi, m);
    denom = v3_dot(v->wo, m) + v->eta * wi_m;
    return ggx_vndf_pdf(v->wo, m, v->b->alpha) * v->eta * v->eta * (-wi_m) / (denom * denom);
}

static int glossy_transmission_sample(const lobe_view *v, vec2 u, vec3 *wi)
{
    vec3 m = ggx_vndf_sample(v->wo, u, v->b->alpha);
    if (v3_dot(v->wo, m) <= 0) return 0;
    if (!refract_about(v->wo, m, v->eta, wi)) return 0; /* total internal reflection */
    return wi->z < 0;
}

static int glossy_transmission_inverse(const lobe_view *v, vec3 wi, vec2 *u)
{
    vec3 m;
    if (!transmission_half_vector(v, wi, &m)) return 0;
    return ggx_vndf_sample_inverse(v->wo, m, v->b->alpha, u);
}

const lobe_ops lobe_glossy_reflection_ops = {glossy_reflection_eval, glossy_reflection_pdf,
                                             glossy_reflection_sample, glossy_reflection_inverse, NULL};
const lobe_ops lobe_glossy_transmission_ops = {glossy_transmission_eval, glossy_transmission_pdf,
                                               glossy_transmission_sample, glossy_transmission_inverse, NULL};
