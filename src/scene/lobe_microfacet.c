/* GGX microfacet lobes: reflection (conductor, plastic coat, rough glass) and
 * transmission (rough glass), both sampled from the visible normals of wo
 * (Heitz 2018) and evaluated with the separable Smith G2 (Walter et al. 2007 Eq. 23).
 * wo.z > 0 always (lobes.h). */
#include "lobe_microfacet.h"
#include "restir/scene/microfacet.h"

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

/* Walter et al. 2007 Eq. 20 times |wi.z|: f cos = F(wo.m) D(m) G2 / (4 wo.z), and the
 * VNDF density times the reflection Jacobian 1/(4 wo.m) (Eq. 14). Both need m, D(m) and
 * G1(wo, m): one pass fills whichever of f_cos and pdf is not NULL. */
static void glossy_reflection_eval_pdf(const lobe_view *v, vec3 wi, rgb *f_cos, real *pdf)
{
    vec3 m;
    real a = v->b->alpha, d, g1_wo, wo_m;
    if (f_cos) *f_cos = rgb_gray(0);
    if (pdf) *pdf = 0;
    if (!reflection_half_vector(v->wo, wi, &m)) return;
    d = ggx_D(m, a);
    g1_wo = ggx_G1(v->wo, m, a);
    wo_m = v3_dot(v->wo, m);
    /* D G2 with G2 = G1(wo) G1(wi): ggx_G2_separable's product, in its order */
    if (f_cos) *f_cos = rgb_scale(lobe_specular_fresnel(v, wo_m), d * (g1_wo * ggx_G1(wi, m, a)) / (4 * v->wo.z));
    if (pdf && wo_m > 0) *pdf = ggx_vndf_pdf_terms(v->wo, wo_m, g1_wo, d) / (4 * wo_m);
}

static rgb glossy_reflection_eval(const lobe_view *v, vec3 wi)
{
    rgb f;
    glossy_reflection_eval_pdf(v, wi, &f, NULL);
    return f;
}

static real glossy_reflection_pdf(const lobe_view *v, vec3 wi)
{
    real p;
    glossy_reflection_eval_pdf(v, wi, NULL, &p);
    return p;
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
 * f cos = Ks (1 - F(wo.m)) D G2 |wi.m| (wo.m) / (wo.z (wo.m + eta wi.m)^2), and the VNDF
 * density times the refraction Jacobian eta^2 |wi.m| / (wo.m + eta wi.m)^2 (Eq. 17).
 * One pass fills whichever of f_cos and pdf is not NULL (shared: m, D, G1(wo, m)). */
static void glossy_transmission_eval_pdf(const lobe_view *v, vec3 wi, rgb *f_cos, real *pdf)
{
    vec3 m;
    real a = v->b->alpha, wo_m, wi_m, denom, d, g1_wo, t;
    if (f_cos) *f_cos = rgb_gray(0);
    if (pdf) *pdf = 0;
    if (!transmission_half_vector(v, wi, &m)) return;
    wo_m = v3_dot(v->wo, m);
    wi_m = v3_dot(wi, m);
    denom = wo_m + v->eta * wi_m;
    d = ggx_D(m, a);
    g1_wo = ggx_G1(v->wo, m, a);
    if (f_cos) {
        t = (1 - fresnel_dielectric(wo_m, v->eta)) * d * (g1_wo * ggx_G1(wi, m, a)); /* D G2, G2 = G1 G1 */
        *f_cos = rgb_scale(v->b->specular, t * (-wi_m) * wo_m / (v->wo.z * denom * denom));
    }
    if (pdf) *pdf = ggx_vndf_pdf_terms(v->wo, wo_m, g1_wo, d) * v->eta * v->eta * (-wi_m) / (denom * denom);
}

static rgb glossy_transmission_eval(const lobe_view *v, vec3 wi)
{
    rgb f;
    glossy_transmission_eval_pdf(v, wi, &f, NULL);
    return f;
}

static real glossy_transmission_pdf(const lobe_view *v, vec3 wi)
{
    real p;
    glossy_transmission_eval_pdf(v, wi, NULL, &p);
    return p;
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
                                             glossy_reflection_sample, glossy_reflection_inverse, NULL,
                                             glossy_reflection_eval_pdf};
const lobe_ops lobe_glossy_transmission_ops = {glossy_transmission_eval, glossy_transmission_pdf,
                                               glossy_transmission_sample, glossy_transmission_inverse, NULL,
                                               glossy_transmission_eval_pdf};
