/* BSDF lobes: structure, selection, finiteness, reciprocity, energy, inverse
 * sampling, pdf = 1/|Jacobian| of the sampler, delta lobes (docs/materials.md).
 * The chi-square tests of sampler vs pdf are in test_chi2.c. */
#include <stdio.h>
#include "restir/scene/bsdf.h"
#include "restir/scene/microfacet.h"
#include "restir/core/rng.h"
#include "test.h"

#define IS_DOUBLE (sizeof(real) == 8)

static bsdf make_bsdf_full(enum material_type type, real roughness, real ior, real kd, real ks)
{
    material m;
    m.name[0] = 0;
    m.type = type;
    m.diffuse = rgb_gray(kd);
    m.specular = rgb_gray(ks);
    m.emission = rgb_gray(0);
    m.roughness = roughness;
    m.ior = ior;
    return bsdf_from_material(&m);
}

static bsdf make_bsdf(enum material_type type, real roughness) { return make_bsdf_full(type, roughness, (real)1.5, (real)0.8, 1); }

/* The materials every property test runs over. */
enum { N_ROUGH = 4, N_CASES = 1 + 4 * N_ROUGH };
static const real roughness_values[N_ROUGH] = {(real)1e-3, (real)0.1, (real)0.5, 1};

static bsdf case_bsdf(int i)
{
    static const enum material_type rough_types[] = {MAT_CONDUCTOR, MAT_PLASTIC, MAT_ROUGH_DIELECTRIC};
    if (i == 0) return make_bsdf(MAT_LAMBERT, 1);
    if (i == N_CASES - 1) return make_bsdf(MAT_DIELECTRIC, 0);
    --i;
    if (i < 3 * N_ROUGH) return make_bsdf(rough_types[i / N_ROUGH], roughness_values[i % N_ROUGH]);
    return make_bsdf_full(MAT_ROUGH_DIELECTRIC, roughness_values[i % N_ROUGH], (real)2.4, 0, 1);
}

static real test_u(uint32_t stream, uint32_t i, uint32_t slot)
{
    return rng_u(rng_key_make(test_seed(), stream, i), RNG_TEST, 0, slot);
}

static vec3 random_direction(uint32_t stream, uint32_t i)
{
    return warp_uniform_sphere(v2(test_u(stream, i, 0), test_u(stream, i, 1)));
}

static vec3 wo_at(real cos_o)
{
    real s = (real)sqrt(fmax(0, 1 - cos_o * cos_o));
    return v3(s * (real)cos(0.3), s * (real)sin(0.3), cos_o);
}

static int finite_nonneg(rgb c)
{
    return isfinite(c.r) && isfinite(c.g) && isfinite(c.b) && c.r >= 0 && c.g >= 0 && c.b >= 0;
}

static real rel_diff(real a, real b)
{
    real m = fmax(fabs(a), fabs(b));
    return m > 0 ? fabs(a - b) / m : 0;
}

/* ---- structure and selection ---- */

TEST(bsdf_lobe_structure)
{
    bsdf lam = make_bsdf(MAT_LAMBERT, 1), con = make_bsdf(MAT_CONDUCTOR, (real)0.15);
    bsdf pla = make_bsdf(MAT_PLASTIC, (real)0.5), die = make_bsdf(MAT_DIELECTRIC, 0);
    bsdf rd = make_bsdf(MAT_ROUGH_DIELECTRIC, (real)0.3);
    CHECK(bsdf_lobe_count(&lam) == 1 && bsdf_lobe_count(&con) == 1 && bsdf_lobe_count(&pla) == 2);
    CHECK(bsdf_lobe_count(&die) == 2 && bsdf_lobe_count(&rd) == 2);
    CHECK(bsdf_lobe_roughness(&lam, 0) == 1 && bsdf_lobe_roughness(&pla, 0) == 1);
    CHECK_NEAR(bsdf_lobe_roughness(&con, 0), 0.15, 1e-6);
    CHECK(bsdf_lobe_roughness(&die, 0) == 0 && bsdf_lobe_is_delta(&die, 1) && !bsdf_lobe_is_delta(&rd, 1));
    /* GRIS §7.6 with the 0.2 threshold on linear roughness */
    CHECK(!bsdf_lobe_is_rough(&con, 0, (real)0.2) && bsdf_lobe_is_rough(&pla, 0, (real)0.2));
    CHECK(!bsdf_lobe_is_rough(&pla, 1, (real)0.6) && !bsdf_lobe_is_rough(&die, 0, (real)0.2));
    CHECK(bsdf_any_lobe_rough(&pla, wo_at((real)0.5), (real)0.6) && !bsdf_any_lobe_rough(&con, wo_at((real)0.5), (real)0.2));
    CHECK_NEAR(con.alpha, 0.0225, 1e-6);
    CHECK(make_bsdf(MAT_CONDUCTOR, 0).alpha == GGX_ALPHA_MIN);
}

