/* A 1-D GRIS estimator: the statistical proof that the MIS weights (mis.c) and the
 * reservoir code (reservoir.c) are right before the renderer uses them.
 *
 * Target domain Omega = [0,1) with integrand f and target p̂ (both 0 on [0.95, 1)):
 *     f(y) = 0.5 + 3 y^2,   p̂(y) = 1 + y   (y < 0.95),   I = int f = 0.475 + 0.95^3.
 * Domains (each one's sample X_i in Omega_i = [0,1) is resampled by RIS from K uniform
 * candidates towards its own target p̂_i, so W_i is itself a UCW, as in ReSTIR):
 *     canon_a  canonical: identity, p̂
 *     canon_b  canonical: identity, p̂, candidates from the pdf 2x instead of uniform
 *     square   T(x) = x^2 on D(T) = [0, 0.8): image [0, 0.64), Jacobian 2x (non-unit)
 *     affine   T(x) = 0.3 + 0.7 x:            image [0.3, 1),  Jacobian 0.7
 *     window   T(x) = x on D(T) = [0.2, 0.9): image [0.2, 0.9) (a "visibility" failure)
 * so supports differ and shifts fail. One run = one GRIS step, the estimate is F(Y) W_Y
 * (GRIS Eq. 3); many independent runs give a z-test of the mean against I.
 *
 * Expected outcomes (docs/mis-derivations.md §7): Talbot, uniform and defensive pairwise
 * are unbiased; constant MIS has the mean  int f(y) c_G(y) / C dy  (c_G(y): confidence of
 * the domains that can produce y), which the test predicts and confirms; dropping the
 * Jacobian from the resampling weight, or not reporting a failed back-shift in the MIS
 * weights, is detected as biased. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/mis.h"
#include "restir/restir/reservoir.h"
#include "test.h"

#define TOY_K 3          /* RIS candidates per domain sample */
#define TOY_MAX_DOMAINS 5
#define TOY_RUNS 60000
#define TOY_Z_LIMIT 4.0  /* |z| above this rejects "the mean is I" (two-sided p ~ 6e-5) */
#define TOY_SUPPORT 0.95 /* f and p̂ vanish on [0.95, 1) */

static real toy_f(real y) { return y < TOY_SUPPORT ? (real)0.5 + 3 * y * y : 0; }
static real toy_target(real y) { return y < TOY_SUPPORT ? 1 + y : 0; }
/* int_0^y f */
static double toy_f_integral(double y)
{
    if (y > TOY_SUPPORT) y = TOY_SUPPORT;
    return 0.5 * y + y * y * y;
}

/* ---- the domains ---- */
typedef enum { CANON_A, CANON_B, SQUARE, AFFINE, WINDOW } toy_kind;

static real kind_target(toy_kind k, real x)
{
    switch (k) {
    case CANON_A:
    case CANON_B: return toy_target(x);
    case SQUARE: return 1 + x;
    case AFFINE: return 2 - x;
    case WINDOW: return (real)0.2 + 3 * x * x;
    }
    return 0;
}

/* T_i: Omega_i -> Omega. Returns 0 if x is outside D(T_i) (the shift fails). */
static int kind_shift(toy_kind k, real x, real *y, real *jacobian)
{
    switch (k) {
    case CANON_A:
    case CANON_B: *y = x; *jacobian = 1; return 1;
    case SQUARE:
        if (!(x > 0 && x < (real)0.8)) return 0;
        *y = x * x;
        *jacobian = 2 * x;
        return 1;
    case AFFINE: *y = (real)0.3 + (real)0.7 * x; *jacobian = (real)0.7; return 1;
    case WINDOW:
        if (!(x >= (real)0.2 && x < (real)0.9)) return 0;
        *y = x;
        *jacobian = 1;
        return 1;
    }
    return 0;
}

/* T_i^{-1}: Omega -> Omega_i with |dT_i^{-1}/dy|. Returns 0 if y is not in the image of T_i.
 * `ignore_domain` is the broken variant: it reports no failure when y is only outside the
 * image because x would leave D(T_i) (as a back-shift that skips the connectability test). */
static int kind_inverse(toy_kind k, real y, real *x, real *jacobian, int ignore_domain)
{
    switch (k) {
    case CANON_A:
    case CANON_B: *x = y; *jacobian = 1; return 1;
    case SQUARE:
        if (!(y > 0) || (!ignore_domain && !(y < (real)0.64))) return 0;
        *x = (real)sqrt((double)y);
        *jacobian = 1 / (2 * *x);
        return 1;
    case AFFINE:
        if (!(y >= (real)0.3)) return 0;
        *x = (y - (real)0.3) / (real)0.7;
        *jacobian = 1 / (real)0.7;
        return 1;
    case WINDOW:
        if (!ignore_domain && !(y >= (real)0.2 && y < (real)0.9)) return 0;
        *x = y;
        *jacobian = 1;
        return 1;
    }
    return 0;
}

