/* Exact oracles for ReSTIR PT's spatial reuse (docs/statistics.md "Exact oracles"): answers
 * known without noise, so a planted bug shows exactly instead of at some |z|.
 *
 *   restir_exact_gris_step_recomputed: after every GRIS step of 3 chained spatial passes
 *     (so pass 2+ shifts already-shifted samples), at every pixel:
 *       - the output confidence is exactly the sum of the input confidences (GRIS §6.2);
 *       - the stored target p̂(Y) equals a fresh evaluation of the offset path by the
 *         path-sampling code (rt_fresh_contribution), not by the shift code;
 *       - the stored W equals sum_j w_j / p̂(Y) recomputed from scratch (GRIS Eqs. 19, 22):
 *         every p̂ from the fresh evaluation, the MIS weights of mis.h over the true input
 *         confidences, the Jacobians of the shifts.
 *   restir_exact_shadow_stays_black: direct light only, a wall between the light and half
 *     the floor, a neighbour radius that crosses the wall: every fully shadowed pixel is
 *     exactly 0 after 1 and 3 spatial passes (a reconnection whose segment is not
 *     visibility-tested brings light into the shadow).
 *   restir_exact_furnace: inside an emitting Lambertian sphere L_D is known in closed form;
 *     every shift x MIS family x {1, 3} passes agrees with it, and the same runs with the
 *     resampled part scaled by 1.01^K (W x 1.01 in each of K passes) are rejected at |z| > 10
 *     (TEST_LONG; make test runs the same matrix smaller, where |z| is 3-7). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/stochastic_spatial.h"
#include "restir/frame/offline.h"
#include "pt_util.h"
#include "restir_util.h"
#include "test.h"
#include "restir/restir/stochastic_check.h"
#include "restir/frame/options.h"

static int verbose(void) { return getenv("RESTIR_TEST_VERBOSE") != NULL; }

/* Relative agreement of two values computed by different code. Not 1e-12: a path traced
 * by the path sampler follows its sampled direction, a reconnection (and the fresh
 * evaluation) the direction to x_k's float position; on a glossy lobe (roughness 0.3)
 * that changes F by up to ~1e-5 relative. Every bug these checks are for is >= 1e-3. */
static int agree(double a, double b)
{
    double tol = sizeof(real) == 4 ? 3e-3 : 1e-4;
    return fabs(a - b) <= tol * fmax(fabs(a), fabs(b)) + 1e-30;
}

/* ---- the GRIS step, recomputed from scratch ------------------------------------------- */

enum { STEP_MAX_M = 5 };

typedef struct {
    scene s;
    light_set lights;
    restir_context c;
    path_vertex *x1;    /* per pixel */
    unsigned char *hit; /* per pixel: x1 valid */
    reservoir *a, *b;   /* ping-pong */
    spatial_workspace w;
    /* what the checks saw */
    long steps, failed_shifts, failed_steps, selected_neighbor, max_m;
    double worst_target, worst_w; /* largest relative differences */
} step_bench;

static double rel(double a, double b) { return fabs(a - b) / fmax(fmax(fabs(a), fabs(b)), 1e-300); }

/* p̂ of sample x as a path of the pixel with primary hit y1, evaluated afresh. */
static real fresh_target(const step_bench *b, const path_vertex *y1, const path_sample *x)
{
    return luminance(rt_fresh_contribution(&b->c, y1, &b->x1[x->pixel], x));
}

