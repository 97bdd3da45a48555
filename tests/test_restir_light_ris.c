/* ReSTIR PT with light RIS for NEE (docs/enhanced.md §6, "Shifts"): the reconnection of an
 * NEE path at k = d keeps the light point and the candidates, so the PSS Jacobian gains
 * the selection-probability ratio P'_s/P_s; the integral identity that ratio must satisfy
 * is checked paired (same candidates) at one pair of vertices; then every shift × {pairwise,
 * defensive} on the many-lights hall against the plain path tracer, with and without tiles,
 * and the light-ris-pdf ablation detected. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "restir/light_ris.h"
#include "restir/path_replay.h"
#include "restir/reconnection.h"
#include "pt_util.h"
#include "restir_util.h"
#include "test.h"

/* A Lambertian floor under eight small lights of different heights and powers, nothing
 * in between: every floor point sees every light's front face, so the reconnection of a
 * direct-light NEE path between two floor points never fails and the light RIS selection
 * probabilities at the two points differ strongly (near lights dominate). */
static int make_lamp_floor(scene *s)
{
    static const float where[8][3] = {{-0.8f, 0.8f, -0.7f}, {0.7f, 0.7f, -0.6f}, {-0.6f, 0.9f, 0.8f},
                                      {0.9f, 0.75f, 0.7f},  {0.0f, 1.2f, 0.0f},   {-0.2f, 0.6f, 0.1f},
                                      {0.3f, 0.9f, -0.2f},  {0.5f, 0.6f, 0.2f}};
    uint32_t floor_m, m[8];
    int i;
    if (test_scene_begin(s, 2 + 2 * 8, 9)) return -1;
    floor_m = test_scene_material(s, MAT_LAMBERT, rgb_gray((real)0.7), rgb_gray(0));
    for (i = 0; i < 8; ++i)
        m[i] = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make((real)(1 + 3 * i), (real)(2 + i), 4));
    test_scene_quad(s, v3f(-1.5f, 0, -1.5f), v3f(0, 0, 3), v3f(3, 0, 0), floor_m); /* +y */
    for (i = 0; i < 8; ++i) /* 0.1 m squares facing down: (x) x (z) = -y */
        test_scene_quad(s, v3f(where[i][0], where[i][1], where[i][2]), v3f(0.1f, 0, 0), v3f(0, 0, 0.1f), m[i]);
    test_scene_camera(s, v3(0, 3, -0.01), v3(0, 0, 0), v3(0, 1, 0), 60, 32);
    return test_scene_prepare(s);
}

/* For NEE paths x of pixel a (numbers of sample n) shifted by reconnection to pixel b:
 * A_n = p̂(T(x)) |J| and B_n = p̂ of the path of pixel b built from the SAME numbers. Given
 * the candidates, E[A | Z] = Σ_s P_s p̂'_s (P'_s/P_s) = Σ_s P'_s p̂'_s = E[B | Z] exactly, so
 * the mean of A - B is 0; a Jacobian without P'_s/P_s gives Σ_s P_s p̂'_s instead. Returns
 * the paired z of mean(A - B). */
static double selection_ratio_z(int tiles, long *used)
{
    scene s;
    light_set ls;
    restir_context c;
    path_vertex xa, xb;
    rerror e;
    double sum = 0, sq = 0;
    long n, count = 0;
    const long paths = 8000;
    if (make_lamp_floor(&s)) return 0;
    if (lights_build(&ls, &s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&s);
        return 0;
    }
    rt_context(&c, &s, &ls, RESTIR_SHIFT_RECONNECTION);
    c.path.light_ris = 32;
    c.path.light_tiles = tiles;
    c.path.image_width = s.width;
    if (!rt_primary_vertex(&s, 8, 9, &xa) || !rt_primary_vertex(&s, 23, 22, &xb)) {
        test_fail(__FILE__, __LINE__, "the primary rays miss the floor");
        goto done;
    }
    for (n = 0; n < paths; ++n) {
        path_sample x, y;
        path_trunk t;
        path_end end;
        real J;
        double a = 0, b;
        path_sample_begin(&x, test_seed() * 977u + 3u, 9 * 32 + 8, (uint32_t)n);
        x.length = 2;
        x.technique = PATH_TECH_NEE;
        if (path_record(&c, &xa, &x) != SHIFT_OK) continue; /* no candidate with p̂ > 0: never */
        if (shift_reconnection(&c, &xb, &x, &y, &J, NULL) == SHIFT_OK) a = (double)y.target * (double)J;
        b = path_replay(&t, &c, &xb, &x, &end) == SHIFT_OK ? (double)luminance(end.F) : 0;
        sum += a - b;
        sq += (a - b) * (a - b);
        ++count;
    }
    *used = count;
done:
    lights_free(&ls);
    scene_free(&s);
    if (count < 2) return 0;
    {
        double mean = sum / (double)count, var = (sq - sum * mean) / (double)(count - 1);
        return var > 0 ? mean / sqrt(var / (double)count) : 0;
    }
}

