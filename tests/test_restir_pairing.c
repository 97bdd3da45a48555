/* Paired neighbour selection (--pairing paired; Enhanced §3; neighbors.h "paired"):
 *   - reciprocity: j is a neighbour of i exactly when i is one of j (every pixel, every
 *     pass), on a G-buffer without rejection;
 *   - offline ReSTIR PT with paired neighbours agrees with the reference path tracer
 *     (`restir check`, K runs; a subset here, the matrix in TEST_LONG);
 *   - the pair step (Enhanced §3: each pair's two shifts made once by a pre-pass) gives
 *     bit-identical images to the per-pixel step (--no-pair-step) with exactly half the
 *     shifts under pairwise MIS: an exact oracle, every shift and MIS family;
 *   - --ablate pair-mis (one side of the pair's MIS dropped) is detected by a paired test
 *     against the pair step on the same seeds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"
#include "restir/frame/options.h"

#define ALPHA 1e-3

TEST(pairing_neighbors_reciprocal)
{
    neighbor_options no;
    reuse_texture tex[PAIRING_MAX_TEXTURES];
    gbuffer g;
    rerror e;
    uint32_t nb[PAIRING_MAX_TEXTURES], back[PAIRING_MAX_TEXTURES];
    int x, y, i, pass, missing = 0, total = 0;
    neighbor_options_default(&no);
    no.pattern = NEIGHBOR_PAIRED;
    no.count = 3;
    no.reject_geometry = 0;
    if (reuse_textures_build(tex, 3, pairing_sigma_for_radius(10), test_seed(), &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return;
    }
    no.textures = tex;
    g.width = 64;
    g.height = 48;
    g.texels = calloc((size_t)g.width * (size_t)g.height, sizeof *g.texels);
    for (i = 0; i < g.width * g.height; ++i) g.texels[i].valid = 1;
    for (pass = 0; pass < 3; ++pass)
        for (y = 0; y < g.height; ++y)
            for (x = 0; x < g.width; ++x) {
                int n = neighbor_select(&no, &g, test_seed(), (uint32_t)pass, x, y, nb, 3, NULL, &e), k;
                for (k = 0; k < n; ++k) {
                    int jx = (int)(nb[k] % (uint32_t)g.width), jy = (int)(nb[k] / (uint32_t)g.width), m, found = 0;
                    int nback = neighbor_select(&no, &g, test_seed(), (uint32_t)pass, jx, jy, back, 3, NULL, &e);
                    for (m = 0; m < nback; ++m) found |= back[m] == (uint32_t)(y * g.width + x);
                    missing += !found;
                    total++;
                }
            }
    free(g.texels);
    reuse_textures_free(tex, 3);
    CHECKF(total > g.width * g.height, "only %d neighbour links", total);
    CHECKF(missing == 0, "%d of %d neighbour links are not reciprocal", missing, total);
}

typedef struct {
    int shift, mis, passes, frames;
} pr_case;

static void expect(const scene *s, const check_side *pt, const char *name, const pr_case *m, int runs)
{
    restir_options o;
    check_side a;
    char what[256];
    rt_spatial_options(&o, test_seed() * 3571u + 31u * (uint32_t)m->shift + 7u * (uint32_t)m->mis + (uint32_t)m->passes,
                       m->shift, m->mis, m->passes, 3, 4.0 * s->width / 16);
    o.spatial.pairing = RESTIR_PAIRING_PAIRED;
    o.frames = m->frames;
    o.candidates = 2;
    o.max_depth = 4;
    if (rt_restir_side(s, &o, runs, 4, &a)) return;
    snprintf(what, sizeof what, "%s paired shift %s mis %s passes %d", name, restir_shift_names[m->shift],
             restir_mis_names[m->mis], m->passes);
    rt_expect_verdict(&a, pt, ALPHA, 4, what, 0, NULL);
}

static void cases_on(const char *path, const pr_case *cases, int n, int runs, uint32_t spp)
{
    rt_bench b;
    int i;
    if (rt_bench_open(&b, path, 16, runs, spp, 4, test_seed() * 7919u + 5)) return;
    for (i = 0; i < n && !test_has_failed(); ++i) expect(&b.s, &b.pt, path, &cases[i], runs);
    rt_bench_close(&b);
}

TEST(restir_pairing_unbiased_subset)
{
    static const pr_case glossy[] = {
        {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 3, 4},
        {RESTIR_SHIFT_RECONNECTION, MIS_PAIRWISE_UNIFORM, 1, 4},
    };
    cases_on("scenes/cornell-glossy.scene", glossy, 2, 16, 64);
}

TEST_LONG(restir_pairing_unbiased_matrix_long)
{
    static const char *const scenes[] = {"scenes/cornell.scene", "scenes/cornell-glossy.scene", "scenes/glass.scene",
                                         NULL};
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    pr_case m[RESTIR_SHIFT_COUNT * 3];
    int sc, sh, f, n = 0;
    for (sh = 0; sh < RESTIR_SHIFT_COUNT; ++sh)
        for (f = 0; f < 3; ++f) {
            m[n].shift = sh;
            m[n].mis = families[f];
            m[n].passes = 3;
            m[n].frames = 4;
            ++n;
        }
    for (sc = 0; scenes[sc] && !test_has_failed(); ++sc) {
        int glass = strstr(scenes[sc], "glass") != NULL, i;
        for (i = 0; i < n; ++i) m[i].frames = glass ? 16 : 4;
        cases_on(scenes[sc], m, n, 24, glass ? 256 : 64);
    }
}

/* ---- the pair step (Enhanced §3; src/frame/pair_step.c) -------------------------------- */