/* Sum_j w_j from scratch for the step whose domains are x1[0..m-1], inputs in[0..m-1]. */
static real wsum_from_scratch(const step_bench *b, mis_family f, int m, const path_vertex *const *x1,
                              const reservoir *const *in)
{
    real P[STEP_MAX_M * STEP_MAX_M], conf[STEP_MAX_M], J[STEP_MAX_M];
    path_sample y[STEP_MAX_M];
    int ok[STEP_MAX_M], i, j;
    mis_input mi;
    real wsum = 0;
    memset(P, 0, sizeof P);
    for (j = 0; j < m; ++j) {
        conf[j] = in[j]->confidence;
        ok[j] = path_sample_is_valid(&in[j]->y) && in[j]->W > 0;
        J[j] = 1;
        if (ok[j] && j > 0) ok[j] = shift_path(&b->c, x1[0], &in[j]->y, &y[j], &J[j], NULL) == SHIFT_OK;
        if (j == 0) y[0] = in[0]->y;
        if (!ok[j]) continue;
        P[j] = fresh_target(b, x1[0], &y[j]);                                      /* p̂(y_j) */
        if (j > 0) P[j * m + j] = fresh_target(b, x1[j], &in[j]->y) / J[j];       /* p̂_j(X_j) / J_j */
    }
    for (j = 0; j < m; ++j)
        for (i = 1; i < m; ++i) {
            path_sample back;
            real Jb;
            if (!ok[j] || i == j) continue;
            if (shift_path(&b->c, x1[i], &y[j], &back, &Jb, NULL) == SHIFT_OK)
                P[i * m + j] = fresh_target(b, x1[i], &back) * Jb; /* GRIS Eq. 35 */
        }
    mi.m = m;
    mi.n_canonical = 1;
    mi.confidence = conf;
    mi.ptarget = P;
    for (j = 0; j < m; ++j)
        if (ok[j]) wsum += mis_weight(f, &mi, j, j, NULL) * P[j] * in[j]->W * J[j]; /* GRIS Eq. 19 */
    return wsum;
}

/* One GRIS step at pixel (x, y) of pass `pass`, then every exact check on its output. */
static void step_at(step_bench *b, mis_family f, int pass, int x, int y, const reservoir *src, reservoir *dst)
{
    static const int ox[4] = {2, -1, 1, -3}, oy[4] = {0, 2, -2, -1};
    int W = b->s.width, H = b->s.height, m = 1, k;
    long p = (long)y * W + x;
    const path_vertex *x1[STEP_MAX_M];
    const reservoir *in[STEP_MAX_M];
    real u[STEP_MAX_M], csum = 0, wsum, fresh;
    spatial_stats st;
    reservoir *out = &dst[p];
    if (!b->hit[p]) {
        reservoir_init(out);
        return;
    }
    x1[0] = &b->x1[p];
    in[0] = &src[p];
    for (k = 0; k < 4; ++k) { /* the offsets turn by 90 degrees per pass */
        int dx = pass % 2 ? -oy[k] : ox[k], dy = pass % 2 ? ox[k] : oy[k];
        int nx = x + (pass >= 2 ? -dx : dx), ny = y + (pass >= 2 ? -dy : dy);
        long q = (long)ny * W + nx;
        if (nx < 0 || ny < 0 || nx >= W || ny >= H || !b->hit[q]) continue;
        x1[m] = &b->x1[q];
        in[m] = &src[q];
        m++;
    }
    for (k = 0; k < m; ++k) {
        u[k] = rng_u(rng_key_make(test_seed(), (uint32_t)p, (uint32_t)pass), RNG_RIS, 40u, (uint32_t)k);
        csum += in[k]->confidence;
    }
    memset(&st, 0, sizeof st);
    spatial_resample(&b->c, f, m, x1, in, u, out, &b->w, &st);
    b->steps++;
    b->max_m = m > b->max_m ? m : b->max_m;
    b->failed_shifts += (long)(st.shifts - st.outcome[SHIFT_OK]);
    b->failed_steps += st.shifts != st.outcome[SHIFT_OK];
    b->selected_neighbor += (long)st.selected_neighbor;
    CHECKF(out->confidence == csum, "pass %d pixel (%d, %d): confidence %.17g, inputs sum to %.17g", pass, x, y,
           (double)out->confidence, (double)csum);
    CHECKF(out->confidence >= 0 && out->W >= 0 && isfinite((double)out->W), "pass %d pixel (%d, %d): W %g c %g",
           pass, x, y, (double)out->W, (double)out->confidence);
    wsum = wsum_from_scratch(b, f, m, x1, in);
    if (!path_sample_is_valid(&out->y)) {
        CHECKF(wsum == 0 && out->W == 0, "pass %d pixel (%d, %d): empty output, but sum w = %g from scratch", pass, x,
               y, (double)wsum);
        return;
    }
    fresh = fresh_target(b, x1[0], &out->y);
    if (rel(out->y.target, fresh) > b->worst_target) b->worst_target = rel(out->y.target, fresh);
    CHECKF(agree(out->y.target, fresh),
           "pass %d pixel (%d, %d): stored p̂(Y) %.17g, fresh evaluation of the path %.17g (d %d, k %d, technique %d)",
           pass, x, y, (double)out->y.target, (double)fresh, out->y.length, out->y.rc_k, out->y.technique);
    CHECKF(fresh > 0, "pass %d pixel (%d, %d): selected a path with p̂ = 0", pass, x, y);
    if (rel(out->W, wsum / fresh) > b->worst_w) b->worst_w = rel(out->W, wsum / fresh);
    CHECKF(agree(out->W, wsum / fresh), "pass %d pixel (%d, %d) mis %s, M %d: stored W %.17g, from scratch %.17g", pass,
           x, y, mis_family_name(f), m, (double)out->W, (double)(wsum / fresh));
}

