/* Scene-file lights (`light sphere|quad|disk`, src/scene/light_shapes.c): emitted power
 * pi L A of the tessellation against the exact shape, front faces on the emitting side,
 * errors with file:line, a bare mesh without emitters lit from a .scene file; and the
 * framing camera of a scene without camera, which must see flat geometry in every plane. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image_io.h"
#include "restir/render/camera.h"
#include "restir/scene/light_shapes.h"
#include "restir/scene/scene.h"
#include "restir/scene/scene_trace.h"
#include "scene_text_util.h"
#include "test.h"
#include "text_util.h"

#define PI_D 3.14159265358979323846

static const char *floor_obj = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 3 2\nf 1 4 3\n";

static int load_lights(scene *s, const char *scene_text, rerror *e)
{
    test_write_file("lit-floor.obj", floor_obj);
    return scene_from_text(s, "lights.scene", scene_text, e);
}

/* Per channel: sum over the triangles of material `name` of pi Ke area (one-sided
 * Lambertian emitter: power pi L A); also their area, and the smallest cosine between a
 * triangle's front normal and the expected emitting direction (outwards from `centre`
 * for a sphere, `dir` otherwise). */
typedef struct {
    double power[3], area, min_cos;
    size_t triangles;
} emitter_sum;

static emitter_sum sum_emitter(const scene *s, const char *name, const double centre[3], const double *dir)
{
    emitter_sum out;
    size_t i;
    memset(&out, 0, sizeof out);
    out.min_cos = 2;
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle *t = &s->triangles[i];
        const material *m = &s->materials[t->material];
        vec3f p0 = s->positions[t->v[0]], p1 = s->positions[t->v[1]], p2 = s->positions[t->v[2]];
        double a[3], b[3], n[3], len, d[3], dl, c;
        int k;
        if (strcmp(m->name, name)) continue;
        a[0] = (double)p1.x - p0.x, a[1] = (double)p1.y - p0.y, a[2] = (double)p1.z - p0.z;
        b[0] = (double)p2.x - p0.x, b[1] = (double)p2.y - p0.y, b[2] = (double)p2.z - p0.z;
        n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        out.area += 0.5 * len;
        out.power[0] += PI_D * m->emission.r * 0.5 * len;
        out.power[1] += PI_D * m->emission.g * 0.5 * len;
        out.power[2] += PI_D * m->emission.b * 0.5 * len;
        for (k = 0; k < 3; ++k)
            d[k] = dir ? dir[k] : ((double)(k == 0 ? p0.x + p1.x + p2.x : k == 1 ? p0.y + p1.y + p2.y : p0.z + p1.z + p2.z) / 3 - centre[k]);
        dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        c = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / (len * dl);
        if (c < out.min_cos) out.min_cos = c;
        out.triangles++;
    }
    return out;
}

/* A sphere light emits pi L 4 pi r^2 = 4 pi^2 r^2 L per channel, to the tessellation's
 * area error (below 1e-3, and below, never above: the triangles are inscribed). */
TEST(light_sphere_power)
{
    scene s;
    rerror e;
    const double c[3] = {0.25, 2, -0.5}, r = 0.75, L[3] = {3, 5, 7};
    emitter_sum sum;
    int k;
    CHECKF(!load_lights(&s, "mesh lit-floor.obj\nlight sphere 0.25 2 -0.5 0.75 3 5 7\n", &e), "%s", e.msg);
    sum = sum_emitter(&s, "light (line 2)", c, NULL);
    CHECKF(sum.triangles == 20 * LIGHT_SPHERE_DIVISIONS * LIGHT_SPHERE_DIVISIONS, "%zu triangles", sum.triangles);
    CHECK(scene_emitter_count(&s) == sum.triangles);
    for (k = 0; k < 3; ++k) {
        double exact = 4 * PI_D * PI_D * r * r * L[k], rel = sum.power[k] / exact - 1;
        CHECKF(rel < 0 && rel > -1e-3, "channel %d: power %.9g vs 4 pi^2 r^2 L = %.9g (relative %.3g)", k,
               sum.power[k], exact, rel);
    }
    /* Every front face points outwards, nearly radially (the triangles are small). */
    CHECKF(sum.min_cos > 0.99, "a sphere triangle faces %g from outwards", sum.min_cos);
    scene_free(&s);
}

