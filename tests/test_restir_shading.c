/* Vector-valued shading weights (--shading vector; Enhanced §6.3; offline.c
 * vector_estimate): the pixel estimate sum_i m_i F(Y_i) W_i |dT_i/dX_i| over the last
 * spatial pass's inputs, while the scalar weights still drive resampling.
 *   - it is the expectation of the scalar estimate F(Y) W_Y over the last selection, so on
 *     the same seeds (same inputs, same candidates) vector - scalar has mean zero: a paired
 *     test against the validated scalar estimator, on the spot scene (E[J] far from 1) and
 *     cornell-glossy;
 *   - unbiased against the reference path tracer (unpaired, `restir check`). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

#define ALPHA 1e-3

static void options(restir_options *o, const scene *s, int shift, int mis, int passes, int frames, int shading)
{
    restir_options_default(o);
    o->seed = test_seed() * 4813u + 11u * (uint32_t)shift + (uint32_t)mis;
    o->shift = shift;
    o->spatial.mis = mis;
    o->spatial_passes = passes;
    o->spatial.neighbors = 4;
    o->spatial.radius = 4.0 * s->width / 16;
    o->frames = frames;
    o->candidates = 2;
    o->max_depth = 4;
    o->threads = 2;
    o->shading = shading;
}

/* path NULL: the spot scene */
static int open_scene(const char *path, scene *s)
{
    rerror e;
    if (path) return rt_load_scene(path, 16, s);
    if (rt_make_spot(s, 16)) return -1;
    if (scene_prepare(s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(s);
        return -1;
    }
    return 0;
}

/* vector against scalar on the same seeds (K runs): not different. */
static void paired_vector_scalar(const char *path, const char *name, int shift, int mis, int runs)
{
    scene s;
    restir_options ov, os;
    check_side a, b;
    check_options opt;
    check_result r, u;
    rerror e;
    if (open_scene(path, &s)) return;
    options(&ov, &s, shift, mis, 3, 4, RESTIR_SHADING_VECTOR);
    options(&os, &s, shift, mis, 3, 4, RESTIR_SHADING_SCALAR);
    if (rt_restir_side(&s, &ov, runs, 4, &a) == 0) {
        if (rt_restir_side(&s, &os, runs, 4, &b) == 0) {
            check_options_default(&opt);
            opt.alpha = ALPHA;
            opt.block_size = 4;
            if (check_compare_paired(&a, &b, &opt, &r, &e) == 0) {
                double z = stats_t_to_z(r.global.t, r.global.dof);
                if (getenv("RESTIR_TEST_VERBOSE") && check_compare(&a, &b, &opt, &u, &e) == 0) {
                    fprintf(stderr, "  paired %s vector vs scalar (%s, %s): mean z %.2f (relative diff %+.4f%%), "
                                    "%ld/%ld blocks rejected, worst block z %.2f; image-mean variance vector/scalar %.3f\n",
                            name, restir_shift_names[shift], restir_mis_names[mis], z, 100 * r.bias, r.rejected,
                            r.tests, r.worst.z, u.lum_a.var_of_mean / u.lum_b.var_of_mean);
                    check_result_free(&u);
                }
                CHECKF(!r.different, "%s: vector shading differs from scalar on the same seeds: mean z %.2f, %ld of %ld "
                                     "blocks rejected, worst z %.2f",
                       name, z, r.rejected, r.tests, r.worst.z);
                check_result_free(&r);
            } else {
                test_fail(__FILE__, __LINE__, "check_compare_paired: %s", e.msg);
            }
            check_side_free(&b);
        }
        check_side_free(&a);
    }
    scene_free(&s);
}

TEST(restir_shading_vector_paired_with_scalar)
{
    paired_vector_scalar(NULL, "spot", RESTIR_SHIFT_RECONNECTION, MIS_PAIRWISE_DEFENSIVE, 48);
    if (!test_has_failed())
        paired_vector_scalar("scenes/cornell-glossy.scene", "cornell-glossy", RESTIR_SHIFT_HYBRID, MIS_TALBOT, 16);
}

TEST(restir_shading_vector_unbiased)
{
    scene s;
    check_side pt, a;
    check_options opt;
    check_result c;
    restir_options o;
    rerror e;
    if (open_scene("scenes/cornell-glossy.scene", &s)) return;
    if (rt_pt_side(&s, test_seed() * 7919u + 5, 16, 64, 4, 0, 4, &pt)) {
        scene_free(&s);
        return;
    }
    options(&o, &s, RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 3, 4, RESTIR_SHADING_VECTOR);
    if (rt_restir_side(&s, &o, 16, 4, &a) == 0) {
        check_options_default(&opt);
        opt.alpha = ALPHA;
        opt.block_size = 4;
        if (check_compare(&a, &pt, &opt, &c, &e) == 0) {
            if (getenv("RESTIR_TEST_VERBOSE"))
                fprintf(stderr, "  cornell-glossy vector hybrid pairwise-defensive 3 passes vs pt: mean z %.2f, %ld/%ld "
                                "blocks rejected, worst block z %.2f\n",
                        rt_mean_z(&c), c.rejected, c.tests, c.worst.z);
            CHECKF(!c.different, "vector shading differs from the path tracer: mean z %.2f, worst z %.2f", rt_mean_z(&c),
                   c.worst.z);
            check_result_free(&c);
        }
        check_side_free(&a);
    }
    check_side_free(&pt);
    scene_free(&s);
}
