/* Textures and alpha cut-outs (docs/materials.md, "Textures"): the decode rule and the
 * reference lookup, the MTL statements, and exact images: a textured plane under a
 * constant environment (rho(uv) L per pixel), a cut-out occluder whose shadow from a small
 * sun is its mask, a white furnace through cut-outs and textured BSDFs. ReSTIR against
 * the path tracer on the textured room is in test_restir_textures.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "pt_util.h"
#include "test.h"
#include "restir/core/image_io.h"
#include "restir/core/pfm.h"
#include "restir/core/png.h"
#include "restir/core/png_read.h"
#include "restir/render/camera.h"
#include "restir/scene/mtl.h"
#include "restir/scene/scene_trace.h"
#include "restir/scene/surface_maps.h"
#include "restir/scene/texture.h"
#include "restir/scene/sky.h"
#include "restir/core/exr.h"

/* Writes a w x h RGB8 PNG (row 0 = top) in the scratch directory; returns its path. */
static const char *write_png(const char *name, int w, int h, const unsigned char *rgb8)
{
    const char *path = test_tmp_path(name);
    rerror e;
    if (png_write_rgb8(path, w, h, rgb8, &e)) test_fail(__FILE__, __LINE__, "%s", e.msg);
    return path;
}

/* ---- decode rule and lookup ------------------------------------------------------------ */

/* A 4 x 2 PFM: texel (i, j) = (i, j, 10 + i + 4 j). Texel centres give the texel exactly,
 * a point half-way between two centres their mean, and u = 0 (the left edge) the mean of
 * the last and the first column (repeat wrap); v = 1 is the top row. */
