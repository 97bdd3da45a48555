/* Stochastic pairwise MIS in the spatial passes (stochastic_spatial.h; docs/stochastic-mis.md):
 *   - unbiased against the reference path tracer (unpaired, `restir check` statistics)
 *     for Ñ in {1, 4, 16} with and without the §4.3 confidence scaling, every shift;
 *   - paired against the deterministic all-M comparator (defensive pairwise MIS over the
 *     same domains, GRIS Eq. 38 = Stochastic MIS Eq. 11, which the stochastic weights
 *     estimate) on the same seeds: run k of both reuses exactly the same initial samples;
 *   - `--ablate stochastic-p` (picks among the non-zero samples without the P(i)
 *     correction) is detected.
 * Neighbours: the 5 x 5 box window (M = up to 24 non-canonical domains) so that Ñ < M. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/animation.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

#define ALPHA 1e-3

typedef rt_bench sto_bench;

typedef struct {
    int shift, n, nc, no_scaling, passes, ablation, frames;
    int candidates; /* 0: 2 path trees */
    int cells;      /* reuse cells (Stochastic MIS §5) instead of the box window */
} sto_case;

static int bench_open(sto_bench *b, const char *path, int res, int runs, uint32_t spp, int max_depth)
{
    return rt_bench_open(b, path, res, runs, spp, max_depth, test_seed() * 7919u + 11);
}

/* mis: a MIS family of the GRIS step, or STOCHASTIC_STEP (the stochastic pairwise step) */
#define STOCHASTIC_STEP (-1)
static void options_for(const sto_bench *b, const sto_case *m, uint32_t seed, int mis, restir_options *o)
{
    restir_options_default(o);
    o->seed = seed;
    o->shift = m->shift;
    if (mis == STOCHASTIC_STEP) o->spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE;
    else o->spatial.mis = (mis_family)mis;
    o->stochastic.n_picks = m->n;
    o->stochastic.n_canonical_picks = m->nc;
    o->stochastic.confidence_scaling = !m->no_scaling;
    o->spatial_passes = m->passes;
    o->spatial.pattern = NEIGHBOR_BOX;
    o->spatial.radius = 2;
    o->spatial.cells = m->cells;
    o->ablation = m->ablation;
    o->frames = m->frames;
    o->candidates = m->candidates ? m->candidates : 2;
    o->max_depth = b->max_depth;
    o->threads = 2;
}

static void case_name(const char *scene_name, const sto_case *m, char *out, size_t n)
{
    snprintf(out, n, "%s shift %s N~ %d N~c %d%s%s passes %d ablate %s", scene_name, restir_shift_names[m->shift], m->n,
             m->nc, m->no_scaling ? " unscaled" : "", m->cells ? " cells" : "", m->passes,
             restir_ablation_names[m->ablation]);
}

/* Unpaired against the path tracer; `biased` says which verdict is expected. */
static void expect_pt(sto_bench *b, const char *scene_name, const sto_case *m, int biased)
{
    restir_options o;
    check_side a;
    char what[256];
    options_for(b, m, test_seed() * 1187u + 13u * (uint32_t)m->shift + 7u * (uint32_t)m->n + (uint32_t)m->no_scaling, STOCHASTIC_STEP, &o);
    if (rt_restir_side(&b->s, &o, b->runs, b->block, &a)) return;
    case_name(scene_name, m, what, sizeof what);
    rt_expect_verdict(&a, &b->pt, ALPHA, b->block, what, biased, NULL);
}

