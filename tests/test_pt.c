/* The reference path tracer: analytic furnace, estimator equality of MIS / NEE-only /
 * BSDF-only (and rejection of the ablations), scale invariance, determinism over thread
 * counts, checkpoints, resume and merging of sample ranges. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "restir/pt.h"
#include "pt_util.h"
#include "test.h"

/* ---- scenes ----------------------------------------------------------------------- */

/* White furnace: the camera sits inside a closed box whose inward faces all emit Le and
 * reflect with Lambertian albedo rho. */
static int make_furnace(scene *s, rgb le, rgb rho, int res)
{
    uint32_t m;
    if (test_scene_begin(s, 12, 2)) return -1;
    m = test_scene_material(s, MAT_LAMBERT, rho, le);
    test_scene_inward_box(s, v3f(-1, -1, -1), v3f(1, 1.5f, 2), m);
    test_scene_camera(s, v3((real)0.1, (real)0.2, 0), v3((real)0.3, (real)0.1, 1), v3(0, 1, 0), 100, res);
    return 0;
}

/* A small "Cornell-like" box [0,1]^3, open towards the camera, with a ceiling light,
 * coloured Lambertian walls, a plastic (two-lobe) block, a rough conductor panel and a
 * smooth glass cube (Dirac lobes only). */
static int make_glossy_box(scene *s, int res)
{
    uint32_t white, red, green, light, plastic, metal, glass;
    if (test_scene_begin(s, 64, 8)) return -1;
    white = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.7, (real)0.7, (real)0.68), rgb_gray(0));
    red = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.6, (real)0.06, (real)0.05), rgb_gray(0));
    green = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.14, (real)0.45, (real)0.09), rgb_gray(0));
    light = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(17, 12, 4));
    plastic = test_scene_material(s, MAT_PLASTIC, rgb_make((real)0.2, (real)0.3, (real)0.7), rgb_gray(0));
    test_scene_last_material(s)->specular = rgb_gray(1);
    test_scene_last_material(s)->roughness = (real)0.3;
    metal = test_scene_material(s, MAT_CONDUCTOR, rgb_gray(0), rgb_gray(0));
    test_scene_last_material(s)->specular = rgb_make((real)0.95, (real)0.64, (real)0.54);
    test_scene_last_material(s)->roughness = (real)0.25;
    glass = test_scene_material(s, MAT_DIELECTRIC, rgb_gray(0), rgb_gray(0));
    test_scene_last_material(s)->specular = rgb_gray(1);
    /* Walls (inward): floor, ceiling, back, left red, right green. */
    test_scene_quad(s, v3f(0, 0, 0), v3f(0, 0, 1), v3f(1, 0, 0), white);
    test_scene_quad(s, v3f(0, 1, 0), v3f(1, 0, 0), v3f(0, 0, 1), white);
    test_scene_quad(s, v3f(0, 0, 1), v3f(0, 1, 0), v3f(1, 0, 0), white);
    test_scene_quad(s, v3f(0, 0, 0), v3f(0, 1, 0), v3f(0, 0, 1), red);
    test_scene_quad(s, v3f(1, 0, 0), v3f(0, 0, 1), v3f(0, 1, 0), green);
    /* Ceiling light, facing down. */
    test_scene_quad(s, v3f(0.35f, 0.995f, 0.35f), v3f(0.3f, 0, 0), v3f(0, 0, 0.3f), light);
    test_scene_outward_box(s, v3f(0.15f, 0, 0.45f), v3f(0.45f, 0.35f, 0.8f), plastic);
    test_scene_quad(s, v3f(0.9f, 0.05f, 0.3f), v3f(-0.25f, 0, 0.5f), v3f(0, 0.6f, 0), metal);
    test_scene_outward_box(s, v3f(0.55f, 0, 0.15f), v3f(0.8f, 0.25f, 0.4f), glass);
    test_scene_camera(s, v3((real)0.5, (real)0.5, (real)-1.3), v3((real)0.5, (real)0.5, 0), v3(0, 1, 0), 42, res);
    return 0;
}

static int prepare(scene *s)
{
    rerror e;
    if (scene_prepare(s, &e)) {
        test_fail(__FILE__, __LINE__, "scene_prepare: %s", e.msg);
        return -1;
    }
    return 0;
}

