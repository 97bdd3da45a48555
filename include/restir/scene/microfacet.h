/* GGX microfacet building blocks and Fresnel terms (isotropic, local frame z = n).
 *
 * D      Walter et al. 2007 Eq. 33 (GGX normal distribution)
 * Lambda Heitz 2014 "Understanding the masking-shadowing function", Eq. 72
 * G1     Smith masking 1/(1+Lambda) with the one-sided test chi+(w.m / w.n)
 *        (Walter et al. 2007 Eq. 34 written with Lambda)
 * G2     separable: G1(wo,m) G1(wi,m) (Walter et al. 2007 Eq. 23)
 * VNDF   D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z (Heitz 2018, "Sampling the GGX
 *        Distribution of Visible Normals", JCGT 7(4)), sampled by its hemisphere-
 *        configuration construction and inverted here (docs/materials.md §3).
 * All microfacet functions expect wo.z > 0 (callers flip to wo's side first). */
#ifndef RESTIR_MICROFACET_H
#define RESTIR_MICROFACET_H

#include "restir/core/vec.h"
#include "restir/core/warp.h"

/* Smallest GGX alpha: alpha = max(r^2, GGX_ALPHA_MIN). 1e-6 (r = 1e-3) keeps D below
 * ~3e11 and away from float underflow; roughness 0 is thus an extremely sharp
 * GGX lobe, not a delta (use MAT_DIELECTRIC for a delta interface). */
#define GGX_ALPHA_MIN ((real)1e-6)

real ggx_alpha_from_roughness(real linear_roughness);

real ggx_D(vec3 m, real alpha);
real ggx_lambda(vec3 w, real alpha);
real ggx_G1(vec3 w, vec3 m, real alpha);
real ggx_G2_separable(vec3 wo, vec3 wi, vec3 m, real alpha);

/* Visible normal distribution D_wo(m) (density of m w.r.t. solid angle); wo.z > 0. */
real ggx_vndf_pdf(vec3 wo, vec3 m, real alpha);
/* The same from its factors wo.m, G1(wo, m) and D(m), for a caller that already has them. */
real ggx_vndf_pdf_terms(vec3 wo, real wo_m, real g1_wo, real d);
/* Heitz 2018: m ~ D_wo from u in [0,1)^2 (polar disk mapping as in the paper). */
vec3 ggx_vndf_sample(vec3 wo, vec2 u, real alpha);
/* Inverse: the u that ggx_vndf_sample maps to m. Returns 0 if m is not visible
 * from wo (wo.m <= 0 after the stretch) or m.z <= 0. */
int ggx_vndf_sample_inverse(vec3 wo, vec3 m, real alpha, vec2 *u);

/* Schlick's approximation F0 + (1-F0)(1-cos)^5 (Schlick 1994). */
real fresnel_schlick(real cos_theta, real f0);
rgb fresnel_schlick_rgb(real cos_theta, rgb f0);
/* Exact unpolarised Fresnel reflectance of a dielectric interface. cos_i = cosine
 * of the incident direction with the interface normal on ITS side (>= 0); eta =
 * n_transmitted / n_incident. Returns 1 on total internal reflection.
 * (Born & Wolf; written as in Walter et al. 2007 Eq. 22.) */
real fresnel_dielectric(real cos_i, real eta);

/* Mirror of w about m: 2 (w.m) m - w. */
vec3 reflect_about(vec3 w, vec3 m);
/* Refraction of w (pointing away from the surface, on the side m points to iff
 * w.m > 0) through an interface with normal m; eta = n_other_side / n_w_side.
 * Returns 0 on total internal reflection. */
int refract_about(vec3 w, vec3 m, real eta, vec3 *wt);

#endif