/* Paired against defensive pairwise MIS over the same domains and seeds. */
static void expect_paired(sto_bench *b, const char *scene_name, const sto_case *m, int biased)
{
    restir_options oa, ob;
    check_side a, d;
    check_result r;
    char what[256];
    int status;
    uint32_t seed = test_seed() * 2654435761u + 101u + (uint32_t)m->n;
    options_for(b, m, seed, STOCHASTIC_STEP, &oa);
    options_for(b, m, seed, MIS_PAIRWISE_DEFENSIVE, &ob);
    ob.ablation = RESTIR_ABLATE_NONE;
    if (rt_restir_side(&b->s, &oa, b->runs, b->block, &a)) return;
    if (rt_restir_side(&b->s, &ob, b->runs, b->block, &d)) {
        check_side_free(&a);
        return;
    }
    status = rt_compare_paired(&a, &d, ALPHA, b->block, &r);
    check_side_free(&a);
    check_side_free(&d);
    if (status) return;
    case_name(scene_name, m, what, sizeof what);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  paired vs all-M defensive, %s: mean z %.2f (relative diff %+.4f%%), worst block z %.2f\n",
                what, stats_t_to_z(r.global.t, r.global.dof), 100 * r.bias, r.worst.z);
    if (biased)
        CHECKF(r.different, "%s: the biased estimator was not detected by the paired test (mean z %.2f, worst block z %.2f)",
               what, stats_t_to_z(r.global.t, r.global.dof), r.worst.z);
    else
        CHECKF(!r.different, "%s: differs from the all-M comparator on the same seeds: mean z %.2f, %ld of %ld blocks rejected, worst z %.2f",
               what, stats_t_to_z(r.global.t, r.global.dof), r.rejected, r.tests, r.worst.z);
    check_result_free(&r);
}

static void matrix(const char *path, int res, int runs, int frames, uint32_t spp, int passes, int cells)
{
    static const int picks[] = {1, 4, 16};
    sto_bench b;
    sto_case m = {0, 1, 1, 0, 1, RESTIR_ABLATE_NONE, 1, 0, 0};
    int k;
    m.frames = frames;
    m.passes = passes;
    m.cells = cells;
    if (bench_open(&b, path, res, runs, spp, 4)) return;
    for (m.shift = 0; m.shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++m.shift)
        for (k = 0; k < 3 && !test_has_failed(); ++k)
            for (m.no_scaling = 0; m.no_scaling < 2 && !test_has_failed(); ++m.no_scaling) {
                m.n = picks[k];
                m.nc = picks[k] > 1 ? 2 : 1;
                expect_pt(&b, path, &m, 0);
            }
    rt_bench_close(&b);
}

/* A subset: every shift, every Ñ, scaling on and off, cornell-glossy; the ablation. */
TEST(restir_stochastic_unbiased_subset)
{
    sto_bench b;
    static const sto_case cases[] = {
        {RESTIR_SHIFT_HYBRID, 1, 1, 0, 1, RESTIR_ABLATE_NONE, 1, 0, 0},
        {RESTIR_SHIFT_RECONNECTION, 4, 2, 1, 1, RESTIR_ABLATE_NONE, 1, 0, 0},
        {RESTIR_SHIFT_REPLAY, 16, 2, 0, 1, RESTIR_ABLATE_NONE, 1, 0, 0},
        {RESTIR_SHIFT_HYBRID, 4, 1, 0, 2, RESTIR_ABLATE_NONE, 1, 0, 0},
        {RESTIR_SHIFT_HYBRID, 1, 1, 0, 1, RESTIR_ABLATE_NONE, 1, 0, 1},
        {RESTIR_SHIFT_RECONNECTION, 16, 4, 1, 2, RESTIR_ABLATE_NONE, 1, 0, 1},
    };
    size_t i;
    if (bench_open(&b, "scenes/cornell-glossy.scene", 16, 16, 16, 4)) return;
    for (i = 0; i < sizeof cases / sizeof cases[0] && !test_has_failed(); ++i)
        expect_pt(&b, "cornell-glossy", &cases[i], 0);
    rt_bench_close(&b);
}

