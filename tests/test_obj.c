/* OBJ and MTL loading: every index form, relative indices, polygons (ear clipping,
 * concave and degenerate), line-format quirks, object ids, materials, and one test per
 * error with its exact "file:line:" prefix. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/progress.h"
#include "restir/core/rng.h"
#include "restir/scene/scene.h"
#include "restir/scene/scene_builder.h"
#include "restir/scene/text.h"
#include "restir/scene/triangulate.h"
#include "scene_text_util.h"
#include "test.h"
#include "restir/scene/mtl.h"

/* Writes the file and loads it; returns scene_load's status (e filled on failure). */
static int load_text(scene *s, const char *name, const char *text, rerror *e) { return scene_from_text(s, name, text, e); }

static int tri_is(const scene *s, size_t i, uint32_t a, uint32_t b, uint32_t c)
{
    return s->triangles[i].v[0] == a && s->triangles[i].v[1] == b && s->triangles[i].v[2] == c;
}

static const char *unit_square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

TEST(obj_index_forms_mixed)
{
    scene s;
    rerror e;
    char text[1024];
    snprintf(text, sizeof text,
             "%svt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvn 0 0 2\n"
             "f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//2 3//1\nf 1/1/1 2/2/2 3/3/1\nf 1/1/1 2 3//2\n",
             unit_square);
    CHECKF(!load_text(&s, "forms.obj", text, &e), "%s", e.msg);
    CHECK(s.triangle_count == 5 && s.position_count == 4 && s.normal_count == 2);
    CHECK(tri_is(&s, 0, 0, 1, 2) && tri_is(&s, 4, 0, 1, 2));
    CHECK(s.triangles[0].n[0] == -1 && s.triangles[1].n[0] == -1);
    CHECK(s.triangles[2].n[0] == 0 && s.triangles[2].n[1] == 1 && s.triangles[2].n[2] == 0);
    CHECK(s.triangles[3].n[1] == 1);
    CHECK(s.triangles[4].n[0] == -1 && s.triangles[4].n[2] == -1); /* not all corners have one */
    CHECK_NEAR(s.normals[1].z, 1, 0);                               /* stored unit length */
    scene_free(&s);
}

TEST(obj_negative_indices)
{
    scene s;
    rerror e;
    CHECKF(!load_text(&s, "neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nvn 0 0 1\nv 5 5 0\n"
                                     "f -4//-1 -1//-1 -2\n",
                      &e),
           "%s", e.msg);
    CHECK(s.triangle_count == 2);
    CHECK(tri_is(&s, 0, 0, 1, 2));
    CHECK(tri_is(&s, 1, 0, 3, 2));
    scene_free(&s);
}

/* Indices are relative to each file: a second mesh of a scene file starts again at 1. */
TEST(obj_indices_per_file)
{
    scene s;
    rerror e;
    test_write_file("part-a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    test_write_file("part-b.obj", "v 0 0 1\nv 1 0 1\nv 0 1 1\nf 1 2 3\nf -3 -2 -1\n");
    CHECKF(!load_text(&s, "parts.scene", "mesh part-a.obj\nmesh part-b.obj\n", &e), "%s", e.msg);
    CHECK(s.triangle_count == 3 && tri_is(&s, 1, 3, 4, 5) && tri_is(&s, 2, 3, 4, 5));
    scene_free(&s);
}

/* A convex quad becomes the fan (0 1 2), (0 2 3), winding kept. */
TEST(obj_quad_is_fan_with_winding)
{
    scene s;
    rerror e;
    char text[256];
    snprintf(text, sizeof text, "%sf 1 2 3 4\nf 4 3 2 1\n", unit_square);
    CHECKF(!load_text(&s, "quad.obj", text, &e), "%s", e.msg);
    CHECK(s.triangle_count == 4);
    CHECK(tri_is(&s, 0, 0, 1, 2) && tri_is(&s, 1, 0, 2, 3));
    CHECK(tri_is(&s, 2, 3, 2, 1) && tri_is(&s, 3, 3, 1, 0));
    scene_free(&s);
}

/* Signed area of a triangle of corners in the plane of the polygon's unit normal n. */
static double projected_area(vec3f a, vec3f b, vec3f c, vec3 n)
{
    vec3 ab = v3_sub(v3_from_f(b), v3_from_f(a)), ac = v3_sub(v3_from_f(c), v3_from_f(a));
    return 0.5 * (double)v3_dot(v3_cross(ab, ac), n);
}

/* Winding number of the polygon around point q (2D, in the basis u, v). */
static int winding_number(const vec3f *corners, size_t n, vec3 q, vec3 u, vec3 v)
{
    int w = 0;
    size_t i;
    double qx = (double)v3_dot(q, u), qy = (double)v3_dot(q, v);
    for (i = 0; i < n; ++i) {
        vec3 a = v3_from_f(corners[i]), b = v3_from_f(corners[(i + 1) % n]);
        double ax = (double)v3_dot(a, u), ay = (double)v3_dot(a, v), bx = (double)v3_dot(b, u), by = (double)v3_dot(b, v);
        double side = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax);
        if (ay <= qy && by > qy && side > 0) w++;
        if (ay > qy && by <= qy && side < 0) w--;
    }
    return w;
}

