/* MCMC mutations (mutate.h; Mutations §3 Algorithm 3, §4.1, §4.3; docs/mutations.md).
 *
 * - Kelemen's perturbation is symmetric: the mirrored number undoes it, values stay in [0,1).
 * - The 1-D toy with a known integral (Eq. 18, App. A): RIS from M uniform candidates with
 *   target p̂, then N Metropolis-Hastings steps with the perturbation, W updated by Eq. 16:
 *   E[g(X) W] = integral of g, without burn-in. Dropping the W update is detected.
 * - The kernel round trip per strategy (rv, pp, fp): from z = propose(y, xi), the mirrored
 *   numbers give back y and the kernel ratios multiply to 1 (reversibility of the deterministic
 *   part of the kernel).
 * - Eq. 20 checked numerically: the code's ratio A(z)/A(y) against a finite-difference
 *   determinant of the map from the current path's determined numbers to the proposal's.
 * - Detailed balance by histogram: the MH flux p̂(u) T(u->v) a(u->v) between bins of the
 *   state is symmetric (flux i->j = flux j->i), and is not with the symmetric-kernel ablation.
 * - The real-time pipeline with mutations agrees with the reference path tracer under the
 *   K-run statistics of `restir check` ({1, 5} mutations x {after temporal, after initial});
 *   --ablate mutation-w and --ablate rv-kernel are detected. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/lights.h"
#include "restir/restir/mutate.h"
#include "restir/restir/shift.h"
#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"
#include "pt_util.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

TEST(mutate_perturb_symmetric_in_range)
{
    rng_key key = rng_key_make(test_seed(), 17, 3);
    int i, bad = 0;
    double worst = 0;
    for (i = 0; i < 20000; ++i) {
        real u = rng_u(key, RNG_TEST, 0, (uint32_t)i), xi = rng_u(key, RNG_TEST, 1, (uint32_t)i);
        real mirror = xi < (real)0.5 ? xi + (real)0.5 : xi - (real)0.5; /* same size, other sign */
        real v = mutate_perturb(u, xi), w = mutate_perturb(v, mirror);
        double step = fabs((double)v - (double)u), back = fabs((double)w - (double)u);
        if (step > 0.5) step = 1 - step;
        if (back > 0.5) back = 1 - back;
        if (!(v >= 0 && v < 1) || step < MUTATE_S1 * 0.999 || step > MUTATE_S2 * 1.001) bad++;
        if (back > worst) worst = back;
    }
    CHECKF(bad == 0, "%d perturbations out of range or outside (s1, s2]", bad);
    CHECKF(worst < 1e-12 * (sizeof(real) == 8 ? 1 : 1e6), "the mirrored perturbation misses u by %g", worst);
}

/* ---- the 1-D toy ---------------------------------------------------------------------- */

static double toy_target(double x) { return 0.05 + 5 * x * x * x * x; } /* p̂ on [0,1) */
static double toy_integrand(double x) { return x < 0.3 ? 1.0 : 3 * x; } /* g; integral 0.3 + 1.5 (1 - 0.09) */

/* One estimate g(X) W of the toy (RIS with M uniform candidates, N mutations). */
static double toy_estimate(rng_key key, int m, int n, int keep_w)
{
    real wsum = 0, x = 0, W;
    uint32_t invalid = 0;
    int i;
    for (i = 0; i < m; ++i) {
        real c = rng_u(key, RNG_TEST, 0, (uint32_t)i);
        if (wrs_update(&wsum, (real)toy_target(c) / m, rng_u(key, RNG_TEST, 1, (uint32_t)i), &invalid)) x = c;
    }
    W = wsum / (real)toy_target(x); /* GRIS Eq. 22 with the 1/M MIS weights */
    for (i = 0; i < n; ++i) {
        real z = mutate_perturb(x, rng_u(key, RNG_MUTATE, 1, (uint32_t)i));
        real a = mutate_acceptance((real)toy_target(x), (real)toy_target(z), 1); /* symmetric kernel */
        if (rng_u(key, RNG_MUTATE, 2, (uint32_t)i) < a) {
            if (!keep_w) W = mutate_weight(W, (real)toy_target(x), (real)toy_target(z)); /* Eq. 23 */
            x = z;
        }
    }
    return toy_integrand(x) * W;
}

static double toy_z(int m, int n, int keep_w, int trials)
{
    double sum = 0, sum2 = 0, exact = 0.3 + 1.5 * (1 - 0.09), mean, var;
    int t;
    for (t = 0; t < trials; ++t) {
        double v = toy_estimate(rng_key_make(test_seed() * 977u + (uint32_t)n, (uint32_t)t, (uint32_t)m), m, n, keep_w);
        sum += v;
        sum2 += v * v;
    }
    mean = sum / trials;
    var = (sum2 / trials - mean * mean) / (trials - 1);
    return (mean - exact) / sqrt(var);
}

TEST(mutate_toy_unbiased_without_burn_in)
{
    static const int ms[] = {1, 4}, ns[] = {1, 5, 50};
    size_t i, j;
    for (i = 0; i < 2; ++i)
        for (j = 0; j < 3; ++j) {
            double z = toy_z(ms[i], ns[j], 0, 40000);
            if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  toy M %d N %d: z %.2f\n", ms[i], ns[j], z);
            CHECKF(fabs(z) < 4.5, "toy M %d, %d mutations: z = %.2f against the exact integral", ms[i], ns[j], z);
        }
    {
        double z = toy_z(1, 50, 1, 40000);
        if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  toy without the W update: z %.2f\n", z);
        CHECKF(fabs(z) > 6, "toy: dropping the Eq. 16 W update was not detected (z = %.2f)", z);
    }
}

/* ---- the kernel round trip ------------------------------------------------------------------ */

