/* BSDFs split into lobes, with per-lobe sampling and its inverse (GRIS §7.6).
 *
 * ReSTIR PT works in a lobe-extended primary-sample path space: at every vertex
 * one random number u_lobe picks a lobe l with probability P(l|wo), and two more
 * (u in [0,1)^2) pick a direction from that lobe alone. The path stores l; shifts
 * decide reconnection from the roughness of the stored lobe; MCMC mutations and
 * random replay need u = sample^-1(wi). NEE and MIS use the all-lobe sums
 * (GRIS Eq. 49/50: BSDF-sampled vertices evaluate one lobe, NEE vertices all lobes).
 * docs/materials.md has every formula, its source and the tests.
 *
 * CONVENTIONS (all functions below)
 * - Directions live in the LOCAL SHADING FRAME: z = shading normal, unit length,
 *   both pointing AWAY from the surface. wo = towards the previous path vertex
 *   (the camera side), wi = towards the next vertex (the light side).
 * - "f_cos" = f(wo, wi) * |cos theta_i| = f * |wi.z|  (BSDF times the cosine of
 *   the SAMPLED/incident direction, shading normal). Every eval returns f_cos,
 *   never f alone. For a delta lobe f_cos is the coefficient of the Dirac.
 * - pdf = density of wi with respect to solid angle for a non-delta lobe. For a
 *   delta lobe the sample's pdf is 1 (the Dirac coefficient), and lobe eval/pdf
 *   at an arbitrary wi are 0 (a Dirac is never hit by chance).
 * - Transport of RADIANCE (camera paths): refraction into a medium of index
 *   eta_i from one of index eta_o scales by (eta_o / eta_i)^2 (non-symmetric BTDF).
 * - Opaque materials (Lambert, conductor, plastic) are TWO-SIDED: they shade as if
 *   the normal were flipped to wo's side; wi on the other side of wo gives 0.
 *   Dielectrics use the side: wo.z > 0 means wo is outside (index 1), inside
 *   (index ior) otherwise.
 * - Roughness is LINEAR (Falcor's linearRoughness, "perceptual"): GGX alpha = r^2
 *   (clamped below by GGX_ALPHA_MIN). GRIS's "roughness 0.5 / 0.15" and the
 *   reconnection threshold 0.2 are on r. A diffuse lobe has roughness 1, a delta
 *   lobe roughness 0.
 * - Microfacet lobes: GGX, separable Smith masking-shadowing
 *   G2 = G1(wo,m) G1(wi,m) (Walter et al. 2007 Eq. 23), visible-normal sampling
 *   (Heitz 2018, JCGT 7(4)).
 * - Any function given wo.z == 0 (or a non-finite/degenerate input) returns black,
 *   pdf 0 and "no sample"; nothing returns NaN or Inf.
 *
 * LOBES PER MATERIAL (index: kind, roughness)
 *   MAT_LAMBERT           0: diffuse (cosine hemisphere), albedo Kd.              r = 1
 *   MAT_CONDUCTOR         0: GGX reflection, Schlick Fresnel with F0 = Ks.          r
 *   MAT_PLASTIC           0: diffuse Kd * (1-F(wo))(1-F(wi)),                      r = 1
 *                         1: GGX dielectric coat reflection Ks * F_dielectric(ior). r
 *   MAT_DIELECTRIC        0: delta reflection Ks*F, 1: refraction Ks*(1-F)/eta^2. r = 0
 *   MAT_ROUGH_DIELECTRIC  0: GGX reflection, 1: GGX transmission (Walter 2007).    r
 * Lobe selection P(l|wo) (computable before sampling; > 0 wherever the lobe is
 * nonzero):
 *   plastic:          P(1) = lum(Ks) F(|wo.z|) / (lum(Ks) F(|wo.z|) + lum(Kd)(1 - F(|wo.z|)))
 *   dielectric:       P(0) = F(|wo.z|) (exact dielectric Fresnel, TIR gives 1)
 *   rough dielectric: P(0) = clamp(F(|wo.z|), 0.05, 0.95) at the macro normal
 * (an all-zero material puts P = 1 on lobe 0).
 */
#ifndef RESTIR_BSDF_H
#define RESTIR_BSDF_H

#include "restir/scene/scene.h"
#include "restir/core/vec.h"
#include "restir/core/warp.h"

#define BSDF_MAX_LOBES 2

enum bsdf_lobe_kind {
    BSDF_LOBE_DIFFUSE = 0,            /* cosine-sampled Lambertian reflection */
    BSDF_LOBE_GLOSSY_REFLECTION = 1,  /* GGX microfacet reflection */
    BSDF_LOBE_GLOSSY_TRANSMISSION = 2,/* GGX microfacet transmission */
    BSDF_LOBE_DELTA_REFLECTION = 3,   /* mirror */
    BSDF_LOBE_DELTA_TRANSMISSION = 4  /* smooth refraction */
};

/* A material prepared for shading (constants derived once). */
typedef struct {
    enum material_type type;
    rgb diffuse;    /* Kd */
    rgb specular;   /* Ks: conductor F0, or coat/glass tint */
    real roughness; /* linear roughness r (as given, clamped to [0,1]) */
    real alpha;     /* GGX alpha = max(r^2, GGX_ALPHA_MIN) */
    real ior;       /* relative index inside/outside; dielectrics keep |ior-1| >= 1e-3 */
} bsdf;

/* One sampled direction. */
typedef struct {
    vec3 wi;        /* sampled direction (local frame) */
    int lobe;       /* lobe it was sampled from */
    int is_delta;   /* 1 if that lobe is a Dirac */
    rgb f_cos;      /* f_lobe(wo,wi)|wi.z| (Dirac coefficient for a delta lobe) */
    real pdf;       /* pdf_lobe(wi), solid angle (1 for a delta lobe) */
    real lobe_prob; /* P(lobe | wo) */
    rgb weight;     /* f_cos / (lobe_prob * pdf): the path-throughput factor */
} bsdf_sample_record;