TEST(restir_light_ris_reconnection_selection_ratio)
{
    long used = 0;
    double z = selection_ratio_z(0, &used);
    if (test_has_failed()) return;
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  selection ratio: z %.2f\n", z);
    test_margin(z);
    CHECKF(used > 7900 && fabs(z) < 4, "mean of p̂(T x)|J| - p̂(x at b): z = %.2f over %ld paths", z, used);
    z = selection_ratio_z(1, &used);
    if (test_has_failed()) return;
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  selection ratio with tiles: z %.2f\n", z);
    test_margin(z);
    CHECKF(used > 7900 && fabs(z) < 4, "with light tiles: z = %.2f over %ld paths", z, used);
}

/* ---- every shift against the path tracer on the many-lights hall ---------------------- */
/* (all cases of one call share the path tracer's side, so they share its depth) */

typedef struct {
    int shift, mis, tiles, ablation;
    int depth; /* longest path */
} lr_case;

static void expect(const scene *s, const check_side *pt, const lr_case *m, int runs, int biased)
{
    restir_options o;
    check_side a;
    check_result c;
    check_options opt;
    rerror e;
    char what[256];
    int status;
    restir_options_default(&o);
    o.seed = test_seed() * 4099u + 31u * (uint32_t)m->shift + 7u * (uint32_t)m->mis + (uint32_t)m->tiles;
    o.shift = m->shift;
    o.mis = m->mis;
    o.spatial_passes = 2;
    o.neighbors = 4;
    o.radius = 4.0 * s->width / 16;
    o.ablation = m->ablation;
    o.frames = 4;
    o.max_depth = m->depth;
    o.threads = 2;
    o.light_ris = 32;
    o.light_tiles = m->tiles;
    if (rt_restir_side(s, &o, runs, 4, &a)) return;
    check_options_default(&opt);
    opt.alpha = 1e-3;
    opt.block_size = 4;
    status = check_compare(&a, pt, &opt, &c, &e);
    check_side_free(&a);
    CHECKF(status == 0, "check_compare: %s", e.msg);
    check_result_free(&c);
    snprintf(what, sizeof what, "many-lights light-ris 32%s shift %s mis %s ablate %s", m->tiles ? " tiles" : "",
             restir_shift_names[m->shift], restir_mis_names[m->mis], restir_ablation_names[m->ablation]);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                rt_mean_z(&c), c.lum_a.mean, c.lum_b.mean, c.rejected, c.tests, c.worst.z);
    test_margin(fabs(rt_mean_z(&c)) > fabs(c.worst.z) ? rt_mean_z(&c) : c.worst.z);
    if (biased)
        CHECKF(c.different, "%s: the biased estimator was not detected (mean z %.2f, worst block z %.2f)", what,
               rt_mean_z(&c), c.worst.z);
    else
        CHECKF(!c.different, "%s: differs from the path tracer: mean z %.2f (p %.3g), %ld of %ld blocks rejected, "
                             "worst z %.2f", what, rt_mean_z(&c), c.global.p, c.rejected, c.tests, c.worst.z);
}

static void cases(const lr_case *m, int n, int res, int runs, uint32_t spp, int biased)
{
    scene s;
    check_side pt;
    int i;
    if (rt_load_scene("scenes/many-lights.scene", res, &s)) return;
    if (rt_pt_side(&s, test_seed() * 7919u + 11, runs, spp, m[0].depth, 0, 4, &pt)) {
        scene_free(&s);
        return;
    }
    for (i = 0; i < n && !test_has_failed(); ++i) expect(&s, &pt, &m[i], runs, biased);
    check_side_free(&pt);
    scene_free(&s);
}

TEST(restir_light_ris_unbiased_subset)
{
    static const lr_case m[] = {
        {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 1, RESTIR_ABLATE_NONE, 3},
        {RESTIR_SHIFT_RECONNECTION, MIS_PAIRWISE_UNIFORM, 0, RESTIR_ABLATE_NONE, 3},
    };
    /* direct light (d = 2), where the BSDF side's MIS weight matters most */
    static const lr_case ablated[] = {{RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 0, RESTIR_ABLATE_LIGHT_RIS_PDF, 2}};
    cases(m, 2, 16, 8, 64, 0);
    if (!test_has_failed()) cases(ablated, 1, 24, 16, 64, 1);
}

TEST_LONG(restir_light_ris_unbiased_matrix_long)
{
    lr_case m[12];
    int shift, mis, tiles, n = 0;
    static const int shifts[] = {RESTIR_SHIFT_RECONNECTION, RESTIR_SHIFT_REPLAY, RESTIR_SHIFT_HYBRID};
    static const int families[] = {MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    for (shift = 0; shift < 3; ++shift)
        for (mis = 0; mis < 2; ++mis)
            for (tiles = 0; tiles < 2; ++tiles) {
                m[n].shift = shifts[shift];
                m[n].mis = families[mis];
                m[n].tiles = tiles;
                m[n].ablation = RESTIR_ABLATE_NONE;
                m[n].depth = 3;
                ++n;
            }
    cases(m, n, 24, 12, 128, 0);
}
