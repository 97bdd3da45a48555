/* Light RIS for NEE (Enhanced §6.1; include/restir/render/light_ris.h, docs/enhanced.md §6): the
 * path tracer with light RIS (with and without light tiles) estimates the plain path
 * tracer's image; one candidate is the plain sampler bit for bit up to rounding; the
 * wrong light pdf in the BSDF side's MIS weight (--ablate light-ris-pdf) is rejected. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/check.h"
#include "restir/render/light_ris.h"
#include "restir/render/pt.h"
#include "restir_util.h"
#include "test.h"
#include "restir/scene/scene_trace.h"

static void options(pt_options *o, int depth, uint32_t spp)
{
    pt_options_default(o);
    o->max_depth = depth;
    o->spp = spp;
    o->threads = 2;
}

/* Side a (K runs of the path tracer with the options a; the side is freed here) against ref
 * at level 1e-3 in 8 x 8 blocks, paired or not: the margin, and with RESTIR_TEST_VERBOSE the
 * numbers, reported as `what`. 0 on success (*c then holds the verdict's numbers). */
static int compare_pt(const scene *s, const pt_options *a, int runs, const check_side *ref, int paired,
                      const char *what, check_result *c)
{
    check_side sa;
    int status;
    if (rt_pt_side_options(s, a, runs, 8, &sa)) return -1;
    status = rt_compare_sides(&sa, ref, 1e-3, 8, paired, c);
    check_side_free(&sa);
    if (status) return status;
    check_result_free(c);
    test_margin(fabs(rt_mean_z(c)) > fabs(c->worst.z) ? rt_mean_z(c) : c->worst.z);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s%s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                paired ? " (paired)" : "", rt_mean_z(c), c->lum_a.mean, c->lum_b.mean, c->rejected, c->tests,
                c->worst.z);
    return 0;
}

/* The ablation a against the correct light RIS side ref rendered with the SAME numbers (a's
 * seed; 16 runs each): paired (check_compare_paired, run k against run k), so only the
 * changed MIS weight of the BSDF hits differs between the sides. Must be rejected. */
static void ablation_paired(const scene *s, const check_side *ref, const pt_options *a, const char *what)
{
    check_result c;
    if (compare_pt(s, a, 16, ref, 1, what, &c)) return;
    CHECKF(c.different, "%s not detected (paired): mean z %.2f, worst block z %.2f", what, rt_mean_z(&c), c.worst.z);
}

/* The plain path tracer with a's depth and spp: 8 runs, 8×8 blocks. */
static int plain_side(const scene *s, const pt_options *a, check_side *side)
{
    pt_options plain = *a;
    plain.light_ris.candidates = plain.light_ris.tiles = 0;
    plain.ablations = 0;
    plain.seed = test_seed() * 131u + 8;
    return rt_pt_side_options(s, &plain, 8, 8, side);
}

/* a (8 runs) against the side ref (level 1e-3); expect_different says which verdict the
 * test requires. */
static void compare_with(const scene *s, const check_side *ref, const pt_options *a, int expect_different,
                         const char *what)
{
    pt_options a_seeded = *a;
    check_result c;
    a_seeded.seed = test_seed() * 131u + 7;
    if (compare_pt(s, &a_seeded, 8, ref, 0, what, &c)) return;
    if (expect_different)
        CHECKF(c.different, "%s not detected: mean p = %.3g (lum %.5g vs %.5g), worst block z %.2f", what,
               c.global.p, c.lum_a.mean, c.lum_b.mean, c.worst.z);
    else
        CHECKF(!c.different,
               "%s vs the reference side: mean p = %.3g (lum %.5g vs %.5g), %ld of %ld blocks rejected, worst block (%d,%d) "
               "ch %d z %.2f",
               what, c.global.p, c.lum_a.mean, c.lum_b.mean, c.rejected, c.tests, c.worst.x, c.worst.y,
               c.worst.channel, c.worst.z);
}

/* M = 1 everywhere (N = 1): candidate 0 uses the plain sampler's numbers and p̃ = p̂/(p̂/p_0)
 * = p_0, and the BSDF side has no fresh candidates, so the image is the plain one up to
 * rounding (exact, not statistical). */