/* The triangulation is a partition of the polygon: every triangle has the polygon's
 * orientation, lies inside it (centroid and edge midpoints have winding number 1), and
 * the unsigned areas add up to the polygon's area. Returns NULL or what failed. */
static const char *check_partition(const vec3f *corners, size_t n, const vec3f *tri, size_t count)
{
    static char why[256];
    vec3 normal = polygon_newell_normal(corners, n), u, v;
    double area = 0.5 * (double)v3_length(normal), sum = 0;
    size_t i;
    int k;
    normal = v3_normalize(normal);
    v3_basis(normal, &u, &v);
    for (i = 0; i < count; ++i) {
        vec3f a = tri[3 * i], b = tri[3 * i + 1], c = tri[3 * i + 2];
        double t = projected_area(a, b, c, normal);
        vec3f pts[3];
        if (t < -1e-9 * area) {
            snprintf(why, sizeof why, "triangle %zu is inverted (area %g)", i, t);
            return why;
        }
        sum += fabs(t);
        pts[0] = v3f_scale(v3f_add(v3f_add(a, b), c), 1.0f / 3);
        pts[1] = v3f_scale(v3f_add(v3f_add(v3f_scale(a, 4), b), c), 1.0f / 6);
        pts[2] = v3f_scale(v3f_add(v3f_add(a, v3f_scale(b, 4)), c), 1.0f / 6);
        for (k = 0; k < 3 && t > 1e-9 * area; ++k)
            if (winding_number(corners, n, v3_from_f(pts[k]), u, v) != 1) {
                snprintf(why, sizeof why, "triangle %zu is outside the polygon", i);
                return why;
            }
    }
    if (fabs(sum - area) > 1e-6 * area) {
        snprintf(why, sizeof why, "areas add up to %.9g, polygon area %.9g", sum, area);
        return why;
    }
    return NULL;
}

static const char *triangulate_and_check(const vec3f *corners, size_t n, size_t expect_triangles)
{
    static char why[300];
    triangulator t;
    uint32_t *tri = malloc(3 * n * sizeof *tri);
    vec3f *points = malloc(3 * n * sizeof *points);
    size_t count = 0, i;
    rerror e;
    const char *problem;
    memset(&t, 0, sizeof t);
    if (!tri || !points || triangulate_polygon(&t, corners, n, tri, &count, &e)) {
        free(tri);
        free(points);
        return "triangulation failed";
    }
    for (i = 0; i < 3 * count; ++i) points[i] = corners[tri[i]];
    problem = check_partition(corners, n, points, count);
    free(points);
    if (!problem && expect_triangles && count != expect_triangles) {
        snprintf(why, sizeof why, "%zu triangles, expected %zu", count, expect_triangles);
        problem = why;
    }
    free(tri);
    triangulator_free(&t);
    return problem;
}

/* A comb (deeply concave), a square with a square hole joined by a bridge edge (corners
 * visited twice), and the same polygons tilted out of every coordinate plane. */