static int render_paired(const scene *s, const restir_options *o, restir_result *r)
{
    rerror e;
    if (restir_render(s, o, r, &e) == 0) return 0;
    test_fail(__FILE__, __LINE__, "restir_render: %s", e.msg);
    return -1;
}

/* The pair step reads the values the per-pixel step computes (the same shift of the same
 * sample to the same primary vertex), so the images are equal bit for bit, and under
 * pairwise MIS each pixel makes one shift per neighbour instead of two. */
TEST(restir_pair_step_bit_identical)
{
    static const int families[] = {MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE, MIS_TALBOT};
    scene s;
    int sh, f;
    if (rt_load_scene("scenes/cornell-glossy.scene", 24, &s)) return;
    for (sh = 0; sh < RESTIR_SHIFT_COUNT && !test_has_failed(); ++sh)
        for (f = 0; f < 3 && !test_has_failed(); ++f) {
            restir_options o;
            restir_result a, b;
            const spatial_stats *sa = &a.stats.spatial, *sb = &b.stats.spatial;
            rt_spatial_options(&o, test_seed() * 7u + 3u, sh, families[f], 2, 4, 5);
            o.spatial.pairing = RESTIR_PAIRING_PAIRED;
            o.candidates = 2;
            o.max_depth = 5;
            o.shading = sh == RESTIR_SHIFT_HYBRID ? RESTIR_SHADING_VECTOR : RESTIR_SHADING_SCALAR;
            if (render_paired(&s, &o, &a)) break;
            o.no_pair_step = 1;
            if (render_paired(&s, &o, &b)) {
                restir_result_free(&a);
                break;
            }
            CHECKF(memcmp(a.mean.px, b.mean.px, sizeof(float) * 3 * (size_t)s.width * (size_t)s.height) == 0,
                   "shift %s mis %s: the pair step's image differs from the per-pixel step's",
                   restir_shift_names[sh], mis_family_name((mis_family)families[f]));
            /* the pre-pass makes exactly the per-pixel step's MIS shifts (X_0 to each partner);
             * the forward shifts are read from the partner's */
            /* the pre-pass makes exactly the per-pixel step's canonical-column MIS shifts (X_0
             * to each partner); Talbot's other entries are shifted as before */
            CHECKF(sa->shifts - sa->mis_shifts == sb->mis_shifts - sa->mis_shifts && sa->outcome[SHIFT_OK] > 0,
                   "shift %s mis %s: %llu pre-pass shifts, the per-pixel step made %llu canonical-column MIS shifts",
                   restir_shift_names[sh], mis_family_name((mis_family)families[f]),
                   (unsigned long long)(sa->shifts - sa->mis_shifts),
                   (unsigned long long)(sb->mis_shifts - sa->mis_shifts));
            if (families[f] != MIS_TALBOT)
                CHECKF(2 * sa->shifts == sb->shifts, "shift %s mis %s: %llu shifts with the pair step, not half of %llu",
                       restir_shift_names[sh], mis_family_name((mis_family)families[f]),
                       (unsigned long long)sa->shifts, (unsigned long long)sb->shifts);
            if (getenv("RESTIR_TEST_VERBOSE"))
                fprintf(stderr, "  pair step shift %s mis %s: identical; %.3f vs %.3f shifts per pixel and pass\n",
                        restir_shift_names[sh], mis_family_name((mis_family)families[f]),
                        (double)sa->shifts / (double)sa->pixels, (double)sb->shifts / (double)sb->pixels);
            restir_result_free(&a);
            restir_result_free(&b);
        }
    scene_free(&s);
}