static real mirror_of(real xi) { return xi < (real)0.5 ? xi + (real)0.5 : xi - (real)0.5; }

/* For reservoirs of a real frame: z = propose(y, xi); the mirrored numbers propose y again
 * from z (same p̂, same x_k), and ratio(y->z) ratio(z->y) = 1. */
static void round_trip(const char *path, int shift, int strategy, int *checked, double *worst)
{
    rt_frame f;
    int x, y;
    if (rt_frame_open(&f, path, 16, shift, 6, test_seed())) return;
    for (y = 0; y < f.s.height && !test_has_failed(); ++y)
        for (x = 0; x < f.s.width && !test_has_failed(); ++x) {
            const path_sample *py = &f.res.reservoirs[y * f.s.width + x].y;
            path_vertex v;
            path_sample u, z, back;
            real xi[PATH_MAX_PSS], mirror[PATH_MAX_PSS], xl[2], r1, r2;
            real un[PATH_MAX_PSS], zn[PATH_MAX_PSS], bn[PATH_MAX_PSS]; /* their numbers (path_sample.h) */
            double tol = sizeof(real) == 8 ? 1e-3 : 2e-2; /* float geometry (vec3f hits) */
            rng_key key = rng_key_make(test_seed(), (uint32_t)(y * f.s.width + x), 5);
            int i;
            if (!path_sample_is_valid(py) || mutate_bsdf_vertices(py) == 0 || !rt_primary_vertex(&f.s, x, y, &v)) continue;
            for (i = 0; i < PATH_MAX_PSS; ++i) {
                xi[i] = rng_u(key, RNG_TEST, 0, (uint32_t)i);
                mirror[i] = mirror_of(xi[i]);
            }
            xl[0] = rng_u(key, RNG_TEST, 1, 0);
            xl[1] = rng_u(key, RNG_TEST, 1, 1);
            u.pss = un;
            z.pss = zn;
            back.pss = bn;
            if (mutate_explicit(&f.c, &v, py, xl, &u)) continue;
            if (mutate_propose(&f.c, &v, &u, strategy, xi, xl, &z, &r1) >= 0) continue;
            /* z's pss is its explicit vector: the perturbed numbers exactly, the determined ones
             * by inverse sampling; the mirrored step must return to y. */
            if (mutate_propose(&f.c, &v, &z, strategy, mirror, xl, &back, &r2) >= 0) continue; /* grazing: float */
            ++*checked;
            if (fabs((double)(r1 * r2) - 1) > *worst) *worst = fabs((double)(r1 * r2) - 1);
            CHECKF(fabs((double)(r1 * r2) - 1) < tol, "%s %s (%d,%d): kernel ratios %g x %g != 1", path,
                   mutate_strategy_names[strategy], x, y, (double)r1, (double)r2);
            CHECKF(fabs((double)back.target - (double)py->target) <= tol * (double)py->target,
                   "%s %s (%d,%d): the mirrored mutation gives p̂ %g, not %g", path, mutate_strategy_names[strategy], x,
                   y, (double)back.target, (double)py->target);
            CHECKF(back.rc_k == py->rc_k, "%s %s (%d,%d): the mirrored mutation has k = %d, not %d", path,
                   mutate_strategy_names[strategy], x, y, back.rc_k, py->rc_k);
        }
    rt_frame_close(&f);
}

TEST(mutate_kernel_round_trip)
{
    int strategy;
    for (strategy = 0; strategy < MUTATE_STRATEGY_COUNT; ++strategy) {
        int checked = 0;
        double worst = 0;
        round_trip("scenes/cornell-glossy.scene", RESTIR_SHIFT_HYBRID, strategy, &checked, &worst);
        round_trip("scenes/glass.scene", RESTIR_SHIFT_HYBRID, strategy, &checked, &worst);
        CHECKF(checked >= 50, "%s: only %d round trips checked", mutate_strategy_names[strategy], checked);
        if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  %s: %d round trips, worst |ratio product - 1| %.2g\n",
                                                 mutate_strategy_names[strategy], checked, worst);
    }
}

/* ---- the pipeline against the path tracer ------------------------------------------------ */

#define ALPHA 1e-3
#define LAST_FRAME 4
#ifndef FLUX_DRAWS
#define FLUX_DRAWS 100000
#endif
#ifndef MUTATE_KERNEL_ITERATIONS
#define MUTATE_KERNEL_ITERATIONS 200
#endif
#ifndef MUTATE_KERNEL_RUNS
#define MUTATE_KERNEL_RUNS 24
#endif

typedef struct {
    int shift, mutations, after, ablation;
    double roughness_threshold; /* 0: the default */
    int strategy;               /* enum mutate_strategy (0: rv) */
} mutate_case;

/* The luminance of F W is exactly unchanged by a mutation (Eq. 17 with p̂ = luminance(F)),
 * so only the colour can show a wrong kernel: with g_channel >= 0 every run image is
 * replaced by that channel in all three (the global luminance test then tests it). */
static int g_channel = -1;

static int keep_last(void *user, int frame, const image *img, const restir_stats *st, rerror *e)
{
    image c;
    size_t i, n = (size_t)img->width * (size_t)img->height;
    int status;
    (void)st;
    if (frame != LAST_FRAME) return 0;
    if (g_channel < 0) return check_side_add_run(user, img, "run", e);
    if (image_alloc(&c, img->width, img->height, e)) return -1;
    for (i = 0; i < n; ++i) c.px[3 * i] = c.px[3 * i + 1] = c.px[3 * i + 2] = img->px[3 * i + (size_t)g_channel];
    status = check_side_add_run(user, &c, "run", e);
    image_free(&c);
    return status;
}