/* path NULL: the spot scene of restir_util.h. Primary vertices of every pixel (centres). */
static int step_bench_open(step_bench *b, const char *path, int res)
{
    rerror e;
    int W, H, x, y;
    memset(b, 0, sizeof *b);
    if (!path) {
        if (rt_make_spot(&b->s, res) || scene_prepare(&b->s, &e)) {
            test_fail(__FILE__, __LINE__, "spot scene");
            return -1;
        }
    } else if (rt_load_scene(path, res, &b->s))
        return -1;
    W = b->s.width;
    H = b->s.height;
    if (lights_build(&b->lights, &b->s, &e) || spatial_workspace_alloc(&b->w, STEP_MAX_M, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&b->s);
        return -1;
    }
    b->x1 = calloc((size_t)W * H, sizeof *b->x1);
    b->hit = calloc((size_t)W * H, 1);
    b->a = calloc((size_t)W * H, sizeof *b->a);
    b->b = calloc((size_t)W * H, sizeof *b->b);
    if (!b->x1 || !b->hit || !b->a || !b->b) {
        test_fail(__FILE__, __LINE__, "out of memory");
        return -1;
    }
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x) b->hit[(long)y * W + x] = (unsigned char)rt_primary_vertex(&b->s, x, y, &b->x1[(long)y * W + x]);
    return 0;
}

static void step_bench_close(step_bench *b)
{
    free(b->x1);
    free(b->hit);
    free(b->a);
    free(b->b);
    spatial_workspace_free(&b->w);
    lights_free(&b->lights);
    scene_free(&b->s);
}

/* Initial reservoirs for shift `shift` (the sample's k depends on it), then `passes`
 * chained passes with every check at every pixel. */
static void step_run(step_bench *b, int shift, mis_family f, int passes, int max_depth, const char *name)
{
    int W = b->s.width, H = b->s.height, x, y, pass;
    initial_options io;
    initial_stats ist;
    reservoir *src = b->a, *dst = b->b, *t;
    restir_options o;
    restir_options_default(&o);
    o.shift = shift;
    restir_context_for(&b->c, &b->s, &b->lights, &o);
    rt_initial_options(&io, &ist, 2, max_depth);
    b->steps = b->failed_shifts = b->failed_steps = b->selected_neighbor = b->max_m = 0;
    b->worst_target = b->worst_w = 0;
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x) {
            long p = (long)y * W + x;
            if (b->hit[p])
                initial_sample_pixel(&b->c, &io, &b->x1[p], test_seed() * 977u + 3u, (uint32_t)p, 0, &src[p], &ist);
            else
                reservoir_init(&src[p]);
        }
    for (pass = 0; pass < passes; ++pass) {
        for (y = 0; y < H && !test_has_failed(); ++y)
            for (x = 0; x < W && !test_has_failed(); ++x) step_at(b, f, pass, x, y, src, dst);
        if (test_has_failed()) {
            test_fail(__FILE__, __LINE__, "%s: shift %s, mis %s, pass %d", name, restir_shift_names[shift],
                      mis_family_name(f), pass);
            return;
        }
        t = src;
        src = dst;
        dst = t;
    }
    if (verbose())
        fprintf(stderr, "  %s shift %s mis %s: %ld steps (M <= %ld), %ld with a failed shift (%ld failed shifts), "
                        "%ld neighbour selections; worst relative differences: p̂ %.2g, W %.2g\n",
                name, restir_shift_names[shift], mis_family_name(f), b->steps, b->max_m, b->failed_steps,
                b->failed_shifts, b->selected_neighbor, b->worst_target, b->worst_w);
    /* the checks must have had something to check: failed shifts (confidence) and
     * selections from neighbours (a shifted Y) */
    CHECKF(b->failed_steps > 0 && b->selected_neighbor > 0, "%s shift %s: %ld steps with failed shifts, %ld neighbour selections",
           name, restir_shift_names[shift], b->failed_steps, b->selected_neighbor);
}

