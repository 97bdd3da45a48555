/* The diffuse lobe: Lambertian Kd/pi, cosine-sampled (Malley's method, warp.h).
 * Under the plastic coat it is weighted by the light transmitted through the
 * smooth coat twice, (1 - F(wo.z)) (1 - F(wi.z)) (docs/materials.md §Plastic),
 * which keeps it reciprocal and the plastic's albedo below 1. */
#include "lobe_diffuse.h"
#include "restir/scene/microfacet.h"

static real coat_transmission(const lobe_view *v, real cos_theta)
{
    if (v->b->type != MAT_PLASTIC) return 1;
    return 1 - fresnel_dielectric(cos_theta, v->eta);
}

static rgb diffuse_eval(const lobe_view *v, vec3 wi)
{
    real w;
    if (wi.z <= 0) return rgb_gray(0);
    w = INV_PI_R * wi.z * coat_transmission(v, v->wo.z) * coat_transmission(v, wi.z);
    return rgb_scale(v->b->diffuse, w);
}

static real diffuse_pdf(const lobe_view *v, vec3 wi)
{
    (void)v;
    return warp_cosine_hemisphere_pdf(wi.z);
}

static int diffuse_sample(const lobe_view *v, vec2 u, vec3 *wi)
{
    (void)v;
    *wi = warp_cosine_hemisphere(u);
    return wi->z > 0;
}

static int diffuse_inverse(const lobe_view *v, vec3 wi, vec2 *u)
{
    (void)v;
    if (wi.z <= 0) return 0;
    *u = warp_cosine_hemisphere_inverse(wi);
    return 1;
}

const lobe_ops lobe_diffuse_ops = {diffuse_eval, diffuse_pdf, diffuse_sample, diffuse_inverse, NULL, NULL};