TEST(triangulate_concave_and_bridged)
{
    vec3f comb[12], keyhole[10], tilted[12];
    const char *problem;
    size_t i;
    float cx[12] = {0, 6, 6, 5, 5, 4, 4, 2, 2, 1, 1, 0}, cy[12] = {0, 0, 5, 5, 1, 1, 5, 5, 1, 1, 5, 5};
    /* The outline counter-clockwise back to its first corner, the bridge to the hole,
     * the hole clockwise back to its first corner, and the bridge back (closing edge). */
    float kx[10] = {0, 4, 4, 0, 0, 1, 1, 3, 3, 1}, ky[10] = {0, 0, 4, 4, 0, 1, 3, 3, 1, 1};
    for (i = 0; i < 12; ++i) comb[i] = v3f(cx[i], cy[i], 0);
    CHECKF(!(problem = triangulate_and_check(comb, 12, 10)), "comb: %s", problem);
    for (i = 0; i < 10; ++i) keyhole[i] = v3f(kx[i], ky[i], 0);
    CHECK_NEAR(v3_length(polygon_newell_normal(keyhole, 10)), 2 * 12, 1e-12);
    CHECKF(!(problem = triangulate_and_check(keyhole, 10, 8)), "keyhole: %s", problem);
    for (i = 0; i < 12; ++i) {
        float x = cx[i], y = cy[i];
        tilted[i] = v3f(0.36f * x + 0.48f * y + 100, -0.8f * x + 0.6f * y - 50, 0.48f * x - 0.64f * y + 7);
    }
    CHECKF(!(problem = triangulate_and_check(tilted, 12, 10)), "tilted comb: %s", problem);
}

/* Random star-shaped (in general concave) polygons in random planes. */
TEST(triangulate_random_star_polygons)
{
    int trial;
    for (trial = 0; trial < 300; ++trial) {
        vec3f corners[40];
        rng_key key = rng_key_make(test_seed(), (uint32_t)trial, 0);
        size_t n = 4 + (size_t)(rng_uniform_double(rng_key_at(key, RNG_TEST, 0, 0)) * 36), i;
        vec3 axis = v3_normalize(v3(rng_uniform_double(rng_key_at(key, RNG_TEST, 1, 0)) - 0.5,
                                    rng_uniform_double(rng_key_at(key, RNG_TEST, 1, 1)) - 0.5,
                                    rng_uniform_double(rng_key_at(key, RNG_TEST, 1, 2)) - 0.5)),
             u, v;
        const char *problem;
        v3_basis(axis, &u, &v);
        for (i = 0; i < n; ++i) {
            double angle = 2 * 3.14159265358979 * ((double)i + 0.8 * rng_uniform_double(rng_key_at(key, RNG_TEST, 2, (uint32_t)i))) / (double)n;
            double r = 0.2 + rng_uniform_double(rng_key_at(key, RNG_TEST, 3, (uint32_t)i));
            vec3 p = v3_add(v3_scale(u, (real)(r * cos(angle))), v3_scale(v, (real)(r * sin(angle))));
            corners[i] = v3f_from(v3_add(p, v3(3, -2, 1)));
        }
        problem = triangulate_and_check(corners, n, n - 2);
        CHECKF(!problem, "trial %d (n = %zu): %s", trial, n, problem);
    }
}

/* Collinear corners and repeated corners: terminates; all-collinear gives nothing. */
TEST(triangulate_degenerate)
{
    vec3f line[5], flat[6];
    triangulator t;
    uint32_t tri[18];
    size_t count = 99, i;
    rerror e;
    const char *problem;
    memset(&t, 0, sizeof t);
    for (i = 0; i < 5; ++i) line[i] = v3f((float)i, 2 * (float)i, 0);
    CHECK(!triangulate_polygon(&t, line, 5, tri, &count, &e) && count == 0);
    /* a square with an extra corner in the middle of each of two edges, and a repeat */
    flat[0] = v3f(0, 0, 0);
    flat[1] = v3f(1, 0, 0);
    flat[2] = v3f(2, 0, 0);
    flat[3] = v3f(2, 2, 0);
    flat[4] = v3f(2, 2, 0);
    flat[5] = v3f(0, 2, 0);
    CHECKF(!(problem = triangulate_and_check(flat, 6, 0)), "%s", problem);
    triangulator_free(&t);
}