/* The red and the green Lambertian materials of the two-tone wall. */
static void red_and_green(scene *s, uint32_t *red, uint32_t *green)
{
    *red = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.9, (real)0.1, (real)0.1), rgb_gray(0));
    *green = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.1, (real)0.9, (real)0.1), rgb_gray(0));
}

/* The floor (material floor) and the back wall, its left half red, its right half green. */
static void floor_and_two_tone_wall(scene *s, uint32_t floor, uint32_t red, uint32_t green)
{
    test_scene_quad(s, v3f(-1, 0, -1), v3f(0, 0, 2), v3f(2, 0, 0), floor);
    test_scene_quad(s, v3f(-1, 0, 0.6f), v3f(0, 1, 0), v3f(1, 0, 0), red);
    test_scene_quad(s, v3f(0, 0, 0.6f), v3f(0, 1, 0), v3f(1, 0, 0), green);
}

/* For the rv kernel (Mutations Eq. 20): a diffuse floor (x_1, connectable), a wall half red,
 * half green (x_2 = the reconnection vertex, k = 2), a white panel in front of the red half
 * facing the wall (x_3, kept by rv) and a light above the gap between them, facing down (x_4,
 * NEE). A(z) = p(v_1, v_2) G(z_2 -> x_3) varies strongly over the wall, so a chain without
 * the kernel ratio drifts towards small A (away from the panel, towards green). */
static int make_panel(scene *s, int res)
{
    uint32_t white, red, green, light;
    if (test_scene_begin(s, 12, 4)) return -1;
    white = test_scene_material(s, MAT_LAMBERT, rgb_gray((real)0.8), rgb_gray(0));
    red_and_green(s, &red, &green);
    light = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(10, 10, 10));
    floor_and_two_tone_wall(s, white, red, green);
    test_scene_quad(s, v3f(-0.6f, 0.05f, 0.5f), v3f(0.4f, 0, 0), v3f(0, 0.4f, 0), white);
    test_scene_quad(s, v3f(-0.6f, 0.5f, 0.51f), v3f(0.4f, 0, 0), v3f(0, 0, 0.08f), light);
    test_scene_camera(s, v3(0, (real)1.2, (real)-0.9), v3(0, 0, (real)0.05), v3(0, 1, 0), 40, res);
    return test_scene_prepare(s);
}

static int g_first_frame = 0; /* 0, or LAST_FRAME for chains after initial without temporal reuse */