/* sum_l P(l|wo) = 1, each in [0,1], and the selection intervals invert the selection. */
TEST(bsdf_lobe_selection)
{
    int c, i, j;
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        for (i = 0; i < 400; ++i) {
            vec3 wo = i == 0 ? v3(1, 0, 0) : random_direction(11, (uint32_t)i);
            real p[BSDF_MAX_LOBES], sum = 0;
            int l;
            bsdf_lobe_probabilities(&b, wo, p);
            for (l = 0; l < BSDF_MAX_LOBES; ++l) {
                CHECKF(p[l] >= 0 && p[l] <= 1, "case %d P(%d) = %g", c, l, (double)p[l]);
                sum += p[l];
            }
            CHECK_NEAR(sum, 1, 1e-6);
            for (j = 0; j < 64; ++j) {
                real u = (j + (real)0.5) / 64, lo, hi;
                l = bsdf_select_lobe(&b, wo, u);
                bsdf_lobe_interval(&b, wo, l, &lo, &hi);
                CHECKF(lo <= u && u < hi, "case %d u=%g lobe %d [%g,%g)", c, (double)u, l, (double)lo, (double)hi);
                CHECK_NEAR(hi - lo, p[l], 1e-6);
                CHECK(p[l] > 0);
            }
        }
    }
}

/* P(l|wo) > 0 wherever lobe l is nonzero (unbiasedness of one-sample lobe choice). */
TEST(bsdf_selection_covers_nonzero_lobes)
{
    int c, i;
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        for (i = 0; i < 2000; ++i) {
            vec3 wo = random_direction(12, (uint32_t)i), wi = random_direction(13, (uint32_t)i);
            real p[BSDF_MAX_LOBES];
            int l;
            bsdf_lobe_probabilities(&b, wo, p);
            for (l = 0; l < bsdf_lobe_count(&b); ++l)
                if (!rgb_is_black(bsdf_lobe_eval(&b, l, wo, wi))) CHECKF(p[l] > 0, "case %d lobe %d", c, l);
        }
    }
}

/* ---- finiteness and robustness ---- */

static int check_all_finite(const bsdf *b, vec3 wo, vec3 wi, char *why, size_t n)
{
    int l;
    real pdf_all = bsdf_pdf(b, wo, wi);
    bsdf_sample_record s;
    if (!finite_nonneg(bsdf_eval(b, wo, wi)) || !(pdf_all >= 0) || !isfinite(pdf_all)) {
        snprintf(why, n, "all-lobe eval/pdf");
        return 0;
    }
    for (l = 0; l < bsdf_lobe_count(b); ++l) {
        real pdf = bsdf_lobe_pdf(b, l, wo, wi);
        vec2 u = v2((real)0.3, (real)0.7);
        if (!finite_nonneg(bsdf_lobe_eval(b, l, wo, wi)) || !(pdf >= 0) || !isfinite(pdf)) {
            snprintf(why, n, "lobe %d eval/pdf", l);
            return 0;
        }
        if (bsdf_lobe_sample(b, l, wo, u, &s) &&
            (!finite_nonneg(s.weight) || !finite_nonneg(s.f_cos) || !(s.pdf > 0) || !isfinite(s.pdf) ||
             !isfinite(s.wi.x + s.wi.y + s.wi.z))) {
            snprintf(why, n, "lobe %d sample", l);
            return 0;
        }
        if (bsdf_lobe_sample_inverse(b, l, wo, wi, &u) && !(u.x >= 0 && u.x < 1 && u.y >= 0 && u.y < 1)) {
            snprintf(why, n, "lobe %d inverse u = (%g, %g)", l, (double)u.x, (double)u.y);
            return 0;
        }
    }
    return 1;
}

/* Extreme inputs: near-delta roughness, grazing, wo below the horizon, wi = wo,
 * wi = -wo (degenerate half vector), wo.z = 0, NaN: no NaN/Inf, no negative values. */
TEST(bsdf_finite_at_extremes)
{
    real nan_value = (real)NAN;
    vec3 special[] = {v3(0, 0, 1), wo_at((real)0.01), wo_at((real)-0.01), wo_at((real)1e-7), wo_at((real)0.7),
                      wo_at((real)-0.7), v3(1, 0, 0), v3(nan_value, 0, 1)};
    int ns = (int)(sizeof special / sizeof special[0]), c, i, j;
    char why[128];
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        for (i = 0; i < ns; ++i) {
            vec3 wo = special[i];
            vec3 wis[] = {wo, v3_neg(wo), v3(-wo.x, -wo.y, wo.z), v3(wo.x, wo.y, -wo.z), v3(0, 0, -1)};
            for (j = 0; j < 5; ++j) CHECKF(check_all_finite(&b, wo, wis[j], why, sizeof why), "case %d wo %d wi %d: %s", c, i, j, why);
            for (j = 0; j < ns; ++j) CHECKF(check_all_finite(&b, wo, special[j], why, sizeof why), "case %d wo %d wi s%d: %s", c, i, j, why);
        }
        for (i = 0; i < 3000; ++i) {
            vec3 wo = random_direction(14, (uint32_t)i), wi = random_direction(15, (uint32_t)i);
            CHECKF(check_all_finite(&b, wo, wi, why, sizeof why), "case %d random %d: %s", c, i, why);
        }
    }
}