static int render(const scene *s, const pt_options *o, pt_result *r)
{
    rerror e;
    if (pt_render(s, o, r, &e)) {
        test_fail(__FILE__, __LINE__, "pt_render: %s", e.msg);
        return -1;
    }
    return 0;
}

static double channel(rgb c, int k) { return k == 0 ? c.r : (k == 1 ? c.g : c.b); }

/* ---- furnace ---------------------------------------------------------------------- */

/* Every path of length d contributes Le rho^(d-1) in expectation (x1 emits Le; each
 * bounce multiplies by rho). With max path length D the pixel value is
 *     L_D = Le sum_{k=0}^{D-1} rho^k = Le (1 - rho^D) / (1 - rho),
 * and Le / (1 - rho) for D -> infinity. Each strategy (and Russian roulette) must
 * reproduce it within the MC confidence interval of the image mean. */
static void furnace_case(enum pt_strategy strategy, int rr, int depth, uint32_t spp)
{
    rgb le = rgb_make(1, (real)0.5, (real)0.25), rho = rgb_make((real)0.5, (real)0.7, (real)0.9);
    scene s;
    pt_options o;
    pt_result r;
    int k;
    CHECK(make_furnace(&s, le, rho, 12) == 0);
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.strategy = strategy;
    o.russian_roulette = rr;
    o.max_depth = depth;
    o.spp = spp;
    o.seed = test_seed() * 7919u + (uint32_t)strategy;
    if (render(&s, &o, &r)) return;
    for (k = 0; k < 3; ++k) {
        double l = channel(le, k), p = channel(rho, k);
        double expected = depth >= PT_MAX_DEPTH_LIMIT ? l / (1 - p) : l * (1 - pow(p, depth)) / (1 - p);
        double mean = 0, var = 0;
        size_t i, n = (size_t)s.width * s.height;
        for (i = 0; i < n; ++i) {
            double sum = r.state.sum[3 * i + k], sq = r.state.sum_sq[3 * i + k], m = sum / spp;
            mean += m;
            var += fmax(sq - sum * m, 0) / ((double)spp * (spp - 1));
        }
        mean /= (double)n;
        var /= (double)n * (double)n;
        /* 4.5 sigma (two-sided p ~ 7e-6 per check); the BSDF-only furnace is exact up to rounding. */
        CHECKF(fabs(mean - expected) <= 4.5 * sqrt(var) + 1e-9 * expected,
               "strategy %s rr %d depth %d channel %d: mean %.9g expected %.9g (se %.3g)", pt_strategy_names[strategy],
               rr, depth, k, mean, expected, sqrt(var));
    }
    CHECK(r.state.nonfinite == 0);
    pt_result_free(&r);
    scene_free(&s);
}

TEST(pt_furnace_truncated_series)
{
    furnace_case(PT_STRATEGY_MIS, 0, 5, 48);
    if (test_has_failed()) return;
    furnace_case(PT_STRATEGY_NEE, 0, 5, 48);
    if (test_has_failed()) return;
    furnace_case(PT_STRATEGY_BSDF, 0, 5, 8);
    if (test_has_failed()) return;
    furnace_case(PT_STRATEGY_MIS, 0, 1, 4); /* emission at x1 only */
    if (test_has_failed()) return;
    furnace_case(PT_STRATEGY_NEE, 0, 2, 32); /* direct light only */
}

TEST(pt_furnace_russian_roulette_infinite_depth)
{
    furnace_case(PT_STRATEGY_MIS, 1, 6, 64);
    if (test_has_failed()) return;
    furnace_case(PT_STRATEGY_BSDF, 1, PT_MAX_DEPTH_LIMIT, 96);
    if (test_has_failed()) return;
    furnace_case(PT_STRATEGY_NEE, 1, PT_MAX_DEPTH_LIMIT, 96);
}

/* ---- estimator equality ------------------------------------------------------------- */

static int render_state(const scene *s, enum pt_strategy strategy, unsigned ablations, uint32_t seed, uint32_t spp,
                        int depth, pt_result *r)
{
    pt_options o;
    pt_options_default(&o);
    o.strategy = strategy;
    o.ablations = ablations;
    o.seed = seed;
    o.spp = spp;
    o.max_depth = depth;
    o.threads = 2;
    return render(s, &o, r);
}