/* ---- construction and lobe structure ---- */
bsdf bsdf_from_material(const material *m);
int bsdf_lobe_count(const bsdf *b);
enum bsdf_lobe_kind bsdf_lobe_kind_of(const bsdf *b, int lobe);
int bsdf_lobe_is_delta(const bsdf *b, int lobe);
/* Linear roughness of the lobe: 1 for diffuse, 0 for delta, r for GGX lobes. */
real bsdf_lobe_roughness(const bsdf *b, int lobe);
/* GRIS §7.6 reconnection test of a lobe: not delta and roughness > threshold. */
int bsdf_lobe_is_rough(const bsdf *b, int lobe, real threshold);
/* For NEE vertices (GRIS §7.6): 1 if some lobe with P(l|wo) > 0 is rough. */
int bsdf_any_lobe_rough(const bsdf *b, vec3 wo, real threshold);

/* ---- lobe selection (one random number per bounce) ---- */
/* P(l|wo) for l < bsdf_lobe_count; entries beyond are 0; they sum to 1. */
void bsdf_lobe_probabilities(const bsdf *b, vec3 wo, real p[BSDF_MAX_LOBES]);
/* Lobe l is chosen iff lo_l <= u_lobe < hi_l with [lo_l, hi_l) consecutive
 * intervals of length P(l|wo) in lobe order. */
int bsdf_select_lobe(const bsdf *b, vec3 wo, real u_lobe);
/* The interval [*lo, *hi) of u_lobe that selects `lobe` (empty if P = 0): the
 * inverse of bsdf_select_lobe, for mutations and replay. */
void bsdf_lobe_interval(const bsdf *b, vec3 wo, int lobe, real *lo, real *hi);

/* ---- one lobe ---- */
/* f_lobe(wo,wi)|wi.z| (0 for delta lobes). */
rgb bsdf_lobe_eval(const bsdf *b, int lobe, vec3 wo, vec3 wi);
/* pdf_lobe(wi | wo), solid angle (0 for delta lobes). */
real bsdf_lobe_pdf(const bsdf *b, int lobe, vec3 wo, vec3 wi);
/* Samples wi from `lobe` with u in [0,1)^2. Returns 1 and fills *s (lobe_prob =
 * P(lobe|wo)), or 0 if there is no valid sample (below the horizon, TIR into a
 * transmission lobe, P(lobe|wo) = 0, wo.z = 0). */
int bsdf_lobe_sample(const bsdf *b, int lobe, vec3 wo, vec2 u, bsdf_sample_record *s);
/* Inverse sampling: the u with bsdf_lobe_sample(b, lobe, wo, u).wi == wi.
 * Returns 1 and fills *u if wi is in the image of the lobe's sampler (pdf > 0),
 * 0 otherwise and always for delta lobes (their u is arbitrary). */
int bsdf_lobe_sample_inverse(const bsdf *b, int lobe, vec3 wo, vec3 wi, vec2 *u);

/* ---- all lobes (NEE, MIS: GRIS Eq. 49) ---- */
/* sum_l f_l(wo,wi)|wi.z| over the non-delta lobes. */
rgb bsdf_eval(const bsdf *b, vec3 wo, vec3 wi);
/* sum_l P(l|wo) pdf_l(wi) over the non-delta lobes. */
real bsdf_pdf(const bsdf *b, vec3 wo, vec3 wi);
/* Selects a lobe with u_lobe, then samples it with u: three numbers per bounce.
 * s->weight = f_l cos / (P(l|wo) pdf_l) (one-sample lobe selection). */
int bsdf_sample(const bsdf *b, vec3 wo, real u_lobe, vec2 u, bsdf_sample_record *s);

/* ---- the same with P(l|wo) computed once per vertex (p = bsdf_lobe_probabilities(b, wo)) ----
 * Bit for bit the functions above; a path vertex needs P(l|wo) for NEE, lobe selection,
 * sampling and the all-lobe pdf, and computes it once (docs/performance.md). */
int bsdf_sample_given(const bsdf *b, vec3 wo, const real p[BSDF_MAX_LOBES], real u_lobe, vec2 u,
                      bsdf_sample_record *s);
/* bsdf_pdf; if known_lobe >= 0, pdf_known_lobe(wi) is not recomputed but known_pdf is used
 * (the pdf of the sample that produced wi, bsdf_sample_record.pdf). */
real bsdf_pdf_given(const bsdf *b, vec3 wo, const real p[BSDF_MAX_LOBES], vec3 wi, int known_lobe, real known_pdf);

/* bsdf_eval and bsdf_pdf_given(b, wo, p, wi, -1, 0) in one pass, bit for bit (NEE needs both). */
void bsdf_eval_pdf_given(const bsdf *b, vec3 wo, const real p[BSDF_MAX_LOBES], vec3 wi, rgb *f_cos, real *pdf);

/* ---- the local shading frame ---- */
typedef struct { vec3 t, b, n; } shading_frame;

static inline shading_frame shading_frame_make(vec3 n)
{
    shading_frame f;
    f.n = n;
    v3_basis(n, &f.t, &f.b);
    return f;
}
static inline vec3 shading_frame_to_local(const shading_frame *f, vec3 w)
{
    return v3(v3_dot(w, f->t), v3_dot(w, f->b), v3_dot(w, f->n));
}
static inline vec3 shading_frame_to_world(const shading_frame *f, vec3 w)
{
    return v3_add(v3_add(v3_scale(f->t, w.x), v3_scale(f->b, w.y)), v3_scale(f->n, w.z));
}

#endif
