/* The generated scenes (include/restir/scene/generate_rooms.h, docs/scenes.md): the shipped
 * files are the generator's output, every solid is closed with outward faces, no two
 * faces of different objects overlap in one plane, the emitters face where they should,
 * the closed door seals the dark room (no ray, no path gets through) and the open door
 * lets light in; `restir generate` and the MTL round trip. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/generate.h"
#include "restir/scene/generate_rooms.h"
#include "restir/core/image.h"
#include "restir/render/pt.h"
#include "mesh_util.h"
#include "test.h"
#include "restir/core/pfm.h"
#include "restir/scene/scene_trace.h"
#include "restir/scene/generate_atrium.h"

static char out[8192];

static vec3f tri_corner(const scene *s, size_t t, int k) { return s->positions[s->triangles[t].v[k]]; }

static vec3 tri_normal(const scene *s, size_t t)
{
    vec3 a = v3_from_f(tri_corner(s, t, 0)), b = v3_from_f(tri_corner(s, t, 1)), c = v3_from_f(tri_corner(s, t, 2));
    return v3_cross(v3_sub(b, a), v3_sub(c, a));
}

static vec3 tri_centroid(const scene *s, size_t t)
{
    vec3 a = v3_from_f(tri_corner(s, t, 0)), b = v3_from_f(tri_corner(s, t, 1)), c = v3_from_f(tri_corner(s, t, 2));
    return v3_scale(v3_add(v3_add(a, b), c), (real)(1.0 / 3));
}

static long object_id(const scene *s, const char *name)
{
    size_t i;
    for (i = 0; i < s->object_count; ++i)
        if (!strcmp(s->object_names[i], name)) return (long)i;
    return -1;
}

static int is_emitter(const scene *s, size_t t) { return !rgb_is_black(s->materials[s->triangles[t].material].emission); }

/* ---- coplanar overlaps ------------------------------------------------------------ */

/* Do two triangles in one plane (unit normal n) overlap with positive area? Separating
 * axis test in 2D: edge normals of both; touching (gap >= -tol) counts as separate. */
static int coplanar_overlap(const vec3 p[3], const vec3 q[3], vec3 n, double tol)
{
    vec3 u, w;
    double P[3][2], Q[3][2];
    int i, k, side;
    v3_basis(n, &u, &w);
    for (i = 0; i < 3; ++i) {
        P[i][0] = v3_dot(p[i], u), P[i][1] = v3_dot(p[i], w);
        Q[i][0] = v3_dot(q[i], u), Q[i][1] = v3_dot(q[i], w);
    }
    for (side = 0; side < 2; ++side) {
        double(*T)[2] = side ? Q : P;
        for (k = 0; k < 3; ++k) {
            double ax = -(T[(k + 1) % 3][1] - T[k][1]), ay = T[(k + 1) % 3][0] - T[k][0], len = hypot(ax, ay);
            double pmin = 1e300, pmax = -1e300, qmin = 1e300, qmax = -1e300;
            for (i = 0; i < 3; ++i) {
                double a = (P[i][0] * ax + P[i][1] * ay) / len, b = (Q[i][0] * ax + Q[i][1] * ay) / len;
                pmin = fmin(pmin, a), pmax = fmax(pmax, a), qmin = fmin(qmin, b), qmax = fmax(qmax, b);
            }
            if (pmax <= qmin + tol || qmax <= pmin + tol) return 0;
        }
    }
    return 1;
}

/* Number of pairs of triangles of different objects that lie in one plane and overlap;
 * `scale` is the scene's size (tolerances are relative to it). */
static long coplanar_overlaps(const scene *s, double scale, char *first, size_t size)
{
    long count = 0;
    size_t i, j;
    for (i = 0; i < s->triangle_count; ++i) {
        vec3 ni = v3_normalize(tri_normal(s, i)), pi[3];
        int k;
        for (k = 0; k < 3; ++k) pi[k] = v3_from_f(tri_corner(s, i, k));
        for (j = i + 1; j < s->triangle_count; ++j) {
            vec3 nj, pj[3];
            if (s->triangles[i].object == s->triangles[j].object) continue;
            nj = v3_normalize(tri_normal(s, j));
            if (fabs(v3_dot(ni, nj)) < 1 - 1e-9) continue;
            for (k = 0; k < 3; ++k) pj[k] = v3_from_f(tri_corner(s, j, k));
            if (fabs(v3_dot(v3_sub(pj[0], pi[0]), ni)) > 1e-6 * scale) continue;
            if (coplanar_overlap(pi, pj, ni, 1e-6 * scale)) {
                if (!count)
                    snprintf(first, size, "%s triangle %zu and %s triangle %zu", s->object_names[s->triangles[i].object],
                             i, s->object_names[s->triangles[j].object], j);
                count++;
            }
        }
    }
    return count;
}