static int pipeline_side(const scene *s, const restir_options *o, int runs, check_side *side)
{
    restir_stats total;
    rerror e;
    if (check_side_begin_runs(side, s->width, s->height, 4, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    if (rt_sequence_runs(s, o, g_first_frame, LAST_FRAME, runs, keep_last, side, &total)) {
        check_side_free(side);
        return -1;
    }
    if (getenv("RESTIR_TEST_VERBOSE") && o->mutation.count > 0)
        fprintf(stderr, "    run 0: %llu pixels, %llu skipped (%llu empty), %llu proposals, %llu accepted\n",
                (unsigned long long)total.mutate.pixels, (unsigned long long)total.mutate.skipped,
                (unsigned long long)total.mutate.skip[MUTATE_SKIP_EMPTY], (unsigned long long)total.mutate.proposals,
                (unsigned long long)total.mutate.accepted);
    if (check_side_end_runs(side, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        check_side_free(side);
        return -1;
    }
    return 0;
}

/* With RESTIR_TEST_VERBOSE: the case and the numbers of its check ("paired" when `vs` is not
 * empty). */
static void verbose_line(const char *name, const char *vs, const mutate_case *m, const check_result *c)
{
    if (!getenv("RESTIR_TEST_VERBOSE")) return;
    fprintf(stderr, "  %s%s %s shift %s %d mutations after %s ablate %s%s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks, worst z %.2f\n",
            *vs ? "paired " : "", name, mutate_strategy_names[m->strategy], restir_shift_names[m->shift], m->mutations,
            mutate_after_names[m->after], restir_ablation_names[m->ablation], vs, rt_mean_z(c), c->lum_a.mean,
            c->lum_b.mean, c->rejected, c->tests, c->worst.z);
}

static void case_options(const mutate_case *m, restir_options *o)
{
    restir_options_default(o);
    o->seed = test_seed() * 1187u + 31u * (uint32_t)m->shift + 7u * (uint32_t)m->mutations + (uint32_t)m->after +
              1000u * (uint32_t)m->ablation + 100003u * (uint32_t)m->strategy;
    o->shift = m->shift;
    o->spatial.mis = MIS_PAIRWISE_DEFENSIVE;
    o->spatial_passes = 0;
    o->candidates = 2;
    o->max_depth = 4;
    o->threads = 2;
    o->mutation.count = m->mutations;
    o->mutation.strategy = m->strategy;
    o->mutation.stages = m->after;
    o->ablation = m->ablation;
    if (m->roughness_threshold > 0) o->roughness_threshold = m->roughness_threshold;
}

/* biased 1: must be detected; 0: must agree; 2: measure only. Returns the mean z. */
static double expect(const scene *s, const char *name, const check_side *pt, const mutate_case *m, int runs,
                     int biased)
{
    restir_options o;
    check_side side;
    check_options opt;
    check_result c;
    rerror e;
    double z = 0;
    case_options(m, &o);
    if (pipeline_side(s, &o, runs, &side)) return 0;
    check_options_default(&opt);
    opt.alpha = ALPHA;
    opt.block_size = 4;
    if (check_compare(&side, pt, &opt, &c, &e)) {
        test_fail(__FILE__, __LINE__, "check_compare: %s", e.msg);
        check_side_free(&side);
        return 0;
    }
    z = rt_mean_z(&c);
    verbose_line(name, "", m, &c);
    if (biased == 0)
        if (c.different) test_fail(__FILE__, __LINE__, "%s %s shift %s, %d mutations after %s: differs from the path tracer (mean z %.2f, %ld of %ld blocks, worst z %.2f)",
               name, mutate_strategy_names[m->strategy], restir_shift_names[m->shift], m->mutations, mutate_after_names[m->after], z, c.rejected, c.tests,
               c.worst.z);
    if (biased == 1)
        if (!c.different) test_fail(__FILE__, __LINE__, "%s: --ablate %s was not detected (mean z %.2f, worst z %.2f)", name,
               restir_ablation_names[m->ablation], z, c.worst.z);
    check_result_free(&c);
    check_side_free(&side);
    return z;
}

static int open_scene(const char *path, int res, int runs, scene *s, check_side *pt)
{
    if (rt_load_scene(path, res, s)) return -1;
    if (rt_pt_side_at(s, test_seed() * 7919u + 5, runs, 64, 4, 0, LAST_FRAME, 4, pt)) {
        scene_free(s);
        return -1;
    }
    return 0;
}

static void run_cases(const char *path, int res, int runs, const mutate_case *cases, size_t n, int biased)
{
    scene s;
    check_side pt;
    size_t i;
    if (open_scene(path, res, runs, &s, &pt)) return;
    for (i = 0; i < n && !test_has_failed(); ++i) expect(&s, path, &pt, &cases[i], runs, biased);
    check_side_free(&pt);
    scene_free(&s);
}

TEST(mutate_pipeline_unbiased_subset)
{
    static const mutate_case cases[] = {
        {RESTIR_SHIFT_HYBRID, 1, MUTATE_AFTER_TEMPORAL, 0, 0, MUTATE_RV},
        {RESTIR_SHIFT_HYBRID, 5, MUTATE_AFTER_INITIAL, 0, 0, MUTATE_RV},
        {RESTIR_SHIFT_HYBRID, 5, MUTATE_AFTER_TEMPORAL, 0, 0, MUTATE_PP},
        {RESTIR_SHIFT_REPLAY, 1, MUTATE_AFTER_INITIAL | MUTATE_AFTER_TEMPORAL, 0, 0, MUTATE_FP},
    };
    run_cases("scenes/cornell-glossy.scene", 16, 12, cases, sizeof cases / sizeof cases[0], 0);
}

/* Paired (docs/statistics.md "Paired check"): case a against the same pipeline without
 * mutations on the SAME seeds (the frames share their initial and temporal samples, so the
 * difference isolates the mutations). biased as in expect(). */
static double expect_paired(const char *path, int res, int runs, const mutate_case *m, int biased)
{
    scene s;
    restir_options oa, ob;
    check_side a, b;
    check_result c;
    double z = 0;
    if (!strcmp(path, "two-tone")) {
        if (rt_make_two_tone(&s, res)) return 0;
    } else if (!strcmp(path, "panel")) {
        if (make_panel(&s, res)) return 0;
    } else if (rt_load_scene(path, res, &s))
        return 0;
    case_options(m, &oa);
    if (!strcmp(path, "two-tone") || !strcmp(path, "panel")) oa.paths = RESTIR_PATHS_INDIRECT; /* DI would dominate */
    if (m->after == MUTATE_AFTER_INITIAL) { /* one long chain per frame: only the last frame */
        oa.temporal.enabled = 0;
        g_first_frame = LAST_FRAME;
    }
    ob = oa;
    ob.mutation.count = 0;
    ob.ablation = RESTIR_ABLATE_NONE;
    if (pipeline_side(&s, &oa, runs, &a)) {
        scene_free(&s);
        return 0;
    }
    if (pipeline_side(&s, &ob, runs, &b)) {
        check_side_free(&a);
        scene_free(&s);
        return 0;
    }
    if (rt_compare_paired(&a, &b, ALPHA, 4, &c) == 0) {
        z = rt_mean_z(&c);
        verbose_line(path, " vs none", m, &c);
        if (biased == 0)
            if (c.different) test_fail(__FILE__, __LINE__, "paired %s shift %s, %d mutations after %s: mutations change the mean (z %.2f, worst %.2f)",
                   path, restir_shift_names[m->shift], m->mutations, mutate_after_names[m->after], z, c.worst.z);
        if (biased == 1)
            if (!c.different) test_fail(__FILE__, __LINE__, "paired %s: --ablate %s was not detected (mean z %.2f, worst z %.2f)", path,
                   restir_ablation_names[m->ablation], z, c.worst.z);
        check_result_free(&c);
    }
    check_side_free(&a);
    check_side_free(&b);
    scene_free(&s);
    g_first_frame = 0;
    return z;
}

TEST(mutate_paired_on_off)
{
    static const mutate_case on = {RESTIR_SHIFT_HYBRID, 5, MUTATE_AFTER_TEMPORAL, 0, 0, MUTATE_RV};
    expect_paired("scenes/glass.scene", 16, 12, &on, 0);
}

/* Paired on/off per strategy in a colour channel (two-tone: red), and --ablate mutation-w
 * detected by the pipeline (the exact test mutate_luminance_invariant_exact detects it in
 * make test). */
TEST_LONG(mutate_paired_on_off_and_ablations_detected_long)
{
    static const mutate_case w = {RESTIR_SHIFT_HYBRID, 50, MUTATE_AFTER_TEMPORAL, RESTIR_ABLATE_MUTATION_W, 0, MUTATE_RV};
    int strategy;
    expect_paired("scenes/cornell-glossy.scene", 16, 40, &w, 1);
    g_channel = 0; /* red: the luminance cannot move (Eq. 17) */
    for (strategy = 0; strategy < MUTATE_STRATEGY_COUNT; ++strategy) {
        mutate_case tone_on = {RESTIR_SHIFT_HYBRID, 20, MUTATE_AFTER_TEMPORAL, 0, 0.5, 0};
        tone_on.strategy = strategy;
        expect_paired("two-tone", 16, 16, &tone_on, 0);
    }
    g_channel = -1;
}

/* The rv kernel ratio (Mutations Eq. 20) in the pipeline: on the panel scene, long chains
 * after initial resampling agree with no mutations in the red channel (paired, same seeds);
 * with the ratio dropped (--ablate rv-kernel) the difference is MEASURED, not asserted: the
 * per-step asymmetry is small (Kelemen steps), so the pipeline test has little power
 * (docs/mutations.md); mutate_detailed_balance_histogram detects the ablation per step. */
TEST_LONG(mutate_rv_kernel_ablation_pipeline_long)
{
    static const mutate_case rv = {RESTIR_SHIFT_HYBRID, MUTATE_KERNEL_ITERATIONS, MUTATE_AFTER_INITIAL, 0, 0, MUTATE_RV};
    static const mutate_case kernel = {RESTIR_SHIFT_HYBRID, MUTATE_KERNEL_ITERATIONS, MUTATE_AFTER_INITIAL,
                                       RESTIR_ABLATE_RV_KERNEL, 0, MUTATE_RV};
    g_channel = 0;
    expect_paired("panel", 16, MUTATE_KERNEL_RUNS, &rv, 0);
    expect_paired("panel", 16, MUTATE_KERNEL_RUNS, &kernel, 2);
    g_channel = -1;
}

/* ---- Eq. 20 against a finite-difference Jacobian ---------------------------------------------- */

/* The determined direction numbers b' of the rv proposal as a function of the current path's
 * b (direction numbers at x_k and x_{k+1}; m = 2 or 4 of them): x_{k+1} and w_{k+1} of the
 * path replayed with b, then inverse sampling at z_k (trunk tz) and at x_{k+1} seen from z_k.
 * P[0..1] receive the lobe probabilities at (z_k, x_{k+1}) and, via Py, at (y_k, x_{k+1}). */
static int rv_map(const restir_context *c, const path_vertex *y1, const path_sample *u, const path_trunk *tz,
                  const double *b, int m, double *out, double Pz[2], double Py[2])
{
    path_sample yy = *u;
    path_trunk ty, tv = *tz;
    path_end end;
    real n[3], lo, hi, numbers[PATH_MAX_PSS];
    int k = u->rc_k, j;
    path_sample_copy_pss(u, numbers); /* yy's own numbers: u's are not to be changed */
    yy.pss = numbers;
    for (j = 0; j < m; ++j) yy.pss[(k - 1 + j / 2) * 3 + 1 + j % 2] = (real)b[j];
    if (path_replay(&ty, c, y1, &yy, &end) != SHIFT_OK) return -1;
    if (!mutate_invert_bounce(&tv.v[k], u->lobe[k], mutate_direction_to(&tv.v[k], ty.v[k + 1].position), (real)0.5, n))
        return -1;
    out[0] = n[1];
    out[1] = n[2];
    bsdf_lobe_interval(&tv.v[k].b, tv.v[k].wo_local, u->lobe[k], &lo, &hi);
    Pz[0] = hi - lo;
    bsdf_lobe_interval(&ty.v[k].b, ty.v[k].wo_local, u->lobe[k], &lo, &hi);
    Py[0] = hi - lo;
    Pz[1] = Py[1] = 1;
    if (m == 2) return 0;
    if (trunk_sample(&tv, n) != SHIFT_OK || trunk_trace(&tv, c->path.scene) != SHIFT_OK) return -1;
    if (!mutate_invert_bounce(&tv.v[k + 1], u->lobe[k + 1], ty.b[k + 1].wi, (real)0.5, n)) return -1;
    out[2] = n[1];
    out[3] = n[2];
    bsdf_lobe_interval(&tv.v[k + 1].b, tv.v[k + 1].wo_local, u->lobe[k + 1], &lo, &hi);
    Pz[1] = hi - lo;
    bsdf_lobe_interval(&ty.v[k + 1].b, ty.v[k + 1].wo_local, u->lobe[k + 1], &lo, &hi);
    Py[1] = hi - lo;
    return 0;
}

/* Mutations Eq. 20 is |det db'/db| (docs/mutations.md, App. C): the code's kernel ratio from
 * mutate_propose against central differences of rv_map, the lobe-number factor P_z/P_y of
 * each determined vertex multiplied in (its number is drawn uniformly in the lobe interval). */
static void eq20_fd(const char *path, int *checked, double *worst)
{
    rt_frame f;
    int x, y;
    const double h = 2e-4;
    if (rt_frame_open(&f, path, 16, RESTIR_SHIFT_HYBRID, 6, test_seed() + 3)) return;
    for (y = 0; y < f.s.height && !test_has_failed(); ++y)
        for (x = 0; x < f.s.width && !test_has_failed(); ++x) {
            const path_sample *py = &f.res.reservoirs[y * f.s.width + x].y;
            path_vertex v;
            path_sample u, z, zz;
            path_trunk tz;
            real xi[PATH_MAX_PSS], xl[2] = {(real)0.5, (real)0.5}, ratio;
            real un[PATH_MAX_PSS], zn[PATH_MAX_PSS], zzn[PATH_MAX_PSS]; /* their numbers (path_sample.h) */
            double b[4], J[6][6], plus[4], minus[4], Pz[2], Py[2], fd, rel;
            rng_key key = rng_key_make(test_seed(), (uint32_t)(y * f.s.width + x), 9);
            int i, j, m, k = py->rc_k, nb = mutate_bsdf_vertices(py), ok = 1;
            if (!path_sample_is_valid(py) || k == PATH_RC_NONE || k > nb || !rt_primary_vertex(&f.s, x, y, &v)) continue;
            m = k + 1 <= nb ? 4 : 2;
            for (i = 0; i < PATH_MAX_PSS; ++i) xi[i] = rng_u(key, RNG_TEST, 0, (uint32_t)i);
            u.pss = un;
            z.pss = zn;
            if (mutate_explicit(&f.c, &v, py, xl, &u)) continue;
            if (mutate_propose(&f.c, &v, &u, MUTATE_RV, xi, xl, &z, &ratio) >= 0) continue;
            zz = u;
            path_sample_copy_pss(&u, zzn);
            zz.pss = zzn;
            for (i = 0; i < 3; ++i) zz.pss[(k - 2) * 3 + i] = mutate_perturb(u.pss[(k - 2) * 3 + i], xi[(k - 2) * 3 + i]);
            if (trunk_replay(&tz, &f.c, &v, &zz, k) != SHIFT_OK) continue;
            for (j = 0; j < m; ++j) {
                b[j] = (double)u.pss[(k - 1 + j / 2) * 3 + 1 + j % 2];
                if (b[j] < 10 * h || b[j] > 1 - 10 * h) ok = 0;
            }
            for (j = 0; j < m && ok; ++j) {
                double bp[4], bm[4];
                memcpy(bp, b, sizeof b);
                memcpy(bm, b, sizeof b);
                bp[j] += h;
                bm[j] -= h;
                if (rv_map(&f.c, &v, &u, &tz, bp, m, plus, Pz, Py) || rv_map(&f.c, &v, &u, &tz, bm, m, minus, Pz, Py)) ok = 0;
                for (i = 0; i < m && ok; ++i) J[i][j] = (plus[i] - minus[i]) / (2 * h);
            }
            if (!ok || rv_map(&f.c, &v, &u, &tz, b, m, plus, Pz, Py)) continue;
            fd = fabs(rt_determinant(J, m)) * (Pz[0] / Py[0]) * (Pz[1] / Py[1]);
            rel = fabs(fd / (double)ratio - 1);
            ++*checked;
            if (rel > *worst) *worst = rel;
            CHECKF(rel < 0.02, "%s (%d,%d): Eq. 20 ratio %g, finite-difference |db'/db| %g", path, x, y, (double)ratio, fd);
        }
    rt_frame_close(&f);
}

TEST(mutate_eq20_finite_difference)
{
    int checked = 0;
    double worst = 0;
    eq20_fd("scenes/cornell-glossy.scene", &checked, &worst);
    eq20_fd("scenes/glass.scene", &checked, &worst);
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  %d paths, worst relative difference %.2g\n", checked, worst);
    CHECKF(checked >= 20, "only %d paths checked", checked);
}

/* ---- detailed balance by histogram ---------------------------------------------------------- */

#define FLUX_BINS 8

/* log A(y) with A = mutate_rv_ratio_terms (0 without reconnection vertex). */
static double log_a(const restir_context *c, const path_vertex *y1, const path_sample *y)
{
    path_trunk t;
    path_end end;
    real a;
    if (y->rc_k == PATH_RC_NONE || path_replay(&t, c, y1, y, &end) != SHIFT_OK) return 0;
    a = mutate_rv_ratio_terms(&t, y->rc_k, mutate_bsdf_vertices(y));
    return a > 0 ? log((double)a) : 0;
}

/* The bin of a state: floor(2 log2 A) mod FLUX_BINS (any function of the state partitions
 * it; this one is where a wrong kernel pushes the chain). */
static int flux_bin(double la)
{
    int b = (int)floor(2 * la / log(2.0));
    return ((b % FLUX_BINS) + FLUX_BINS) % FLUX_BINS;
}

/* Detailed balance (Mutations Eq. 15 / 29) of one mutate_reservoir iteration, by histogram:
 * states u drawn uniformly in the primary sample space of a pixel (fresh numbers, length 4,
 * NEE) carry the stationary weight p̂(u); the flux p̂(u) T(u->v) a(u->v) from bin i to bin j
 * must equal the flux from j to i. Returns the largest |z| over the bin pairs (paired per
 * draw: D = w (1{i->j} - 1{j->i})). *z_log receives the z of the antisymmetric statistic
 * E[p̂(u) a (log A(v) - log A(u))], zero under detailed balance for the same reason (any
 * antisymmetric g(u, v) has E_pi[g T a] = 0) and more powerful: every accepted move counts. */
static double flux_worst_z(const scene *sc, const restir_context *c, int strategy, int draws, double *moved,
                           double *z_log)
{
    double g = 0, g2 = 0;
    double sum[FLUX_BINS][FLUX_BINS], sum2[FLUX_BINS][FLUX_BINS], worst = 0, total = 0, off = 0;
    int n, i, j;
    memset(sum, 0, sizeof sum);
    memset(sum2, 0, sizeof sum2);
    for (n = 0; n < draws; ++n) {
        rng_key key = rng_key_make(test_seed() * 31u + (uint32_t)strategy, (uint32_t)n, 77);
        int px = (int)(rng_u(key, RNG_TEST, 0, 0) * sc->width), py = (int)(rng_u(key, RNG_TEST, 0, 1) * sc->height);
        path_vertex v;
        reservoir r;
        mutate_stats st;
        real numbers[PATH_MAX_PSS];
        int b0, b1, q;
        double la0, la1;
        memset(&r, 0, sizeof r);
        if (!rt_primary_vertex(sc, px, py, &v)) continue;
        path_sample_begin(&r.y, test_seed(), (uint32_t)(py * sc->width + px), 1000000u + (uint32_t)n);
        r.y.length = 4;
        r.y.technique = PATH_TECH_NEE;
        r.y.n_pss = 3 * 3;
        r.y.pss = numbers;
        for (q = 0; q < r.y.n_pss; ++q) r.y.pss[q] = rng_u(key, RNG_TEST, 1, (uint32_t)q);
        if (path_record(c, &v, &r.y) != SHIFT_OK || !(r.y.target > 0)) continue;
        r.W = 1;
        la0 = log_a(c, &v, &r.y);
        b0 = flux_bin(la0);
        memset(&st, 0, sizeof st);
        mutate_reservoir(c, &v, rng_key_make(test_seed(), (uint32_t)n, 3), MUTATE_AFTER_INITIAL, strategy, 1, &r, numbers,
                         &st);
        la1 = log_a(c, &v, &r.y);
        b1 = flux_bin(la1);
        total += 1;
        {
            double d = (double)r.y.target * (double)r.W * (la1 - la0);
            g += d;
            g2 += d * d;
        }
        if (b0 != b1) {
            double w = (double)r.y.target * (double)r.W; /* = p̂(u): W after the Eq. 16 update */
            int lo = b0 < b1 ? b0 : b1, hi = b0 < b1 ? b1 : b0;
            double d = b0 < b1 ? w : -w;
            sum[lo][hi] += d;
            sum2[lo][hi] += d * d;
            off += 1;
        }
    }
    for (i = 0; i < FLUX_BINS; ++i)
        for (j = i + 1; j < FLUX_BINS; ++j) {
            double mean = sum[i][j] / draws, var = (sum2[i][j] / draws - mean * mean) / (draws - 1);
            if (var > 0 && fabs(mean / sqrt(var)) > worst) worst = fabs(mean / sqrt(var));
        }
    *moved = total > 0 ? off / total : 0;
    {
        double mean = g / draws, var = (g2 / draws - mean * mean) / (draws - 1);
        *z_log = var > 0 ? mean / sqrt(var) : 0;
    }
    return worst;
}

static void detailed_balance(int ablate_strategy)
{
    scene sc;
    light_set lights;
    restir_context c;
    rerror e;
    int strategy;
    if (make_panel(&sc, 16)) return;
    if (lights_build(&lights, &sc, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&sc);
        return;
    }
    rt_context(&c, &sc, &lights, RESTIR_SHIFT_HYBRID);
    for (strategy = 0; strategy < MUTATE_STRATEGY_COUNT && !test_has_failed(); ++strategy) {
        double moved, zl, z = flux_worst_z(&sc, &c, strategy, FLUX_DRAWS, &moved, &zl);
        if (getenv("RESTIR_TEST_VERBOSE"))
            fprintf(stderr, "  %s: flux asymmetry worst |z| %.2f over %d bin pairs (%.1f%% of the draws change bin), "
                            "log-A statistic z %.2f\n",
                    mutate_strategy_names[strategy], z, FLUX_BINS * (FLUX_BINS - 1) / 2, 100 * moved, zl);
        CHECKF(z < 4.5, "%s: detailed balance violated, flux asymmetry |z| = %.2f", mutate_strategy_names[strategy], z);
        CHECKF(fabs(zl) < 4.5, "%s: detailed balance violated, log-A statistic z = %.2f", mutate_strategy_names[strategy],
               zl);
        if (strategy == ablate_strategy) {
            c.ablation = RESTIR_ABLATE_RV_KERNEL;
            z = flux_worst_z(&sc, &c, strategy, strategy == MUTATE_RV ? 4 * FLUX_DRAWS : FLUX_DRAWS, &moved, &zl);
            c.ablation = RESTIR_ABLATE_NONE;
            if (getenv("RESTIR_TEST_VERBOSE"))
                fprintf(stderr, "  %s --ablate rv-kernel: flux asymmetry worst |z| %.2f, log-A statistic z %.2f\n",
                        mutate_strategy_names[strategy], z, zl);
            CHECKF(fabs(zl) > 6, "%s: --ablate rv-kernel not detected (log-A statistic z = %.2f, flux |z| %.2f)",
                   mutate_strategy_names[strategy], zl, z);
        }
    }
    lights_free(&lights);
    scene_free(&sc);
}

TEST(mutate_detailed_balance_histogram) { detailed_balance(MUTATE_RV); }

/* The same with the symmetric-kernel ablation of pp detected (4 x 10^5 draws). */
TEST_LONG(mutate_detailed_balance_pp_ablation_long) { detailed_balance(MUTATE_PP); }

/* Exact oracle of Mutations Eq. 17: with p̂ = luminance(F), every accepted step keeps
 * p̂(x^k) W^k = p̂(x^{k-1}) W^{k-1} (the weight sum), so the luminance of each pixel's
 * estimate F W is unchanged by any number of mutations, to rounding; and the chain moves. */
TEST(mutate_luminance_invariant_exact)
{
    static const char *const files[] = {"scenes/cornell-glossy.scene", "scenes/glass.scene"};
    static const int shifts[] = {RESTIR_SHIFT_HYBRID, RESTIR_SHIFT_HYBRID};
    static const int strategies[] = {MUTATE_RV, MUTATE_PP};
    size_t f;
    for (f = 0; f < 2 && !test_has_failed(); ++f) {
        scene s;
        restir_options o;
        restir_result res;
        light_set lights;
        restir_context c;
        mutate_stats st;
        rerror e;
        int x, y, moved = 0;
        double worst = 0;
        real *rows, numbers[PATH_MAX_PSS]; /* the mutated samples' numbers: one row per pixel (reservoir.h) */
        if (rt_load_scene(files[f], 16, &s)) return;
        restir_options_default(&o);
        o.shift = shifts[f];
        o.max_depth = 6;
        o.keep_reservoirs = 1;
        o.seed = test_seed() + 11;
        if (restir_render(&s, &o, &res, &e) || lights_build(&lights, &s, &e)) {
            test_fail(__FILE__, __LINE__, "%s", e.msg);
            scene_free(&s);
            return;
        }
        rt_context(&c, &s, &lights, o.shift);
        memset(&st, 0, sizeof st);
        rows = calloc((size_t)s.width * (size_t)s.height * PATH_MAX_PSS, sizeof *rows);
        CHECK(rows != NULL);
        for (y = 0; y < s.height && rows; ++y)
            for (x = 0; x < s.width; ++x) {
                reservoir *r = &res.reservoirs[y * s.width + x];
                double before = (double)r->y.target * (double)r->W, after, rel;
                path_vertex v;
                if (!rt_primary_vertex(&s, x, y, &v)) continue;
                mutate_reservoir(&c, &v, rng_key_make(test_seed(), (uint32_t)(y * s.width + x), 0), MUTATE_AFTER_TEMPORAL,
                                 strategies[f], 20, r, rows + (size_t)(y * s.width + x) * PATH_MAX_PSS, &st);
                after = (double)luminance(r->y.F) * (double)r->W;
                rel = before > 0 ? fabs(after - before) / before : fabs(after);
                if (rel > worst) worst = rel;
            }
        moved = st.accepted > 0;
        CHECKF(worst < (sizeof(real) == 8 ? 1e-9 : 1e-3), "%s: luminance of F W changed by %g (relative) under mutation",
               files[f], worst);
        /* --ablate mutation-w: the same chains without the Eq. 16 update break the invariant */
        if (f == 0) {
            restir_context cw = c;
            double broken = 0;
            cw.ablation = RESTIR_ABLATE_MUTATION_W;
            for (y = 0; y < s.height; ++y)
                for (x = 0; x < s.width; ++x) {
                    reservoir r = res.reservoirs[y * s.width + x];
                    double before = (double)r.y.target * (double)r.W, after;
                    path_vertex v;
                    if (!rt_primary_vertex(&s, x, y, &v)) continue;
                    mutate_reservoir(&cw, &v, rng_key_make(test_seed(), (uint32_t)(y * s.width + x), 1),
                                     MUTATE_AFTER_TEMPORAL, strategies[f], 20, &r, numbers, &st);
                    after = (double)luminance(r.y.F) * (double)r.W;
                    if (before > 0 && fabs(after - before) / before > broken) broken = fabs(after - before) / before;
                }
            if (getenv("RESTIR_TEST_VERBOSE"))
                fprintf(stderr, "  %s: worst relative change %.2g, with --ablate mutation-w %.2g\n", files[f], worst, broken);
            CHECKF(broken > 1e-3, "%s: --ablate mutation-w not detected by the exact invariant (%g)", files[f], broken);
        }
        CHECKF(moved, "%s: no mutation was accepted (%llu proposals)", files[f], (unsigned long long)st.proposals);
        free(rows);
        lights_free(&lights);
        restir_result_free(&res);
        scene_free(&s);
    }
}

/* The matrix of issue 13: {rv, pp, fp} x {1, 5} mutations x {after temporal, after initial}
 * on cornell, cornell-glossy, glass and ajar, hybrid shift (frame 4 of 24 sequences against
 * the path tracer). */
TEST_LONG(mutate_pipeline_unbiased_matrix_long)
{
    static const char *const files[] = {"scenes/cornell.scene", "scenes/cornell-glossy.scene", "scenes/glass.scene",
                                        "scenes/ajar.scene"};
    mutate_case cases[12];
    size_t f;
    int n = 0, sh, m, a;
    for (sh = 0; sh < MUTATE_STRATEGY_COUNT; ++sh)
        for (m = 0; m < 2; ++m)
            for (a = 0; a < 2; ++a) {
                mutate_case c = {RESTIR_SHIFT_HYBRID, m ? 5 : 1, a ? MUTATE_AFTER_INITIAL : MUTATE_AFTER_TEMPORAL, 0, 0, 0};
                c.strategy = sh;
                cases[n++] = c;
            }
    for (f = 0; f < sizeof files / sizeof files[0] && !test_has_failed(); ++f) run_cases(files[f], 16, 24, cases, 12, 0);
}

/* Addressed numbers (docs/rng.md): the frames with mutations are byte-identical for 1 and 3
 * threads. */
static int keep_image(void *user, int frame, const image *img, const restir_stats *st, rerror *e)
{
    image *out = user;
    (void)st;
    if (frame != 2) return 0;
    if (image_alloc(out, img->width, img->height, e)) return -1;
    memcpy(out->px, img->px, 3 * (size_t)img->width * (size_t)img->height * sizeof *img->px);
    return 0;
}

TEST(mutate_threads_identical)
{
    scene s;
    restir_options o;
    restir_sequence q;
    restir_stats total;
    image img[2];
    rerror e;
    int t;
    if (rt_load_scene("scenes/cornell-glossy.scene", 16, &s)) return;
    memset(&q, 0, sizeof q);
    memset(img, 0, sizeof img);
    q.last = 2;
    for (t = 0; t < 2; ++t) {
        restir_options_default(&o);
        o.shift = RESTIR_SHIFT_REPLAY;
        o.max_depth = 4;
        o.mutation.count = 3;
        o.mutation.stages = MUTATE_AFTER_INITIAL | MUTATE_AFTER_TEMPORAL;
        o.spatial_passes = 1;
        o.mutation.stages |= MUTATE_AFTER_SPATIAL;
        o.threads = t ? 3 : 1;
        o.seed = test_seed();
        if (restir_render_sequence(&s, &o, &q, keep_image, &img[t], &total, &e)) {
            test_fail(__FILE__, __LINE__, "%s", e.msg);
            break;
        }
    }
    if (!test_has_failed())
        CHECKF(img[0].px && img[1].px && !memcmp(img[0].px, img[1].px, 3 * 16 * 16 * sizeof *img[0].px),
               "mutated frames differ between 1 and 3 threads");
    image_free(&img[0]);
    image_free(&img[1]);
    scene_free(&s);
}