TEST(texture_bilinear_repeat_lookup)
{
    image img;
    scene_texture t;
    rerror e;
    int i, j;
    rgb c;
    if (image_alloc(&img, 4, 2, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return;
    }
    for (j = 0; j < 2; ++j)
        for (i = 0; i < 4; ++i) {
            float *p = image_pixel(&img, i, j);
            p[0] = (float)i;
            p[1] = (float)j;
            p[2] = (float)(10 + i + 4 * j);
        }
    if (pfm_write(test_tmp_path("lookup.pfm"), &img, &e) || texture_load(&t, test_tmp_path("lookup.pfm"), TEXTURE_COLOUR, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        image_free(&img);
        return;
    }
    image_free(&img);
    for (j = 0; j < 2; ++j)
        for (i = 0; i < 4; ++i) {
            vec2 uv = v2((i + (real)0.5) / 4, 1 - (j + (real)0.5) / 2);
            c = texture_rgb(&t, uv);
            CHECKF(c.r == i && c.g == j && c.b == 10 + i + 4 * j, "texel (%d, %d): %g %g %g", i, j, c.r, c.g, c.b);
            c = texture_rgb(&t, v2(uv.x + 3, uv.y - 2)); /* repeat: whole periods away */
            CHECKF(fabs(c.b - (10 + i + 4 * j)) < 1e-5, "texel (%d, %d) wrapped: %g", i, j, c.b);
        }
    c = texture_rgb(&t, v2((real)0.25, (real)0.75)); /* between texels 0 and 1 of the top row */
    CHECKF(fabs(c.r - 0.5) < 1e-6 && c.g == 0, "midpoint: %g %g", c.r, c.g);
    c = texture_rgb(&t, v2(0, (real)0.75)); /* u = 0: between the last and the first column */
    CHECKF(fabs(c.r - 1.5) < 1e-6 && fabs(c.b - 11.5) < 1e-5, "wrap at u = 0: %g %g", c.r, c.b);
    c = texture_rgb(&t, v2((real)0.125, (real)0.5)); /* v = 0.5: between the two rows */
    CHECKF(fabs(c.g - 0.5) < 1e-6 && fabs(c.b - 12) < 1e-5, "between rows: %g %g", c.g, c.b);
    CHECKF(texture_scalar(&t, v2((real)0.625, (real)0.25)) == 2, "scalar = the first channel");
    c = texture_rgb(&t, v2((real)NAN, (real)INFINITY)); /* non-finite reads as (0, 0): a defined texel mix */
    CHECKF(isfinite(c.r) && isfinite(c.g) && isfinite(c.b), "non-finite uv gave %g %g %g", c.r, c.g, c.b);
    texture_free(&t);
}

/* One PNG read three ways: a colour map decodes sRGB (srgb_to_linear(v/255)), a scalar and
 * an alpha map take v/255 of the first channel (an RGB file has no alpha channel). */
TEST(texture_png_decode_rule)
{
    static const unsigned char px[2 * 1 * 3] = {128, 64, 255, 0, 200, 10};
    const char *path = write_png("rule.png", 2, 1, px);
    scene_texture colour, scalar, alpha;
    rerror e;
    int i;
    if (texture_load(&colour, path, TEXTURE_COLOUR, &e) || texture_load(&scalar, path, TEXTURE_SCALAR, &e) ||
        texture_load(&alpha, path, TEXTURE_ALPHA, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return;
    }
    CHECK(colour.channels == 3 && scalar.channels == 1 && alpha.channels == 1);
    for (i = 0; i < 6; ++i)
        CHECKF(fabs(colour.px[i] - srgb_to_linear(px[i] / 255.0)) < 1e-7, "colour %d: %g", i, (double)colour.px[i]);
    for (i = 0; i < 2; ++i) {
        CHECKF(fabs(scalar.px[i] - px[3 * i] / 255.0) < 1e-7, "scalar %d: %g", i, (double)scalar.px[i]);
        CHECKF(fabs(alpha.px[i] - px[3 * i] / 255.0) < 1e-7, "alpha %d: %g", i, (double)alpha.px[i]);
    }
    texture_free(&colour);
    texture_free(&scalar);
    texture_free(&alpha);
}

/* ---- MTL and OBJ statements ------------------------------------------------------------- */

static const unsigned char grey_2x2[2 * 2 * 3] = {255, 255, 255, 0, 0, 0, 0, 0, 0, 255, 255, 255};

static int load_text_scene(scene *s, const char *obj, const char *mtl, rerror *e)
{
    char path[4096];
    test_write_file("tx.mtl", mtl);
    snprintf(path, sizeof path, "%s", test_write_file("tx.obj", obj));
    return scene_load(s, path, e);
}

static const char quad_obj[] = "mtllib tx.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               "vn 0 0 1\nusemtl m\nf 1/1/1 2/2/1 3/3/1\nf 1/1 3/3 4/4\nf 1 2 3\n";

TEST(texture_mtl_statements)
{
    scene s;
    rerror e;
    const material *m;
    vec2 uv;
    write_png("tx-map.png", 2, 2, grey_2x2);
    CHECKF(!load_text_scene(&s, quad_obj,
                            "newmtl m\nKs 0.5 0.5 0.5\nNs 100\nmap_Kd tx-map.png\nmap_Ns tx-map.png\nmap_d tx-map.png\n", &e),
           "%s", e.msg);
    if (test_has_failed()) return;
    m = &s.materials[0];
    CHECK(s.texcoord_count == 4 && s.texture_count == 3 && s.has_cutouts);
    CHECKF(m->type == MAT_PLASTIC && m->diffuse.r == 1, "map_Kd without Kd multiplies 1: type %d kd %g", m->type,
           m->diffuse.r);
    CHECK(m->map_kd && m->map_alpha && m->map_roughness && m->roughness_from_ns && m->roughness_map_scale == 100);
    CHECK(s.triangles[0].t[0] == 0 && s.triangles[0].t[2] == 2 && s.triangles[1].t[2] == 3);
    CHECK(s.triangles[2].t[0] == -1 && s.triangles[2].t[1] == -1); /* f v v v: no UVs */
    uv = scene_uv(&s, 1, 0.25f, 0.5f);                           /* corners 1, 3, 4: (0,0) (1,1) (0,1) */
    CHECKF(fabs(uv.x - 0.25) < 1e-7 && fabs(uv.y - 0.75) < 1e-7, "uv %g %g", uv.x, uv.y);
    uv = scene_uv(&s, 2, 0.25f, 0.5f);
    CHECK(uv.x == 0 && uv.y == 0);
    scene_free(&s);

    /* a map with an option, a missing file, a cut-out on an emitter: file:line errors */
    CHECK(load_text_scene(&s, quad_obj, "newmtl m\nmap_Kd -s 2 2 1 tx-map.png\n", &e) != 0);
    CHECKF(strstr(e.msg, "tx.mtl:2: map_Kd: option") != NULL, "%s", e.msg);
    CHECK(load_text_scene(&s, quad_obj, "newmtl m\nKd 1 1 1\nmap_Pr nowhere.png\n", &e) != 0);
    CHECKF(strstr(e.msg, "tx.mtl:3: map_Pr: ") != NULL && strstr(e.msg, "nowhere.png") != NULL, "%s", e.msg);
    CHECK(load_text_scene(&s, quad_obj, "newmtl m\nKe 1 1 1\nmap_d tx-map.png\n", &e) != 0);
    CHECKF(strstr(e.msg, "tx.mtl:1: material 'm': map_d") != NULL, "%s", e.msg);
    /* a map file that cannot be read: with allow_missing_mtl a warning, and the material is untextured */
    {
        scene_load_options opt;
        char path[4096];
        memset(&opt, 0, sizeof opt);
        opt.allow_missing_mtl = 1;
        test_write_file("tx.mtl", "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd nowhere.png\n");
        snprintf(path, sizeof path, "%s", test_write_file("tx.obj", quad_obj));
        CHECKF(!scene_load_with_options(&s, path, &opt, &e), "%s", e.msg);
        if (!test_has_failed()) {
            CHECK(s.warning_count == 1 && strstr(s.warnings[0], "tx.mtl:3: map_Kd: ") &&
                  strstr(s.warnings[0], "(the map is ignored)"));
            CHECK(!s.materials[0].map_kd && s.materials[0].diffuse.r == (real)0.5 && s.texture_count == 0);
            scene_free(&s);
        }
    }
    /* bump and the other maps stay ignored; a map of a data kind shares nothing with a colour one */
    CHECKF(!load_text_scene(&s, quad_obj, "newmtl m\nmap_bump tx-map.png\nmap_Ks x.png\nmap_Kd tx-map.png\nmap_Pr tx-map.png\n",
                            &e),
           "%s", e.msg);
    if (!test_has_failed()) {
        CHECK(s.texture_count == 2 && !s.has_cutouts && s.materials[0].map_roughness && !s.materials[0].roughness_from_ns);
        scene_free(&s);
    }
}

/* ---- exact images ------------------------------------------------------------------------ */

static int render(const scene *s, enum pt_strategy strategy, int depth, uint32_t spp, pt_result *r)
{
    pt_options o;
    test_pt_options(&o, (uint32_t)test_seed(), spp, depth);
    o.strategy = strategy;
    o.russian_roulette = 0;
    return test_pt_render(s, &o, r);
}

/* The primary hit of pixel (x, y) (pixel centre, as the unjittered renders). */
static int primary_hit(const scene *s, int x, int y, surface_hit *h)
{
    camera cam;
    ray r;
    camera_init(&cam, s->camera, s->width, s->height);
    r = camera_ray(&cam, x + (real)0.5, y + (real)0.5);
    return scene_intersect(s, &r, h);
}

/* 8 x 8 colour checker of 2 x 2-texel squares: sRGB codes (200, 60, 30) and (40, 120, 220). */
static void checker_png(const char *name)
{
    unsigned char px[8 * 8 * 3];
    int x, y;
    for (y = 0; y < 8; ++y)
        for (x = 0; x < 8; ++x) {
            unsigned char *p = px + 3 * (8 * y + x);
            int a = ((x / 2) + (y / 2)) & 1;
            p[0] = (unsigned char)(a ? 200 : 40);
            p[1] = (unsigned char)(a ? 60 : 120);
            p[2] = (unsigned char)(a ? 30 : 220);
        }
    write_png(name, 8, 8, px);
}

static const char plane_obj[] = "mtllib tx.mtl\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 0 -1\n"
                                "vt 0 0\nvt 2 0\nvt 2 2\nvt 0 2\nusemtl plane\nf 1/1 2/2 3/3 4/4\n";

/* A Lambertian plane with map_Kd (sRGB PNG, UVs repeating twice) under a constant
 * environment L, seen from above: every plane point sees only sky, so its radiance is
 * rho(uv) L, and each BSDF-sampled path (f cos/pdf = rho) gives exactly that; rho(uv) is
 * Kd times the bilinear lookup at the pixel centre's hit. Background: L. */
TEST(texture_plane_constant_environment_exact)
{
    const rgb L = rgb_make((real)1, (real)2, (real)3), kd = rgb_make((real)0.9, (real)0.8, (real)1);
    scene s;
    pt_result r;
    int x, y, surface = 0, distinct = 0;
    real first_r = -1;
    checker_png("checker.png");
    if (test_scene_from_text(&s, "tx", "newmtl plane\nKd 0.9 0.8 1\nmap_Kd checker.png\n", plane_obj,
                             "mesh tx.obj\ncamera eye 0 3 0.001 target 0 0 0 up 0 0 -1 fov 45\nsize 32 32\n"
                             "environment constant 1 2 3\n"))
        return;
    if (render(&s, PT_STRATEGY_BSDF, 3, 2, &r)) {
        scene_free(&s);
        return;
    }
    for (y = 0; y < s.height; ++y)
        for (x = 0; x < s.width; ++x) {
            const float *p = image_pixel(&r.mean, x, y);
            surface_hit h;
            material m;
            double want[3];
            int c;
            if (!primary_hit(&s, x, y, &h)) {
                CHECKF(p[0] == (float)L.r && p[1] == (float)L.g && p[2] == (float)L.b, "background (%d, %d)", x, y);
                continue;
            }
            surface++;
            m = scene_material_at(&s, h.triangle, h.b1, h.b2);
            want[0] = m.diffuse.r * L.r, want[1] = m.diffuse.g * L.g, want[2] = m.diffuse.b * L.b;
            /* the lookup itself: the checker's two sRGB colours times Kd, or a bilinear mix of them */
            CHECK(m.diffuse.r >= kd.r * srgb_to_linear(40 / 255.0) - 1e-6 &&
                  m.diffuse.r <= kd.r * srgb_to_linear(200 / 255.0) + 1e-6);
            if (first_r < 0) first_r = m.diffuse.r;
            else if (fabs(m.diffuse.r - first_r) > 0.05) distinct = 1;
            for (c = 0; c < 3; ++c)
                CHECKF(fabs(p[c] - want[c]) <= 1e-5 * want[c], "pixel (%d, %d) channel %d: %.7g, rho(uv) L = %.7g", x, y,
                       c, p[c], want[c]);
        }
    CHECKF(surface > 200 && distinct, "%d plane pixels, texture varies: %d", surface, distinct);
    pt_result_free(&r);
    scene_free(&s);
}

/* Writes the shadow scene: a white Lambert ground (y = 0) seen from straight above, a sun
 * at 45 degrees in +x (angular radius 0.25 degrees) and a cut-out card at y = 1 whose
 * shadow falls on the imaged ground while the card itself is outside the view. */
static int load_shadow_scene(scene *s, const char *mask_png)
{
    char mtl[512];
    snprintf(mtl, sizeof mtl, "newmtl ground\nKd 0.8 0.8 0.8\nnewmtl card\nKd 0.5 0.5 0.5\nmap_d %s\n", mask_png);
    return test_scene_from_text(s, "shadow", mtl,
                                "mtllib shadow.mtl\nusemtl ground\nv -3 0 3\nv 3 0 3\nv 3 0 -3\nv -3 0 -3\n"
                                "f 1 2 3 4\nusemtl card\nv 0.4 1 0.6\nv 1.6 1 0.6\nv 1.6 1 -0.6\nv 0.4 1 -0.6\n"
                                "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 5/1 6/2 7/3 8/4\n",
                                "mesh shadow.obj\ncamera eye 0 3 0.0001 target 0 0 0 up 0 0 -1 fov 18\nsize 32 32\n"
                                "sun 1 1 0 0.25 200 300 400\n");
}

/* The shadow of a cut-out card under a small sun is its mask. The card (mask: an 8 x 8
 * checker of 2 x 2-texel squares, alpha 1 or 0) sits 1 above the ground, the sun at 45
 * degrees, so the ground point (x, 0, z) looks at the card point (x + 1, 1, z). With
 * NEE only and the same numbers, each pixel is either 0 (the mask is opaque there) or
 * exactly the pixel of the same scene with an all-transparent card: no partial values
 * away from the mask's edges (the penumbra is 1 * tan(0.25 deg) = 0.004 wide). The card is
 * outside the camera's view; primary rays through a transparent card are checked too. */
TEST(texture_cutout_shadow_is_the_mask)
{
    unsigned char mask[8 * 8 * 3], clear[8 * 8 * 3];
    scene s, ref;
    pt_result a, b;
    int x, y, lit = 0, dark = 0, i;
    for (i = 0; i < 64; ++i) {
        int on = (((i % 8) / 2) + ((i / 8) / 2)) & 1;
        memset(mask + 3 * i, on ? 255 : 0, 3);
        memset(clear + 3 * i, 0, 3);
    }
    write_png("mask.png", 8, 8, mask);
    write_png("clear.png", 8, 8, clear);
    if (load_shadow_scene(&s, "mask.png")) return;
    if (load_shadow_scene(&ref, "clear.png")) {
        scene_free(&s);
        return;
    }
    if (render(&s, PT_STRATEGY_NEE, 2, 4, &a)) goto done;
    if (render(&ref, PT_STRATEGY_NEE, 2, 4, &b)) {
        pt_result_free(&a);
        goto done;
    }
    for (y = 0; y < s.height; ++y)
        for (x = 0; x < s.width; ++x) {
            const float *p = image_pixel(&a.mean, x, y), *q = image_pixel(&b.mean, x, y);
            surface_hit h;
            real cu, cv, fu, fv;
            int opaque, c;
            if (!primary_hit(&s, x, y, &h)) continue;
            CHECKF(h.triangle < 2, "pixel (%d, %d) sees the card", x, y);
            /* the card point the sun ray crosses, in the card's UV (u along x from 0.4, v along -z from 0.6) */
            cu = (h.position.x + 1 - (real)0.4) / (real)1.2;
            cv = ((real)0.6 - h.position.z) / (real)1.2;
            if (cu < 0 || cu > 1 || cv < 0 || cv > 1) opaque = 0;
            else {
                /* mask texel edges at multiples of 1/8 in u and v; skip points near an edge */
                fu = cu * 4 - (real)floor(cu * 4);
                fv = cv * 4 - (real)floor(cv * 4);
                if (fu < 0.04 || fu > 0.96 || fv < 0.04 || fv > 0.96) continue;
                opaque = (((int)(cu * 8) / 2) + ((7 - (int)(cv * 8)) / 2)) & 1;
            }
            for (c = 0; c < 3; ++c) {
                CHECKF(q[c] > 0, "reference pixel (%d, %d) is dark", x, y);
                if (opaque) CHECKF(p[c] == 0, "pixel (%d, %d) under an opaque texel is %g", x, y, p[c]);
                else CHECKF(p[c] == q[c], "pixel (%d, %d) under a hole is %g, unshadowed %g", x, y, p[c], q[c]);
            }
            if (opaque) dark++;
            else lit++;
        }
    CHECKF(lit > 100 && dark > 100, "lit %d, shadowed %d pixels", lit, dark);
    pt_result_free(&a);
    pt_result_free(&b);
done:
    scene_free(&s);
    scene_free(&ref);
}

/* A white furnace through textures and cut-outs: under a constant environment L, a scene
 * where every surface has albedo exactly 1 (Kd 1 times a white sRGB map: code 255 decodes
 * to 1) has radiance L everywhere, whatever the geometry, if paths are long enough to escape.
 * Here a ground, a textured box and a cut-out card with holes over the ground (paths bounce
 * between them, through the holes, and see the card's cut-away parts as sky). BSDF sampling
 * only: each path's value is L exactly once it escapes (f cos/pdf = 1 per bounce). */
TEST(texture_white_furnace_with_cutouts)
{
    unsigned char white[4 * 4 * 3], holes[4 * 4 * 3];
    scene s;
    pt_result r;
    int x, y, c, i;
    for (i = 0; i < 16; ++i) {
        memset(white + 3 * i, 255, 3);
        memset(holes + 3 * i, (i % 3) ? 255 : 0, 3);
    }
    write_png("white.png", 4, 4, white);
    write_png("holes.png", 4, 4, holes);
    if (test_scene_from_text(&s, "furnace",
                             "newmtl w\nKd 1 1 1\nmap_Kd white.png\nnewmtl card\nKd 1 1 1\nmap_Kd white.png\nmap_d holes.png\n",
                             "mtllib furnace.mtl\nusemtl w\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nv -2 0 -2\n"
                                   "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n"
                                   "v -0.3 0 -0.3\nv 0.3 0 -0.3\nv 0.3 0.6 -0.3\nv -0.3 0.6 -0.3\nf 5/1 6/2 7/3 8/4\n"
                                   "v -0.3 0.6 -0.3\nv 0.3 0.6 -0.3\nv 0.3 0.6 0.3\nv -0.3 0.6 0.3\nf 12/1 11/2 10/3 9/4\n"
                                   "usemtl card\nv -1.5 0.3 1\nv 1.5 0.3 1\nv 1.5 0.3 -1.5\nv -1.5 0.3 -1.5\n"
                                   "f 13/1 14/2 15/3 16/4\n",
                             "mesh furnace.obj\ncamera eye 0.5 2 3 target 0 0 0 up 0 1 0 fov 50\nsize 24 24\n"
                             "environment constant 0.5 1 2\n"))
        return;
    if (render(&s, PT_STRATEGY_BSDF, 64, 8, &r)) {
        scene_free(&s);
        return;
    }
    for (y = 0; y < s.height; ++y)
        for (x = 0; x < s.width; ++x) {
            const float *p = image_pixel(&r.mean, x, y);
            static const double L[3] = {0.5, 1, 2};
            for (c = 0; c < 3; ++c)
                CHECKF(fabs(p[c] - L[c]) <= 1e-5 * L[c], "pixel (%d, %d) channel %d: %.7g, L = %g", x, y, c, p[c], L[c]);
        }
    pt_result_free(&r);
    scene_free(&s);
}

/* ---- environment maps by extension ------------------------------------------------------- */

/* The same 6 x 3 radiance map written as PFM and as EXR (float, ZIP) loads to the same
 * texels; a PNG map is the sRGB-decoded picture; another extension is refused. */
TEST(sky_exr_and_png_maps)
{
    image img;
    scene_sky a, b, c;
    unsigned char px[6 * 3 * 3];
    rerror e;
    int i;
    if (image_alloc(&img, 6, 3, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return;
    }
    for (i = 0; i < 6 * 3 * 3; ++i) {
        img.px[i] = (float)(0.25 * (i % 7) + 0.125 * (i % 3));
        px[i] = (unsigned char)(37 * i % 256);
    }
    sky_init(&a);
    sky_init(&b);
    sky_init(&c);
    CHECKF(!pfm_write(test_tmp_path("env.pfm"), &img, &e) && !exr_write(test_tmp_path("env.exr"), &img, EXR_ZIP, EXR_FLOAT, &e) &&
               !png_write_rgb8(test_tmp_path("env.png"), 6, 3, px, &e),
           "%s", e.msg);
    CHECKF(!sky_load_map(&a, test_tmp_path("env.pfm"), 1, &e) && !sky_load_map(&b, test_tmp_path("env.exr"), 1, &e) &&
               !sky_load_map(&c, test_tmp_path("env.png"), 1, &e),
           "%s", e.msg);
    if (!test_has_failed()) {
        CHECK(a.width == 6 && b.width == 6 && b.height == 3 && c.height == 3);
        CHECK(!memcmp(a.texels, b.texels, 6 * 3 * 3 * sizeof *a.texels));
        for (i = 0; i < 6 * 3 * 3; ++i)
            CHECKF(fabs(c.texels[i] - srgb_to_linear(px[i] / 255.0)) < 1e-7, "png texel %d: %g", i, (double)c.texels[i]);
    }
    sky_free(&a);
    sky_free(&b);
    sky_free(&c);
    sky_init(&a);
    CHECK(sky_load_map(&a, test_tmp_path("env.hdr"), 1, &e) != 0 && strstr(e.msg, ".exr") != NULL);
    sky_free(&a);
    image_free(&img);
}
