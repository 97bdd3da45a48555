/* GGX microfacet distribution, Smith masking, visible-normal sampling and its
 * inverse, Fresnel terms (see include/restir/scene/microfacet.h and docs/materials.md). */
#include "restir/scene/microfacet.h"

real ggx_alpha_from_roughness(real linear_roughness)
{
    real r = linear_roughness > 0 ? (linear_roughness < 1 ? linear_roughness : 1) : 0;
    real alpha = r * r;
    return alpha > GGX_ALPHA_MIN ? alpha : GGX_ALPHA_MIN;
}

/* Walter et al. 2007 Eq. 33: D(m) = alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2), written as
 * 1 / (pi alpha^2 (sin^2/alpha^2 + cos^2)^2): no cancellation near m = n when alpha is tiny. */
real ggx_D(vec3 m, real alpha)
{
    real sin2 = m.x * m.x + m.y * m.y, a2 = alpha * alpha, k;
    if (m.z <= 0) return 0;
    k = sin2 / a2 + m.z * m.z;
    return 1 / (PI_R * a2 * k * k);
}

/* Heitz 2014 Eq. 72: Lambda = (-1 + sqrt(1 + alpha^2 tan^2)) / 2, in the form
 * a / (2 (sqrt(1 + a) + 1)) with a = alpha^2 tan^2, stable for small a. */
real ggx_lambda(vec3 w, real alpha)
{
    real z2 = w.z * w.z, a;
    if (z2 <= 0) return REAL_MAX;
    a = alpha * alpha * (w.x * w.x + w.y * w.y) / z2;
    return a / (2 * ((real)sqrt(1 + a) + 1));
}

/* Smith G1 with the one-sided test chi+(w.m / w.n) (Walter et al. 2007 Eq. 34, via Lambda). */
real ggx_G1(vec3 w, vec3 m, real alpha)
{
    real lambda;
    if (v3_dot(w, m) * w.z <= 0) return 0;
    lambda = ggx_lambda(w, alpha);
    return lambda >= REAL_MAX ? 0 : 1 / (1 + lambda);
}

/* Walter et al. 2007 Eq. 23: G(i, o, m) = G1(i, m) G1(o, m). */
real ggx_G2_separable(vec3 wo, vec3 wi, vec3 m, real alpha)
{
    return ggx_G1(wo, m, alpha) * ggx_G1(wi, m, alpha);
}

/* Heitz 2018 (VNDF definition): D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z. */
real ggx_vndf_pdf(vec3 wo, vec3 m, real alpha)
{
    real wo_m = v3_dot(wo, m);
    if (wo.z <= 0 || wo_m <= 0) return 0;
    return ggx_vndf_pdf_terms(wo, wo_m, ggx_G1(wo, m, alpha), ggx_D(m, alpha));
}

real ggx_vndf_pdf_terms(vec3 wo, real wo_m, real g1_wo, real d)
{
    if (wo.z <= 0 || wo_m <= 0) return 0;
    return g1_wo * wo_m * d / wo.z;
}

/* The orthonormal basis (T1, T2, Vh) of the hemisphere configuration (Heitz 2018 §4). */
static void vndf_basis(vec3 wo, real alpha, vec3 *vh, vec3 *t1, vec3 *t2)
{
    real len2;
    *vh = v3_normalize(v3(alpha * wo.x, alpha * wo.y, wo.z));
    len2 = vh->x * vh->x + vh->y * vh->y;
    *t1 = len2 > 0 ? v3_scale(v3(-vh->y, vh->x, 0), 1 / (real)sqrt(len2)) : v3(1, 0, 0);
    *t2 = v3_cross(*vh, *t1);
}

/* Heitz 2018: stretch wo to the hemisphere configuration, sample the projected
 * hemisphere (a disk whose lower half is squashed by s = (1 + Vh.z)/2), lift the
 * point onto the hemisphere and unstretch the normal. */
vec3 ggx_vndf_sample(vec3 wo, vec2 u, real alpha)
{
    vec3 vh, t1v, t2v, nh;
    real r = (real)sqrt(u.x), phi = 2 * PI_R * u.y, s, p1, p2, lift;
    vndf_basis(wo, alpha, &vh, &t1v, &t2v);
    p1 = r * (real)cos(phi);
    p2 = r * (real)sin(phi);
    s = (real)0.5 * (1 + vh.z);
    p2 = (1 - s) * (real)sqrt(fmax(0, 1 - p1 * p1)) + s * p2;
    lift = (real)sqrt(fmax(0, 1 - p1 * p1 - p2 * p2));
    nh = v3_add(v3_add(v3_scale(t1v, p1), v3_scale(t2v, p2)), v3_scale(vh, lift));
    return v3_normalize(v3(alpha * nh.x, alpha * nh.y, fmax(0, nh.z)));
}