/* Renders strategy a and b with independent seeds and compares them. */
static int compare_strategies(const scene *s, enum pt_strategy a, unsigned abl_a, enum pt_strategy b,
                              unsigned abl_b, uint32_t spp, int depth, pt_compare *c)
{
    pt_result ra, rb;
    if (render_state(s, a, abl_a, test_seed() * 31u + 1, spp, depth, &ra)) return -1;
    if (render_state(s, b, abl_b, test_seed() * 31u + 2, spp, depth, &rb)) {
        pt_result_free(&ra);
        return -1;
    }
    pt_compare_states(&ra.state, &rb.state, 4, c);
    pt_result_free(&ra);
    pt_result_free(&rb);
    return 0;
}

#define ALPHA 1e-3

static void check_equal(const scene *s, enum pt_strategy a, enum pt_strategy b, uint32_t spp, int depth)
{
    pt_compare c;
    if (compare_strategies(s, a, 0, b, 0, spp, depth, &c)) return;
    CHECKF(pt_compare_equal(&c, ALPHA),
           "%s vs %s (d <= %d): block p = %.3g (worst z %.2f of %d tests), mean p = %.3g (means %.5g vs %.5g, se %.3g)",
           pt_strategy_names[a], pt_strategy_names[b], depth, c.p_blocks, c.worst_z, c.tests, c.p_mean, c.mean_a[1],
           c.mean_b[1], c.se_mean[1]);
}

static void check_rejected(const scene *s, enum pt_strategy a, unsigned abl, enum pt_strategy b, uint32_t spp,
                           int depth)
{
    pt_compare c;
    if (compare_strategies(s, a, abl, b, 0, spp, depth, &c)) return;
    CHECKF(!pt_compare_equal(&c, ALPHA), "ablation %u of %s not detected against %s: block p = %.3g, mean p = %.3g",
           abl, pt_strategy_names[a], pt_strategy_names[b], c.p_blocks, c.p_mean);
}

/* MIS, NEE-only and BSDF-only estimate the same image: full transport (path length up to 5,
 * through the glass cube's Dirac lobes too) and direct lighting alone (d <= 2). */
TEST(pt_strategies_agree_glossy_box)
{
    scene s;
    CHECK(make_glossy_box(&s, 24) == 0);
    if (prepare(&s)) return;
    check_equal(&s, PT_STRATEGY_MIS, PT_STRATEGY_NEE, 256, 5);
    if (!test_has_failed()) check_equal(&s, PT_STRATEGY_MIS, PT_STRATEGY_BSDF, 256, 5);
    if (!test_has_failed()) check_equal(&s, PT_STRATEGY_NEE, PT_STRATEGY_BSDF, 256, 5);
    if (!test_has_failed()) check_equal(&s, PT_STRATEGY_MIS, PT_STRATEGY_NEE, 256, 2);
    if (!test_has_failed()) check_equal(&s, PT_STRATEGY_MIS, PT_STRATEGY_BSDF, 256, 2);
    scene_free(&s);
}

/* The same comparison rejects the deliberately broken estimators. Both ablations act on
 * the last vertex of a path, so direct lighting (d <= 2) shows them with the most power:
 * light-pdf biases NEE by 1/1.05 (MIS by up to that), mis-sum loses up to ~10% of the
 * direct light where the balance and power heuristics disagree most. */
TEST(pt_strategies_reject_ablations_glossy_box)
{
    scene s;
    CHECK(make_glossy_box(&s, 24) == 0);
    if (prepare(&s)) return;
    check_rejected(&s, PT_STRATEGY_MIS, PT_ABLATE_LIGHT_PDF, PT_STRATEGY_NEE, 256, 2);
    if (!test_has_failed()) check_rejected(&s, PT_STRATEGY_NEE, PT_ABLATE_LIGHT_PDF, PT_STRATEGY_MIS, 256, 2);
    if (!test_has_failed()) check_rejected(&s, PT_STRATEGY_MIS, PT_ABLATE_MIS_SUM, PT_STRATEGY_NEE, 256, 2);
    if (!test_has_failed()) check_rejected(&s, PT_STRATEGY_MIS, PT_ABLATE_LIGHT_PDF, PT_STRATEGY_MIS, 256, 5);
    scene_free(&s);
}