/* ---- tests -------------------------------------------------------------------------- */

/* The shipped files are exactly what the generator writes (default door angle). */
static void check_matches_generated(const char *path, const scene *g)
{
    scene s;
    rerror e;
    size_t i;
    CHECKF(scene_load(&s, path, &e) == 0, "%s", e.msg);
    CHECKF(s.warning_count == 0, "%s: %s", path, s.warnings[0]);
    CHECK(s.triangle_count == g->triangle_count && s.position_count == g->position_count);
    CHECK(s.material_count == g->material_count && s.object_count == g->object_count);
    for (i = 0; i < s.position_count; ++i)
        CHECKF(!memcmp(&s.positions[i], &g->positions[i], sizeof(vec3f)), "%s: vertex %zu differs", path, i);
    for (i = 0; i < s.triangle_count; ++i)
        CHECK(!memcmp(s.triangles[i].v, g->triangles[i].v, sizeof g->triangles[i].v) &&
              s.triangles[i].material == g->triangles[i].material && s.triangles[i].object == g->triangles[i].object);
    for (i = 0; i < s.material_count; ++i) {
        const material *a = &s.materials[i], *b = &g->materials[i];
        CHECKF(!strcmp(a->name, b->name) && a->type == b->type && a->roughness == b->roughness && a->ior == b->ior &&
                   !memcmp(&a->diffuse, &b->diffuse, sizeof(rgb)) && !memcmp(&a->specular, &b->specular, sizeof(rgb)) &&
                   !memcmp(&a->emission, &b->emission, sizeof(rgb)),
               "%s: material %s differs", path, a->name);
    }
    CHECK(s.has_camera && s.width == 512 && s.height == 512);
    CHECK(!memcmp(&s.camera.eye, &g->camera.eye, sizeof(vec3)) && !memcmp(&s.camera.target, &g->camera.target, sizeof(vec3)));
    CHECK(s.camera.fov_y_degrees == g->camera.fov_y_degrees);
    scene_free(&s);
}

TEST(scenes_shipped_files_are_the_generated_scenes)
{
    scene g;
    rerror e;
    CHECKF(generate_ajar(&g, AJAR_DEFAULT_DOOR_ANGLE, &e) == 0, "%s", e.msg);
    check_matches_generated("scenes/ajar.scene", &g);
    scene_free(&g);
    CHECKF(generate_glass_room(&g, &e) == 0, "%s", e.msg);
    check_matches_generated("scenes/glass.scene", &g);
    CHECK(g.triangle_count == 10 + 2 + 12 + 2 * 64 * 31);
    scene_free(&g);
    CHECKF(generate_corridor(&g, &e) == 0, "%s", e.msg);
    check_matches_generated("scenes/corridor.scene", &g);
    scene_free(&g);
}

/* Every object of the door-ajar building (at several angles) and the glass room's
 * sphere and block are closed solids with outward faces; the emitters are not solids. */
TEST(scenes_solids_closed_and_outward)
{
    const double angles[] = {0, AJAR_DEFAULT_DOOR_ANGLE, 37.5, 90};
    scene s;
    rerror e;
    double volume;
    const char *problem;
    uint32_t o;
    int a;
    for (a = 0; a < 4; ++a) {
        CHECKF(generate_ajar(&s, angles[a], &e) == 0, "%s", e.msg);
        CHECK(s.object_count == 13);
        for (o = 0; o < s.object_count; ++o) {
            if (!strcmp(s.object_names[o], "light")) continue;
            problem = check_closed_outward(&s, o, &volume);
            CHECKF(!problem, "ajar(%g) %s: %s", angles[a], s.object_names[o], problem);
        }
        /* The door is a 1.0 x 2.17 x 0.05 m slab at every angle. */
        check_closed_outward(&s, (uint32_t)object_id(&s, "door"), &volume);
        CHECK_NEAR(volume, 1.0 * 2.17 * 0.05, 1e-5);
        scene_free(&s);
    }
    CHECKF(generate_glass_room(&s, &e) == 0, "%s", e.msg);
    problem = check_closed_outward(&s, (uint32_t)object_id(&s, "glass_sphere"), &volume);
    CHECKF(!problem, "glass sphere: %s", problem);
    CHECK(volume < 4.0 / 3 * 3.14159265 * 1e6 && volume > 0.98 * 4.0 / 3 * 3.14159265 * 1e6);
    problem = check_closed_outward(&s, (uint32_t)object_id(&s, "tall_block"), &volume);
    CHECKF(!problem, "tall block: %s", problem);
    scene_free(&s);
    CHECK(generate_ajar(&s, -1, &e) != 0 && generate_ajar(&s, 90.5, &e) != 0 && generate_ajar(&s, NAN, &e) != 0);
}