/* A quad is exact (4 |u x v|, facing u x v); a disk is within 1e-3 (facing its normal). */
TEST(light_quad_and_disk_area_and_side)
{
    scene s;
    rerror e;
    const double up[3] = {0, -1, 0}, tilt[3] = {1, 1, 0}, none[3] = {0, 0, 0};
    emitter_sum q, d;
    int k;
    CHECKF(!load_lights(&s,
                        "mesh lit-floor.obj\nlight quad 0 3 0 0.5 0 0 0 0 0.25 1 2 3\n"
                        "light disk 0 1 0 1 1 0 0.5 4 4 4\n",
                        &e),
           "%s", e.msg);
    q = sum_emitter(&s, "light (line 2)", none, up); /* (0.5,0,0) x (0,0,0.25) = (0,-0.125,0): down */
    d = sum_emitter(&s, "light (line 3)", none, tilt);
    CHECK(q.triangles == 2 && d.triangles == LIGHT_DISK_SEGMENTS);
    CHECK_NEAR(q.area, 4 * 0.5 * 0.25, 1e-7);
    for (k = 0; k < 3; ++k) CHECK_NEAR(q.power[k], PI_D * 0.5 * (k + 1), 1e-6);
    CHECKF(d.area < PI_D * 0.25 && d.area > PI_D * 0.25 * (1 - 1e-3), "disk area %.9g vs %.9g", d.area, PI_D * 0.25);
    CHECKF(q.min_cos > 0.999999 && d.min_cos > 0.999999, "quad cos %g, disk cos %g", q.min_cos, d.min_cos);
    CHECK(s.triangle_count == 2 + 2 + LIGHT_DISK_SEGMENTS); /* the mesh's triangles come first */
    CHECK(s.materials[s.triangles[0].material].emission.r == 0);
    scene_free(&s);
}

TEST(light_errors_have_file_and_line)
{
    static const bad_input cases[] = {
        {"mesh lit-floor.obj\nlight\n", "lights.scene:2: light: missing shape"},
        {"mesh lit-floor.obj\nlight cube 0 0 0 1 1 1 1\n", "lights.scene:2: light: unknown shape 'cube'"},
        {"mesh lit-floor.obj\nlight sphere 0 0 0 1 1 1\n", "lights.scene:2: light sphere: expected 7 numbers"},
        {"mesh lit-floor.obj\nlight sphere 0 0 0 1 1 1 1 9\n", "lights.scene:2: light sphere: unexpected '9'"},
        {"mesh lit-floor.obj\n\nlight sphere 0 0 0 -1 1 1 1\n", "lights.scene:3: light sphere: radius -1 is not > 0"},
        {"mesh lit-floor.obj\nlight sphere 0 0 0 1 0 0 0\n", "lights.scene:2: light sphere: radiance 0 0 0"},
        {"mesh lit-floor.obj\nlight sphere 0 0 0 1 1 -1 1\n", "lights.scene:2: light sphere: radiance outside"},
        {"mesh lit-floor.obj\nlight sphere 0 0 0 1 1 nan 1\n", "lights.scene:2: light sphere: number is not finite"},
        {"mesh lit-floor.obj\nlight sphere 1e19 0 0 1 1 1 1\n", "lights.scene:2: light sphere: a coordinate"},
        {"mesh lit-floor.obj\nlight quad 0 0 0 1 0 0 2 0 0 1 1 1\n", "lights.scene:2: light quad: u and v are zero or parallel"},
        {"mesh lit-floor.obj\nlight disk 0 0 0 0 0 0 1 1 1 1\n", "lights.scene:2: light disk: the normal is zero"},
        {"mesh lit-floor.obj\nlight disk 0 0 0 0 1 0 0 1 1 1\n", "lights.scene:2: light disk: radius 0 is not > 0"},
        {NULL, "lights.scene:526: light: the lights would have more than 4194304 triangles"},
    };
    size_t i;
    char *many = malloc(600 * 40 + 32);
    CHECK(many != NULL);
    strcpy(many, "mesh lit-floor.obj\n"); /* then 600 sphere lines: the 525th is one too many */
    for (i = 0; i < 600; ++i) strcat(many, "light sphere 0 0 0 1 1 1 1\n");
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        scene s;
        rerror e;
        int failed = load_lights(&s, cases[i].input ? cases[i].input : many, &e) != 0;
        if (!failed) scene_free(&s);
        if (!failed) free(many);
        CHECKF(failed, "case %zu loaded", i);
        if (!strstr(e.msg, cases[i].expect)) free(many);
        CHECKF(strstr(e.msg, cases[i].expect) != NULL, "case %zu: '%s' lacks '%s'", i, e.msg, cases[i].expect);
    }
    free(many);
}

/* A bare mesh without any emitter (a bunny-like closed blob over a floor) lit by a `light
 * sphere` of the scene file, no camera (the framing camera): the render is finite and
 * lit in R, G and B; the same scene without the light line is refused (no emitters). */
