/* ReSTIR PT on the textured interior (scenes/textured-room.scene; docs/materials.md,
 * "Textures"): textured floor (map_Kd, map_Pr), painting (map_Kd), emissive sign (map_Ke)
 * and cut-out leaves (map_d), under a ceiling light and a constant sky. Reconnection and
 * hybrid shifts with spatial reuse, and temporal reuse, against the path tracer: unpaired,
 * Welch per block and per channel R, G, B. A reconnection vertex re-evaluates its textured
 * BSDF from its stored triangle and barycentrics, and every shift's visibility ray runs the
 * alpha test: the planted bugs tests/mutants/texture-*.patch and alpha-*.patch break this. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/frame/pipeline.h"
#include "restir/frame/options.h"
#include "restir/core/png.h"
#include "restir/frame/offline.h"
#include "pt_util.h"

#define ALPHA 1e-3
#define RES 16
#define RUNS 16
#define BLOCK 4

static int verbose(void) { return getenv("RESTIR_TEST_VERBOSE") != NULL; }

static void room_options(restir_options *o, int shift, int mis, int passes, uint32_t salt)
{
    rt_spatial_options(o, test_seed() * 4099u + 977u * salt + 29u, shift, mis, passes, 3, 4.0);
    o->frames = 2;
    o->candidates = 2;
    o->max_depth = 4;
}

static void report(const char *what, const check_result *c)
{
    if (verbose())
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                rt_mean_z(c), c->lum_a.mean, c->lum_b.mean, c->rejected, c->tests, c->worst.z);
    test_margin(fabs(rt_mean_z(c)) > fabs(c->worst.z) ? rt_mean_z(c) : c->worst.z);
    CHECKF(!c->different, "%s: differs: mean z %.2f (p %.3g), %ld of %ld blocks rejected, worst z %.2f", what,
           rt_mean_z(c), c->global.p, c->rejected, c->tests, c->worst.z);
}

static int pt_reference(const scene *s, check_side *pt)
{
    pt_options ref;
    pt_options_default(&ref);
    ref.seed = test_seed() * 7919u + 5;
    ref.spp = 64;
    ref.max_depth = 4;
    ref.threads = 2;
    return rt_pt_side_options(s, &ref, RUNS, BLOCK, pt);
}

/* The textured room at RES and its path-traced side; on failure nothing is left to free. */
static int open_room(scene *s, check_side *pt)
{
    if (rt_load_scene("scenes/textured-room.scene", RES, s)) return -1;
    if (pt_reference(s, pt)) {
        scene_free(s);
        return -1;
    }
    return 0;
}

static void compare(const check_side *a, const check_side *pt, const char *what)
{
    check_options opt;
    check_result c;
    rerror e;
    int status;
    check_options_default(&opt);
    opt.alpha = ALPHA;
    opt.block_size = BLOCK;
    status = check_compare(a, pt, &opt, &c, &e);
    CHECKF(status == 0, "check_compare: %s", e.msg);
    if (status) return;
    report(what, &c);
    check_result_free(&c);
}

/* Spatial reuse (2 passes): reconnection with pairwise-defensive MIS, hybrid with Talbot,
 * hybrid with light RIS and tiles (8 candidates: the textured sign's emission at light
 * points known only by their position, docs/materials.md §7.5), random replay with
 * pairwise-defensive MIS, and the stochastic pairwise step (Stochastic MIS, one pick) with
 * the hybrid shift. */
TEST(restir_textures_spatial)
{
    static const int shifts[] = {RESTIR_SHIFT_RECONNECTION, RESTIR_SHIFT_HYBRID, RESTIR_SHIFT_HYBRID,
                                 RESTIR_SHIFT_REPLAY, RESTIR_SHIFT_HYBRID};
    static const int families[] = {MIS_PAIRWISE_DEFENSIVE, MIS_TALBOT, MIS_PAIRWISE_DEFENSIVE, MIS_PAIRWISE_DEFENSIVE,
                                   MIS_PAIRWISE_DEFENSIVE};
    scene s;
    check_side pt;
    int i;
    if (open_room(&s, &pt)) return;
    for (i = 0; i < 5 && !test_has_failed(); ++i) {
        restir_options o;
        check_side a;
        char what[128];
        room_options(&o, shifts[i], families[i], 2, (uint32_t)i);
        if (i == 2) {
            o.light_ris.candidates = 8;
            o.light_ris.tiles = 1;
        }
        if (i == 4) o.spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE;
        if (rt_restir_side(&s, &o, RUNS, BLOCK, &a)) break;
        snprintf(what, sizeof what, "textured-room spatial shift %s mis %s%s", restir_shift_names[shifts[i]],
                 i == 4 ? "stochastic-pairwise" : restir_mis_names[families[i]], i == 2 ? " light-ris 8 tiles" : "");
        compare(&a, &pt, what);
        check_side_free(&a);
    }
    check_side_free(&pt);
    scene_free(&s);
}