/* The glass room's walls face the room and meet at shared edges (only the four edges of
 * the open front are borders); the light faces down from just below the ceiling. */
TEST(scenes_glass_room_orientation)
{
    scene s;
    rerror e;
    size_t t;
    vec3 centre = v3(278, 274.4, 279.6);
    int lights = 0;
    CHECKF(generate_glass_room(&s, &e) == 0, "%s", e.msg);
    for (t = 0; t < s.triangle_count; ++t) {
        const char *name = s.object_names[s.triangles[t].object];
        vec3 n = tri_normal(&s, t), c = tri_centroid(&s, t);
        if (is_emitter(&s, t)) {
            lights++;
            CHECK(!strcmp(name, "light") && n.y < 0 && n.x == 0 && n.z == 0 && c.y > 548.6 && c.y < 548.8);
            CHECK(fabs(c.x - 278) < 20 && fabs(c.z - 279.6) < 20);
        } else if (strstr(name, "wall") || !strcmp(name, "floor") || !strcmp(name, "ceiling")) {
            CHECKF(v3_dot(n, v3_sub(centre, c)) > 0, "%s triangle %zu faces outward", name, t);
        }
    }
    CHECK(lights == 2 && scene_emitter_count(&s) == 2);
    CHECK(s.materials[s.triangles[s.triangle_count - 1].material].type == MAT_DIELECTRIC);
    CHECK(s.materials[s.triangles[s.triangle_count - 1].material].ior == (real)1.5);
    scene_free(&s);
}

/* The emitter is in the lit room, faces the doorway, and cannot be seen from the camera. */
TEST(scenes_ajar_emitter_faces_the_doorway)
{
    scene s;
    rerror e;
    size_t t;
    vec3 doorway = v3(2.65, 1.05, 4.075);
    CHECKF(generate_ajar(&s, AJAR_DEFAULT_DOOR_ANGLE, &e) == 0, "%s", e.msg);
    CHECK(scene_emitter_count(&s) == 2);
    for (t = 0; t < s.triangle_count; ++t) {
        vec3 n, c;
        if (!is_emitter(&s, t)) continue;
        n = tri_normal(&s, t);
        c = tri_centroid(&s, t);
        CHECK(c.z > 4.15 && n.z < 0 && n.x == 0 && n.y == 0);
        CHECK(v3_dot(n, v3_sub(doorway, c)) > 0);
        CHECK(v3_dot(n, v3_sub(s.camera.eye, c)) > 0); /* it faces the camera's way ... */
    }
    CHECK(s.camera.eye.z < 4 && s.camera.target.z < 4); /* ... but the camera is in the dark room */
    scene_free(&s);
}

TEST(scenes_no_coplanar_overlaps)
{
    scene s;
    rerror e;
    char first[256] = "";
    long n;
    CHECKF(generate_ajar(&s, 0, &e) == 0, "%s", e.msg);
    n = coplanar_overlaps(&s, 7, first, sizeof first);
    CHECKF(n == 0, "ajar(0): %ld coplanar overlaps, first: %s", n, first);
    scene_free(&s);
    CHECKF(generate_ajar(&s, AJAR_DEFAULT_DOOR_ANGLE, &e) == 0, "%s", e.msg);
    n = coplanar_overlaps(&s, 7, first, sizeof first);
    CHECKF(n == 0, "ajar: %ld coplanar overlaps, first: %s", n, first);
    scene_free(&s);
    CHECKF(generate_glass_room(&s, &e) == 0, "%s", e.msg);
    n = coplanar_overlaps(&s, 600, first, sizeof first);
    CHECKF(n == 0, "glass: %ld coplanar overlaps, first: %s", n, first);
    /* The detector works: a copy of the floor quad under another object name overlaps. */
    s.triangles[1].object = s.triangles[0].object + 1;
    s.triangles[0] = s.triangles[1];
    s.triangles[0].object = s.triangles[1].object - 1;
    CHECK(coplanar_overlaps(&s, 600, first, sizeof first) > 0);
    scene_free(&s);
}