/* "p̂ from i" at y (GRIS Eq. 35), 0 when the back-shift fails. */
static real toy_p_from(toy_kind k, real y, int ignore_domain)
{
    real x, jac;
    if (!kind_inverse(k, y, &x, &jac, ignore_domain)) return 0;
    return kind_target(k, x) * jac;
}

/* A 1-D sample travels in a path_sample as its single primary-sample number, kept in
 * *number (the numbers are out of line, path_sample.h; only pss[0] is ever read here). */
static void toy_sample(path_sample *s, real x, real target, real *number)
{
    path_sample_clear(s);
    s->technique = PATH_TECH_BSDF;
    s->length = 2;
    s->n_pss = 1;
    s->pss = number;
    s->pss[0] = x;
    path_sample_set_contribution(s, rgb_gray(target));
}

/* RIS from TOY_K candidates (uniform, or pdf 2x for CANON_B) towards kind_target: the
 * reservoir recipe of initial sampling, with ris_candidate_weight's 1/K. */
static int toy_domain_sample(toy_kind k, rng_key key, uint32_t domain, real *x, real *W)
{
    reservoir r;
    real numbers[TOY_K];
    int c;
    reservoir_init(&r);
    for (c = 0; c < TOY_K; ++c) {
        real u = rng_u(key, RNG_TEST, domain, (uint32_t)c);
        real xc = k == CANON_B ? (real)sqrt((double)u) : u;
        real pdf = k == CANON_B ? 2 * xc : 1;
        path_sample s;
        if (!(pdf > 0)) continue;
        toy_sample(&s, xc, kind_target(k, xc), &numbers[c]);
        reservoir_stream(&r, &s, ris_candidate_weight(s.target, 1 / pdf, TOY_K),
                         rng_u(key, RNG_RIS, domain, (uint32_t)c));
    }
    reservoir_finalize(&r);
    if (!path_sample_is_valid(&r.y)) return 0;
    *x = r.y.pss[0];
    *W = r.W;
    return 1;
}

/* ---- one GRIS step ---- */
typedef enum { TOY_CORRECT, TOY_DROP_JACOBIAN, TOY_IGNORE_BACKSHIFT_FAILURE, TOY_FALCOR_PAIR_WITHOUT_K } toy_variant;

typedef struct {
    const char *name;
    int m, n_canonical;
    toy_kind kind[TOY_MAX_DOMAINS];
    real c[TOY_MAX_DOMAINS];
} toy_config;

static const toy_config config_one_canonical = {
    "R=1", 4, 1, {CANON_A, SQUARE, AFFINE, WINDOW, CANON_A}, {1, 2, 0.5, 3, 0}};
static const toy_config config_two_canonical = {
    "R=2", 5, 2, {CANON_A, CANON_B, SQUARE, AFFINE, WINDOW}, {1, 0.7, 2, 0.5, 3}};

/* A planted broken weight: the Falcor form (mis_pairwise_defensive_falcor) whose
 * neighbour side forgets the 1/k of the canonical term, c_i q_i / (c_i q_i + c_R p̂), while
 * the canonical side keeps it: the weights no longer sum to 1 (R = 1 only). */
static real falcor_without_k(const mis_input *in, int i, int j)
{
    real n = (real)(in->m - 1), p = mis_ptarget(in, 0, j), c_R = in->confidence[0], q, a;
    if (i == 0) return mis_pairwise_defensive_falcor(in, i, j, NULL);
    q = mis_ptarget(in, i, j);
    a = in->confidence[i] * q;
    return a + c_R * p > 0 ? a / (a + c_R * p) / (n + 1) : 0;
}

/* The selected y and its W of one GRIS step; 0 if the reservoir is empty. */
static int toy_gris_select(const toy_config *cfg, mis_family family, toy_variant variant, uint32_t run, real *y_out,
                           real *W_out);

/* F(Y) W_Y of one run. */
static real toy_gris_run(const toy_config *cfg, mis_family family, toy_variant variant, uint32_t run)
{
    real y, W;
    if (!toy_gris_select(cfg, family, variant, run, &y, &W)) return 0;
    return toy_f(y) * W; /* GRIS Eq. 3 */
}