TEST(restir_exact_gris_step_recomputed)
{
    static const mis_family families[] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE, MIS_CONSTANT};
    step_bench b;
    int shift, f;
    if (step_bench_open(&b, "scenes/cornell-glossy.scene", 16)) return;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift)
        for (f = 0; f < 4 && !test_has_failed(); ++f) step_run(&b, shift, families[f], 3, 5, "cornell-glossy");
    step_bench_close(&b);
    if (test_has_failed()) return;
    /* the spot scene: direct light whose light pdf changes fast (reconnection at k = d) */
    if (step_bench_open(&b, NULL, 16)) return;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift)
        step_run(&b, shift, MIS_PAIRWISE_DEFENSIVE, 2, 3, "spot");
    step_bench_close(&b);
}

/* ---- shadow stays black ---------------------------------------------------------------- */

/* A floor, a thin wall across it (x = 0, higher than the light) and a small light on the
 * +x side facing down: with direct light only (d = 2), every floor point with x < 0 sees
 * no light point at all (the line from it to the light crosses x = 0 below y = 0.8 < 1.5). */
static int make_shadow_wall(scene *s, int res)
{
    uint32_t white, light;
    if (test_scene_begin(s, 16, 2)) return -1;
    white = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.8, (real)0.8, (real)0.8), rgb_gray(0));
    light = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(20, 18, 15));
    test_scene_quad(s, v3f(-1, 0, -1), v3f(0, 0, 2), v3f(2, 0, 0), white); /* floor, +y */
    test_scene_outward_box(s, v3f(-0.02f, 0, -1.2f), v3f(0.02f, 1.5f, 1.2f), white);
    test_scene_quad(s, v3f(0.3f, 0.8f, -0.2f), v3f(0.4f, 0, 0), v3f(0, 0, 0.4f), light); /* faces -y */
    test_scene_camera(s, v3(0, 3, (real)0.01), v3(0, 0, 0), v3(0, 0, 1), 40, res); /* from above */
    return 0;
}

TEST(restir_exact_shadow_stays_black)
{
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE, MIS_CONSTANT};
    enum { RES = 24 };
    unsigned char shadow[RES * RES];
    scene s;
    long n_shadow = 0, n_lit = 0;
    int x, y, shift, f, passes;
    if (make_shadow_wall(&s, RES) || test_scene_prepare(&s)) return;
    for (y = 0; y < RES; ++y)
        for (x = 0; x < RES; ++x) {
            path_vertex v;
            int in = rt_primary_vertex(&s, x, y, &v) && v.position.y < 1e-3 && v.position.x < -0.03;
            shadow[y * RES + x] = (unsigned char)in;
            n_shadow += in;
        }
    CHECKF(n_shadow > RES * RES / 5, "only %ld shadowed floor pixels", n_shadow);
    for (shift = 0; shift < RESTIR_SHIFT_COUNT; ++shift)
        for (f = 0; f < 4; ++f)
            for (passes = 1; passes <= 3; passes += 2) {
                restir_options o;
                restir_result r;
                rerror e;
                long bad = 0, lit = 0, i;
                uint64_t occluded;
                restir_options_default(&o);
                o.shift = shift;
                o.spatial.mis = families[f];
                o.spatial_passes = passes;
                o.max_depth = 2; /* direct light only */
                o.spatial.radius = 6;    /* crosses the wall from 6 pixels away */
                o.candidates = 2;
                o.frames = 2;
                o.threads = 2;
                o.seed = test_seed() * 31u + (uint32_t)(shift * 8 + f * 2 + passes);
                CHECKF(restir_render(&s, &o, &r, &e) == 0, "%s", e.msg);
                for (i = 0; i < RES * RES; ++i) {
                    double sum = r.mean.px[3 * i] + r.mean.px[3 * i + 1] + r.mean.px[3 * i + 2];
                    if (shadow[i] && sum != 0) bad++;
                    if (!shadow[i] && sum > 0) lit++;
                }
                if (verbose())
                    fprintf(stderr, "  shadow: shift %s mis %s passes %d: %ld of %ld shadowed pixels nonzero, %ld lit; "
                                    "%llu occluded shifts\n",
                            restir_shift_names[shift], restir_mis_names[families[f]], passes, bad, n_shadow, lit,
                            (unsigned long long)r.stats.spatial.outcome[SHIFT_FAIL_OCCLUDED]);
                occluded = r.stats.spatial.outcome[SHIFT_FAIL_OCCLUDED];
                restir_result_free(&r);
                CHECKF(bad == 0, "shift %s mis %s, %d passes: %ld of %ld fully shadowed pixels are not 0",
                       restir_shift_names[shift], restir_mis_names[families[f]], passes, bad, n_shadow);
                /* the reuse did try to carry light across the wall (reconnections fail there) */
                if (shift != RESTIR_SHIFT_REPLAY)
                    CHECKF(occluded > 0, "no reconnection crossed the wall");
                n_lit = lit;
            }
    CHECKF(n_lit > RES * RES / 5, "only %ld lit pixels", n_lit);
    scene_free(&s);
}