/* Rays from random points of the dark room towards random points on its walls, the
 * doorway and its junctions: with the door closed none gets beyond the dividing wall;
 * with it open some do (so the check can fail). */
static long rays_escaping_dark_room(double angle, int rays)
{
    scene s;
    rerror e;
    long escaped = 0;
    int i;
    if (generate_ajar(&s, angle, &e) || scene_prepare(&s, &e)) return -1;
    for (i = 0; i < rays; ++i) {
        rng_key k = rng_key_at(rng_key_make(test_seed(), (uint32_t)i, (uint32_t)(angle * 100)), RNG_TEST, 0, 0);
        real u[5];
        vec3f origin, target;
        ray r;
        surface_hit h;
        int j;
        for (j = 0; j < 5; ++j) u[j] = rng_u(k, RNG_TEST, 0, (uint32_t)j);
        origin = v3f((float)(0.05 + 3.9 * u[0]), (float)(0.05 + 2.4 * u[1]), (float)(0.05 + 3.9 * u[2]));
        /* Targets: the dividing wall around the doorway, the side walls, the twelve
         * edges of the room (where solids meet) and the edges of the door frame. */
        switch (i % 4) {
        case 0: target = v3f((float)(2.0 + 1.3 * u[3]), (float)(-0.05 + 2.3 * u[4]), 4.0f); break;
        case 1: target = v3f(u[4] < 0.5 ? 0.0f : 4.0f, (float)(2.5 * u[3]), (float)(4.0 * u[4])); break;
        case 2: {
            float a = (float)(u[3] < 0.5 ? 0 : 1), b = (float)(u[4] < 0.5 ? 0 : 1), t = (float)u[1];
            int axis = (int)(3 * u[0]) % 3;
            target = axis == 0 ? v3f(4 * t, 2.5f * a, 4 * b) : axis == 1 ? v3f(4 * a, 2.5f * t, 4 * b) : v3f(4 * a, 2.5f * b, 4 * t);
            break;
        }
        default:
            target = u[3] < 0.66 ? v3f(u[3] < 0.33 ? 2.2f : 3.1f, (float)(2.1 * u[4]), 4.0f)
                                 : v3f((float)(2.2 + 0.9 * u[4]), u[3] < 0.83 ? 2.1f : 0.0f, 4.0f);
        }
        r.origin = origin;
        r.dir = v3f_normalize(v3f_sub(target, origin));
        r.tmin = 0;
        r.tmax = INFINITY;
        if (!scene_intersect(&s, &r, &h) || h.position.z > 4.02f || h.position.x < -0.01f || h.position.x > 4.01f ||
            h.position.y < -0.01f || h.position.y > 2.51f || h.position.z < -0.01f)
            escaped++;
    }
    scene_free(&s);
    return escaped;
}

TEST(scenes_ajar_closed_door_seals_the_room)
{
    long closed = rays_escaping_dark_room(0, 200000), open = rays_escaping_dark_room(AJAR_DEFAULT_DOOR_ANGLE, 200000);
    CHECKF(closed == 0, "%ld rays left the closed dark room", closed);
    CHECKF(open > 100, "only %ld rays left through the open door", open);
}

/* The reference path tracer sees black in the dark room with the door closed, light
 * with the door ajar. */
static int render_ajar(double angle, int res, uint32_t spp, double *mean, double *max)
{
    scene s;
    rerror e;
    pt_options o;
    pt_result r;
    long i;
    if (generate_ajar(&s, angle, &e) || scene_prepare(&s, &e)) return -1;
    s.width = s.height = res;
    pt_options_default(&o);
    o.spp = spp;
    o.seed = test_seed();
    o.threads = 2;
    o.quiet = 1;
    if (pt_render(&s, &o, &r, &e)) {
        scene_free(&s);
        return -1;
    }
    *mean = *max = 0;
    for (i = 0; i < 3L * res * res; ++i) {
        *mean += r.mean.px[i] / (3.0 * res * res);
        *max = fmax(*max, r.mean.px[i]);
    }
    pt_result_free(&r);
    scene_free(&s);
    return 0;
}

TEST(scenes_ajar_light_only_through_the_door)
{
    double mean, max;
    CHECK(render_ajar(0, 24, 48, &mean, &max) == 0);
    CHECKF(max == 0, "closed door: mean %g, max %g", mean, max);
    CHECK(render_ajar(AJAR_DEFAULT_DOOR_ANGLE, 24, 8, &mean, &max) == 0);
    CHECKF(mean > 0.05, "open door: mean %g", mean);
}