/* ---- determinism, checkpoints, merging --------------------------------------------- */

static int states_identical(const pt_state *a, const pt_state *b)
{
    size_t n = 3 * (size_t)a->width * a->height;
    return a->width == b->width && a->height == b->height && a->spp == b->spp &&
           memcmp(a->sum, b->sum, n * sizeof *a->sum) == 0 && memcmp(a->sum_sq, b->sum_sq, n * sizeof *a->sum_sq) == 0;
}

static int images_identical(const image *a, const image *b)
{
    return a->width == b->width && a->height == b->height &&
           memcmp(a->px, b->px, 3 * sizeof(float) * (size_t)a->width * a->height) == 0;
}

TEST(pt_threads_deterministic)
{
    scene s;
    pt_options o;
    pt_result r1, r2, r7;
    CHECK(make_glossy_box(&s, 40) == 0); /* 3 x 3 tiles of 16 */
    s.width = 44;
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.spp = 6;
    o.jitter = 1;
    o.russian_roulette = 1;
    o.seed = test_seed();
    o.threads = 1;
    if (render(&s, &o, &r1)) return;
    o.threads = 2;
    if (render(&s, &o, &r2)) return;
    o.threads = 7;
    if (render(&s, &o, &r7)) return;
    CHECK(states_identical(&r1.state, &r2.state) && states_identical(&r1.state, &r7.state));
    CHECK(images_identical(&r1.mean, &r2.mean) && images_identical(&r1.mean, &r7.mean));
    CHECK(r1.rays == r7.rays && r1.paths == r7.paths && r1.paths == 6u * 44 * 40);
    pt_result_free(&r1);
    pt_result_free(&r2);
    pt_result_free(&r7);
    scene_free(&s);
}

typedef struct {
    volatile sig_atomic_t *flag;
    int calls, stop_after;
} stop_ctx;

static void stop_after_passes(void *ctx, const pt_state *st)
{
    stop_ctx *c = ctx;
    (void)st;
    if (++c->calls == c->stop_after) *c->flag = 1;
}

/* An interrupted run (stop flag after 3 passes, checkpoint written), resumed to the target,
 * equals an uninterrupted run bit for bit. */
TEST(pt_checkpoint_resume_bit_exact)
{
    scene s;
    pt_options o;
    pt_result full, part, resumed;
    volatile sig_atomic_t flag = 0;
    stop_ctx ctx;
    const char *ck = test_tmp_path("pt-resume.ckpt");
    char ck_path[1024];
    snprintf(ck_path, sizeof ck_path, "%s", ck);
    CHECK(make_glossy_box(&s, 20) == 0);
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.spp = 9;
    o.seed = test_seed() + 5;
    o.sample_offset = 100;
    o.threads = 2;
    if (render(&s, &o, &full)) return;

    ctx.flag = &flag;
    ctx.calls = 0;
    ctx.stop_after = 3;
    o.stop_flag = &flag;
    o.callback_every = 1;
    o.on_passes = stop_after_passes;
    o.callback_ctx = &ctx;
    o.checkpoint_path = ck_path;
    if (render(&s, &o, &part)) return;
    CHECK(part.stopped && part.state.spp == 3 && test_file_exists(ck_path));

    flag = 0;
    o.stop_flag = NULL;
    o.on_passes = NULL;
    o.callback_every = 0;
    o.checkpoint_path = NULL;
    o.resume_path = ck_path;
    o.sample_offset = 0; /* ignored on resume: the checkpoint's range continues */
    o.threads = 7;
    if (render(&s, &o, &resumed)) return;
    CHECK(resumed.spp_added == 6 && resumed.state.sample_offset == 100);
    CHECK(states_identical(&full.state, &resumed.state));
    CHECK(images_identical(&full.mean, &resumed.mean));
    pt_result_free(&full);
    pt_result_free(&part);
    pt_result_free(&resumed);
    scene_free(&s);
}

