/* BSDF dispatch: material -> lobes, lobe selection P(l|wo), one-lobe and
 * all-lobe evaluation (GRIS §7.6, Eq. 49/50), sampling and its inverse.
 * The per-lobe physics lives in lobe_*.c; this file only flips the frame to wo's
 * side, picks the lobe and checks results for finiteness. */
#include "restir/scene/bsdf.h"
#include "restir/scene/microfacet.h"
#include "lobe_delta.h"
#include "lobe_diffuse.h"
#include "lobe_microfacet.h"

/* Lower/upper clamp of P(reflection) for the rough dielectric (docs/materials.md). */
#define ROUGH_DIELECTRIC_P_MIN ((real)0.05)
#define ROUGH_DIELECTRIC_P_MAX ((real)0.95)

static int is_dielectric(enum material_type t) { return t == MAT_DIELECTRIC || t == MAT_ROUGH_DIELECTRIC; }

static real clamp_real(real x, real lo, real hi) { return x < lo ? lo : (x > hi ? hi : x); }

/* x > 0 ? x : 0 is fmax(x, 0) (NaN gives 0) without a libm call per vertex; only a -0
 * may come out as +0, which no product or comparison downstream tells apart. */
static real nonnegative_real(real x) { return x > 0 ? x : 0; }

static rgb nonnegative(rgb c) { return rgb_make(nonnegative_real(c.r), nonnegative_real(c.g), nonnegative_real(c.b)); }

/* Dielectrics need |ior - 1| >= 1e-3: at ior = 1 the refraction half vector
 * (Walter et al. 2007 Eq. 16) degenerates. A non-positive ior means "none" (1). */
static real prepared_ior(const material *m)
{
    real ior = m->ior > 0 ? m->ior : 1;
    if (is_dielectric(m->type) && fabs(ior - 1) < (real)1e-3) ior = ior >= 1 ? (real)1.001 : (real)0.999;
    return ior;
}

bsdf bsdf_from_material(const material *m)
{
    bsdf b;
    b.type = m->type;
    b.diffuse = nonnegative(m->diffuse);
    b.specular = nonnegative(m->specular);
    b.roughness = clamp_real(m->roughness, 0, 1);
    b.alpha = ggx_alpha_from_roughness(b.roughness);
    b.ior = prepared_ior(m);
    return b;
}

/* ---- lobe structure ---- */

int bsdf_lobe_count(const bsdf *b) { return b->type == MAT_LAMBERT || b->type == MAT_CONDUCTOR ? 1 : 2; }

enum bsdf_lobe_kind bsdf_lobe_kind_of(const bsdf *b, int lobe)
{
    switch (b->type) {
    case MAT_LAMBERT: return BSDF_LOBE_DIFFUSE;
    case MAT_CONDUCTOR: return BSDF_LOBE_GLOSSY_REFLECTION;
    case MAT_PLASTIC: return lobe == 0 ? BSDF_LOBE_DIFFUSE : BSDF_LOBE_GLOSSY_REFLECTION;
    case MAT_DIELECTRIC: return lobe == 0 ? BSDF_LOBE_DELTA_REFLECTION : BSDF_LOBE_DELTA_TRANSMISSION;
    case MAT_ROUGH_DIELECTRIC: return lobe == 0 ? BSDF_LOBE_GLOSSY_REFLECTION : BSDF_LOBE_GLOSSY_TRANSMISSION;
    }
    return BSDF_LOBE_DIFFUSE;
}

static const lobe_ops *ops_of(enum bsdf_lobe_kind kind)
{
    switch (kind) {
    case BSDF_LOBE_DIFFUSE: return &lobe_diffuse_ops;
    case BSDF_LOBE_GLOSSY_REFLECTION: return &lobe_glossy_reflection_ops;
    case BSDF_LOBE_GLOSSY_TRANSMISSION: return &lobe_glossy_transmission_ops;
    case BSDF_LOBE_DELTA_REFLECTION: return &lobe_delta_reflection_ops;
    case BSDF_LOBE_DELTA_TRANSMISSION: return &lobe_delta_transmission_ops;
    }
    return &lobe_diffuse_ops;
}