TEST(light_sphere_lights_a_bare_mesh)
{
    static const char *blob =
        "v 0 0.2 0\nv 0.3 0.5 0\nv -0.3 0.5 0\nv 0 0.5 0.3\nv 0 0.5 -0.3\nv 0 0.9 0\n"
        "f 1 2 4\nf 1 4 3\nf 1 3 5\nf 1 5 2\nf 6 4 2\nf 6 3 4\nf 6 5 3\nf 6 2 5\n"
        "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 7 9 8\nf 7 10 9\n";
    char out[4096], scene_path[1024], dark_path[1024], pfm[1024];
    image img;
    rerror e;
    double sum[3] = {0, 0, 0};
    size_t i, lit = 0, n;
    int k;
    test_write_file("blob.obj", blob);
    snprintf(scene_path, sizeof scene_path, "%s",
             test_write_file("blob-lit.scene", "mesh blob.obj\nsize 24 24\nlight sphere 0.6 1.4 0.6 0.15 20 16 12\n"));
    snprintf(dark_path, sizeof dark_path, "%s", test_write_file("blob-dark.scene", "mesh blob.obj\nsize 24 24\n"));
    snprintf(pfm, sizeof pfm, "%s", test_tmp_path("blob-lit.pfm"));
    CHECKF(test_cli(out, sizeof out, "render %s --method pt --spp 16 --quiet --no-png -o %s", scene_path, pfm) == 0,
           "%s", out);
    CHECKF(!image_read(pfm, &img, NULL, &e), "%s", e.msg);
    n = (size_t)img.width * (size_t)img.height;
    for (i = 0; i < n; ++i) {
        int any = 0;
        for (k = 0; k < 3; ++k) {
            float v = img.px[3 * i + (size_t)k];
            CHECKF(isfinite(v) && v >= 0, "pixel %zu channel %d = %g", i, k, (double)v);
            sum[k] += v;
            any |= v > 0;
        }
        lit += (size_t)any;
    }
    image_free(&img);
    for (k = 0; k < 3; ++k) CHECKF(sum[k] > 0, "channel %d is black", k);
    CHECKF(lit > n / 8, "only %zu of %zu pixels are lit", lit, n);
    /* Without the light line the mesh has no emitter: refused, not rendered black. */
    CHECKF(test_cli(out, sizeof out, "render %s --method pt --spp 1 --quiet --no-png -o %s", dark_path, pfm) == 2 &&
               strstr(out, "no emitters"),
           "%s", out);
}

/* The framing camera (no camera line, or a bare OBJ) sees a flat quad in any plane: at
 * least a tenth of the image's pixels hit it. The xy quad keeps the historical +z view. */
TEST(framing_camera_sees_flat_quads)
{
    static const struct {
        const char *name, *obj;
    } quads[] = {
        {"xy", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n"},
        {"xz", "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 2 3 4\n"},
        {"yz", "v 0 -1 -1\nv 0 1 -1\nv 0 1 1\nv 0 -1 1\nf 1 2 3 4\n"},
        {"x=y", "v -1 -1 -1\nv 1 1 -1\nv 1 1 1\nv -1 -1 1\nf 1 2 3 4\n"},
        {"xz-far", "v 100 5 100\nv 140 5 100\nv 140 5 130\nv 100 5 130\nf 1 2 3 4\n"},
    };
    size_t q;
    for (q = 0; q < sizeof quads / sizeof quads[0]; ++q) {
        scene s;
        rerror e;
        camera cam;
        char name[64], path[1024];
        int x, y, hits = 0, grid = 32;
        snprintf(name, sizeof name, "flat-%zu.obj", q);
        snprintf(path, sizeof path, "%s", test_write_file(name, quads[q].obj));
        CHECKF(!scene_load(&s, path, &e), "%s", e.msg);
        CHECKF(!scene_prepare(&s, &e), "%s", e.msg);
        camera_init(&cam, s.camera, s.width, s.height);
        for (y = 0; y < grid; ++y)
            for (x = 0; x < grid; ++x) {
                ray r = camera_ray(&cam, (real)((x + 0.5) * s.width / grid), (real)((y + 0.5) * s.height / grid));
                surface_hit h;
                hits += scene_intersect(&s, &r, &h);
            }
        if (q == 0)
            CHECK(s.camera.eye.x == s.camera.target.x && s.camera.eye.y == s.camera.target.y &&
                  s.camera.eye.z > s.camera.target.z);
        scene_free(&s);
        CHECKF(hits * 10 >= grid * grid, "quad in %s: %d of %d rays hit it", quads[q].name, hits, grid * grid);
    }
}
