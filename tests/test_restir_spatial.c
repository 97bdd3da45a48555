/* Spatial reuse (spatial.h, restir_render with K passes): offline ReSTIR PT with every
 * unbiased resampling MIS family agrees with the reference path tracer under the K-run
 * statistics of `restir check`; constant MIS (GRIS §5.6) and --ablate jacobian are
 * detected as biased by the same comparison.
 *
 * Why constant MIS is biased here: with m_i = c_i / sum c every domain is assumed to
 * cover the pixel's whole path space. Where a neighbour's shift of a path fails (the
 * reconnection segment is occluded, the replayed ray misses), that neighbour's share of
 * the weight at that path is lost: the pixel comes out darker by the failed fraction.
 * The reconnection shift on cornell-glossy fails often at the tall block's shadow edges. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/json_text.h"
#include "restir/frame/offline.h"
#include "restir_util.h"
#include "test.h"

#define ALPHA 1e-3

typedef struct {
    int shift, mis, passes, ablation, neighbors;
    int frames;
} spatial_case;

typedef struct {
    scene s;
    check_side pt;
    int res, block, runs, max_depth;
} spatial_bench;

/* path NULL: the spot scene of restir_util.h. */
static int bench_open(spatial_bench *b, const char *path, int res, int runs, uint32_t spp, int max_depth)
{
    memset(b, 0, sizeof *b);
    b->res = res;
    b->block = 4;
    b->runs = runs;
    b->max_depth = max_depth;
    if (rt_load_scene(path, res, &b->s)) return -1; /* NULL: the spot scene */
    if (rt_pt_side(&b->s, test_seed() * 7919u + 5, runs, spp, max_depth, 0, b->block, &b->pt)) {
        scene_free(&b->s);
        return -1;
    }
    return 0;
}

static void bench_close(spatial_bench *b)
{
    check_side_free(&b->pt);
    scene_free(&b->s);
}

/* K runs of offline ReSTIR PT for case m against the reference; `biased` says which
 * verdict is expected. */
static void expect(spatial_bench *b, const char *name, const spatial_case *m, int biased)
{
    restir_options o;
    check_side a;
    check_result c;
    check_options opt;
    rerror e;
    char what[256];
    int status;
    restir_options_default(&o);
    o.seed = test_seed() * 1181u + 31u * (uint32_t)m->shift + 7u * (uint32_t)m->mis + (uint32_t)m->passes;
    o.shift = m->shift;
    o.spatial.mis = m->mis;
    o.spatial_passes = m->passes;
    o.spatial.neighbors = m->neighbors;
    o.spatial.radius = 4.0 * b->res / 16;
    o.ablation = m->ablation;
    o.frames = m->frames;
    o.candidates = 2;
    o.max_depth = b->max_depth;
    o.threads = 2;
    if (rt_restir_side(&b->s, &o, b->runs, b->block, &a)) return;
    check_options_default(&opt);
    opt.alpha = ALPHA;
    opt.block_size = b->block;
    status = check_compare(&a, &b->pt, &opt, &c, &e);
    check_side_free(&a);
    CHECKF(status == 0, "check_compare: %s", e.msg);
    snprintf(what, sizeof what, "%s shift %s mis %s passes %d ablate %s", name, restir_shift_names[m->shift],
             restir_mis_names[m->mis], m->passes, restir_ablation_names[m->ablation]);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                rt_mean_z(&c), c.lum_a.mean, c.lum_b.mean, c.rejected, c.tests, c.worst.z);
    if (biased)
        CHECKF(c.different, "%s: the biased estimator was not detected (mean z %.2f, worst block z %.2f)", what,
               rt_mean_z(&c), c.worst.z);
    else
        CHECKF(!c.different, "%s: differs from the path tracer: mean z %.2f (p %.3g), %ld of %ld blocks rejected, worst z %.2f",
               what, rt_mean_z(&c), c.global.p, c.rejected, c.tests, c.worst.z);
    check_result_free(&c);
}

/* The whole matrix on one scene: shift x {talbot, pairwise, defensive} x {1, 3 passes}. */
static void matrix(const char *path, int res, int runs, int frames, uint32_t spp)
{
    spatial_bench b;
    spatial_case m = {0, 0, 0, RESTIR_ABLATE_NONE, 4, 0};
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    static const int passes[] = {1, 3};
    int f, p;
    m.frames = frames;
    if (bench_open(&b, path, res, runs, spp, 4)) return;
    for (m.shift = 0; m.shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++m.shift)
        for (f = 0; f < 3 && !test_has_failed(); ++f)
            for (p = 0; p < 2 && !test_has_failed(); ++p) {
                m.mis = families[f];
                m.passes = passes[p];
                expect(&b, path, &m, 0);
            }
    bench_close(&b);
}

/* A light but discriminating subset: every shift, every unbiased family and both pass
 * counts appear at least once, on the three scenes. */