int bsdf_lobe_is_delta(const bsdf *b, int lobe)
{
    enum bsdf_lobe_kind k = bsdf_lobe_kind_of(b, lobe);
    return k == BSDF_LOBE_DELTA_REFLECTION || k == BSDF_LOBE_DELTA_TRANSMISSION;
}

real bsdf_lobe_roughness(const bsdf *b, int lobe)
{
    enum bsdf_lobe_kind k = bsdf_lobe_kind_of(b, lobe);
    if (k == BSDF_LOBE_DIFFUSE) return 1;
    return bsdf_lobe_is_delta(b, lobe) ? 0 : b->roughness;
}

/* GRIS §7.6: the reconnection criterion looks at the roughness of the sampled lobe only. */
int bsdf_lobe_is_rough(const bsdf *b, int lobe, real threshold)
{
    return !bsdf_lobe_is_delta(b, lobe) && bsdf_lobe_roughness(b, lobe) > threshold;
}

/* GRIS §7.6: an NEE vertex counts as rough if at least one of its lobes is. */
int bsdf_any_lobe_rough(const bsdf *b, vec3 wo, real threshold)
{
    real p[BSDF_MAX_LOBES];
    int l;
    bsdf_lobe_probabilities(b, wo, p);
    for (l = 0; l < bsdf_lobe_count(b); ++l)
        if (p[l] > 0 && bsdf_lobe_is_rough(b, l, threshold)) return 1;
    return 0;
}

/* ---- the view from wo's side (lobes.h) ---- */

static int valid_direction(vec3 w) { return isfinite(w.x) && isfinite(w.y) && isfinite(w.z) && w.z != 0; }

static vec3 flip_z(vec3 w, real flip) { return v3(w.x, w.y, w.z * flip); }

/* Fills *v and returns the flip (+1/-1), or 0 if wo is unusable (wo.z = 0, NaN). */
static real make_view(const bsdf *b, vec3 wo, lobe_view *v)
{
    real flip;
    if (!valid_direction(wo)) return 0;
    flip = wo.z > 0 ? 1 : -1;
    v->b = b;
    v->wo = flip_z(wo, flip);
    v->eta = b->ior;
    if (is_dielectric(b->type) && flip < 0) v->eta = 1 / b->ior; /* wo inside the medium */
    return flip;
}

/* ---- lobe selection ---- */

/* P(l|wo): documented in bsdf.h and docs/materials.md §Lobe selection. */
void bsdf_lobe_probabilities(const bsdf *b, vec3 wo, real p[BSDF_MAX_LOBES])
{
    lobe_view v;
    real f, spec, diff;
    p[0] = 1;
    p[1] = 0;
    if (bsdf_lobe_count(b) == 1 || !make_view(b, wo, &v)) return;
    f = fresnel_dielectric(v.wo.z, v.eta);
    if (b->type == MAT_PLASTIC) {
        spec = luminance(b->specular) * f;
        diff = luminance(b->diffuse) * (1 - f);
        if (spec + diff > 0) p[1] = spec / (spec + diff);
    } else if (b->type == MAT_DIELECTRIC) {
        p[1] = 1 - f;
    } else {
        p[1] = 1 - clamp_real(f, ROUGH_DIELECTRIC_P_MIN, ROUGH_DIELECTRIC_P_MAX);
    }
    p[0] = 1 - p[1];
}

/* bsdf_select_lobe with P(l|wo) already computed (p). */
static int select_lobe_given(const bsdf *b, const real p[BSDF_MAX_LOBES], real u_lobe)
{
    real upper = 0;
    int l, last = bsdf_lobe_count(b) - 1;
    for (l = 0; l < last; ++l) {
        upper += p[l];
        if (u_lobe < upper) return l;
    }
    return last;
}