/* A sample agrees exactly with a later evaluation of its direction, and the
 * all-lobe pdf is sum_l P(l|wo) pdf_l (GRIS Eq. 49). */
/* bsdf_eval_pdf_given (NEE's one pass) is bsdf_eval and bsdf_pdf_given, bit for bit. */
static int eval_pdf_exact(const bsdf *b, vec3 wo, const real p[BSDF_MAX_LOBES], vec3 wi)
{
    rgb f, e = bsdf_eval(b, wo, wi);
    real pdf;
    bsdf_eval_pdf_given(b, wo, p, wi, &f, &pdf);
    return f.r == e.r && f.g == e.g && f.b == e.b && pdf == bsdf_pdf_given(b, wo, p, wi, -1, 0);
}

TEST(bsdf_sample_consistent_with_eval)
{
    int c, i;
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        for (i = 0; i < 2000; ++i) {
            vec3 wo = random_direction(16, (uint32_t)i);
            vec2 u = v2(test_u(17, (uint32_t)i, 0), test_u(17, (uint32_t)i, 1));
            bsdf_sample_record s, g;
            real ul = test_u(17, (uint32_t)i, 2), p[BSDF_MAX_LOBES], sum = 0;
            int l, ok = bsdf_sample(&b, wo, ul, u, &s);
            bsdf_lobe_probabilities(&b, wo, p);
            /* The path vertex's shortcuts (docs/performance.md) are exact: P(l|wo) given
             * once (bsdf_sample_given), the sampled lobe's pdf taken from the sample
             * (bsdf_pdf_given) give bsdf_sample and bsdf_pdf bit for bit. */
            CHECK(bsdf_sample_given(&b, wo, p, ul, u, &g) == ok);
            CHECK(bsdf_pdf_given(&b, wo, p, wo, -1, 0) == bsdf_pdf(&b, wo, wo));
            CHECKF(eval_pdf_exact(&b, wo, p, random_direction(18, (uint32_t)i)), "case %d random wi %d", c, i);
            if (!ok) continue;
            CHECKF(eval_pdf_exact(&b, wo, p, s.wi), "case %d sampled wi %d", c, i);
            CHECK(g.wi.x == s.wi.x && g.wi.y == s.wi.y && g.wi.z == s.wi.z && g.lobe == s.lobe && g.pdf == s.pdf);
            CHECK(g.weight.r == s.weight.r && g.weight.g == s.weight.g && g.weight.b == s.weight.b);
            CHECK(s.lobe_prob == p[s.lobe]);
            CHECK(rel_diff(s.weight.g, s.f_cos.g / (s.lobe_prob * s.pdf)) < 1e-5);
            if (s.is_delta) continue;
            /* eval and pdf of the sampled direction are the sample's own f and pdf, exactly */
            CHECK(bsdf_lobe_eval(&b, s.lobe, wo, s.wi).g == s.f_cos.g);
            CHECK(bsdf_lobe_pdf(&b, s.lobe, wo, s.wi) == s.pdf);
            CHECK(bsdf_pdf_given(&b, wo, p, s.wi, s.lobe, s.pdf) == bsdf_pdf(&b, wo, s.wi));
            for (l = 0; l < bsdf_lobe_count(&b); ++l) sum += p[l] * bsdf_lobe_pdf(&b, l, wo, s.wi);
            CHECK(rel_diff(bsdf_pdf(&b, wo, s.wi), sum) < 1e-5);
        }
    }
}

/* ---- reciprocity ---- */

/* f(wo,wi) = f(wi,wo) for reflection lobes; for transmission (radiance transport)
 * f(wo,wi) / n_o^2 = f(wi,wo) / n_i^2 (Veach 1997 §5.2, Walter et al. 2007 §5.2).
 * Pairs: random, plus wi sampled from the lobe (so near-delta lobes are nonzero). */