TEST(light_ris_one_candidate_is_the_plain_sampler)
{
    scene s;
    pt_options o;
    pt_result plain, ris;
    rerror e;
    size_t i;
    double worst = 0;
    if (rt_load_scene("scenes/many-lights.scene", 16, &s)) return;
    options(&o, 4, 4);
    o.seed = test_seed();
    CHECKF(pt_render(&s, &o, &plain, &e) == 0, "%s", e.msg);
    o.light_ris.candidates = 1;
    CHECKF(pt_render(&s, &o, &ris, &e) == 0, "%s", e.msg);
    for (i = 0; i < 3 * (size_t)s.width * s.height; ++i) {
        double a = plain.state.sum[i], b = ris.state.sum[i];
        double rel = fabs(a - b) / fmax(fabs(a), 1e-30);
        if (rel > worst) worst = rel;
    }
    pt_result_free(&plain);
    pt_result_free(&ris);
    scene_free(&s);
    CHECKF(worst < (sizeof(real) == 4 ? 1e-3 : 1e-9), "N = 1 differs from the plain sampler by %.3g (relative)",
           worst);
}

/* NEE's light pdf (vertex_sample_light_numbers) takes the sample's own P(l)/area_l and
 * |y - x|^2 instead of looking the light up again: exactly path_light_pdf's value, at
 * vertices on every kind of surface of the many-lights hall (docs/performance.md). */
TEST(nee_light_pdf_equals_path_light_pdf)
{
    scene s;
    light_set ls;
    path_context c;
    uint32_t i, checked = 0;
    if (rt_load_scene_lights("scenes/many-lights.scene", 16, &s, &ls)) return;
    memset(&c, 0, sizeof c);
    c.scene = &s;
    c.lights = &ls;
    for (i = 0; i < 4000; ++i) {
        rng_key k = rng_key_make(test_seed(), i, 0);
        real u[4], b[3];
        surface_hit h;
        path_vertex v;
        nee_sample n;
        uint32_t tri;
        rng_u_slots(k, RNG_TEST, 0, 0, 4, u);
        rng_u_slots(k, RNG_TEST, 1, 0, 3, b);
        tri = (uint32_t)(b[0] * (real)s.triangle_count) % (uint32_t)s.triangle_count;
        if (b[1] + b[2] >= 1 || !scene_surface_point(&s, tri, (float)b[1], (float)b[2], &h)) continue;
        path_vertex_make(&v, &s, &h, v3_neg(v3_from_f(h.ng)));
        n.pdf_light = -1;
        vertex_sample_light_numbers(&c, &v, u, &n);
        if (n.pdf_light == -1) continue; /* no light point, or x on it */
        ++checked;
        if (n.pdf_light != path_light_pdf(&c, n.y.triangle, v.position, v3_from_f(n.y.position), v3_from_f(n.y.normal))) {
            CHECKF(0, "vertex %u: %.17g != %.17g", i, (double)n.pdf_light,
                   (double)path_light_pdf(&c, n.y.triangle, v.position, v3_from_f(n.y.position), v3_from_f(n.y.normal)));
            break;
        }
    }
    CHECKF(checked > 1000, "only %u vertices checked", checked);
    lights_free(&ls);
    scene_free(&s);
}

/* The decay schedule of Enhanced §7: max(1, N / B^2) candidates at x_B. */
TEST(light_ris_candidate_schedule)
{
    path_context c;
    memset(&c, 0, sizeof c);
    CHECK(light_ris_count(&c, 1) == 0);
    c.light_ris = 32;
    CHECK(light_ris_count(&c, 1) == 32 && light_ris_count(&c, 2) == 8 && light_ris_count(&c, 3) == 3);
    CHECK(light_ris_count(&c, 4) == 2 && light_ris_count(&c, 5) == 1 && light_ris_count(&c, 200) == 1);
    CHECK(light_ris_count(&c, 5000) == 1);
}

/* Tile entries are addressed: the same (seed, frame, tile, entry) gives the same light
 * sample, another frame another one; the tile of a path depends on its 8×8 screen tile
 * and its frame only. */