TEST(restir_stochastic_paired_and_ablation)
{
    sto_bench b;
    sto_case ok = {RESTIR_SHIFT_HYBRID, 4, 2, 1, 1, RESTIR_ABLATE_NONE, 1, 0, 0};
    sto_case cells = {RESTIR_SHIFT_HYBRID, 4, 2, 1, 1, RESTIR_ABLATE_NONE, 1, 0, 1};
    /* the ablation: direct light only (max depth 2) and 1 path tree, so that shadowed and
     * penumbra pixels hold zero samples; unscaled confidences give the picks most weight */
    sto_case naive = {RESTIR_SHIFT_HYBRID, 1, 1, 1, 1, RESTIR_ABLATE_STOCHASTIC_P, 1, 1, 0};
    memset(&b, 0, sizeof b);
    b.res = 16;
    b.block = 4;
    b.runs = 12;
    b.max_depth = 4;
    if (rt_load_scene("scenes/cornell-glossy.scene", 16, &b.s)) return;
    expect_paired(&b, "cornell-glossy", &ok, 0);
    if (!test_has_failed()) expect_paired(&b, "cornell-glossy", &cells, 0); /* vs all-M over the same cell (Fig. 7d) */
    scene_free(&b.s);
    b.max_depth = 2;
    b.runs = 32;
    if (rt_load_scene("scenes/cornell-glossy.scene", 32, &b.s)) return;
    if (!test_has_failed()) expect_paired(&b, "cornell-glossy 32", &naive, 1);
    scene_free(&b.s);
}

TEST_LONG(restir_stochastic_unbiased_matrix_long)
{
    int cells;
    for (cells = 0; cells < 2 && !test_has_failed(); ++cells) {
        matrix("scenes/cornell.scene", 16, 16, 1, 16, 1, cells);
        if (!test_has_failed()) matrix("scenes/cornell-glossy.scene", 16, 16, 1, 16, 1, cells);
        if (!test_has_failed()) matrix("scenes/glass.scene", 16, 16, 2, 32, 1, cells);
    }
}

/* ---- the real-time pipeline: the pillars disocclusion sequence (scenes/pillars.scene) ---- */

#define SEQ_TIMES RT_MAX_TIMES

/* Pillars frames `times` with temporal reuse (Talbot) + one stochastic spatial pass per
 * case, each frame against the path tracer on the scene posed at that frame. */
static void pillars(const sto_case *cases, int n_cases, const int *times, int nt, int runs, double alpha)
{
    scene s;
    check_side pt[SEQ_TIMES];
    rerror e;
    int i, c;
    if (rt_load_scene("scenes/pillars.scene", 16, &s)) return;
    for (i = 0; i < nt; ++i) {
        if (scene_pose_at(&s, times[i], &e) ||
            rt_pt_side_at(&s, test_seed() * 7919u + 5 + 131u * (uint32_t)i, runs, 64, 4, 0, times[i], 4, &pt[i])) {
            test_fail(__FILE__, __LINE__, "pillars reference of frame %d", times[i]);
            while (i-- > 0) check_side_free(&pt[i]);
            scene_free(&s);
            return;
        }
    }
    if (scene_pose_at(&s, 0, &e)) test_fail(__FILE__, __LINE__, "%s", e.msg);
    for (c = 0; c < n_cases && !test_has_failed(); ++c) {
        const sto_case *m = &cases[c];
        restir_options o;
        rt_frame_sides q;
        sto_bench dummy;
        dummy.max_depth = 4;
        options_for(&dummy, m, test_seed() * 1181u + 17u * (uint32_t)c, STOCHASTIC_STEP, &o);
        o.temporal.enabled = 1;
        o.temporal.mis = MIS_TALBOT;
        memset(&q, 0, sizeof q);
        q.nt = nt;
        for (i = 0; i < nt; ++i) q.times[i] = times[i];
        if (rt_frame_sides_run(&s, &o, runs, 4, &q)) break;
        for (i = 0; i < nt; ++i) {
            check_options opt;
            check_result r;
            char what[256];
            int status;
            check_options_default(&opt);
            opt.alpha = alpha;
            opt.block_size = 4;
            status = check_compare(&q.side[i], &pt[i], &opt, &r, &e);
            CHECKF(status == 0, "check_compare: %s", e.msg);
            if (status) continue;
            case_name("pillars", m, what, sizeof what);
            if (getenv("RESTIR_TEST_VERBOSE"))
                fprintf(stderr, "  %s frame %d: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n",
                        what, times[i], rt_mean_z(&r), r.lum_a.mean, r.lum_b.mean, r.rejected, r.tests, r.worst.z);
            CHECKF(!r.different, "%s frame %d: differs from the path tracer: mean z %.2f, %ld of %ld blocks rejected, worst z %.2f",
                   what, times[i], rt_mean_z(&r), r.rejected, r.tests, r.worst.z);
            check_result_free(&r);
        }
        for (i = 0; i < nt; ++i) check_side_free(&q.side[i]);
    }
    for (i = 0; i < nt; ++i) check_side_free(&pt[i]);
    scene_free(&s);
}