static int check_pair_reciprocal(const bsdf *b, int l, vec3 wo, vec3 wi, real *worst)
{
    real f_oi = bsdf_lobe_eval(b, l, wo, wi).g / fabs(wi.z), f_io = bsdf_lobe_eval(b, l, wi, wo).g / fabs(wo.z);
    if (wo.z * wi.z < 0) { /* transmission: n of wo's side over n of wi's side */
        real n_o = wo.z > 0 ? 1 : b->ior, n_i = wi.z > 0 ? 1 : b->ior;
        f_oi /= n_o * n_o;
        f_io /= n_i * n_i;
    }
    if (fmax(f_oi, f_io) < 1e-6) return 1;
    /* float: near the critical angle 1 - F ~ sqrt(cos^2 - cos_c^2) turns the rounding of a
     * cosine into %-level errors, so the float build checks non-grazing reflection pairs */
    if (!IS_DOUBLE && (wo.z * wi.z < 0 || fmin(fabs(wo.z), fabs(wi.z)) < (real)0.05)) return 1;
    *worst = fmax(*worst, rel_diff(f_oi, f_io));
    return rel_diff(f_oi, f_io) < (IS_DOUBLE ? 1e-7 : 1e-2);
}

TEST(bsdf_reciprocity)
{
    int c, i, l;
    real worst = 0;
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        for (l = 0; l < bsdf_lobe_count(&b); ++l) {
            if (bsdf_lobe_is_delta(&b, l)) continue;
            for (i = 0; i < 2000; ++i) {
                vec3 wo = random_direction(20, (uint32_t)i), wi = random_direction(21, (uint32_t)i);
                bsdf_sample_record s;
                CHECKF(check_pair_reciprocal(&b, l, wo, wi, &worst), "case %d lobe %d random pair %d", c, l, i);
                if (!IS_DOUBLE && b.alpha < (real)1e-4) continue; /* lobe narrower than float directions resolve */
                if (bsdf_lobe_sample(&b, l, wo, v2(test_u(22, (uint32_t)i, 0), test_u(22, (uint32_t)i, 1)), &s))
                    CHECKF(check_pair_reciprocal(&b, l, wo, s.wi, &worst), "case %d lobe %d sampled pair %d", c, l, i);
            }
        }
    }
    printf("    worst relative reciprocity mismatch %.3g (tolerance %g)\n", (double)worst, IS_DOUBLE ? 1e-7 : 1e-2);
}

/* ---- energy ---- */

typedef struct { double mean[3], err[3]; } albedo_estimate;

static void add_rgb(double sum[3], double sum2[3], rgb c)
{
    double v[3];
    int k;
    v[0] = c.r, v[1] = c.g, v[2] = c.b;
    for (k = 0; k < 3; ++k) sum[k] += v[k], sum2[k] += v[k] * v[k];
}

static void finish(albedo_estimate *a, const double sum[3], const double sum2[3], long n)
{
    int k;
    for (k = 0; k < 3; ++k) {
        a->mean[k] = sum[k] / n;
        a->err[k] = sqrt(fmax(0, sum2[k] / n - a->mean[k] * a->mean[k]) / (n - 1));
    }
}

/* Directional albedo of `lobe` (or of the whole BSDF with lobe < 0) by its own
 * sampler. energy != 0 multiplies refracted samples by (n_i/n_o)^2, undoing the
 * radiance scaling: what remains is the fraction of energy scattered, <= 1. */
static albedo_estimate sampled_albedo(const bsdf *b, int lobe, vec3 wo, long n, uint32_t stream, int energy)
{
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    albedo_estimate a;
    long i;
    for (i = 0; i < n; ++i) {
        vec2 u = v2(test_u(stream, (uint32_t)i, 0), test_u(stream, (uint32_t)i, 1));
        bsdf_sample_record s;
        rgb w;
        int ok = lobe < 0 ? bsdf_sample(b, wo, test_u(stream, (uint32_t)i, 2), u, &s) : bsdf_lobe_sample(b, lobe, wo, u, &s);
        if (!ok) {
            add_rgb(sum, sum2, rgb_gray(0));
            continue;
        }
        w = lobe < 0 ? s.weight : rgb_scale(s.f_cos, 1 / s.pdf);
        if (energy && s.wi.z * wo.z < 0) {
            real eta = wo.z > 0 ? b->ior : 1 / b->ior;
            w = rgb_scale(w, eta * eta);
        }
        add_rgb(sum, sum2, w);
    }
    finish(&a, sum, sum2, n);
    return a;
}

/* Albedo <= 1 (within 4 standard errors) for every lobe and every material with
 * white Kd = Ks = 1, roughness 1e-3..1, cos theta_o = 1..0.01, both sides. */