/* ---- the ReSTIR furnace ------------------------------------------------------------------ */

/* Inside the emitting Lambertian sphere (pt_util.h) every path of length d contributes
 * Le rho^(d-1) in expectation, so with paths of at most D segments every pixel is
 *     L_D = Le (1 - rho^D) / (1 - rho)
 * (docs/path-tracer.md "Furnace"). Emission at x1 (Le) is exact; the resampled part
 * F(Y) W_Y must average to L_D - Le. Spatial reuse correlates the pixels, so the test
 * runs R independent runs (disjoint frame ranges) and tests the R image means (a t-test
 * with R - 1 degrees of freedom). The same runs with the resampled part scaled by 1.01^K
 * (what W x 1.01 in each of K passes does: each pass's weights carry the previous W) must
 * be rejected at |z| > 10 in the long version. */
enum { FURNACE_DEPTH = 3, FURNACE_MAX_RUNS = 64 };

typedef struct {
    int res, runs, candidates; /* image edge, independent runs, path trees */
} furnace_size;

typedef struct {
    double z, z_scaled, rel_se;       /* K passes against L_D */
    double z0;                        /* 0 passes (initial resampling) against L_D */
    double z_paired, z_paired_scaled; /* K passes minus 0 passes, same seeds */
} furnace_verdict;