static real wrap01(real x) { return x < 0 ? x + 1 : (x >= 1 ? x - 1 : x); }

/* Inverse of ggx_vndf_sample, step by step backwards: stretch m back to the
 * hemisphere normal Nh (normals transform with the inverse transpose, so
 * Nh ~ (m.x/alpha, m.y/alpha, m.z)); its disk point is (Nh.T1, Nh.T2) because the
 * lift adds only a Vh component; undo the squash of the second coordinate; polar
 * coordinates give u. The image of the sampler is exactly {m.z > 0, wo.m > 0}
 * and wo.m has the sign of Vh.Nh (the stretch preserves it). */
int ggx_vndf_sample_inverse(vec3 wo, vec3 m, real alpha, vec2 *u)
{
    vec3 vh, t1v, t2v, nh;
    real p1, p2, s, r2, phi;
    if (m.z <= 0 || wo.z <= 0) return 0;
    vndf_basis(wo, alpha, &vh, &t1v, &t2v);
    nh = v3_normalize(v3(m.x / alpha, m.y / alpha, m.z));
    if (v3_dot(nh, vh) <= 0) return 0;
    p1 = v3_dot(nh, t1v);
    s = (real)0.5 * (1 + vh.z);
    p2 = (v3_dot(nh, t2v) - (1 - s) * (real)sqrt(fmax(0, 1 - p1 * p1))) / s;
    r2 = p1 * p1 + p2 * p2;
    phi = (real)atan2(p2, p1);
    *u = v2(r2 < 1 ? r2 : (real)1 - REAL_EPSILON / 2, wrap01(phi / (2 * PI_R)));
    return 1;
}

/* Schlick 1994: F0 + (1 - F0)(1 - cos)^5. */
real fresnel_schlick(real cos_theta, real f0)
{
    real c = 1 - (cos_theta < 0 ? 0 : (cos_theta > 1 ? 1 : cos_theta));
    real c2 = c * c;
    return f0 + (1 - f0) * c2 * c2 * c;
}

rgb fresnel_schlick_rgb(real cos_theta, rgb f0)
{
    return rgb_make(fresnel_schlick(cos_theta, f0.r), fresnel_schlick(cos_theta, f0.g),
                    fresnel_schlick(cos_theta, f0.b));
}

/* Walter et al. 2007 Eq. 22: with c = cos_i and g = sqrt(eta^2 - 1 + c^2),
 * F = (g-c)^2 / (2 (g+c)^2) * (1 + ((c (g+c) - 1) / (c (g-c) + 1))^2); g^2 < 0 is TIR. */
real fresnel_dielectric(real cos_i, real eta)
{
    real c = cos_i < 0 ? 0 : (cos_i > 1 ? 1 : cos_i), g2 = eta * eta - 1 + c * c, g, a, b;
    if (eta == 1) return 0;
    if (g2 <= 0) return 1;
    g = (real)sqrt(g2);
    a = (g - c) / (g + c);
    b = (c * (g + c) - 1) / (c * (g - c) + 1);
    return (real)0.5 * a * a * (1 + b * b);
}

vec3 reflect_about(vec3 w, vec3 m) { return v3_sub(v3_scale(m, 2 * v3_dot(w, m)), w); }

/* Snell's law in vector form: wt = -w/eta + (c/eta - cos_t) m' with m' = m flipped to
 * w's side, c = w.m', cos_t = sqrt(1 - (1 - c^2)/eta^2). */
int refract_about(vec3 w, vec3 m, real eta, vec3 *wt)
{
    real c = v3_dot(w, m), sin2_t, cos_t;
    if (c < 0) {
        m = v3_neg(m);
        c = -c;
    }
    sin2_t = (1 - c * c) / (eta * eta);
    if (sin2_t >= 1) return 0;
    cos_t = (real)sqrt(1 - sin2_t);
    *wt = v3_add(v3_scale(w, -1 / eta), v3_scale(m, c / eta - cos_t));
    return 1;
}