TEST(restir_stochastic_pillars_sequence_subset)
{
    static const int times[] = {4};
    static const sto_case cases[] = {
        {RESTIR_SHIFT_HYBRID, 4, 1, 0, 1, RESTIR_ABLATE_NONE, 1, 0, 1},
        {RESTIR_SHIFT_REPLAY, 1, 1, 1, 1, RESTIR_ABLATE_NONE, 1, 0, 0},
    };
    pillars(cases, 2, times, 1, 16, ALPHA);
}

/* Every shift x Ñ in {1, 4, 16} x scaling on/off x {box window, cells}, frames 1, 4, 16. */
TEST_LONG(restir_stochastic_pillars_sequence_long)
{
    static const int times[] = {1, 4, 16};
    static const int picks[] = {1, 4, 16};
    sto_case cases[RESTIR_SHIFT_COUNT * 3 * 2 * 2];
    int n = 0, sh, k, sc, ce;
    for (sh = 0; sh < RESTIR_SHIFT_COUNT; ++sh)
        for (k = 0; k < 3; ++k)
            for (sc = 0; sc < 2; ++sc)
                for (ce = 0; ce < 2; ++ce) {
                    sto_case m = {0, 1, 1, 0, 1, RESTIR_ABLATE_NONE, 1, 0, 0};
                    m.shift = sh;
                    m.n = picks[k];
                    m.nc = picks[k] > 1 ? 2 : 1;
                    m.no_scaling = sc;
                    m.cells = ce;
                    cases[n++] = m;
                }
    pillars(cases, n, times, 3, 24, 1e-4); /* 216 comparisons */
}

/* The CLI: the options reach the renderer (--stats echoes them), bad values exit 2 and
 * write nothing. */
TEST(restir_stochastic_cli)
{
    const char *json = test_tmp_keep("stochastic-cli.json"), *pfm = test_tmp_keep("stochastic-cli.pfm");
    const char *bad = test_tmp_keep("stochastic-cli-bad.pfm");
    char out[16384];
    int status;
    status = test_cli(out, sizeof out,
                      "render scenes/cornell.scene --method restir --size 16x16 --spatial-passes 1 --mis "
                      "stochastic-pairwise --stochastic-n 3 --stochastic-nc 2 --no-confidence-scaling --reuse-cells "
                      "--quiet --no-png -o %s --stats %s",
                      pfm, json);
    CHECKF(status == 0, "exit %d: %s", status, out);
    status = test_cli(out, sizeof out, "render scenes/cornell.scene --method restir --stochastic-n 0 -o %s", bad);
    CHECKF(status == 2, "--stochastic-n 0: exit %d", status);
    status = test_cli(out, sizeof out, "render scenes/cornell.scene --method restir --temporal-mis stochastic-pairwise "
                                       "--spatial-passes 1 -o %s", bad);
    CHECKF(status == 2, "--temporal-mis stochastic-pairwise: exit %d (%s)", status, out);
    CHECK(!test_file_exists(bad));
    {
        FILE *f = fopen(json, "rb");
        char buf[8192];
        size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
        if (f) fclose(f);
        buf[n] = 0;
        CHECKF(strstr(buf, "\"stochastic_n\": 3, \"stochastic_nc\": 2, \"confidence_scaling\": false, \"reuse_cells\": true") != NULL,
               "stats config: %.300s", buf);
    }
}

/* Reuse cells (reuse_cells.h) on a real G-buffer: Algorithm 1's lists are a partition of
 * the hit pixels into cells inside one tile with one hash; the non-zero lists hold exactly
 * the non-zero samples; confidence sums; the §5.1 search returns a cell of the same object
 * with a similar normal, and depends on the confidences, never on the sample values. */