/* Image-mean luminance of one furnace run with `passes` spatial passes. */
static int furnace_run(const scene *s, const furnace_size *z, int shift, int mis, int passes, int run, double *mean)
{
    restir_options o;
    restir_result r;
    rerror e;
    double sum = 0;
    size_t i, n = (size_t)s->width * s->height;
    restir_options_default(&o);
    o.shift = shift;
    o.spatial.mis = mis;
    o.spatial_passes = passes;
    o.max_depth = FURNACE_DEPTH;
    o.spatial.radius = 4;
    o.spatial.neighbors = 4;
    o.candidates = z->candidates;
    o.frames = 1;
    o.first_frame = run;
    o.threads = 2;
    o.seed = test_seed() * 613u + (uint32_t)(shift * 4 + mis); /* the same for every pass count */
    if (restir_render(s, &o, &r, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    for (i = 0; i < n; ++i) sum += luminance(rgb_make(r.mean.px[3 * i], r.mean.px[3 * i + 1], r.mean.px[3 * i + 2]));
    restir_result_free(&r);
    *mean = sum / (double)n;
    return 0;
}

/* The normal-equivalent z of the one-sample t-test of x[0..n-1] against mu. */
static double t_z(const double *x, int n, double mu, double *se)
{
    double mean, var;
    stats_mean_var(x, n, &mean, &var);
    *se = sqrt(var / n);
    return stats_t_to_z((mean - mu) / *se, n - 1);
}

static int furnace_case(const scene *s, const furnace_size *z, int shift, int mis, int passes, furnace_verdict *v)
{
    const double le = 1, rho = 0.8;
    const double expected = le * (1 - pow(rho, FURNACE_DEPTH)) / (1 - rho);
    double k_mean[FURNACE_MAX_RUNS], scaled[FURNACE_MAX_RUNS], base[FURNACE_MAX_RUNS], diff[FURNACE_MAX_RUNS];
    double sdiff[FURNACE_MAX_RUNS], se;
    int n = z->runs;
    int k;
    for (k = 0; k < n; ++k) {
        if (furnace_run(s, z, shift, mis, passes, k, &k_mean[k]) || furnace_run(s, z, shift, mis, 0, k, &base[k]))
            return -1;
        scaled[k] = le + pow(1.01, passes) * (k_mean[k] - le); /* W x 1.01 in every pass compounds */
        diff[k] = k_mean[k] - base[k];
        sdiff[k] = scaled[k] - base[k];
    }
    v->z0 = t_z(base, n, expected, &se);
    v->z_scaled = t_z(scaled, n, expected, &se);
    v->z = t_z(k_mean, n, expected, &se);
    v->rel_se = se / expected;
    v->z_paired = t_z(diff, n, 0, &se);
    v->z_paired_scaled = t_z(sdiff, n, 0, &se);
    return 0;
}
/* Every shift x {Talbot, pairwise, defensive} x {1, 3} passes agrees with L_D (|z| < 5,
 * and so does initial resampling alone); with scale_z > 0 the runs with W x 1.01 must also
 * be rejected at |z| > scale_z. */
static void furnace_matrix(const furnace_size *z, double scale_z)
{
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    scene s;
    int shift, f, p;
    double weakest = 1e300;
    if (test_scene_furnace_sphere(&s, rgb_gray(1), rgb_gray((real)0.8), z->res) || test_scene_prepare(&s)) return;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift)
        for (f = 0; f < 3 && !test_has_failed(); ++f)
            for (p = 1; p <= 3 && !test_has_failed(); p += 2) {
                furnace_verdict v;
                if (furnace_case(&s, z, shift, families[f], p, &v)) break;
                if (verbose())
                    fprintf(stderr, "  furnace %d^2 x %d runs: shift %s mis %s passes %d: z %.2f (0 passes %.2f), W x 1.01: z %.1f "
                                    "(relative se %.2g); paired with 0 passes: z %.2f, W x 1.01: z %.1f\n",
                            z->res, z->runs, restir_shift_names[shift], restir_mis_names[families[f]], p, v.z, v.z0, v.z_scaled,
                            v.rel_se, v.z_paired, v.z_paired_scaled);
                CHECKF(fabs(v.z) < 5 && fabs(v.z0) < 5, "furnace: shift %s mis %s passes %d: z %.2f from L_D (0 passes: %.2f)",
                       restir_shift_names[shift], restir_mis_names[families[f]], p, v.z, v.z0);
                if (fabs(v.z_scaled) < weakest) weakest = fabs(v.z_scaled);
            }
    if (verbose()) fprintf(stderr, "  furnace %d^2 x %d runs: W x 1.01 rejected at |z| >= %.1f everywhere\n", z->res, z->runs, weakest);
    if (!test_has_failed() && scale_z > 0)
        CHECKF(weakest > scale_z, "furnace: W x 1.01 detected only at |z| = %.1f somewhere (wanted > %.0f)", weakest, scale_z);
    scene_free(&s);
}

TEST(restir_exact_furnace)
{
    furnace_size z = {12, 12, 2};
    furnace_matrix(&z, 0);
}

TEST_LONG(restir_exact_furnace_long)
{
    furnace_size z = {32, 48, 4};
    furnace_matrix(&z, 10);
}

/* ---- the debug build's invariants, driven directly ------------------------------------ */

/* The debug-invariant tests' setup: the reconnection shift on b, and the initial
 * reservoirs of pixel (x, y) and its 4 neighbours (domains 0..4) drawn as initial sampling
 * does (2 path trees, depth 4). Returns STEP_MAX_M, or less where a domain has no hit. */
static void debug_bench_reconnection(step_bench *b)
{
    restir_options o;
    restir_options_default(&o);
    o.shift = RESTIR_SHIFT_RECONNECTION;
    restir_context_for(&b->c, &b->s, &b->lights, &o);
}

static int debug_cross(step_bench *b, int x, int y, reservoir *r, const path_vertex **x1, const reservoir **in)
{
    static const int ox[STEP_MAX_M] = {0, 1, -1, 0, 0}, oy[STEP_MAX_M] = {0, 0, 0, 1, -1};
    initial_options io;
    initial_stats ist;
    int k;
    rt_initial_options(&io, &ist, 2, 4);
    for (k = 0; k < STEP_MAX_M; ++k) {
        long q = (long)(y + oy[k]) * b->s.width + x + ox[k];
        if (!b->hit[q]) return k;
        initial_sample_pixel(&b->c, &io, &b->x1[q], test_seed(), (uint32_t)q, 0, &r[k], &ist);
        x1[k] = &b->x1[q];
        in[k] = &r[k];
    }
    return STEP_MAX_M;
}

/* spatial_check_step (the check `make DEBUG=1` runs after every GRIS step) accepts a real
 * step and rejects each planted violation with a message naming it: a non-finite W, an
 * output confidence that is not the sum of the inputs, a negative input confidence, an
 * m_j the step used that differs from the MIS weights over the input confidences, and a
 * successful reconnection whose segment is blocked. */
TEST(restir_debug_invariants_fire)
{
    step_bench b;
    const path_vertex *x1[STEP_MAX_M];
    const reservoir *in[STEP_MAX_M];
    reservoir r[STEP_MAX_M], out, saved;
    real u[STEP_MAX_M];
    spatial_stats st;
    char why[512];
    int x, y, k, found = 0, m = 0, j = -1;
    if (step_bench_open(&b, "scenes/cornell-glossy.scene", 16)) return;
    debug_bench_reconnection(&b);
    for (k = 0; k < STEP_MAX_M; ++k) u[k] = (real)0.5;
    /* a pixel whose 4 neighbours all shift in, one of them with a reconnection */
    for (y = 2; y < 14 && !found; ++y)
        for (x = 2; x < 14 && !found; ++x) {
            if ((m = debug_cross(&b, x, y, r, x1, in)) < STEP_MAX_M) continue;
            memset(&st, 0, sizeof st);
            spatial_resample(&b.c, MIS_TALBOT, m, x1, in, u, &out, &b.w, &st);
            for (k = 1; k < m && j < 0; ++k)
                if (b.w.valid[k] && b.w.shifted[k].rc_k != PATH_RC_NONE) j = k;
            found = j > 0;
        }
    CHECKF(found, "no pixel with a reconnected neighbour");
    CHECKF(spatial_check_step(&b.c, MIS_TALBOT, m, x1, in, &out, &b.w, why, sizeof why) == 0, "a correct step: %s", why);
    saved = out;
    out.W = (real)NAN;
    CHECK(spatial_check_step(&b.c, MIS_TALBOT, m, x1, in, &out, &b.w, why, sizeof why) != 0 && strstr(why, "W = nan"));
    out = saved;
    out.confidence += 1;
    CHECK(spatial_check_step(&b.c, MIS_TALBOT, m, x1, in, &out, &b.w, why, sizeof why) != 0 && strstr(why, "confidence"));
    out = saved;
    r[2].confidence = -r[2].confidence;
    CHECK(spatial_check_step(&b.c, MIS_TALBOT, m, x1, in, &out, &b.w, why, sizeof why) != 0 && strstr(why, "< 0"));
    r[2].confidence = -r[2].confidence;
    b.w.mis[j] *= (real)1.1;
    CHECK(spatial_check_step(&b.c, MIS_TALBOT, m, x1, in, &out, &b.w, why, sizeof why) != 0 && strstr(why, "used"));
    b.w.mis[j] /= (real)1.1;
    /* x_k moved far below the floor (the scene is ~550 units tall): the segment from
     * y_{k-1} now crosses it */
    b.w.shifted[j].rc_position.y -= 5000;
    CHECK(spatial_check_step(&b.c, MIS_TALBOT, m, x1, in, &out, &b.w, why, sizeof why) != 0 && strstr(why, "occluded"));
    if (verbose()) fprintf(stderr, "  invariant messages, e.g.: %s\n", why);
    step_bench_close(&b);
}

/* stochastic_check_step (what `make DEBUG=1` runs after every stochastic pairwise step;
 * the four tests/mutants/stochastic-* patches each abort the DEBUG suite there) accepts a
 * real step with Ñ = Ñ_c = 2 of M = 4 and rejects each planted violation: an output
 * confidence that ignores the §4.3 scaling, a P(i) in m~_i that is not Eq. 17's, an m~_i or
 * an m~_c that differs from mis.c's pairwise weights, a wrong pick count, and a successful
 * reconnection whose segment is blocked. */
TEST(restir_debug_stochastic_invariants_fire)
{
    step_bench b;
    stochastic_workspace sw;
    stochastic_options so = {2, 2, 1, 0};
    const path_vertex *x1[STEP_MAX_M];
    const reservoir *in[STEP_MAX_M];
    reservoir r[STEP_MAX_M], out, saved;
    real u[STEP_MAX_M] = {0.5, 0.5, 0.5, 0.5, 0.5}, up[2] = {0.3, 0.8}, uc[2] = {0.1, 0.6};
    spatial_stats st;
    rerror e;
    char why[512];
    int x, y, k, m = 0, j = -1;
    if (step_bench_open(&b, "scenes/cornell-glossy.scene", 16)) return;
    CHECKF(stochastic_workspace_alloc(&sw, STEP_MAX_M, &e) == 0, "%s", e.msg);
    debug_bench_reconnection(&b);
    for (y = 2; y < 14 && j < 0; ++y)
        for (x = 2; x < 14 && j < 0; ++x) {
            if ((m = debug_cross(&b, x, y, r, x1, in)) < STEP_MAX_M || !(r[0].W > 0)) continue;
            memset(&st, 0, sizeof st);
            stochastic_pairwise_resample(&b.c, &so, m, x1, in, u, up, uc, &out, &sw, &st);
            for (k = 0; k < m - 1 && j < 0; ++k)
                if (sw.K[k] && sw.jacobian[k] > 0 && sw.shifted[k].rc_k != PATH_RC_NONE) j = k;
        }
    CHECKF(j >= 0, "no pixel whose picked neighbour reconnects");
    if (j < 0) goto done;
    CHECKF(stochastic_check_step(&b.c, &so, m, x1, in, &out, &sw, why, sizeof why) == 0, "a correct step: %s", why);
    saved = out;
    out.confidence = r[0].confidence + r[1].confidence + r[2].confidence + r[3].confidence + r[4].confidence;
    CHECK(stochastic_check_step(&b.c, &so, m, x1, in, &out, &sw, why, sizeof why) != 0 && strstr(why, "confidence"));
    out = saved;
#define PLANT(field, factor, text)                                                                              \
    do {                                                                                                        \
        real keep = field;                                                                                      \
        field *= (real)(factor);                                                                                \
        CHECKF(stochastic_check_step(&b.c, &so, m, x1, in, &out, &sw, why, sizeof why) != 0 && strstr(why, text), \
               "%s x %g not caught: %s", #field, (double)(factor), why);                                        \
        field = keep;                                                                                           \
    } while (0)
    PLANT(sw.P_used[j], 0.5, "Eq. 17");
    PLANT(sw.m_used[j], 1.1, "m~_i used");
    PLANT(sw.m_c_used, 1.1, "m~_c used");
#undef PLANT
    sw.K[j]++;
    CHECK(stochastic_check_step(&b.c, &so, m, x1, in, &out, &sw, why, sizeof why) != 0 && strstr(why, "picks made"));
    sw.K[j]--;
    sw.shifted[j].rc_position.y -= 5000; /* below the floor: the segment from y_{k-1} crosses it */
    CHECK(stochastic_check_step(&b.c, &so, m, x1, in, &out, &sw, why, sizeof why) != 0 && strstr(why, "occluded"));
    if (verbose()) fprintf(stderr, "  stochastic invariant messages, e.g.: %s\n", why);
done:
    stochastic_workspace_free(&sw);
    step_bench_close(&b);
}