/* The shared data's concave 66-gon with a bridged hole (a fan would be wrong) and the
 * 10-gon with collinear corners: the loader's triangles partition the polygon.
 * Skipped when ../shared/data is absent. */
TEST(obj_shared_concave_polygons)
{
    const char *files[] = {"../shared/data/assimp/concave_polygon.obj", "../shared/data/tinyobjloader/issue-319-003.obj"};
    size_t f;
    for (f = 0; f < 2; ++f) {
        text_reader tr;
        rerror e;
        scene s;
        vec3f corners[128], *points;
        size_t n = 0, i;
        char *line;
        const char *problem;
        if (!test_file_exists(files[f])) return;
        CHECKF(!scene_load(&s, files[f], &e), "%s", e.msg);
        /* The face's corners, read again independently of the loader. */
        CHECK(!text_open(&tr, files[f], &e));
        while ((line = text_next_line(&tr)) != NULL) {
            char *rest = line, *tok = text_next_token(&rest);
            if (!tok || strcmp(tok, "f")) continue;
            while ((tok = text_next_token(&rest)) != NULL && n < 128)
                corners[n++] = s.positions[strtol(tok, NULL, 10) - 1];
        }
        text_close(&tr);
        CHECK(n >= 10);
        CHECKF(s.triangle_count == n - 2, "%zu triangles", s.triangle_count);
        points = malloc(3 * s.triangle_count * sizeof *points);
        CHECK(points != NULL);
        for (i = 0; i < s.triangle_count; ++i) {
            points[3 * i] = s.positions[s.triangles[i].v[0]];
            points[3 * i + 1] = s.positions[s.triangles[i].v[1]];
            points[3 * i + 2] = s.positions[s.triangles[i].v[2]];
        }
        problem = check_partition(corners, n, points, s.triangle_count);
        free(points);
        CHECKF(!problem, "%s: %s", files[f], problem);
        scene_free(&s);
    }
}

/* CRLF, tabs, leading/trailing whitespace, blank lines, comments (whole-line and after a
 * statement), a continuation line, a UTF-8 byte-order mark and no final newline. */
TEST(obj_line_format_quirks)
{
    scene s;
    rerror e;
    CHECKF(!load_text(&s, "quirks.obj",
                      "\xEF\xBB\xBF# header\r\n\r\n   \t \r\n  v\t0 0 0  \r\nv 1 0 0 # trailing comment\r\n"
                      "v 0 1 0\r\nv 0 0 1\r\n\tf 1 2 \\\r\n 3\r\nf 1 3 4",
                      &e),
           "%s", e.msg);
    CHECK(s.triangle_count == 2 && tri_is(&s, 0, 0, 1, 2) && tri_is(&s, 1, 0, 2, 3));
    scene_free(&s);
}

/* A face line of 4000 corners (a convex polygon, ~24 kB): no line-length limit, and
 * convex faces triangulate in linear time. */
TEST(obj_very_long_line)
{
    enum { N = 4000 };
    scene s;
    rerror e;
    char *text = malloc((size_t)N * 60), *p = text;
    int i;
    CHECK(text != NULL);
    for (i = 0; i < N; ++i) p += sprintf(p, "v %.9f %.9f 0\n", cos(2 * 3.14159265358979 * i / N), sin(2 * 3.14159265358979 * i / N));
    p += sprintf(p, "f");
    for (i = 1; i <= N; ++i) p += sprintf(p, " %d", i);
    test_write_file("long.obj", text);
    free(text);
    CHECKF(!scene_load(&s, test_tmp_path("long.obj"), &e), "%s", e.msg);
    CHECKF(s.triangle_count == N - 2, "%zu", s.triangle_count);
    scene_free(&s);
}

TEST(obj_object_ids)
{
    scene s;
    rerror e;
    char text[512];
    snprintf(text, sizeof text, "%sf 1 2 3\no wall\nf 1 2 3\ng  front cube \nf 1 3 4\no wall\nf 1 2 4\ng\nf 2 3 4\n",
             unit_square);
    CHECKF(!load_text(&s, "objects.obj", text, &e), "%s", e.msg);
    CHECK(s.object_count == 3);
    CHECK(!strcmp(s.object_names[0], "default") && !strcmp(s.object_names[1], "wall") &&
          !strcmp(s.object_names[2], "front cube"));
    CHECK(s.triangles[0].object == 0 && s.triangles[1].object == 1 && s.triangles[2].object == 2);
    CHECK(s.triangles[3].object == 1 && s.triangles[4].object == 0);
    scene_free(&s);
}