static int toy_gris_select(const toy_config *cfg, mis_family family, toy_variant variant, uint32_t run, real *y_out,
                           real *W_out)
{
    rng_key key = rng_key_make(test_seed() ^ 0x6a09e667u, run, 0);
    real y[TOY_MAX_DOMAINS], W[TOY_MAX_DOMAINS], J[TOY_MAX_DOMAINS];
    real ptarget[TOY_MAX_DOMAINS * TOY_MAX_DOMAINS], numbers[TOY_MAX_DOMAINS];
    int ok[TOY_MAX_DOMAINS], i, j, M = cfg->m;
    mis_input in;
    reservoir r;
    for (j = 0; j < M; ++j) {
        real x;
        ok[j] = toy_domain_sample(cfg->kind[j], key, (uint32_t)j, &x, &W[j]) &&
                kind_shift(cfg->kind[j], x, &y[j], &J[j]);
        if (!ok[j]) continue;
        for (i = 0; i < M; ++i) /* the "p̂ from i" matrix at y_j (mis.h) */
            ptarget[i * M + j] = i == j ? kind_target(cfg->kind[j], x) / J[j]
                                        : toy_p_from(cfg->kind[i], y[j], variant == TOY_IGNORE_BACKSHIFT_FAILURE);
    }
    in.m = M;
    in.n_canonical = cfg->n_canonical;
    in.confidence = cfg->c;
    in.ptarget = ptarget;
    reservoir_init(&r);
    for (j = 0; j < M; ++j) {
        path_sample s;
        real w;
        if (ok[j]) {
            real jac = variant == TOY_DROP_JACOBIAN ? 1 : J[j];
            toy_sample(&s, y[j], toy_target(y[j]), &numbers[j]);
            real m = variant == TOY_FALCOR_PAIR_WITHOUT_K ? falcor_without_k(&in, j, j) : mis_weight(family, &in, j, j, NULL);
            w = gris_resampling_weight(m, s.target, W[j], jac); /* GRIS Eq. 19 */
            reservoir_stream(&r, &s, w, rng_u(key, RNG_RIS, 100, (uint32_t)j));
        }
        reservoir_add_confidence(&r, cfg->c[j]);
    }
    reservoir_finalize(&r); /* GRIS Eq. 22 */
    if (!path_sample_is_valid(&r.y)) return 0;
    *y_out = r.y.pss[0];
    *W_out = r.W;
    return 1;
}

typedef struct {
    double mean, std_error;
} toy_stats;

static toy_stats toy_run_many(const toy_config *cfg, mis_family family, toy_variant variant)
{
    double sum = 0, sum2 = 0;
    toy_stats s;
    uint32_t run;
    for (run = 0; run < TOY_RUNS; ++run) {
        double v = (double)toy_gris_run(cfg, family, variant, run);
        sum += v;
        sum2 += v * v;
    }
    s.mean = sum / TOY_RUNS;
    s.std_error = sqrt((sum2 / TOY_RUNS - s.mean * s.mean) / (TOY_RUNS - 1));
    return s;
}

static double toy_integral(void) { return toy_f_integral(1.0); }

/* Which domains of the configuration can produce y (the set G(y) of Eq. 20). */
static real covering_confidence(const toy_config *cfg, double y)
{
    real c = 0;
    int i;
    for (i = 0; i < cfg->m; ++i)
        if (toy_p_from(cfg->kind[i], (real)y, 0) > 0) c += cfg->c[i];
    return c;
}

/* docs/mis-derivations.md §7: E[F(Y) W_Y] = int f(y) sum_{i in G(y)} m_i(y) dy, which for
 * constant weights is int f(y) c_G(y) / C dy. G(y) is piecewise constant with breakpoints
 * at the image boundaries, so the integral is exact from the antiderivative of f. */
static double constant_mis_expected_mean(const toy_config *cfg)
{
    static const double breaks[] = {0, 0.2, 0.3, 0.64, 0.9, TOY_SUPPORT};
    double total = 0, C = 0;
    int i;
    for (i = 0; i < cfg->m; ++i) C += cfg->c[i];
    for (i = 0; i + 1 < (int)(sizeof breaks / sizeof breaks[0]); ++i) {
        double mid = 0.5 * (breaks[i] + breaks[i + 1]);
        total += (toy_f_integral(breaks[i + 1]) - toy_f_integral(breaks[i])) * covering_confidence(cfg, mid) / C;
    }
    return total;
}