TEST(restir_spatial_unbiased_subset)
{
    spatial_bench b;
    spatial_case glossy[] = {
        {RESTIR_SHIFT_RECONNECTION, MIS_PAIRWISE_DEFENSIVE, 3, RESTIR_ABLATE_NONE, 4, 4},
        {RESTIR_SHIFT_REPLAY, MIS_TALBOT, 1, RESTIR_ABLATE_NONE, 4, 4},
        {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_UNIFORM, 3, RESTIR_ABLATE_NONE, 4, 4},
    };
    spatial_case cornell = {RESTIR_SHIFT_HYBRID, MIS_TALBOT, 3, RESTIR_ABLATE_NONE, 4, 4};
    /* glass: caustics through a small light are heavy-tailed on both sides; more frames */
    spatial_case glass = {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 3, RESTIR_ABLATE_NONE, 4, 16};
    size_t i;
    if (bench_open(&b, "scenes/cornell-glossy.scene", 16, 16, 64, 4)) return;
    for (i = 0; i < sizeof glossy / sizeof glossy[0] && !test_has_failed(); ++i) expect(&b, "cornell-glossy", &glossy[i], 0);
    bench_close(&b);
    if (test_has_failed() || bench_open(&b, "scenes/cornell.scene", 16, 16, 64, 4)) return;
    expect(&b, "cornell", &cornell, 0);
    bench_close(&b);
    if (test_has_failed() || bench_open(&b, "scenes/glass.scene", 16, 16, 256, 4)) return;
    expect(&b, "glass", &glass, 0);
    bench_close(&b);
}

/* Constant MIS where shifts fail (occlusion at the tall block, cornell-glossy) and the
 * dropped Jacobian (the spot scene, where E[J] is far from 1): both detected, while the
 * unbiased family passes on the same spot reference. */
TEST(restir_spatial_constant_mis_and_jacobian_ablation_detected)
{
    spatial_bench b;
    spatial_case constant = {RESTIR_SHIFT_RECONNECTION, MIS_CONSTANT, 3, RESTIR_ABLATE_NONE, 6, 4};
    spatial_case jacobian = {RESTIR_SHIFT_RECONNECTION, MIS_PAIRWISE_DEFENSIVE, 3, RESTIR_ABLATE_JACOBIAN, 4, 8};
    spatial_case fine = {RESTIR_SHIFT_RECONNECTION, MIS_PAIRWISE_DEFENSIVE, 3, RESTIR_ABLATE_NONE, 4, 8};
    if (bench_open(&b, "scenes/cornell-glossy.scene", 16, 16, 64, 4)) return;
    expect(&b, "cornell-glossy", &constant, 1);
    bench_close(&b);
    if (test_has_failed() || bench_open(&b, NULL, 16, 16, 256, 3)) return;
    expect(&b, "spot", &jacobian, 1);
    if (!test_has_failed()) expect(&b, "spot", &fine, 0);
    bench_close(&b);
}

TEST_LONG(restir_spatial_unbiased_matrix_long)
{
    matrix("scenes/cornell.scene", 16, 24, 4, 64);
    if (!test_has_failed()) matrix("scenes/cornell-glossy.scene", 16, 24, 4, 64);
    if (!test_has_failed()) matrix("scenes/glass.scene", 16, 24, 16, 256); /* heavy caustic tails */
}

/* The CLI: --preset gris-offline with an override, the effective configuration and the
 * per-pass milliseconds in --stats (well-formed JSON); --time-limit renders >= 1 frame. */
TEST(restir_spatial_cli_preset_stats_time_limit)
{
    char out[4096], cmd[1024];
    const char *img = test_tmp_path("preset.pfm"), *stats = test_tmp_path("preset.json");
    json_reader jr;
    rerror e;
    scene s;
    restir_options o;
    restir_result r;
    snprintf(cmd, sizeof cmd,
             "render scenes/cornell.scene --method restir --preset gris-offline --candidates 2 --mis pairwise "
             "--size 12x12 --quiet --no-png -o %s --stats %s",
             img, stats);
    CHECKF(test_cli(out, sizeof out, "%s", cmd) == 0, "%s", out);
    CHECKF(json_reader_open(&jr, stats, &e) == 0, "%s", e.msg);
    if (test_has_failed()) return;
    CHECKF(json_skip_value(&jr) == 0 && json_expect_end(&jr) == 0, "%s", e.msg);
    CHECK(strstr(jr.text, "\"candidates\": 2,") && strstr(jr.text, "\"spatial_passes\": 3,"));
    CHECK(strstr(jr.text, "\"neighbors\": 6,") && strstr(jr.text, "\"radius\": 10,") &&
          strstr(jr.text, "\"mis\": \"pairwise\""));
    CHECK(strstr(jr.text, "\"spatial\": [") && strstr(jr.text, "\"shifts_per_pixel_per_frame\""));
    json_reader_close(&jr);
    CHECK(test_cli(out, sizeof out, "render scenes/cornell.scene --method restir --preset nonsense -o %s", img) == 2);
    /* --time-limit is shared with the path tracer's row and handed to restir */
    CHECKF(test_cli(out, sizeof out,
                    "render scenes/cornell.scene --method restir --time-limit 0.1 --size 8x8 --quiet --no-png -o %s "
                    "--stats %s",
                    img, stats) == 0,
           "%s", out);
    CHECKF(json_reader_open(&jr, stats, &e) == 0, "%s", e.msg);
    if (test_has_failed()) return;
    CHECK(strstr(jr.text, "\"time_limit\": 0.1,") && !strstr(jr.text, "\"frames\": 1,\n"));
    json_reader_close(&jr);
    if (rt_load_scene("scenes/cornell.scene", 8, &s)) return;
    restir_options_default(&o);
    o.spatial_passes = 1;
    o.time_limit = 0.05;
    CHECKF(restir_render(&s, &o, &r, &e) == 0, "%s", e.msg);
    if (!test_has_failed()) {
        CHECK(r.stats.frames >= 1 && r.seconds >= 0.05);
        restir_result_free(&r);
    }
    scene_free(&s);
}

