/* ReSTIR PT initial resampling (include/restir/restir/initial.h): with one path tree it is the
 * reference path tracer's tree (the luminance of F(Y) W_Y equals the path tracer's
 * sample, pixel by pixel), and with N trees it is an unbiased estimator of the same image
 * (K-run statistics of `restir check`). */
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/frame/offline.h"
#include "restir/frame/options.h"

#ifdef RESTIR_REAL_FLOAT
#define LUM_RTOL 2e-4
#else
#define LUM_RTOL 2e-6 /* both images are stored as float */
#endif

static int restir_frame(const scene *s, const restir_options *base, int frame, restir_result *r)
{
    restir_options o = *base;
    rerror e;
    o.first_frame = frame;
    o.frames = 1;
    if (restir_render(s, &o, r, &e)) {
        test_fail(__FILE__, __LINE__, "restir_render: %s", e.msg);
        return -1;
    }
    return 0;
}

static int pt_sample(const scene *s, const restir_options *ro, int frame, int depth, pt_result *r)
{
    pt_options o;
    rerror e;
    pt_options_default(&o);
    o.seed = ro->seed;
    o.sample_offset = (uint32_t)frame;
    o.spp = 1;
    o.max_depth = depth;
    o.russian_roulette = ro->russian_roulette;
    o.rr_min_depth = ro->rr_min_depth;
    if (pt_render(s, &o, r, &e)) {
        test_fail(__FILE__, __LINE__, "pt_render: %s", e.msg);
        return -1;
    }
    return 0;
}

static double pixel_lum(const image *img, long p) { return 0.2126 * img->px[3 * p] + 0.7152 * img->px[3 * p + 1] + 0.0722 * img->px[3 * p + 2]; }

/* lum(Le(x1) + F(Y) W_Y) = lum(L_PT) for every pixel: with one tree the reservoir's
 * W = sum_i p̂(x_i) / (P_rr,i p̂(Y)), so lum(F(Y) W) = sum_i lum(F_i) / P_rr,i, the path
 * tracer's sample. Indirect: lum(F W) = lum(L_PT(D)) - lum(L_PT(2)) of the same sample. */
static void tree_is_pt(const char *path, int rr, int indirect)
{
    scene s;
    restir_options o;
    int f, depth = 6;
    long p, checked = 0;
    if (rt_load_scene(path, 16, &s)) return;
    restir_options_default(&o);
    o.seed = test_seed() * 977u + 5;
    o.max_depth = depth;
    o.russian_roulette = rr;
    o.rr_min_depth = 2;
    o.paths = indirect ? RESTIR_PATHS_INDIRECT : RESTIR_PATHS_ALL;
    for (f = 0; f < 6 && !test_has_failed(); ++f) {
        restir_result rr_res;
        pt_result full, direct;
        if (restir_frame(&s, &o, f, &rr_res)) break;
        if (pt_sample(&s, &o, f, depth, &full)) break;
        if (indirect && pt_sample(&s, &o, f, 2, &direct)) break;
        CHECKF(rr_res.stats.initial.record_failed == 0 && rr_res.stats.initial.record_mismatch == 0,
               "%s: recorded paths differ from the streamed candidates (%llu failed, %llu mismatched)", path,
               (unsigned long long)rr_res.stats.initial.record_failed,
               (unsigned long long)rr_res.stats.initial.record_mismatch);
        for (p = 0; p < (long)s.width * s.height; ++p) {
            double a = pixel_lum(&rr_res.mean, p);
            double b = indirect ? pixel_lum(&full.mean, p) - pixel_lum(&direct.mean, p) : pixel_lum(&full.mean, p);
            double tol = LUM_RTOL * (fabs(b) + (indirect ? pixel_lum(&full.mean, p) : 0)) + 1e-12;
            CHECKF(fabs(a - b) <= tol, "%s rr %d indirect %d frame %d pixel %ld: restir lum %.9g, path tracer %.9g", path,
                   rr, indirect, f, p, a, b);
            checked += b > 0;
        }
        restir_result_free(&rr_res);
        pt_result_free(&full);
        if (indirect) pt_result_free(&direct);
    }
    CHECK(checked > 100);
    scene_free(&s);
}