static int toy_report(const char *what, const toy_config *cfg, mis_family f, toy_stats s, double expected,
                      double *z)
{
    *z = (s.mean - expected) / s.std_error;
    if (getenv("RESTIR_TEST_VERBOSE")) /* the numbers behind the verdicts */
        printf("    toy %s %-9s %-28s mean %.5f +- %.5f  expected %.5f  z = %+.2f\n", cfg->name, mis_family_name(f),
               what, s.mean, s.std_error, expected, *z);
    return fabs(*z) < TOY_Z_LIMIT;
}

/* GRIS Eqs. 36-38 with confidences give an unbiased GRIS estimator with failed shifts,
 * different supports, a non-unit Jacobian, resampled inputs (RIS UCWs) and |R| = 1 or 2. */
TEST(mis_toy_gris_unbiased)
{
    const toy_config *configs[2] = {&config_one_canonical, &config_two_canonical};
    static const mis_family families[3] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    int c, f;
    for (c = 0; c < 2; ++c) {
        for (f = 0; f < 3; ++f) {
            double z;
            toy_stats s = toy_run_many(configs[c], families[f], TOY_CORRECT);
            CHECKF(toy_report("(unbiased)", configs[c], families[f], s, toy_integral(), &z),
                   "%s %s: biased? z = %.2f", configs[c]->name, mis_family_name(families[f]), z);
        }
    }
}

/* Constant MIS where supports differ (GRIS §5.6) is DETECTED as biased, and its mean is the
 * one predicted by docs/mis-derivations.md §7. */
TEST(mis_toy_constant_mis_biased)
{
    const toy_config *configs[2] = {&config_one_canonical, &config_two_canonical};
    int c;
    for (c = 0; c < 2; ++c) {
        double z, z_pred, predicted = constant_mis_expected_mean(configs[c]);
        toy_stats s = toy_run_many(configs[c], MIS_CONSTANT, TOY_CORRECT);
        CHECKF(!toy_report("(vs I: must reject)", configs[c], MIS_CONSTANT, s, toy_integral(), &z),
               "%s: constant MIS not detected as biased (z = %.2f)", configs[c]->name, z);
        CHECKF(toy_report("(vs predicted biased mean)", configs[c], MIS_CONSTANT, s, predicted, &z_pred),
               "%s: constant MIS mean %.5f differs from the predicted %.5f (z = %.2f)", configs[c]->name, s.mean,
               predicted, z_pred);
    }
}

/* Broken variants (the "ablations" of docs/statistics.md): the same z-test rejects
 *  - a resampling weight without the shift Jacobian |dT/dx| (GRIS Eq. 19 without its last
 *    factor; T(x) = x^2 and 0.7x have non-unit Jacobians), for every family;
 *  - MIS weights whose back-shift does not report failure (y outside T_i's image treated as
 *    reachable: the invertibility pitfall 3 of docs/restir-pt.md §11), for Talbot and defensive. */
TEST(mis_toy_broken_weights_detected)
{
    static const mis_family families[3] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    const toy_config *cfg = &config_one_canonical;
    int f;
    double z;
    for (f = 0; f < 3; ++f) {
        toy_stats s = toy_run_many(cfg, families[f], TOY_DROP_JACOBIAN);
        CHECKF(!toy_report("dropped Jacobian (must reject)", cfg, families[f], s, toy_integral(), &z),
               "%s: dropped Jacobian not detected (z = %.2f)", mis_family_name(families[f]), z);
    }
    for (f = 0; f < 3; f += 2) {
        toy_stats s = toy_run_many(cfg, families[f], TOY_IGNORE_BACKSHIFT_FAILURE);
        CHECKF(!toy_report("unreported failure (must reject)", cfg, families[f], s, toy_integral(), &z),
               "%s: unreported back-shift failure not detected (z = %.2f)", mis_family_name(families[f]), z);
    }
}

/* ---- both confidence forms of defensive pairwise MIS (issue 31; docs/mis-derivations.md §3.5) ----
 * An RGB integrand, one function per channel, all 0 on [0.95, 1) like f:
 *     R: 0.5 + 3 y^2,   G: 2 - y,   B: 0.2 + 4 y^3. */
static double toy_rgb_integral(int ch, double y)
{
    if (y > TOY_SUPPORT) y = TOY_SUPPORT;
    if (ch == 0) return 0.5 * y + y * y * y;
    if (ch == 1) return 2 * y - 0.5 * y * y;
    return 0.2 * y + y * y * y * y;
}
static double toy_rgb(int ch, double y)
{
    if (y >= TOY_SUPPORT) return 0;
    return ch == 0 ? 0.5 + 3 * y * y : ch == 1 ? 2 - y : 0.2 + 4 * y * y * y;
}