/* One GRIS step with M = 5 domains of neighbouring pixels (all with a sample): the shift
 * evaluations are M - 1 forward shifts plus, for MIS, (M - 1)^2 (Talbot), M - 1 (pairwise,
 * both) and 0 (constant), i.e. mis_shift_count() -- exactly so when every shift succeeds
 * (a failed forward shift drops its column), at most so otherwise; the output confidence
 * is the sum of the inputs; the output W is finite and the sample valid. Several pixel
 * neighbourhoods are tried; at least one must have every shift succeed. */
enum { STEP_M = 5 };

static void step_counts_at(const restir_context *c, const scene *s, int cx, int cy, spatial_workspace *w, int *all_exact)
{
    static const int dx[STEP_M] = {0, 2, -1, 1, 0}, dy[STEP_M] = {0, 0, 1, -2, 2};
    initial_options io;
    initial_stats ist;
    path_vertex v[STEP_M];
    const path_vertex *x1[STEP_M];
    reservoir r[STEP_M], out;
    const reservoir *in[STEP_M];
    real u[STEP_M];
    int d, f, exact = 0;
    memset(&io, 0, sizeof io);
    memset(&ist, 0, sizeof ist);
    io.trees = 4;
    io.max_depth = 5;
    io.rr_min_depth = 3;
    for (d = 0; d < STEP_M; ++d) {
        int x = cx + dx[d], y = cy + dy[d];
        if (!rt_primary_vertex(s, x, y, &v[d])) return;
        initial_sample_pixel(c, &io, &v[d], test_seed(), (uint32_t)(y * s->width + x), 0, &r[d], &ist);
        if (!path_sample_is_valid(&r[d].y) || !(r[d].W > 0)) return;
        x1[d] = &v[d];
        in[d] = &r[d];
        u[d] = (real)(d + 0.5) / STEP_M;
    }
    for (f = 0; f < MIS_FAMILY_COUNT; ++f) {
        spatial_stats st;
        long expected = mis_shift_count((mis_family)f, STEP_M, 1);
        memset(&st, 0, sizeof st);
        spatial_resample(c, (mis_family)f, STEP_M, x1, in, u, &out, w, &st);
        if (st.outcome[SHIFT_OK] == st.shifts) {
            CHECKF((long)st.mis_shifts == expected, "%s: %llu MIS shifts, expected %ld", mis_family_name((mis_family)f),
                   (unsigned long long)st.mis_shifts, expected);
            exact++;
        }
        CHECK((long)st.mis_shifts <= expected && st.shifts - st.mis_shifts == STEP_M - 1);
        CHECK(out.confidence == 4 * STEP_M);
        CHECK(path_sample_is_valid(&out.y) && out.W > 0 && isfinite((double)out.W));
    }
    *all_exact += exact == MIS_FAMILY_COUNT;
}

TEST(restir_spatial_step_shift_counts)
{
    static const int centres[][2] = {{12, 14}, {16, 8}, {8, 20}, {20, 20}, {16, 26}, {6, 8}, {26, 10}, {10, 4}};
    scene s;
    light_set lights;
    restir_context c;
    spatial_workspace w;
    rerror e;
    int k, all_exact = 0;
    if (rt_load_scene("scenes/cornell.scene", 32, &s)) return;
    CHECKF(lights_build(&lights, &s, &e) == 0, "%s", e.msg);
    rt_context(&c, &s, &lights, RESTIR_SHIFT_RECONNECTION);
    CHECK(spatial_workspace_alloc(&w, STEP_M, &e) == 0);
    for (k = 0; k < (int)(sizeof centres / sizeof centres[0]) && !test_has_failed(); ++k)
        step_counts_at(&c, &s, centres[k][0], centres[k][1], &w, &all_exact);
    CHECKF(all_exact > 0, "no neighbourhood had every shift succeed");
    spatial_workspace_free(&w);
    lights_free(&lights);
    scene_free(&s);
}