/* K = 2 spatial passes against 0 passes on the same numbers (check_compare_paired: the initial
 * samples cancel, so spatial reuse alone is tested, per block and channel R, G, B), every
 * shift, the MIS family alternating. */
TEST(restir_textures_paired_every_shift)
{
    static const int shifts[] = {RESTIR_SHIFT_RECONNECTION, RESTIR_SHIFT_REPLAY, RESTIR_SHIFT_HYBRID};
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_DEFENSIVE, MIS_PAIRWISE_UNIFORM};
    scene s;
    int i;
    if (rt_load_scene("scenes/textured-room.scene", RES, &s)) return;
    for (i = 0; i < 3 && !test_has_failed(); ++i) {
        restir_options with, without;
        check_side a, b;
        check_result c;
        char what[128];
        room_options(&with, shifts[i], families[i], 2, 20u + (uint32_t)i);
        without = with;
        without.spatial_passes = 0;
        if (rt_restir_side(&s, &with, RUNS, BLOCK, &a)) break;
        if (rt_restir_side(&s, &without, RUNS, BLOCK, &b) == 0) {
            snprintf(what, sizeof what, "textured-room paired 2 vs 0 passes shift %s mis %s",
                     restir_shift_names[shifts[i]], restir_mis_names[families[i]]);
            if (rt_compare_sides(&a, &b, ALPHA, BLOCK, 1, &c) == 0) {
                report(what, &c);
                check_result_free(&c);
            }
            check_side_free(&b);
        }
        check_side_free(&a);
    }
    scene_free(&s);
}

/* Temporal reuse (still camera, frame 3 of each sequence) with the hybrid shift and one
 * spatial pass after it: Talbot temporal MIS; then with two MCMC mutations after temporal
 * reuse (Mutations Algorithm 3), rv with Talbot and pp with pairwise-defensive temporal MIS
 * (mutated primary-sample-space numbers re-evaluate textured BSDFs and cut-outs). */
TEST(restir_textures_temporal)
{
    static const int strategies[] = {-1, MUTATE_RV, MUTATE_PP};
    scene s;
    check_side pt;
    int i;
    if (open_room(&s, &pt)) return;
    for (i = 0; i < 3 && !test_has_failed(); ++i) {
        restir_options o;
        rt_frame_sides q;
        char what[128];
        room_options(&o, RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 1, 7u + (uint32_t)i);
        o.temporal.mis = i == 2 ? MIS_PAIRWISE_DEFENSIVE : MIS_TALBOT;
        if (strategies[i] >= 0) {
            o.mutation.count = 2;
            o.mutation.strategy = strategies[i];
        }
        memset(&q, 0, sizeof q);
        q.times[0] = 3;
        q.nt = 1;
        snprintf(what, sizeof what, "textured-room temporal frame 3 shift hybrid temporal %s mutations %s",
                 restir_mis_names[o.temporal.mis], strategies[i] >= 0 ? mutate_strategy_names[strategies[i]] : "none");
        if (rt_frame_sides_run(&s, &o, RUNS, BLOCK, &q)) {
            test_fail(__FILE__, __LINE__, "%s: the sequences failed", what);
            break;
        }
        compare(&q.side[0], &pt, what);
        rt_frame_sides_free(&q);
    }
    check_side_free(&pt);
    scene_free(&s);
}

/* ---- a cut-out canopy over a textured court ---------------------------------------------- */

/* Writes an 8 x 8 RGB8 PNG: a two-colour checker (colour set), else a mask open (0) on a
 * third of the texels and opaque (255) elsewhere. */