int bsdf_select_lobe(const bsdf *b, vec3 wo, real u_lobe)
{
    real p[BSDF_MAX_LOBES];
    bsdf_lobe_probabilities(b, wo, p);
    return select_lobe_given(b, p, u_lobe);
}

void bsdf_lobe_interval(const bsdf *b, vec3 wo, int lobe, real *lo, real *hi)
{
    real p[BSDF_MAX_LOBES], lower = 0;
    int l, last = bsdf_lobe_count(b) - 1;
    bsdf_lobe_probabilities(b, wo, p);
    for (l = 0; l < lobe; ++l) lower += p[l];
    *lo = lower;
    *hi = lobe == last ? 1 : lower + p[lobe];
    if (p[lobe] <= 0) *hi = *lo;
}

/* ---- one lobe ---- */

rgb bsdf_lobe_eval(const bsdf *b, int lobe, vec3 wo, vec3 wi)
{
    lobe_view v;
    real flip = make_view(b, wo, &v);
    if (!flip || !valid_direction(wi)) return rgb_gray(0);
    return ops_of(bsdf_lobe_kind_of(b, lobe))->eval(&v, flip_z(wi, flip));
}

real bsdf_lobe_pdf(const bsdf *b, int lobe, vec3 wo, vec3 wi)
{
    lobe_view v;
    real flip = make_view(b, wo, &v);
    if (!flip || !valid_direction(wi)) return 0;
    return ops_of(bsdf_lobe_kind_of(b, lobe))->pdf(&v, flip_z(wi, flip));
}

static int finite_rgb(rgb c) { return isfinite(c.r) && isfinite(c.g) && isfinite(c.b); }

/* Fills f_cos and pdf of a sampled direction: re-evaluated through eval/pdf, so a
 * sample and a later evaluation of the same direction agree exactly. */
static int finish_sample(const lobe_ops *ops, const lobe_view *v, vec3 wi_view, bsdf_sample_record *s)
{
    if (ops->delta_coefficient) {
        s->f_cos = ops->delta_coefficient(v);
        s->pdf = 1;
    } else if (ops->eval_pdf) {
        ops->eval_pdf(v, wi_view, &s->f_cos, &s->pdf);
    } else {
        s->f_cos = ops->eval(v, wi_view);
        s->pdf = ops->pdf(v, wi_view);
    }
    if (!(s->pdf > 0) || !isfinite(s->pdf) || !finite_rgb(s->f_cos)) return 0;
    s->weight = rgb_scale(s->f_cos, 1 / (s->lobe_prob * s->pdf));
    return finite_rgb(s->weight);
}

/* bsdf_lobe_sample with P(l|wo) already computed (p). */
static int lobe_sample_given(const bsdf *b, int lobe, vec3 wo, const real p[BSDF_MAX_LOBES], vec2 u,
                             bsdf_sample_record *s)
{
    lobe_view v;
    real flip = make_view(b, wo, &v);
    const lobe_ops *ops = ops_of(bsdf_lobe_kind_of(b, lobe));
    vec3 wi;
    if (!flip) return 0;
    if (!(p[lobe] > 0) || !ops->sample(&v, u, &wi)) return 0;
    s->wi = flip_z(wi, flip);
    s->lobe = lobe;
    s->is_delta = ops->delta_coefficient != NULL;
    s->lobe_prob = p[lobe];
    return finish_sample(ops, &v, wi, s);
}

int bsdf_lobe_sample(const bsdf *b, int lobe, vec3 wo, vec2 u, bsdf_sample_record *s)
{
    real p[BSDF_MAX_LOBES];
    bsdf_lobe_probabilities(b, wo, p);
    return lobe_sample_given(b, lobe, wo, p, u, s);
}

/* Largest real below 1: inverses land on the half-open square [0,1)^2 like the samplers' inputs. */
static real below_one(real x)
{
    real top = 1 - REAL_EPSILON / 2;
    return x < 0 ? 0 : (x > top ? top : x);
}