TEST(pt_checkpoint_rejects_mismatch_and_corruption)
{
    scene s;
    pt_options o;
    pt_result r;
    rerror e;
    pt_state st;
    const char *p = test_tmp_path("pt-mismatch.ckpt");
    char path[1024];
    FILE *f;
    snprintf(path, sizeof path, "%s", p);
    CHECK(make_glossy_box(&s, 8) == 0);
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.spp = 2;
    o.checkpoint_path = path;
    if (render(&s, &o, &r)) return;
    pt_result_free(&r);
    CHECK(pt_checkpoint_read(path, &st, &e) == 0 && st.spp == 2 && st.seed == 1);
    pt_state_free(&st);
    /* A different estimator (strategy) must not continue this state. */
    o.checkpoint_path = NULL;
    o.resume_path = path;
    o.spp = 4;
    o.strategy = PT_STRATEGY_NEE;
    CHECK(pt_render(&s, &o, &r, &e) != 0);
    CHECKF(strstr(e.msg, "different scene or estimator") != NULL, "%s", e.msg);
    /* One flipped byte in the payload fails the checksum. */
    f = fopen(path, "r+b");
    CHECK(f != NULL);
    fseek(f, 80, SEEK_SET);
    fputc(0x5a ^ 0xff, f);
    fclose(f);
    CHECK(pt_checkpoint_read(path, &st, &e) != 0);
    CHECKF(strstr(e.msg, "corrupt") != NULL, "%s", e.msg);
    /* Truncation. */
    CHECK(truncate(path, 40) == 0);
    CHECK(pt_checkpoint_read(path, &st, &e) != 0);
    CHECKF(strstr(e.msg, "truncated") != NULL, "%s", e.msg);
    scene_free(&s);
}

static double max_rel_diff(const image *a, const image *b)
{
    size_t i, n = 3 * (size_t)a->width * a->height;
    double worst = 0;
    for (i = 0; i < n; ++i) {
        double d = fabs((double)a->px[i] - (double)b->px[i]), m = fmax(fabs((double)a->px[i]), 1e-30);
        if (d / m > worst) worst = d / m;
    }
    return worst;
}

/* Runs over the sample ranges [0, 5) and [5, 12) merge into the run over [0, 12):
 * from the checkpoint states (double sums) and from the float mean images with counts. */
TEST(pt_merge_sample_ranges)
{
    scene s;
    pt_options o;
    pt_result whole, a, b;
    image merged, merged_means, means[2];
    double counts[2] = {5, 7};
    rerror e;
    CHECK(make_glossy_box(&s, 16) == 0);
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.seed = test_seed() + 11;
    o.spp = 12;
    if (render(&s, &o, &whole)) return;
    o.spp = 5;
    if (render(&s, &o, &a)) return;
    o.spp = 7;
    o.sample_offset = 5;
    if (render(&s, &o, &b)) return;
    means[0] = a.mean;
    means[1] = b.mean;
    CHECKF(pt_merge_means(means, counts, 2, &merged_means, &e) == 0, "%s", e.msg);
    CHECKF(pt_state_merge(&a.state, &b.state, &e) == 0, "%s", e.msg);
    CHECK(a.state.spp == 12 && a.state.sample_offset == 0);
    CHECKF(pt_state_mean(&a.state, &merged, &e) == 0, "%s", e.msg);
    /* Double sums in another order: equal to float rounding (at most one float ulp). */
    CHECKF(max_rel_diff(&merged, &whole.mean) <= 1.2e-7, "state merge differs by %g", max_rel_diff(&merged, &whole.mean));
    CHECKF(max_rel_diff(&merged_means, &whole.mean) <= 4e-7, "mean merge differs by %g",
           max_rel_diff(&merged_means, &whole.mean));
    /* Overlapping or non-adjacent ranges are refused. */
    CHECK(pt_state_merge(&a.state, &b.state, &e) != 0);
    CHECKF(strstr(e.msg, "not adjacent") != NULL, "%s", e.msg);
    image_free(&merged);
    image_free(&merged_means);
    pt_result_free(&whole);
    pt_result_free(&a);
    pt_result_free(&b);
    scene_free(&s);
}