/* Every material type comes back from the generated MTL (bare OBJ, no scene file). */
TEST(scenes_generated_mtl_round_trips_material_types)
{
    scene s, back;
    rerror e;
    const char *path = test_tmp_path("gen/types.obj");
    size_t i;
    CHECKF(generate_ajar(&s, 5, &e) == 0, "%s", e.msg);
    /* Turn two materials into the dielectrics. */
    s.materials[4].type = MAT_DIELECTRIC;
    s.materials[4].specular = rgb_gray(1);
    s.materials[4].ior = (real)1.33;
    s.materials[4].roughness = 0;
    s.materials[5].type = MAT_ROUGH_DIELECTRIC;
    s.materials[5].specular = rgb_gray(1);
    s.materials[5].roughness = (real)0.3;
    s.materials[5].ior = (real)1.7;
    CHECKF(generate_write_obj(&s, path, &e) == 0, "%s", e.msg);
    CHECKF(scene_load(&back, path, &e) == 0, "%s", e.msg);
    CHECK(back.material_count == s.material_count && back.warning_count == 0);
    for (i = 0; i < s.material_count; ++i) {
        const material *a = &s.materials[i], *b = &back.materials[i];
        CHECKF(a->type == b->type, "%s: type %d came back as %d", a->name, a->type, b->type);
        CHECK(!memcmp(&a->emission, &b->emission, sizeof(rgb)));
        if (a->type != MAT_LAMBERT) CHECKF(a->roughness == b->roughness, "%s: roughness %.17g came back as %.17g", a->name, (double)a->roughness, (double)b->roughness);
        if (a->type == MAT_CONDUCTOR || a->type == MAT_PLASTIC) CHECK(!memcmp(&a->specular, &b->specular, sizeof(rgb)));
        if (a->type != MAT_CONDUCTOR && a->type < MAT_DIELECTRIC) CHECK(!memcmp(&a->diffuse, &b->diffuse, sizeof(rgb)));
        if (a->type >= MAT_PLASTIC) CHECK(a->ior == b->ior);
    }
    scene_free(&back);
    scene_free(&s);
}

TEST(scenes_cli_generate)
{
    /* a copy: test_tmp_path's buffers rotate (test_cli takes one), and the later
     * `generate corridor -o %s` once wrote its OBJ as cli-output.txt */
    char obj[4200];
    char scene_path[4200], mtl[4200];
    scene s;
    rerror e;
    snprintf(obj, sizeof obj, "%s", test_tmp_path("gen/ajar20.obj"));
    snprintf(scene_path, sizeof scene_path, "%.*s.scene", (int)(strlen(obj) - 4), obj);
    snprintf(mtl, sizeof mtl, "%.*s.mtl", (int)(strlen(obj) - 4), obj);
    CHECKF(test_cli(out, sizeof out, "generate ajar --door-angle 20 -o %s", obj) == 0, "%s", out);
    CHECK(test_file_exists(obj) && test_file_exists(mtl) && test_file_exists(scene_path));
    CHECKF(scene_load(&s, scene_path, &e) == 0, "%s", e.msg);
    CHECK(s.object_count == 13 && s.has_camera && scene_emitter_count(&s) == 2);
    scene_free(&s);
    CHECK(test_cli(out, sizeof out, "generate ajar --door-angle 91 -o %s", obj) == 2);
    CHECK(test_cli(out, sizeof out, "generate glass --door-angle 5 -o %s", obj) == 2);
    CHECK(test_cli(out, sizeof out, "generate teapot -o %s", obj) == 2);
    CHECK(test_cli(out, sizeof out, "generate glass") == 2);
    CHECK(test_cli(out, sizeof out, "generate --help") == 0 && strstr(out, "--door-angle") && strstr(out, "corridor"));
    CHECK(test_cli(out, sizeof out, "generate corridor --subdivisions 3 -o %s", obj) == 2);
    CHECKF(test_cli(out, sizeof out, "generate corridor -o %s", obj) == 0, "%s", out);
    CHECKF(scene_load(&s, scene_path, &e) == 0, "%s", e.msg);
    CHECK(s.has_camera && scene_emitter_count(&s) == 2); /* one 1 x 1 quad light: two triangles */
    scene_free(&s);
}