int bsdf_lobe_sample_inverse(const bsdf *b, int lobe, vec3 wo, vec3 wi, vec2 *u)
{
    lobe_view v;
    real flip = make_view(b, wo, &v);
    const lobe_ops *ops = ops_of(bsdf_lobe_kind_of(b, lobe));
    if (!flip || !ops->inverse || !valid_direction(wi)) return 0;
    if (!ops->inverse(&v, flip_z(wi, flip), u)) return 0;
    *u = v2(below_one(u->x), below_one(u->y));
    return 1;
}

/* ---- all lobes: GRIS Eq. 49 (NEE vertices evaluate every lobe; MIS uses the all-lobe pdf) ---- */

rgb bsdf_eval(const bsdf *b, vec3 wo, vec3 wi)
{
    rgb sum = rgb_gray(0);
    int l;
    for (l = 0; l < bsdf_lobe_count(b); ++l) sum = rgb_add(sum, bsdf_lobe_eval(b, l, wo, wi));
    return sum;
}

real bsdf_pdf(const bsdf *b, vec3 wo, vec3 wi)
{
    real p[BSDF_MAX_LOBES];
    bsdf_lobe_probabilities(b, wo, p);
    return bsdf_pdf_given(b, wo, p, wi, -1, 0);
}

/* known_lobe's pdf_l(wi) is taken as known_pdf (a sampled direction's own pdf: the
 * same function of the same arguments, so the same value; docs/performance.md). */
real bsdf_pdf_given(const bsdf *b, vec3 wo, const real p[BSDF_MAX_LOBES], vec3 wi, int known_lobe, real known_pdf)
{
    real sum = 0;
    int l;
    for (l = 0; l < bsdf_lobe_count(b); ++l)
        if (p[l] > 0) sum += p[l] * (l == known_lobe && valid_direction(wi) ? known_pdf : bsdf_lobe_pdf(b, l, wo, wi));
    return sum;
}

/* bsdf_eval and bsdf_pdf_given(b, wo, p, wi, -1, 0) of one direction in one pass (an NEE
 * vertex needs both): one view, and a GGX lobe's m, D(m), G1(wo, m) once (lobe eval_pdf).
 * The same sums in the same order, so the same bits. */
void bsdf_eval_pdf_given(const bsdf *b, vec3 wo, const real p[BSDF_MAX_LOBES], vec3 wi, rgb *f_cos, real *pdf)
{
    lobe_view v;
    real flip = make_view(b, wo, &v);
    vec3 wi_view;
    int l;
    *f_cos = rgb_gray(0);
    *pdf = 0;
    if (!flip || !valid_direction(wi)) return;
    wi_view = flip_z(wi, flip);
    for (l = 0; l < bsdf_lobe_count(b); ++l) {
        const lobe_ops *ops = ops_of(bsdf_lobe_kind_of(b, l));
        rgb f;
        real pdf_l = 0;
        if (ops->eval_pdf) {
            ops->eval_pdf(&v, wi_view, &f, p[l] > 0 ? &pdf_l : NULL);
        } else {
            f = ops->eval(&v, wi_view);
            if (p[l] > 0) pdf_l = ops->pdf(&v, wi_view);
        }
        *f_cos = rgb_add(*f_cos, f);
        if (p[l] > 0) *pdf += p[l] * pdf_l;
    }
}

int bsdf_sample(const bsdf *b, vec3 wo, real u_lobe, vec2 u, bsdf_sample_record *s)
{
    real p[BSDF_MAX_LOBES];
    bsdf_lobe_probabilities(b, wo, p);
    return bsdf_sample_given(b, wo, p, u_lobe, u, s);
}

int bsdf_sample_given(const bsdf *b, vec3 wo, const real p[BSDF_MAX_LOBES], real u_lobe, vec2 u,
                      bsdf_sample_record *s)
{
    return lobe_sample_given(b, select_lobe_given(b, p, u_lobe), wo, p, u, s);
}