TEST(bsdf_albedo_at_most_one)
{
    static const real cosines[] = {1, (real)0.7, (real)0.3, (real)0.01, (real)-0.7, (real)-0.01};
    static const enum material_type types[] = {MAT_LAMBERT, MAT_CONDUCTOR, MAT_PLASTIC, MAT_DIELECTRIC, MAT_ROUGH_DIELECTRIC};
    double worst = 0;
    int t, r, a, l;
    for (t = 0; t < 5; ++t)
        for (r = 0; r < N_ROUGH; ++r)
            for (a = 0; a < 6; ++a) {
                bsdf b = make_bsdf_full(types[t], roughness_values[r], (real)1.5, 1, 1);
                vec3 wo = wo_at(cosines[a]);
                for (l = -1; l < bsdf_lobe_count(&b); ++l) {
                    albedo_estimate e = sampled_albedo(&b, l, wo, 20000, (uint32_t)(100 + 31 * t + 7 * r + a), 1);
                    CHECKF(e.mean[1] <= 1 + 4 * e.err[1] + 1e-6, "type %d r=%g cos=%g lobe %d: albedo %g +- %g", types[t],
                           (double)roughness_values[r], (double)cosines[a], l, e.mean[1], e.err[1]);
                    if (e.mean[1] > worst) worst = e.mean[1];
                }
            }
    printf("    largest albedo estimate %.4f\n", worst);
}

/* Known albedos: Lambert = Kd exactly; smooth glass R + T = 1 exactly (energy form)
 * and T carries 1/eta^2 in radiance form; a white near-delta conductor ~ G1(wi) ~ 1. */
TEST(bsdf_albedo_known_values)
{
    bsdf lam = make_bsdf_full(MAT_LAMBERT, 1, 1, (real)0.6, 0), glass = make_bsdf(MAT_DIELECTRIC, 0);
    bsdf mirror = make_bsdf_full(MAT_CONDUCTOR, (real)1e-3, 1, 0, 1);
    albedo_estimate e = sampled_albedo(&lam, -1, wo_at((real)0.4), 1000, 30, 0);
    CHECK_NEAR(e.mean[1], 0.6, 1e-6);
    CHECK(e.err[1] < 1e-6);
    e = sampled_albedo(&glass, -1, wo_at((real)0.4), 1000, 31, 1);
    CHECK_NEAR(e.mean[1], 1, 1e-5);
    e = sampled_albedo(&glass, 1, wo_at((real)0.8), 10, 32, 0); /* per-lobe f_cos/pdf = Ks (1-F)/eta^2 */
    CHECK_NEAR(e.mean[1], (1 - fresnel_dielectric((real)0.8, (real)1.5)) / 2.25, 1e-6);
    e = sampled_albedo(&glass, 1, wo_at((real)-0.8), 10, 33, 0); /* from inside: eta = 1/1.5 */
    CHECK_NEAR(e.mean[1], (1 - fresnel_dielectric((real)0.8, (real)(1 / 1.5))) * 2.25, 1e-5);
    e = sampled_albedo(&mirror, -1, wo_at((real)0.5), 1000, 34, 0);
    CHECK(e.mean[1] > 0.999 && e.mean[1] <= 1);
}

/* Albedo from the lobe's own sampler (f/pdf) agrees with an estimate that never
 * calls the sampler or the pdf (uniform sphere directions, f_cos * 4 pi): checks
 * eval against pdf for the rough lobes. 2 x 200k samples, |z| < 5. */
TEST(bsdf_albedo_independent_estimate)
{
    static const enum material_type types[] = {MAT_CONDUCTOR, MAT_PLASTIC, MAT_ROUGH_DIELECTRIC};
    int t, l, k;
    for (t = 0; t < 3; ++t) {
        bsdf b = make_bsdf_full(types[t], (real)0.6, (real)1.5, (real)0.7, 1);
        for (k = 0; k < 2; ++k) {
            vec3 wo = wo_at(k ? (real)0.35 : (real)-0.8);
            for (l = 0; l < bsdf_lobe_count(&b); ++l) {
                double sum = 0, sum2 = 0, mean, err, z;
                albedo_estimate e = sampled_albedo(&b, l, wo, 200000, (uint32_t)(40 + 3 * t + k), 0);
                long i, n = 200000;
                for (i = 0; i < n; ++i) {
                    vec3 wi = warp_uniform_sphere(v2(test_u(50 + (uint32_t)t, (uint32_t)i, 0), test_u(50 + (uint32_t)t, (uint32_t)i, 1)));
                    double v = bsdf_lobe_eval(&b, l, wo, wi).g * 4 * 3.14159265358979323846;
                    sum += v;
                    sum2 += v * v;
                }
                mean = sum / n;
                err = sqrt((sum2 / n - mean * mean) / (n - 1));
                z = (mean - e.mean[1]) / sqrt(err * err + e.err[1] * e.err[1]);
                CHECKF(fabs(z) < 5, "type %d lobe %d side %d: sampled %g +- %g, uniform %g +- %g", types[t], l, k,
                       e.mean[1], e.err[1], mean, err);
            }
        }
    }
}