TEST(light_tiles_are_addressed)
{
    scene s;
    light_set ls;
    light_sample a, b;
    path_context c;
    rerror e;
    int differ = 0, f;
    if (rt_load_scene("scenes/many-lights.scene", 16, &s)) return;
    CHECKF(lights_build(&ls, &s, &e) == 0, "%s", e.msg);
    CHECK(light_tile_entry(&ls, 3, 5, 17, 1023, &a) && light_tile_entry(&ls, 3, 5, 17, 1023, &b));
    CHECK(a.triangle == b.triangle && a.position.x == b.position.x && a.position.z == b.position.z);
    for (f = 6; f < 10; ++f) {
        CHECK(light_tile_entry(&ls, 3, (uint32_t)f, 17, 1023, &b));
        differ += a.triangle != b.triangle;
    }
    CHECK(differ > 0);
    memset(&c, 0, sizeof c);
    c.image_width = 20;
    /* pixels (0,0) and (7,7) share a screen tile; so do (8,0) and (15,7) */
    CHECK(light_tile_of(&c, rng_key_make(1, 0, 4)) == light_tile_of(&c, rng_key_make(1, 7 * 20 + 7, 4)));
    CHECK(light_tile_of(&c, rng_key_make(1, 8, 4)) == light_tile_of(&c, rng_key_make(1, 7 * 20 + 15, 4)));
    lights_free(&ls);
    scene_free(&s);
}

/* Light RIS with n candidates (the options o otherwise), then the same with light tiles,
 * against the plain sampler on s. 0 if both agree with it (a test failure otherwise). */
static int ris_against_plain(const scene *s, pt_options *o, int n)
{
    check_side plain;
    char what[64];
    if (plain_side(s, o, &plain)) return -1;
    o->light_ris.candidates = n;
    snprintf(what, sizeof what, "light RIS N = %d", n);
    compare_with(s, &plain, o, 0, what);
    o->light_ris.tiles = 1;
    snprintf(what, sizeof what, "light RIS N = %d with tiles", n);
    if (!test_has_failed()) compare_with(s, &plain, o, 0, what);
    check_side_free(&plain);
    return test_has_failed() ? -1 : 0;
}

/* Light RIS (N = 32 at x1, the paper's count) against the plain sampler on the
 * many-lights hall: direct and one-bounce light (d <= 3), where the NEE/BSDF MIS weights
 * carry p̃ on both sides. Then the same with light tiles; the ablation is compared with the
 * correct light RIS, paired (the same numbers on both sides). */
TEST(light_ris_unbiased_many_lights)
{
    scene s;
    pt_options o;
    check_side ris;
    if (rt_load_scene("scenes/many-lights.scene", 24, &s)) return;
    options(&o, 3, 16);
    if (ris_against_plain(&s, &o, 32) == 0) {
        o.light_ris.tiles = 0;
        o.seed = test_seed() * 131u + 9;
        o.spp = 8; /* 16 runs of 8: a paired z saturates near 5 with 8 runs (7 dof) */
        if (rt_pt_side_options(&s, &o, 16, 8, &ris) == 0) {
            o.ablations = PT_ABLATE_LIGHT_RIS_PDF;
            ablation_paired(&s, &ris, &o, "ablation light-ris-pdf vs light RIS");
            check_side_free(&ris);
        }
    }
    scene_free(&s);
}

/* The glossy Cornell box (one area light): longer paths (d <= 5), N = 8, with tiles. */
TEST(light_ris_unbiased_cornell_glossy)
{
    scene s;
    pt_options o;
    if (rt_load_scene("scenes/cornell-glossy.scene", 24, &s)) return;
    options(&o, 5, 16);
    ris_against_plain(&s, &o, 8);
    scene_free(&s);
}

/* Bad light-RIS options: exit 2 with one message, no output file (docs/cli.md). */
TEST(light_ris_cli_bad_options_exit_2)
{
    static const char *const cases[] = {
        "render scenes/cornell.scene --light-tiles",                           /* tiles without RIS */
        "render scenes/cornell.scene --light-ris 5000",                        /* out of range */
        "render scenes/cornell.scene --method aov --aov normal --light-ris 4", /* not a lighting method */
        "render scenes/cornell.scene --method restir --light-ris 4 --mutations 1 --sequence 0..1",
        "render scenes/shadow.scene --method restir --light-ris 4 --sequence 0..1", /* animated objects */
    };
    char out[4096], dest[1024];
    size_t i;
    snprintf(dest, sizeof dest, "%s", test_tmp_path("lr-bad.pfm"));
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        int status;
        remove(dest);
        status = test_cli(out, sizeof out, "%s --size 8x8 --quiet -o %s --no-png", cases[i], dest);
        CHECKF(status == 2 && !test_file_exists(dest), "'%s': exit %d, output %s: %s", cases[i], status,
               test_file_exists(dest) ? "written" : "none", out);
    }
    CHECKF(test_cli(out, sizeof out,
                    "render scenes/cornell.scene --light-ris 4 --light-tiles --size 8x8 --spp 1 --quiet -o %s --no-png",
                    dest) == 0 &&
               test_file_exists(dest),
           "%s", out);
}