TEST(restir_stochastic_reuse_cells_invariants)
{
    scene s;
    restir_options o;
    restir_result r;
    gbuffer g;
    camera cam;
    reuse_cells rc;
    rerror e;
    long p, n;
    int c, x, y, found = 0;
    if (rt_load_scene("scenes/cornell-glossy.scene", 40, &s)) return;
    restir_options_default(&o);
    o.keep_reservoirs = 1;
    o.threads = 2;
    memset(&g, 0, sizeof g);
    memset(&rc, 0, sizeof rc);
    if (restir_render(&s, &o, &r, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&s);
        return;
    }
    camera_init(&cam, scene_camera_at(&s, 0), s.width, s.height);
    CHECK(gbuffer_build(&g, &s, &cam, o.seed, 0, 0, 1, &e) == 0);
    CHECK(reuse_cells_build(&rc, &g, r.reservoirs, &e) == 0);
    n = (long)s.width * s.height;
    CHECK(rc.tiles == 25 && rc.cell_count >= rc.tiles / 2);
    {
        long listed = 0, nz = 0;
        for (c = 0; c < rc.cell_count && !test_has_failed(); ++c) {
            int i, t0 = -1;
            double conf = 0;
            for (i = rc.start[c]; i < rc.start[c + 1]; ++i) {
                long q = rc.pixels[i];
                int t = (int)(q % s.width) / REUSE_TILE + ((int)(q / s.width) / REUSE_TILE) * 5;
                CHECK(rc.cell_of[q] == c && g.texels[q].valid);
                CHECK(rc.hash[q] == rc.hash[rc.pixels[rc.start[c]]]);
                if (t0 < 0) t0 = t;
                CHECKF(t == t0, "cell %d spans tiles %d and %d", c, t0, t);
                conf += (double)r.reservoirs[q].confidence;
                listed++;
            }
            CHECK(fabs(conf - rc.confidence[c]) < 1e-9 && reuse_cell_size(&rc, c) <= REUSE_CELL_MAX_PIXELS);
            for (i = rc.nz_start[c]; i < rc.nz_start[c + 1]; ++i) {
                const reservoir *q = &r.reservoirs[rc.nz_pixels[i]];
                CHECK(rc.cell_of[rc.nz_pixels[i]] == c && path_sample_is_valid(&q->y) && q->W > 0 && q->y.target > 0);
                nz++;
            }
        }
        for (p = 0; p < n; ++p) {
            const reservoir *q = &r.reservoirs[p];
            listed -= g.texels[p].valid;
            nz -= g.texels[p].valid && path_sample_is_valid(&q->y) && q->W > 0 && q->y.target > 0;
        }
        CHECKF(listed == 0 && nz == 0, "lists miss or repeat pixels: %ld, non-zero %ld", listed, nz);
    }
    for (y = 0; y < s.height; y += 3)
        for (x = 0; x < s.width; x += 3) {
            const gbuffer_texel *t = gbuffer_at(&g, x, y);
            int cell = reuse_cell_search(&rc, &g, 0.5f, o.seed, 7, x, y), again;
            uint32_t dom[REUSE_CELL_MAX_PIXELS];
            if (cell < 0) continue;
            found++;
            CHECK(t->valid && g.texels[rc.pixels[rc.start[cell]]].hit.object == t->hit.object);
            CHECK(reuse_cell_domains(&rc, cell, (uint32_t)(y * s.width + x), dom) ==
                  reuse_cell_size(&rc, cell) - (rc.cell_of[y * s.width + x] == cell));
            /* the sample values do not enter the search: zero every W and search again */
            for (p = 0; p < n; ++p) r.reservoirs[p].W = 0;
            reuse_cells_build(&rc, &g, r.reservoirs, &e);
            again = reuse_cell_search(&rc, &g, 0.5f, o.seed, 7, x, y);
            CHECK(again == cell);
        }
    /* 40 x 40 is small for the paper's 30-120 px search: most points fall outside the image */
    CHECKF(found >= 10, "the search found a cell for %d of the probed pixels", found);
    reuse_cells_free(&rc);
    gbuffer_free(&g);
    restir_result_free(&r);
    scene_free(&s);
}