/* ---- inverse sampling and the sampler's Jacobian ---- */

/* sample^-1(sample(u)) = u for every non-delta lobe over a grid of u in
 * [0.01, 0.99]^2 (away from the seams u2 = 0|1 of the polar map and the centre
 * u1 = 0 where the azimuth is undefined), all materials, cos theta_o from 1 to
 * 0.01 and below the horizon. */
TEST(bsdf_inverse_sampling_roundtrip)
{
    static const real cosines[] = {1, (real)0.7, (real)0.3, (real)0.01, (real)-0.5, (real)-0.01};
    double tol = IS_DOUBLE ? 1e-7 : 2e-3, worst = 0;
    int c, a, l, i, j;
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        if (!IS_DOUBLE && b.alpha < (real)1e-2) continue; /* float: u resolution ~ direction resolution / alpha */
        for (a = 0; a < 6; ++a)
            for (l = 0; l < bsdf_lobe_count(&b); ++l) {
                vec3 wo = wo_at(cosines[a]);
                if (bsdf_lobe_is_delta(&b, l)) {
                    vec2 u;
                    CHECK(!bsdf_lobe_sample_inverse(&b, l, wo, v3(0, 0, 1), &u));
                    continue;
                }
                for (i = 0; i < 41; ++i)
                    for (j = 0; j < 43; ++j) {
                        vec2 u = v2((real)0.01 + (real)0.98 * i / 40, (real)0.01 + (real)0.98 * j / 42), back;
                        bsdf_sample_record s;
                        double err;
                        if (!bsdf_lobe_sample(&b, l, wo, u, &s)) continue;
                        CHECKF(bsdf_lobe_sample_inverse(&b, l, wo, s.wi, &back), "case %d cos %g lobe %d u (%g, %g): no inverse",
                               c, (double)cosines[a], l, (double)u.x, (double)u.y);
                        err = fmax(fabs(back.x - u.x), fabs(back.y - u.y));
                        if (err > worst) worst = err;
                        CHECKF(err <= tol, "case %d cos %g lobe %d u (%g, %g) -> (%g, %g)", c, (double)cosines[a], l,
                               (double)u.x, (double)u.y, (double)back.x, (double)back.y);
                    }
            }
    }
    printf("    worst |u - inverse(sample(u))| = %.3g (tolerance %.0e)\n", worst, tol);
}

/* The pdf is the density of the sampler's pushforward: pdf(w(u)) |dw/du1 x dw/du2| = 1,
 * with the Jacobian by central differences. This is the check that also covers the
 * near-delta lobes (alpha = 1e-6), where a histogram is hard to resolve; the
 * double build runs it at every roughness, the float build from roughness 0.1. */
static int sample_at(const bsdf *b, int l, vec3 wo, real u1, real u2, vec3 *w)
{
    bsdf_sample_record s;
    if (!bsdf_lobe_sample(b, l, wo, v2(u1, u2), &s)) return 0;
    *w = s.wi;
    return 1;
}

TEST(bsdf_pdf_is_sampling_density)
{
    static const real cosines[] = {1, (real)0.6, (real)0.05, (real)-0.6};
    real h = IS_DOUBLE ? (real)1e-5 : (real)5e-4;
    double tol = IS_DOUBLE ? 1e-3 : 5e-2, worst = 0;
    int c, a, l, i;
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        if (!IS_DOUBLE && b.roughness < (real)0.1 && b.type != MAT_LAMBERT) continue;
        for (a = 0; a < 4; ++a)
            for (l = 0; l < bsdf_lobe_count(&b); ++l) {
                vec3 wo = wo_at(cosines[a]);
                if (bsdf_lobe_is_delta(&b, l)) continue;
                for (i = 0; i < 200; ++i) {
                    real u1 = (real)0.05 + (real)0.9 * test_u(60, (uint32_t)i, 0), u2 = (real)0.05 + (real)0.9 * test_u(60, (uint32_t)i, 1);
                    vec3 w, xp, xm, yp, ym;
                    double jac, pdf, ratio;
                    if (!sample_at(&b, l, wo, u1, u2, &w) || !sample_at(&b, l, wo, u1 + h, u2, &xp) ||
                        !sample_at(&b, l, wo, u1 - h, u2, &xm) || !sample_at(&b, l, wo, u1, u2 + h, &yp) ||
                        !sample_at(&b, l, wo, u1, u2 - h, &ym))
                        continue;
                    jac = v3_length(v3_cross(v3_scale(v3_sub(xp, xm), 1 / (2 * h)), v3_scale(v3_sub(yp, ym), 1 / (2 * h))));
                    pdf = bsdf_lobe_pdf(&b, l, wo, w);
                    ratio = pdf * jac;
                    if (fabs(ratio - 1) > worst) worst = fabs(ratio - 1);
                    CHECKF(fabs(ratio - 1) < tol, "case %d cos %g lobe %d u (%g, %g): pdf %g, 1/|J| %g", c,
                           (double)cosines[a], l, (double)u1, (double)u2, pdf, 1 / jac);
                }
            }
    }
    printf("    worst |pdf |J| - 1| = %.3g\n", worst);
}