/* mtllib with two files, an escaped space, a whole-line name with spaces; usemtl names
 * with spaces; faces before any usemtl use "default"; an undefined name warns. */
TEST(obj_usemtl_and_mtllib)
{
    scene s;
    rerror e;
    char text[1024];
    const material *m;
    test_write_file("lib a.mtl", "newmtl red paint\nKd 1 0 0\n");
    test_write_file("lib-b.mtl", "newmtl blue\nKd 0 0 1\nnewmtl glow\nKe 2 3 4\n");
    test_write_file("lib c.mtl", "newmtl green\nKd 0 1 0\n");
    snprintf(text, sizeof text,
             "mtllib lib\\ a.mtl lib-b.mtl\nmtllib lib c.mtl\n%sf 1 2 3\nusemtl  red paint \nf 1 2 3\n"
             "usemtl blue\nf 1 3 4\nusemtl glow\nf 1 2 4\nusemtl green\nf 2 3 4\nusemtl nowhere\nf 1 2 3\n",
             unit_square);
    CHECKF(!load_text(&s, "mtl.obj", text, &e), "%s", e.msg);
    CHECK(s.triangle_count == 6);
    CHECK(!strcmp(s.materials[s.triangles[0].material].name, "default"));
    CHECK(!strcmp(s.materials[s.triangles[1].material].name, "red paint"));
    CHECK(!strcmp(s.materials[s.triangles[2].material].name, "blue"));
    CHECK(!strcmp(s.materials[s.triangles[4].material].name, "green"));
    m = find_material(&s, "red paint");
    CHECK(m && m->type == MAT_LAMBERT && m->diffuse.r == 1 && m->diffuse.g == 0);
    CHECK(scene_emitter_count(&s) == 1);
    CHECK(s.warning_count == 1);
    CHECKF(error_at(s.warnings[0], "mtl.obj", 16, "'nowhere' is not defined"), "%s", s.warnings[0]);
    m = find_material(&s, "nowhere");
    CHECK(m && m->type == MAT_LAMBERT && m->diffuse.r == (real)0.8);
    scene_free(&s);
}