/* --ablate pair-mis against the pair step on the same seeds (docs/statistics.md "Paired
 * check"): run k of both sides draws the same samples and neighbours, and without the
 * ablation the two images are equal, so every difference is the ablation's. The canonical
 * sample's MIS weight then ignores that its partners could have produced it: the weights
 * at X_0 sum to more than 1, a bias upwards. The control is restir_pairing_unbiased_subset
 * (the pair step is the default with --pairing paired). */
TEST(restir_pair_mis_detected)
{
    scene s;
    restir_options o, ob;
    check_side a, b;
    check_result r;
    if (rt_load_scene("scenes/cornell-glossy.scene", 16, &s)) return;
    rt_spatial_options(&o, test_seed() * 2246822519u + 13u, RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 1, 3, 4);
    o.spatial.pairing = RESTIR_PAIRING_PAIRED;
    o.frames = 2;
    o.candidates = 2;
    o.max_depth = 4;
    ob = o;
    o.ablation = RESTIR_ABLATE_PAIR_MIS;
    if (rt_restir_side(&s, &o, 16, 4, &a) == 0) {
        if (rt_restir_side(&s, &ob, 16, 4, &b) == 0) {
            if (rt_compare_paired(&a, &b, ALPHA, 4, &r) == 0) {
                double z = stats_t_to_z(r.global.t, r.global.dof);
                if (getenv("RESTIR_TEST_VERBOSE"))
                    fprintf(stderr, "  pair-mis vs pair step: mean z %.2f (relative diff %+.3f%%), %ld/%ld blocks "
                                    "rejected, worst block z %.2f\n",
                            z, 100 * r.bias, r.rejected, r.tests, r.worst.z);
                CHECKF(r.different && z > 0, "pair-mis not detected: mean z %.2f, %ld/%ld blocks, worst z %.2f", z,
                       r.rejected, r.tests, r.worst.z);
                check_result_free(&r);
            }
            check_side_free(&b);
        }
        check_side_free(&a);
    }
    scene_free(&s);
}

/* The real-time pipeline runs the same spatial stage: with temporal reuse (the spatial
 * output is the next frame's temporal input) the frames stay bit-identical to the
 * per-pixel step, and identical for 1 and 2 threads. */
#define PAIR_SEQ_FRAMES 3


TEST(restir_pair_step_sequence_identical)
{
    scene s;
    restir_options o;
    image f[3][PAIR_SEQ_FRAMES];
    int v, k, ok = 0;
    if (rt_load_scene("scenes/cornell-glossy.scene", 20, &s)) return;
    restir_options_default(&o);
    restir_options_preset_gris_realtime(&o);
    o.seed = test_seed() * 31u + 5u;
    o.spatial_passes = 2;
    o.spatial.neighbors = 3;
    o.spatial.radius = 5;
    o.spatial.pairing = RESTIR_PAIRING_PAIRED;
    o.max_depth = 5;
    for (v = 0; v < 3; ++v) {
        restir_options ov = o;
        ov.no_pair_step = v == 2;
        ov.threads = v == 1 ? 1 : 2;
        ok += rt_sequence_images(&s, &ov, 0, PAIR_SEQ_FRAMES - 1, f[v]) == 0;
    }
    if (ok == 3)
        for (k = 0; k < PAIR_SEQ_FRAMES; ++k) {
            size_t n = sizeof(float) * 3 * (size_t)f[0][k].width * (size_t)f[0][k].height;
            CHECKF(f[0][k].px && f[1][k].px && f[2][k].px, "frame %d missing", k);
            if (!f[0][k].px || !f[1][k].px || !f[2][k].px) break;
            CHECKF(memcmp(f[0][k].px, f[1][k].px, n) == 0, "frame %d: the pair step differs for 1 and 2 threads", k);
            CHECKF(memcmp(f[0][k].px, f[2][k].px, n) == 0, "frame %d: the pair step differs from the per-pixel step", k);
        }
    for (v = 0; v < 3; ++v) /* rt_sequence_images zeroed every entry */
        for (k = 0; k < PAIR_SEQ_FRAMES; ++k) image_free(&f[v][k]);
    scene_free(&s);
}