/* ---- closed forms (eval and pdf written independently agree with the algebra) ---- */

/* f cos / pdf of a VNDF-sampled GGX lobe reduces to F G1(wi, m) for reflection and
 * Ks (1 - F) G1(wi, m) / eta^2 for transmission (Heitz 2018 §2; Walter et al. 2007). */
TEST(bsdf_microfacet_weights_closed_form)
{
    int i;
    bsdf con = make_bsdf_full(MAT_CONDUCTOR, (real)0.4, 1, 0, (real)0.7);
    bsdf rd = make_bsdf(MAT_ROUGH_DIELECTRIC, (real)0.4);
    for (i = 0; i < 2000; ++i) {
        vec3 wo = random_direction(70, (uint32_t)i), m;
        vec2 u = v2(test_u(71, (uint32_t)i, 0), test_u(71, (uint32_t)i, 1));
        bsdf_sample_record s;
        real flip = wo.z > 0 ? 1 : -1, eta = wo.z > 0 ? rd.ior : 1 / rd.ior, expect;
        vec3 wo_up = v3(wo.x, wo.y, wo.z * flip), wi_up;
        if (bsdf_lobe_sample(&con, 0, wo, u, &s)) {
            wi_up = v3(s.wi.x, s.wi.y, s.wi.z * flip);
            m = v3_normalize(v3_add(wo_up, wi_up));
            expect = fresnel_schlick(v3_dot(wo_up, m), (real)0.7) * ggx_G1(wi_up, m, con.alpha);
            CHECKF(rel_diff(s.f_cos.g / s.pdf, expect) < 1e-5, "conductor %d: %g vs %g", i, (double)(s.f_cos.g / s.pdf), (double)expect);
        }
        if (bsdf_lobe_sample(&rd, 1, wo, u, &s)) {
            wi_up = v3(s.wi.x, s.wi.y, s.wi.z * flip);
            m = v3_normalize(v3_add(wo_up, v3_scale(wi_up, eta)));
            if (m.z < 0) m = v3_neg(m);
            expect = (1 - fresnel_dielectric(v3_dot(wo_up, m), eta)) * ggx_G1(wi_up, m, rd.alpha) / (eta * eta);
            CHECKF(rel_diff(s.f_cos.g / s.pdf, expect) < 1e-4, "transmission %d: %g vs %g", i, (double)(s.f_cos.g / s.pdf),
                   (double)expect);
        }
    }
}

/* GGX D is normalised: integral of D(m) m.z over the hemisphere = 1 (Walter et al.
 * 2007 Eq. 4), and the VNDF integrates to 1 (Heitz 2018). Midpoint quadrature in
 * s with tan theta = alpha tan(pi s / 2): resolves the peak at any alpha and the
 * tail up to the horizon (the Jacobian stays finite at s = 1);
 * the azimuth runs only over the arc where wo.m > 0, so the integrand is smooth. */
static double vndf_ring(vec3 wo, real a, double c, double sn, int nphi)
{
    double so = sqrt(fmax(0, 1 - wo.z * wo.z)), phio = atan2(wo.y, wo.x), A = so * sn, B = wo.z * c;
    double half = A <= B ? 3.14159265358979323846 : acos(-B / A), sum = 0;
    int j;
    for (j = 0; j < nphi; ++j) {
        double phi = phio - half + 2 * half * (j + 0.5) / nphi;
        vec3 m = v3((real)(sn * cos(phi)), (real)(sn * sin(phi)), (real)c);
        sum += ggx_vndf_pdf(wo, m, a) * 2 * half / nphi;
    }
    return sum;
}

TEST(ggx_normalisation)
{
    static const real alphas[] = {(real)1e-6, (real)1e-2, (real)0.25, 1};
    int k, i;
    for (k = 0; k < 4; ++k) {
        real a = alphas[k];
        double sum_d = 0, sum_v = 0;
        vec3 wo = wo_at((real)0.3);
        int n = 4000;
        for (i = 0; i < n; ++i) {
            double s = (i + 0.5) / n, T = tan(0.5 * 3.14159265358979323846 * s), c = 1 / sqrt(1 + a * a * T * T);
            double w = a * a * T * c * c * c * 0.5 * 3.14159265358979323846 * (1 + T * T) / n; /* |dc/ds| ds */
            double sn = a * T * c; /* not sqrt(1 - c^2): that cancels at alpha = 1e-6 */
            sum_d += ggx_D(v3((real)sn, 0, (real)c), a) * c * w * 2 * 3.14159265358979323846;
            sum_v += vndf_ring(wo, a, c, sn, 64) * w;
        }
        CHECKF(fabs(sum_d - 1) < 1e-4, "alpha %g: integral D cos = %g", (double)a, sum_d);
        CHECKF(fabs(sum_v - 1) < 1e-4, "alpha %g: integral VNDF = %g", (double)a, sum_v);
    }
}