static int write_map(const char *name, int colour)
{
    unsigned char px[8 * 8 * 3];
    rerror e;
    int x, y;
    for (y = 0; y < 8; ++y)
        for (x = 0; x < 8; ++x) {
            unsigned char *p = px + 3 * (8 * y + x);
            int a = (x + y) & 1;
            if (colour) p[0] = (unsigned char)(a ? 250 : 30), p[1] = (unsigned char)(a ? 240 : 90), p[2] = (unsigned char)(a ? 40 : 230);
            else p[0] = p[1] = p[2] = (unsigned char)((x + 2 * y) % 3 ? 255 : 0); /* a third open */
        }
    if (png_write_rgb8(test_tmp_path(name), 8, 8, px, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    return 0;
}

/* A court (floor y = 0 and a back wall z = -2, both with a high-contrast map_Kd checker,
 * the floor rough plastic with map_Pr) under a canopy at y = 1.2 whose map_d opens a third
 * of its texels, lit by an area light above the canopy and a dim constant sky: all
 * direct light passes the cut-outs, and reconnection vertices lie on textured surfaces. */
static int load_canopy(scene *s)
{
    if (write_map("canopy-kd.png", 1) || write_map("canopy-mask.png", 0)) return -1;
    return test_scene_from_text(s, "canopy",
                                "newmtl court\nKd 1 1 1\nPr 0.7\nmap_Kd canopy-kd.png\nmap_Pr canopy-mask.png\n"
                                "newmtl wall\nKd 1 1 1\nmap_Kd canopy-kd.png\n"
                                "newmtl canopy\nKd 0.6 0.6 0.6\nmap_d canopy-mask.png\n"
                                "newmtl light\nKd 0 0 0\nKe 6 6 6\n",
                                "mtllib canopy.mtl\nvt 0 0\nvt 2 0\nvt 2 2\nvt 0 2\n"
                                "usemtl court\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nv -2 0 -2\nf 1/1 2/2 3/3 4/4\n"
                                "usemtl wall\nv -2 0 -2\nv 2 0 -2\nv 2 2.5 -2\nv -2 2.5 -2\nf 5/1 6/2 7/3 8/4\n"
                                "usemtl canopy\nv -1.5 1.2 1.5\nv 1.5 1.2 1.5\nv 1.5 1.2 -1.9\nv -1.5 1.2 -1.9\nf 9/1 10/2 11/3 12/4\n"
                                "usemtl light\nv -0.6 2.2 -0.6\nv -0.6 2.2 0.6\nv 0.6 2.2 0.6\nv 0.6 2.2 -0.6\nf 13 16 15 14\n",
                                "mesh canopy.obj\ncamera eye 0 0.9 3.5 target 0 0.5 -1 up 0 1 0 fov 50\nsize 16 16\n"
                                "environment constant 0.05 0.06 0.08\n");
}

/* Reconnection (pairwise-defensive) and hybrid (Talbot) spatial reuse under the canopy. */
TEST(restir_textures_cutout_canopy)
{
    static const int shifts[] = {RESTIR_SHIFT_RECONNECTION, RESTIR_SHIFT_HYBRID};
    static const int families[] = {MIS_PAIRWISE_DEFENSIVE, MIS_TALBOT};
    scene s;
    check_side pt;
    int i;
    if (load_canopy(&s)) return;
    if (pt_reference(&s, &pt)) {
        scene_free(&s);
        return;
    }
    for (i = 0; i < 2 && !test_has_failed(); ++i) {
        restir_options o;
        check_side a;
        char what[128];
        room_options(&o, shifts[i], families[i], 2, 20u + (uint32_t)i);
        if (rt_restir_side(&s, &o, RUNS, BLOCK, &a)) break;
        snprintf(what, sizeof what, "canopy spatial shift %s mis %s", restir_shift_names[shifts[i]],
                 restir_mis_names[families[i]]);
        compare(&a, &pt, what);
        check_side_free(&a);
    }
    check_side_free(&pt);
    scene_free(&s);
}

/* ---- a cut-out wall's shadow stays black through every shift -------------------------------- */

/* As restir_exact_shadow_stays_black, with the wall a single cut-out card: a floor, a card
 * across it at x = 0 (1.5 high, its map_d opaque below y = 0.75 and open above) and a small
 * light on the +x side at y = 0.8 facing down. With direct light only every floor point with
 * x < 0 is in the opaque part's shadow (the line to the light crosses x = 0 below y = 0.62),
 * so those pixels must be exactly 0 after any reuse; a shift whose visibility ray skipped
 * the alpha test (culling the card) would carry light across it. The card's open part lets
 * light reach the far side only along lines above the light, i.e. nowhere on the floor. */
static int load_cutout_wall(scene *s)
{
    unsigned char px[4 * 8 * 3];
    rerror e;
    int i;
    for (i = 0; i < 32; ++i) memset(px + 3 * i, i / 4 >= 3 ? 255 : 0, 3); /* rows 3..7 (v < 0.625) opaque */
    if (png_write_rgb8(test_tmp_path("wall-mask.png"), 4, 8, px, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    return test_scene_from_text(s, "cutwall",
                                "newmtl white\nKd 0.8 0.8 0.8\nnewmtl card\nKd 0.8 0.8 0.8\nmap_d wall-mask.png\n"
                                "newmtl light\nKd 0 0 0\nKe 20 18 15\n",
                                "mtllib cutwall.mtl\nusemtl white\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nf 1 2 3 4\n"
                                "usemtl card\nv 0 0 -1.2\nv 0 0 1.2\nv 0 1.5 1.2\nv 0 1.5 -1.2\nvt 0 0.25\nvt 1 0.25\nvt 1 1\nvt 0 1\n"
                                "f 5/1 6/2 7/3 8/4\n"
                                "usemtl light\nv 0.3 0.8 -0.2\nv 0.7 0.8 -0.2\nv 0.7 0.8 0.2\nv 0.3 0.8 0.2\nf 9 10 11 12\n",
                                "mesh cutwall.obj\ncamera eye 0 3 0.01 target 0 0 0 up 0 0 1 fov 40\nsize 24 24\n");
}

TEST(restir_textures_cutout_shadow_stays_black)
{
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_DEFENSIVE};
    enum { R = 24 };
    unsigned char shadow[R * R];
    scene s;
    long n_shadow = 0, n_lit = 0;
    int x, y, shift, f;
    if (load_cutout_wall(&s)) return;
    for (y = 0; y < R; ++y)
        for (x = 0; x < R; ++x) {
            path_vertex v;
            int in = rt_primary_vertex(&s, x, y, &v) && v.position.y < 1e-3 && v.position.x < -0.03;
            shadow[y * R + x] = (unsigned char)in;
            n_shadow += in;
        }
    CHECKF(n_shadow > R * R / 5, "only %ld shadowed floor pixels", n_shadow);
    for (shift = 0; shift < RESTIR_SHIFT_COUNT; ++shift)
        for (f = 0; f < 2; ++f) {
            restir_options o;
            restir_result r;
            rerror e;
            long bad = 0, lit = 0, i;
            restir_options_default(&o);
            o.shift = shift;
            o.spatial.mis = families[f];
            o.spatial_passes = 2;
            o.max_depth = 2; /* direct light only */
            o.spatial.radius = 6;
            o.candidates = 2;
            o.frames = 2;
            o.threads = 2;
            o.seed = test_seed() * 37u + (uint32_t)(shift * 4 + f);
            CHECKF(restir_render(&s, &o, &r, &e) == 0, "%s", e.msg);
            if (test_has_failed()) break;
            for (i = 0; i < R * R; ++i) {
                double sum = r.mean.px[3 * i] + r.mean.px[3 * i + 1] + r.mean.px[3 * i + 2];
                if (shadow[i] && sum != 0) bad++;
                if (!shadow[i] && sum > 0) lit++;
            }
            if (verbose())
                fprintf(stderr, "  cut-out shadow: shift %s mis %s: %ld of %ld shadowed pixels nonzero, %ld lit\n",
                        restir_shift_names[shift], restir_mis_names[families[f]], bad, n_shadow, lit);
            restir_result_free(&r);
            CHECKF(bad == 0, "shift %s mis %s: %ld of %ld pixels in the cut-out's shadow are not 0",
                   restir_shift_names[shift], restir_mis_names[families[f]], bad, n_shadow);
            n_lit = lit;
        }
    CHECKF(n_lit > R * R / 5, "only %ld lit pixels", n_lit);
    scene_free(&s);
}