TEST(pt_time_limit_whole_passes)
{
    scene s;
    pt_options o;
    pt_result r;
    CHECK(make_glossy_box(&s, 16) == 0);
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.spp = 0;
    o.time_limit = 0.2;
    if (render(&s, &o, &r)) return;
    CHECKF(r.state.spp >= 1 && r.seconds >= 0.2 && r.seconds < 2, "spp %u in %g s", r.state.spp, r.seconds);
    CHECK(r.paths == (uint64_t)r.state.spp * 16 * 16);
    pt_result_free(&r);
    scene_free(&s);
}

TEST(pt_options_validated)
{
    scene s;
    pt_options o;
    pt_result r;
    rerror e;
    CHECK(make_glossy_box(&s, 8) == 0);
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.max_depth = 0;
    CHECK(pt_render(&s, &o, &r, &e) != 0 && strstr(e.msg, "max depth") != NULL);
    o.max_depth = 256;
    CHECK(pt_render(&s, &o, &r, &e) != 0);
    pt_options_default(&o);
    o.spp = 0;
    CHECK(pt_render(&s, &o, &r, &e) != 0 && strstr(e.msg, "time limit") != NULL);
    pt_options_default(&o);
    o.sample_offset = UINT32_MAX - 3;
    CHECK(pt_render(&s, &o, &r, &e) != 0 && strstr(e.msg, "2^32") != NULL);
    CHECK(pt_ablation_from_name("light-pdf") == PT_ABLATE_LIGHT_PDF);
    CHECK(pt_ablation_from_name("mis-sum") == PT_ABLATE_MIS_SUM);
    CHECK(pt_ablation_from_name("nonsense") == 0);
    scene_free(&s);
}

#ifndef RESTIR_REAL_FLOAT
/* NaN/Inf policy: a sample whose L overflows is counted, reported with its address and
 * accumulated as 0; the image stays finite and every pixel keeps the same count. The floor
 * of an emissive furnace box gets the absurd albedo 1.5e308, so NEE from floor points towards
 * close wall points overflows (f Le / p_light > DBL_MAX) while other samples stay finite.
 * (One sample per pixel: the sum of two finite samples could overflow too.) */
TEST(pt_nonfinite_samples_counted)
{
    scene s;
    pt_options o;
    pt_result r;
    size_t i, pixels;
    uint32_t m_floor;
    CHECK(make_furnace(&s, rgb_gray(1), rgb_gray((real)0.5), 10) == 0);
    m_floor = test_scene_material(&s, MAT_LAMBERT, rgb_gray(1.5e308), rgb_gray(1));
    s.triangles[4].material = s.triangles[5].material = m_floor; /* the y = lo quad */
    test_scene_camera(&s, v3(0, 0, 0), v3(0, -1, (real)0.3), v3(0, 0, 1), 120, 16);
    if (prepare(&s)) return;
    pt_options_default(&o);
    o.spp = 1;
    o.max_depth = 2;
    if (render(&s, &o, &r)) return;
    pixels = (size_t)s.width * s.height;
    CHECKF(r.state.nonfinite > 0 && r.state.nonfinite < pixels / 2, "%llu nonfinite samples",
           (unsigned long long)r.state.nonfinite);
    CHECK(r.state.first_nonfinite_pixel < pixels && r.state.first_nonfinite_sample == 0);
    for (i = 0; i < 3 * pixels; ++i) CHECK(isfinite(r.state.sum[i])); /* (the float image cannot hold 1e308) */
    CHECK(r.paths == pixels && r.state.spp == 1);
    pt_result_free(&r);
    scene_free(&s);
}
#endif

TEST(pt_bench_json)
{
    scene s;
    rerror e;
    char buf[2048];
    FILE *f = tmpfile();
    size_t n;
    CHECK(f != NULL);
    CHECK(make_glossy_box(&s, 8) == 0);
    if (prepare(&s)) return;
    CHECKF(bench_pt(f, &s, "glossy \"box\"", 2, 1, &e) == 0, "%s", e.msg);
    rewind(f);
    n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    CHECKF(strstr(buf, "\"samples_per_second\"") && strstr(buf, "\"rays_per_second\"") &&
               strstr(buf, "glossy \\\"box\\\"") && strstr(buf, "\"paths\": 128"),
           "%s", buf);
    scene_free(&s);
}