/* scenes/hall.scene, hall-far.scene, hall-wide.scene and the hall-glossy variants (scripts/gen_hall.sh;
 * the near/far footprint comparison of docs/results.md) load and render: 8 x 8 offline
 * ReSTIR PT (the near view with the Enhanced features), every pixel finite and
 * non-negative, some light. */
TEST(scenes_hall_smoke)
{
    static const char *const files[] = {"scenes/hall.scene", "scenes/hall-far.scene", "scenes/hall-glossy.scene",
                                        "scenes/hall-glossy-far.scene", "scenes/hall-wide.scene"};
    static const char *const options[] = {"--rc-criterion footprint --pairing paired --shading vector --force-nee-reconnection",
                                          "", "", "", ""};
    char pfm[1024];
    image img;
    rerror e;
    int channels, i, x, y, c;
    for (i = 0; i < 5; ++i) {
        double sum = 0;
        int bad = 0;
        snprintf(pfm, sizeof pfm, "%s", test_tmp_path("hall.pfm"));
        CHECKF(test_cli(out, sizeof out,
                        "render %s --method restir --size 8x8 --frames 2 %s -o %s --no-png --quiet", files[i], options[i],
                        pfm) == 0,
               "%s", out);
        CHECKF(!pfm_read(pfm, &img, &channels, &e), "%s", e.msg);
        for (y = 0; y < img.height; ++y)
            for (x = 0; x < img.width; ++x)
                for (c = 0; c < 3; ++c) {
                    float v = image_pixel(&img, x, y)[c];
                    bad += !(v >= 0 && v < 1e30f);
                    sum += v;
                }
        CHECKF(bad == 0 && sum > 0, "%s: %d bad values, sum %g", files[i], bad, sum);
        image_free(&img);
    }
}

/* The atrium (generate_atrium.c; the Sponza-like interior of the traversal yardstick):
 * a quarter of a million triangles, every object a union of closed solids with outward
 * faces (curtains, columns, the 229-corner arcade walls included), the camera inside the
 * courtyard, the same triangles on a second call, and a few paths through it that find
 * light and stay finite (32 x 24, 2 spp). */
TEST(scenes_atrium_closed_deterministic_lit)
{
    scene s, t;
    rerror e;
    double volume;
    const char *problem;
    uint32_t o;
    CHECKF(generate_atrium(&s, &e) == 0, "%s", e.msg);
    CHECKF(s.triangle_count > 250000 && s.triangle_count < 280000, "%zu triangles", s.triangle_count);
    CHECK(s.object_count == 13 && s.has_camera && scene_emitter_count(&s) == 24);
    for (o = 0; o < s.object_count; ++o) {
        problem = check_closed_outward(&s, o, &volume);
        CHECKF(!problem, "atrium %s: %s", s.object_names[o], problem);
    }
    CHECK(fabs(s.camera.eye.x) < 15 && fabs(s.camera.eye.z) < 6 && s.camera.eye.y > 0 && s.camera.eye.y < 5);
    CHECKF(generate_atrium(&t, &e) == 0, "%s", e.msg);
    CHECK(t.triangle_count == s.triangle_count && t.position_count == s.position_count);
    if (t.triangle_count == s.triangle_count && t.position_count == s.position_count) {
        CHECK(!memcmp(t.positions, s.positions, s.position_count * sizeof *s.positions));
        CHECK(!memcmp(t.triangles, s.triangles, s.triangle_count * sizeof *s.triangles));
    }
    scene_free(&t);
    scene_free(&s);
    {
        const char *obj = test_tmp_path("gen/atrium.obj");
        char scene_path[4200], pfm[4200];
        image img;
        int channels, i, bad = 0;
        double sum = 0;
        snprintf(scene_path, sizeof scene_path, "%.*s.scene", (int)(strlen(obj) - 4), obj);
        snprintf(pfm, sizeof pfm, "%s", test_tmp_path("atrium.pfm"));
        CHECKF(test_cli(out, sizeof out, "generate atrium -o %s", obj) == 0, "%s", out);
        CHECKF(test_cli(out, sizeof out, "render %s --method pt --size 32x24 --spp 2 --threads 2 -o %s", scene_path, pfm) == 0,
               "%s", out);
        CHECKF(pfm_read(pfm, &img, &channels, &e) == 0, "%s", e.msg);
        for (i = 0; i < img.width * img.height * 3; ++i) {
            double v = img.px[i];
            if (!(v >= 0 && isfinite(v))) bad++;
            sum += v;
        }
        CHECK(bad == 0 && sum > 0);
        image_free(&img);
    }
}