/* The MTL -> material mapping of docs/scene-format.md, rule by rule. */
TEST(mtl_mapping_rules)
{
    scene s;
    rerror e;
    const material *m;
    const char *mtl =
        "newmtl matte\nKd 0.5 0.4 0.3\nKs 0 0 0\nillum 2\n"
        "newmtl noshine\nKd 0.5 0.5 0.5\nKs 0.9 0.9 0.9\nillum 1\n"
        "newmtl plastic\nKd 0.5 0.5 0.5\nKs 0.04\nNs 98\nNi 1.45\n"
        "newmtl mirror\nKd 0 0 0\nKs 0.9 0.8 0.7\nNs 1000\nillum 5\n"
        "newmtl glass\nKd 0 0 0\nKs 0.3 0.3 0.3\nTf 0.1 0.1 0.1\nNi 2.5\nillum 7\n"
        "newmtl roughglass\nKd 1 1 1\nPr 0.3\nNi 1.33\nd 0.5\n"
        "newmtl thin\nKd 1 1 1\nd 0.5\n"
        "newmtl metal\nKd 0.9 0.6 0.2\nPm 1\nPr 0.25\n"
        "newmtl pbrplastic\nKd 0.2 0.3 0.4\nPm 0.2\nPr 0.6\n"
        "newmtl blackspec\nKd 0 0 0\nKs 0.5 0.5 0.5\nNs 0\n"
        "newmtl lamp\nKd 0 0 0\nKe 17 12 4\nKa 20 20 20\nmap_Ka -o 1 2 3 tex.png\nmap_bump -bm 2 bump.png\n";
    test_write_file("mapping.mtl", mtl);
    CHECKF(!load_text(&s, "mapping.obj", "mtllib mapping.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &e), "%s", e.msg);
    CHECK((m = find_material(&s, "matte")) && m->type == MAT_LAMBERT && m->diffuse.g == (real)0.4);
    CHECK((m = find_material(&s, "noshine")) && m->type == MAT_LAMBERT);
    CHECK((m = find_material(&s, "plastic")) && m->type == MAT_PLASTIC && m->specular.b == (real)0.04);
    CHECK_NEAR(m->roughness, sqrt(sqrt(2.0 / 100)), 4 * REAL_EPSILON); /* Ns 98: alpha = sqrt(2/100) */
    CHECK_NEAR(m->ior, 1.45, 4 * REAL_EPSILON);
    CHECK((m = find_material(&s, "mirror")) && m->type == MAT_CONDUCTOR && m->roughness == 0 && m->specular.g == (real)0.8);
    CHECK((m = find_material(&s, "glass")) && m->type == MAT_DIELECTRIC && m->ior == (real)2.5 && m->specular.r == 1);
    CHECK((m = find_material(&s, "roughglass")) && m->type == MAT_ROUGH_DIELECTRIC && m->roughness == (real)0.3);
    CHECK_NEAR(m->ior, 1.33, 4 * REAL_EPSILON);
    CHECK((m = find_material(&s, "thin")) && m->type == MAT_LAMBERT); /* d < 1 without Ni: warned, opaque */
    CHECK((m = find_material(&s, "metal")) && m->type == MAT_CONDUCTOR && m->specular.r == (real)0.9 &&
          m->roughness == (real)0.25);
    CHECK((m = find_material(&s, "pbrplastic")) && m->type == MAT_PLASTIC && m->specular.r == 1 &&
          m->roughness == (real)0.6 && m->ior == (real)1.5);
    CHECK((m = find_material(&s, "blackspec")) && m->type == MAT_CONDUCTOR && m->roughness == 1);
    CHECK((m = find_material(&s, "lamp")) && m->type == MAT_LAMBERT && m->emission.g == 12 && m->diffuse.r == 0);
    CHECK(s.warning_count == 1 && strstr(s.warnings[0], "mapping.mtl:30: material 'thin'"));
    scene_free(&s);
}

TEST(mtl_roughness_from_phong_exponent)
{
    CHECK_NEAR(roughness_from_phong_exponent(0), 1, 1e-15);
    /* alpha = sqrt(2 / (Ns + 2)) inverts Ns = 2 / alpha^2 - 2 (Walter et al. 2007). */
    CHECK_NEAR(2 / pow(roughness_from_phong_exponent(200), 4) - 2, 200, 200 * 16 * REAL_EPSILON);
}

/* ---- errors: one line, "file:line: what" ---- */

TEST(obj_error_missing_and_unreadable_file)
{
    scene s;
    rerror e;
    char dir[1024];
    CHECK(scene_load(&s, test_tmp_path("no-such-file.obj"), &e) != 0);
    CHECKF(error_at(e.msg, "no-such-file.obj", 0, "cannot open"), "%s", e.msg);
    /* A directory opens but cannot be read. */
    snprintf(dir, sizeof dir, "%s", test_tmp_path("a-directory.obj"));
    mkdir(dir, 0755);
    CHECK(scene_load(&s, dir, &e) != 0);
    CHECKF(error_at(e.msg, "a-directory.obj", 0, "cannot"), "%s", e.msg);
}

static int load_bad_obj(scene *s, const char *text, rerror *e) { return scene_from_text(s, "bad.obj", text, e); }

TEST(obj_errors_have_file_and_line)
{
    static const bad_line cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 3.1+e2 0 0\n", 3, "malformed number '3.1+e2'"},
        {"v 0 0 0\nv 1 0 0\nv 1..2 0 0\n", 3, "malformed number"},
        {"v 0 0 0\nv 1 0\n", 2, "at least 3 numbers"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0 is invalid"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", 5, "vertex index 4 out of range (3 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", 4, "relative vertex index -4 reaches before the first"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", 4, "normal index 1 out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n", 5, "texture coordinate index 2 out of range"},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "face with 2 vertices"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", 4, "malformed face vertex '3x'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999\n", 4, "index out of range"},
        {"v 0 0 0\nv nan 0 0\n", 2, "not finite 'nan'"},
        {"v 0 0 0\nv 1 -inf 0\n", 2, "not finite '-inf'"},
        {"v 0 0 0\nv 1.#INF 0 0\n", 2, "not finite"},
        {"v 0 0 0\nv 1e39 0 0\n", 2, "out of range '1e39'"},
        {"v 0 0 0\nvn 0 0 nan\n", 2, "not finite"},
        {"v 0 0 0\nfrobnicate 1 2\n", 2, "unknown OBJ statement 'frobnicate'"},
        {"v 0 0 0\nsurf 0 1 0 1 1 2 3\n", 2, "free-form surfaces"},
        {"v 0 0 0\nmtllib missing.mtl\n", 2, "cannot open material library 'missing.mtl'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", 0, "no triangles"},
        {"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", 0, "no triangles"},
        {"# nothing\n", 0, "no triangles"},
    };
    expect_bad_lines(cases, sizeof cases / sizeof cases[0], "bad.obj", load_bad_obj);
}

TEST(obj_encodings)
{
    /* "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" in UTF-16 LE with a BOM, then with a NUL in UTF-8. */
    const char *ascii = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n";
    unsigned char buf[256];
    size_t n = 0, i;
    FILE *f;
    scene s;
    rerror e;
    char path[1024];
    buf[n++] = 0xFF;
    buf[n++] = 0xFE;
    for (i = 0; ascii[i]; ++i) {
        buf[n++] = (unsigned char)ascii[i];
        buf[n++] = 0;
    }
    snprintf(path, sizeof path, "%s", test_tmp_path("utf16.obj"));
    f = fopen(path, "wb");
    CHECK(f && fwrite(buf, 1, n, f) == n);
    fclose(f);
    CHECKF(!scene_load(&s, path, &e), "%s", e.msg);
    CHECK(s.triangle_count == 1);
    scene_free(&s);
    snprintf(path, sizeof path, "%s", test_tmp_path("nul.obj"));
    f = fopen(path, "wb");
    CHECK(f && fwrite("v 0 0 0\nv 1\0 0 0\n", 1, 18, f) == 18);
    fclose(f);
    CHECK(scene_load(&s, path, &e) != 0);
    CHECKF(error_at(e.msg, "nul.obj", 2, "NUL byte"), "%s", e.msg);
}

TEST(obj_missing_mtllib_can_be_allowed)
{
    scene s;
    rerror e;
    scene_load_options opt;
    const char *path = test_write_file("nolib.obj", "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
    char copy[1024];
    snprintf(copy, sizeof copy, "%s", path);
    opt.allow_missing_mtl = 1;
    CHECKF(!scene_load_with_options(&s, copy, &opt, &e), "%s", e.msg);
    CHECK(s.warning_count == 2);
    CHECKF(error_at(s.warnings[0], "nolib.obj", 1, "cannot open material library 'gone.mtl'"), "%s", s.warnings[0]);
    scene_free(&s);
}

/* The text as bad.mtl, loaded through an OBJ that uses it. */
static int load_bad_mtl(scene *s, const char *text, rerror *e)
{
    test_write_file("bad.mtl", text);
    return load_text(s, "usesbad.obj", "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", e);
}

TEST(mtl_errors_have_file_and_line)
{
    static const bad_line cases[] = {
        {"newmtl a\nKd 0.5 0.5\n", 2, "Kd: expected 1 or 3 numbers"},
        {"newmtl a\nKd 1.5 0.5 0.5\n", 2, "outside [0, 1]"},
        {"newmtl a\nKe -1 0 0\n", 2, "outside"},
        {"newmtl a\nNs abc\n", 2, "malformed number 'abc'"},
        {"newmtl a\nd nan\n", 2, "not finite"},
        {"newmtl a\nillum 2.5\n", 2, "illum: expected an integer"},
        {"newmtl a\n\nPr\n", 3, "Pr: missing value"},
        {"Kd 1 1 1\n", 1, "before the first newmtl"},
        {"newmtl a\nKd spectral file.rfl\n", 2, "only RGB"},
        {"newmtl a\nshininess 4\n", 2, "unknown MTL statement 'shininess'"},
    };
    expect_bad_lines(cases, sizeof cases / sizeof cases[0], "bad.mtl", load_bad_mtl);
}

TEST(text_number_grammar)
{
    static const char *good[] = {"0", "-1", "+2.", ".5", "-.7e+2", "1e-05", "3.25E2", "007", NULL};
    static const char *bad[] = {"", "-", ".", "e5", "1e", "1e+", "0x10", "1,5", "1.2.3", "3.1+e2", "--1", NULL};
    const char **p;
    double v;
    float f;
    for (p = good; *p; ++p) CHECKF(text_parse_double(*p, &v) == NUMBER_OK, "'%s'", *p);
    for (p = bad; *p; ++p) CHECKF(text_parse_double(*p, &v) == NUMBER_MALFORMED, "'%s'", *p);
    CHECK(text_parse_double("-.7e+2", &v) == NUMBER_OK && v == -70);
    CHECK(text_parse_float("0.1", &f) == NUMBER_OK && f == 0.1f); /* correctly rounded */
    CHECK(text_parse_float("NaN", &f) == NUMBER_NOT_FINITE);
    CHECK(text_parse_float("1e39", &f) == NUMBER_OUT_OF_RANGE);
}

/* Linear-time loading: a generated grid of about one million triangles. */
TEST_LONG(obj_million_triangles)
{
    enum { N = 708 }; /* 2 (N-1)^2 = 999,698 triangles */
    char path[1024];
    FILE *f;
    int i, j;
    scene s;
    rerror e;
    double t0;
    snprintf(path, sizeof path, "%s", test_tmp_path("million.obj"));
    f = fopen(path, "wb");
    CHECK(f != NULL);
    for (j = 0; j < N; ++j)
        for (i = 0; i < N; ++i) fprintf(f, "v %.6f %.6f %.6f\n", i / (double)N, 0.01 * sin(i * 0.1 + j * 0.2), j / (double)N);
    fprintf(f, "vn 0 1 0\n");
    for (j = 0; j + 1 < N; ++j)
        for (i = 0; i + 1 < N; ++i) {
            int a = j * N + i + 1, b = a + 1, c = a + N + 1, d = a + N;
            fprintf(f, "f %d//1 %d//1 %d//1\nf %d//1 %d//1 %d//1\n", a, d, c, a, c, b);
        }
    fclose(f);
    t0 = now_seconds();
    CHECKF(!scene_load(&s, path, &e), "%s", e.msg);
    printf("    loaded %zu triangles, %zu vertices in %.2f s\n", s.triangle_count, s.position_count,
           now_seconds() - t0);
    CHECK(s.triangle_count == 2 * (size_t)(N - 1) * (N - 1));
    scene_free(&s);
    remove(path);
}

/* Warnings are capped; the last one counts the rest. A library named twice is read
 * once; a name defined by two libraries keeps the first definition (one warning). */
TEST(obj_warning_cap_and_redefinitions)
{
    scene s, empty;
    rerror e;
    char *text = malloc(20000), *p = text;
    int i;
    CHECK(text != NULL);
    test_write_file("one.mtl", "newmtl shared\nKd 0.1 0.1 0.1\n");
    test_write_file("two.mtl", "newmtl shared\nKd 0.9 0.9 0.9\n");
    p += sprintf(p, "mtllib one.mtl\nmtllib one.mtl two.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shared\nf 1 2 3\n");
    for (i = 0; i < 150; ++i) p += sprintf(p, "usemtl undefined%d\nf 1 2 3\n", i);
    test_write_file("many.obj", text);
    free(text);
    CHECKF(!scene_load(&s, test_tmp_path("many.obj"), &e), "%s", e.msg);
    CHECK(s.warning_count == SCENE_MAX_WARNINGS);
    CHECKF(strstr(s.warnings[0], "two.mtl:1: material 'shared' defined again"), "%s", s.warnings[0]);
    CHECKF(strstr(s.warnings[SCENE_MAX_WARNINGS - 1], "and 52 more warnings"), "%s", s.warnings[SCENE_MAX_WARNINGS - 1]);
    CHECK(s.materials[s.triangles[0].material].diffuse.r == (real)0.1);
    scene_free(&s);
    memset(&empty, 0, sizeof empty);
    scene_free(&empty); /* freeing a zeroed scene is harmless */
}
