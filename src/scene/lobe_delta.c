/* Delta lobes of the smooth dielectric: mirror reflection and refraction about the
 * shading normal. The Dirac coefficients (f_cos) are Ks F and Ks (1 - F) / eta^2:
 * the 1/eta^2 = (n_wo / n_wi)^2 is the radiance scaling across the interface
 * (camera paths carry radiance; docs/materials.md §Conventions). eval and pdf of
 * a Dirac at an arbitrary direction are 0. */
#include "lobe_delta.h"
#include "restir/scene/microfacet.h"

static rgb delta_eval(const lobe_view *v, vec3 wi)
{
    (void)v;
    (void)wi;
    return rgb_gray(0);
}

static real delta_pdf(const lobe_view *v, vec3 wi)
{
    (void)v;
    (void)wi;
    return 0;
}

static int mirror_sample(const lobe_view *v, vec2 u, vec3 *wi)
{
    (void)u;
    *wi = v3(-v->wo.x, -v->wo.y, v->wo.z);
    return 1;
}

static rgb mirror_coefficient(const lobe_view *v)
{
    return rgb_scale(v->b->specular, fresnel_dielectric(v->wo.z, v->eta));
}

static int refraction_sample(const lobe_view *v, vec2 u, vec3 *wi)
{
    (void)u;
    return refract_about(v->wo, v3(0, 0, 1), v->eta, wi) && wi->z < 0;
}

static rgb refraction_coefficient(const lobe_view *v)
{
    real t = 1 - fresnel_dielectric(v->wo.z, v->eta);
    return rgb_scale(v->b->specular, t / (v->eta * v->eta));
}

const lobe_ops lobe_delta_reflection_ops = {delta_eval, delta_pdf, mirror_sample, NULL, mirror_coefficient, NULL};
const lobe_ops lobe_delta_transmission_ops = {delta_eval, delta_pdf, refraction_sample, NULL,
                                              refraction_coefficient, NULL};