/* ---- delta lobes, sides ---- */

TEST(bsdf_smooth_dielectric)
{
    bsdf g = make_bsdf(MAT_DIELECTRIC, 0);
    vec3 wo = wo_at((real)0.8), wo_in = wo_at((real)-0.3);
    real p[BSDF_MAX_LOBES], f = fresnel_dielectric((real)0.8, (real)1.5);
    bsdf_sample_record s;
    bsdf_lobe_probabilities(&g, wo, p);
    CHECK_NEAR(p[0], f, 1e-6);
    CHECK(bsdf_lobe_sample(&g, 0, wo, v2(0, 0), &s) && s.is_delta && s.pdf == 1);
    CHECK_NEAR(s.wi.x, -wo.x, 1e-6);
    CHECK_NEAR(s.wi.z, wo.z, 1e-6);
    CHECK_NEAR(s.weight.g, 1, 1e-6);
    CHECK(bsdf_lobe_sample(&g, 1, wo, v2(0, 0), &s) && s.is_delta);
    /* Snell: sin_t = sin_o / 1.5, and the tangent direction is reversed */
    CHECK_NEAR(sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y), 0.6 / 1.5, 1e-6);
    CHECK(s.wi.z < 0 && s.wi.x * wo.x < 0);
    CHECK_NEAR(s.weight.g, 1 / 2.25, 1e-6); /* radiance scaling (n_o/n_i)^2 */
    CHECK_NEAR(v3_length(s.wi), 1, 1e-6);
    /* inside, beyond the critical angle (sin 0.954 > 1/1.5): total internal reflection */
    bsdf_lobe_probabilities(&g, wo_in, p);
    CHECK(p[0] == 1 && p[1] == 0);
    CHECK(!bsdf_lobe_sample(&g, 1, wo_in, v2(0, 0), &s));
    CHECK(bsdf_sample(&g, wo_in, (real)0.999, v2(0, 0), &s) && s.lobe == 0 && s.wi.z < 0);
    /* a Dirac is never hit by eval/pdf */
    CHECK(rgb_is_black(bsdf_eval(&g, wo, v3(-wo.x, -wo.y, wo.z))) && bsdf_pdf(&g, wo, v3(-wo.x, -wo.y, wo.z)) == 0);
}

/* Opaque materials are two-sided: mirroring wo and wi through the surface changes
 * nothing; wi on the other side of wo is black. Dielectrics see the side. */
TEST(bsdf_two_sided)
{
    int c, i;
    for (c = 0; c < N_CASES; ++c) {
        bsdf b = case_bsdf(c);
        int opaque = b.type == MAT_LAMBERT || b.type == MAT_CONDUCTOR || b.type == MAT_PLASTIC;
        for (i = 0; i < 500; ++i) {
            vec3 wo = random_direction(80, (uint32_t)i), wi = random_direction(81, (uint32_t)i);
            vec3 wo_f = v3(wo.x, wo.y, -wo.z), wi_f = v3(wi.x, wi.y, -wi.z);
            if (!opaque) continue;
            CHECK(rel_diff(bsdf_eval(&b, wo, wi).g, bsdf_eval(&b, wo_f, wi_f).g) < 1e-6);
            CHECK(rel_diff(bsdf_pdf(&b, wo, wi), bsdf_pdf(&b, wo_f, wi_f)) < 1e-6);
            if (wo.z * wi.z < 0) CHECK(rgb_is_black(bsdf_eval(&b, wo, wi)) && bsdf_pdf(&b, wo, wi) == 0);
        }
    }
    {
        bsdf rd = make_bsdf(MAT_ROUGH_DIELECTRIC, (real)0.3);
        real p_out[BSDF_MAX_LOBES], p_in[BSDF_MAX_LOBES];
        bsdf_lobe_probabilities(&rd, wo_at((real)0.3), p_out);
        bsdf_lobe_probabilities(&rd, wo_at((real)-0.3), p_in); /* TIR at the macro normal inside */
        CHECK_NEAR(p_in[0], 0.95, 1e-6);
        CHECK_NEAR(p_out[0], fresnel_dielectric((real)0.3, (real)1.5), 1e-6);
        bsdf_lobe_probabilities(&rd, wo_at(1), p_out);
        CHECK_NEAR(p_out[0], 0.05, 1e-6); /* F = 0.04 clamped */
    }
}