TEST(restir_initial_tree_is_the_path_tracer_tree)
{
    tree_is_pt("scenes/cornell.scene", 0, 0);
    if (!test_has_failed()) tree_is_pt("scenes/cornell-glossy.scene", 0, 0);
    if (!test_has_failed()) tree_is_pt("scenes/cornell-glossy.scene", 1, 0);
    if (!test_has_failed()) tree_is_pt("scenes/cornell.scene", 0, 1);
    if (!test_has_failed()) tree_is_pt("scenes/cornell-glossy.scene", 1, 1);
}

/* ---- unbiasedness with N trees (K-run statistics) -------------------------------------- */

#define ALPHA 1e-3

static void report(const char *what, const check_result *c)
{
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                rt_mean_z(c), c->lum_a.mean, c->lum_b.mean, c->rejected, c->tests, c->worst.z);
}

/* restir (options o, K runs) against the path tracer (K runs of spp samples). */
static int restir_vs_pt(const scene *s, const restir_options *o, int runs, uint32_t pt_spp, check_result *c)
{
    check_side a, b;
    if (rt_restir_side(s, o, runs, 8, &a)) return -1;
    if (rt_pt_side(s, o->seed * 7u + 3, runs, pt_spp, o->max_depth, o->paths == RESTIR_PATHS_INDIRECT, 8, &b)) {
        check_side_free(&a);
        return -1;
    }
    return rt_compare(&a, &b, ALPHA, 8, c);
}

static void initial_unbiased_at(const char *path, int trees, int rr, int indirect, int res, int runs, int frames)
{
    scene s;
    restir_options o;
    check_result c;
    char what[256];
    if (rt_load_scene(path, res, &s)) return;
    restir_options_default(&o);
    o.seed = test_seed() * 131u + 17;
    o.candidates = trees;
    o.frames = frames;
    o.max_depth = 5;
    o.russian_roulette = rr;
    o.paths = indirect ? RESTIR_PATHS_INDIRECT : RESTIR_PATHS_ALL;
    o.threads = 2;
    if (restir_vs_pt(&s, &o, runs, 32, &c)) return;
    snprintf(what, sizeof what, "%s N=%d rr=%d indirect=%d", path, trees, rr, indirect);
    report(what, &c);
    check_result_free(&c);
    CHECKF(!c.different, "%s: initial sampling differs from the path tracer: mean z %.2f (p %.3g), %ld of %ld blocks "
                         "rejected, worst z %.2f",
           what, rt_mean_z(&c), c.global.p, c.rejected, c.tests, c.worst.z);
    scene_free(&s);
}

static void initial_unbiased(const char *path, int trees, int rr, int indirect)
{
    initial_unbiased_at(path, trees, rr, indirect, 16, 16, 4);
}

TEST_LONG(restir_initial_unbiased_long)
{
    initial_unbiased_at("scenes/cornell.scene", 8, 0, 0, 32, 32, 8);
    if (!test_has_failed()) initial_unbiased_at("scenes/cornell-glossy.scene", 8, 1, 0, 32, 32, 8);
    if (!test_has_failed()) initial_unbiased_at("scenes/cornell-glossy.scene", 4, 1, 1, 32, 32, 16);
}

TEST(restir_initial_unbiased_against_path_tracer)
{
    initial_unbiased("scenes/cornell.scene", 4, 0, 0);
    if (!test_has_failed()) initial_unbiased("scenes/cornell-glossy.scene", 4, 1, 0);
    if (!test_has_failed()) initial_unbiased("scenes/cornell-glossy.scene", 3, 0, 1);
}