typedef struct {
    double sum[2][3], sum2[2][3], dsum[3], dsum2[3]; /* per form and channel; paired differences */
} toy_paired;

/* Runs the stochastic form (MIS_PAIRWISE_DEFENSIVE) and the Falcor form (or the planted
 * `variant` of it) on the same inputs, run by run (the RNG addresses depend on the run
 * only), and accumulates F(Y) W_Y per channel and the paired differences. */
static void toy_paired_runs(const toy_config *cfg, toy_variant falcor_variant, toy_paired *t)
{
    uint32_t run;
    int ch, form;
    memset(t, 0, sizeof *t);
    for (run = 0; run < TOY_RUNS; ++run) {
        double v[2][3];
        for (form = 0; form < 2; ++form) {
            real y, W;
            int ok = form == 0 ? toy_gris_select(cfg, MIS_PAIRWISE_DEFENSIVE, TOY_CORRECT, run, &y, &W)
                               : toy_gris_select(cfg, MIS_PAIRWISE_DEFENSIVE_FALCOR, falcor_variant, run, &y, &W);
            for (ch = 0; ch < 3; ++ch) {
                v[form][ch] = ok ? toy_rgb(ch, (double)y) * (double)W : 0;
                t->sum[form][ch] += v[form][ch];
                t->sum2[form][ch] += v[form][ch] * v[form][ch];
            }
        }
        for (ch = 0; ch < 3; ++ch) {
            double d = v[0][ch] - v[1][ch];
            t->dsum[ch] += d;
            t->dsum2[ch] += d * d;
        }
    }
}

/* z of a mean against `expected` from the sums of n values. */
static double toy_z(double sum, double sum2, double expected)
{
    double n = TOY_RUNS, mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0) / (n - 1));
    return se > 0 ? (mean - expected) / se : (mean == expected ? 0 : INFINITY);
}

/* Both confidence forms are unbiased, per channel R, G, B (z of each form's mean against
 * the integral, and the paired z of their difference, which shares the inputs and so has
 * far less variance); the same test rejects a planted broken Falcor weight (the neighbour's
 * pair without the canonical's 1/k: its weights do not sum to 1) in every channel. */
TEST(mis_toy_pairwise_confidence_forms_unbiased)
{
    const toy_config *configs[2] = {&config_one_canonical, &config_two_canonical};
    toy_paired t;
    int c, ch, form;
    for (c = 0; c < 2; ++c) {
        toy_paired_runs(configs[c], TOY_CORRECT, &t);
        for (ch = 0; ch < 3; ++ch) {
            double I = toy_rgb_integral(ch, 1.0), zd = toy_z(t.dsum[ch], t.dsum2[ch], 0);
            for (form = 0; form < 2; ++form) {
                double z = toy_z(t.sum[form][ch], t.sum2[form][ch], I);
                if (getenv("RESTIR_TEST_VERBOSE"))
                    printf("    %s %-10s channel %c: z vs I = %+.2f (paired z %+.2f)\n", configs[c]->name,
                           form ? "falcor" : "stochastic", "RGB"[ch], z, zd);
                CHECKF(fabs(z) < TOY_Z_LIMIT, "%s, %s form, channel %c: mean %.6f vs I %.6f, z = %.2f", configs[c]->name,
                       form ? "falcor" : "stochastic", "RGB"[ch], t.sum[form][ch] / TOY_RUNS, I, z);
            }
            CHECKF(fabs(zd) < TOY_Z_LIMIT, "%s, channel %c: paired difference stochastic - falcor, z = %.2f",
                   configs[c]->name, "RGB"[ch], zd);
        }
    }
    toy_paired_runs(&config_one_canonical, TOY_FALCOR_PAIR_WITHOUT_K, &t);
    for (ch = 0; ch < 3; ++ch) {
        double I = toy_rgb_integral(ch, 1.0), z = toy_z(t.sum[1][ch], t.sum2[1][ch], I),
               zd = toy_z(t.dsum[ch], t.dsum2[ch], 0);
        if (getenv("RESTIR_TEST_VERBOSE"))
            printf("    planted falcor without 1/k, channel %c: z vs I = %+.2f, paired z = %+.2f\n", "RGB"[ch], z, zd);
        CHECKF(fabs(z) >= TOY_Z_LIMIT && fabs(zd) >= TOY_Z_LIMIT,
               "the planted broken weight passed in channel %c (z = %.2f, paired z = %.2f)", "RGB"[ch], z, zd);
    }
}
