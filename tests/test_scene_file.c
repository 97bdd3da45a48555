/* The scene file: directives, keyframe interpolation, material lines, bare OBJ framing,
 * the shipped Cornell scenes, every error with its "file:line:" prefix, and (test-long)
 * every OBJ of ../shared/data against tests/data-expectations.txt. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/render/camera.h"
#include "restir/scene/scene.h"
#include "scene_text_util.h"
#include "test.h"

static const char *tiny_obj = "mtllib tiny.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                              "usemtl white\nf 1 2 3\nusemtl glow\nf 1 3 4\nusemtl nomtl\nf 1 2 4\n";
static const char *tiny_mtl = "newmtl white\nKd 0.7 0.7 0.7\nnewmtl glow\nKd 0 0 0\nKe 5 5 5\n";

static int load_scene_text(scene *s, const char *text, rerror *e)
{
    test_write_file("tiny.obj", tiny_obj);
    test_write_file("tiny.mtl", tiny_mtl);
    return scene_from_text(s, "t.scene", text, e);
}

TEST(scene_file_directives)
{
    scene s;
    rerror e;
    CHECKF(!load_scene_text(&s,
                            "# a comment\n\nmesh tiny.obj   # trailing comment\n"
                            "camera fov 50 up 0 1 0 eye 1 2 3 target 0 0.5 0\nsize 40 30\n",
                            &e),
           "%s", e.msg);
    CHECK(s.triangle_count == 3 && s.has_camera && s.width == 40 && s.height == 30);
    CHECK(s.camera.eye.x == 1 && s.camera.eye.z == 3 && s.camera.target.y == (real)0.5 && s.camera.fov_y_degrees == 50);
    CHECK(s.keyframe_count == 0);
    CHECK(scene_emitter_count(&s) == 1);
    CHECK(strstr(s.path, "t.scene") != NULL);
    /* usemtl nomtl: no library defines it, so the default and one warning. */
    CHECK(s.warning_count == 1 && strstr(s.warnings[0], "tiny.obj:10: material 'nomtl'"));
    scene_free(&s);
}

TEST(scene_file_defaults_and_quotes)
{
    scene s;
    rerror e;
    test_write_file("with space.obj", tiny_obj);
    CHECKF(!load_scene_text(&s, "mesh \"with space.obj\"\nmaterial \"nomtl\" kd 0.1 0.2 0.3\n", &e), "%s", e.msg);
    CHECK(s.width == 512 && s.height == 512 && !s.has_camera);
    CHECK(s.warning_count == 0); /* the material line defines nomtl */
    CHECK(find_material(&s, "nomtl")->diffuse.b == (real)0.3);
    scene_free(&s);
}

/* Material lines change only the fields they name, define materials no library has,
 * and apply after the meshes even when written first. */
TEST(scene_file_material_overrides)
{
    scene s;
    rerror e;
    const material *m;
    CHECKF(!load_scene_text(&s,
                            "material white type plastic ks 0.5 0.5 0.5 roughness 0.25 ior 1.4\n"
                            "mesh tiny.obj\nmaterial glow ke 1 2 3\nmaterial glow type lambert\n"
                            "material extra type rough-dielectric roughness 0.1 ior 1.33\n",
                            &e),
           "%s", e.msg);
    m = find_material(&s, "white");
    CHECK(m && m->type == MAT_PLASTIC && m->diffuse.r == (real)0.7 && m->specular.g == (real)0.5);
    CHECK(m->roughness == (real)0.25 && m->ior == (real)1.4);
    m = find_material(&s, "glow");
    CHECK(m && m->type == MAT_LAMBERT && m->emission.r == 1 && m->emission.b == 3);
    m = find_material(&s, "extra");
    CHECK(m && m->type == MAT_ROUGH_DIELECTRIC && m->roughness == (real)0.1);
    scene_free(&s);
}

static int pose_near(camera_pose a, camera_pose b, double tol)
{
    return fabs((double)(a.eye.x - b.eye.x)) <= tol && fabs((double)(a.eye.y - b.eye.y)) <= tol &&
           fabs((double)(a.eye.z - b.eye.z)) <= tol && fabs((double)(a.target.x - b.target.x)) <= tol &&
           fabs((double)(a.target.y - b.target.y)) <= tol && fabs((double)(a.up.x - b.up.x)) <= tol &&
           fabs((double)(a.fov_y_degrees - b.fov_y_degrees)) <= tol;
}

/* Linear between keyframes, clamped outside. */
TEST(scene_file_keyframes)
{
    scene s;
    rerror e;
    camera_pose p;
    CHECKF(!load_scene_text(&s,
                            "mesh tiny.obj\nkeyframe 0 eye 0 0 5 target 0 0 0 up 0 1 0 fov 40\n"
                            "keyframe 10 eye 10 0 5 target 2 0 0 up 0 1 0 fov 60\n"
                            "keyframe 12 eye 10 4 5 target 2 0 0 up 1 1 0 fov 60\n",
                            &e),
           "%s", e.msg);
    CHECK(s.keyframe_count == 3 && s.has_camera);
    CHECK(pose_near(s.camera, s.keyframes[0].pose, 0));
    CHECK(pose_near(scene_camera_at(&s, -5), s.keyframes[0].pose, 0));
    CHECK(pose_near(scene_camera_at(&s, 0), s.keyframes[0].pose, 0));
    CHECK(pose_near(scene_camera_at(&s, 10), s.keyframes[1].pose, 0));
    CHECK(pose_near(scene_camera_at(&s, 99), s.keyframes[2].pose, 0));
    p = scene_camera_at(&s, 3);
    CHECK_NEAR(p.eye.x, 3, 8 * REAL_EPSILON);
    CHECK_NEAR(p.target.x, 0.6, 8 * REAL_EPSILON);
    CHECK_NEAR(p.fov_y_degrees, 46, 64 * REAL_EPSILON);
    p = scene_camera_at(&s, 11);
    CHECK_NEAR(p.eye.y, 2, 8 * REAL_EPSILON);
    CHECK_NEAR(p.up.x, 0.5, 8 * REAL_EPSILON);
    scene_free(&s);
    /* Without keyframes every frame sees the static camera. */
    CHECK(!load_scene_text(&s, "mesh tiny.obj\ncamera eye 0 0 5 target 0 0 0 up 0 1 0 fov 40\n", &e));
    CHECK(pose_near(scene_camera_at(&s, 7), s.camera, 0));
    scene_free(&s);
}

/* A bare OBJ: 512 x 512, no camera, framed so the whole bounding box is in view. */
TEST(scene_bare_obj_framing)
{
    scene s;
    rerror e;
    camera c;
    int corner;
    char path[1024];
    snprintf(path, sizeof path, "%s",
             test_write_file("framed.obj", "v -3 10 2\nv 5 10 2\nv 5 14 -7\nv -3 11 -7\nf 1 2 3 4\n"));
    CHECKF(!scene_load(&s, path, &e), "%s", e.msg);
    CHECK(!s.has_camera && s.width == 512 && s.height == 512 && s.keyframe_count == 0);
    CHECK(s.camera.up.y == 1 && s.camera.fov_y_degrees == 40 && s.camera.eye.z > s.camera.target.z);
    CHECK_NEAR(s.camera.target.x, 1, 1e-6);
    camera_init(&c, s.camera, s.width, s.height);
    for (corner = 0; corner < 8; ++corner) {
        vec3 p = v3(corner & 1 ? 5 : -3, corner & 2 ? 14 : 10, corner & 4 ? 2 : -7);
        real px, py;
        CHECK(camera_project(&c, p, &px, &py));
        CHECKF(px > 0 && px < 512 && py > 0 && py < 512, "corner %d at (%g, %g)", corner, (double)px, (double)py);
    }
    scene_free(&s);
}

/* The shipped scenes: the published Cornell geometry, fronts facing the right way. */
TEST(scene_cornell_box)
{
    const char *files[] = {"scenes/cornell.scene", "scenes/cornell-glossy.scene"};
    const real box_roughness[] = {(real)0.5, (real)0.15};
    vec3f room_centre = v3f(278, 274.4f, 279.6f);
    int f;
    for (f = 0; f < 2; ++f) {
        scene s;
        rerror e;
        size_t i;
        const material *box;
        CHECKF(!scene_load(&s, files[f], &e), "%s", e.msg);
        CHECK(s.warning_count == 0 && s.object_count == 8 && s.triangle_count == 32);
        CHECK(scene_emitter_count(&s) == 2);
        CHECK(s.has_camera && s.camera.eye.z == -800 && s.camera.target.x == 278);
        CHECK_NEAR(s.camera.fov_y_degrees, 39.3076481, 40 * REAL_EPSILON);
        box = find_material(&s, "box");
        CHECK(box && box->type == MAT_PLASTIC && box->roughness == box_roughness[f] && box->ior == (real)1.5);
        CHECK(find_material(&s, "white")->type == MAT_LAMBERT && find_material(&s, "light")->emission.r == 17);
        for (i = 0; i < s.triangle_count; ++i) {
            const triangle *t = &s.triangles[i];
            vec3f p0 = s.positions[t->v[0]], p1 = s.positions[t->v[1]], p2 = s.positions[t->v[2]];
            vec3f n = v3f_normalize(v3f_cross(v3f_sub(p1, p0), v3f_sub(p2, p0)));
            vec3f centroid = v3f_scale(v3f_add(v3f_add(p0, p1), p2), 1.0f / 3);
            const char *object = s.object_names[t->object];
            if (!strcmp(object, "light")) {
                CHECK(n.y < -0.999f && p0.y < 548.8f && p0.y > 548.6f);
            } else if (strstr(object, "block")) {
                /* Outward: away from the block's vertical axis through its footprint centre. */
                vec3f axis = !strcmp(object, "short_block") ? v3f(186, centroid.y, 168.5f) : v3f(368.5f, centroid.y, 351.5f);
                if (n.y > 0.99f) CHECK(centroid.y > 100);
                else CHECKF(v3f_dot(n, v3f_sub(centroid, axis)) > 0, "%s triangle %zu faces inward", object, i);
            } else {
                CHECKF(v3f_dot(n, v3f_sub(room_centre, centroid)) > 0, "%s triangle %zu faces outward", object, i);
            }
        }
        scene_free(&s);
    }
}

TEST(scene_test_data_quad_light)
{
    scene s;
    rerror e;
    CHECKF(!scene_load(&s, "tests/data/quad-light.scene", &e), "%s", e.msg);
    CHECK(s.triangle_count == 5 && scene_emitter_count(&s) == 2 && s.width == 64 && s.height == 48);
    CHECK(s.keyframe_count == 2 && s.warning_count == 0);
    CHECK(find_material(&s, "blocker")->type == MAT_PLASTIC && find_material(&s, "blocker")->roughness == (real)0.5);
    scene_free(&s);
}

TEST(scene_file_errors_have_file_and_line)
{
    static const bad_line cases[] = {
        {"mesh tiny.obj\nfrobnicate 3\n", 2, "unknown directive 'frobnicate'"},
        {"mesh tiny.obj\nsize 40 x30\n", 2, "malformed number 'x30'"},
        {"mesh tiny.obj\nsize 40\n", 2, "size: expected an integer"},
        {"mesh tiny.obj\nsize 0 10\n", 2, "outside [1, 65536]"},
        {"mesh tiny.obj\nsize 10 10 10\n", 2, "unexpected '10'"},
        {"mesh tiny.obj\nsize 10 10\nsize 10 10\n", 3, "size given twice (first on line 2)"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 0 up 0 1 0\n", 2, "missing 'fov'"},
        {"mesh tiny.obj\ncamera eye 0 0 target 0 0 0 up 0 1 0 fov 40\n", 2, "malformed number 'target'"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 0 up 0 1 0 fov nan\n", 2, "not finite 'nan'"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 0 up 0 1 0 fov inf\n", 2, "not finite 'inf'"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 0 up 0 1 0 fov 180\n", 2, "outside (0, 180)"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 1 up 0 1 0 fov 40\n", 2, "same point"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 0 up 0 0 2 fov 40\n", 2, "parallel"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 0 up 0 1 0 fov 40 zoom 2\n", 2, "unknown key 'zoom'"},
        {"mesh tiny.obj\ncamera eye 0 0 1 eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\n", 2, "'eye' given twice"},
        {"mesh tiny.obj\n\ncamera eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\ncamera eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\n",
         4, "camera given twice (first on line 3)"},
        {"mesh tiny.obj\ncamera eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\nkeyframe 0 eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\n",
         3, "cannot be mixed"},
        {"mesh tiny.obj\nkeyframe 5 eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\nkeyframe 5 eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\n",
         3, "frames must increase"},
        {"mesh tiny.obj\nkeyframe 1.5 eye 0 0 1 target 0 0 0 up 0 1 0 fov 40\n", 2, "expected an integer"},
        {"mesh tiny.obj\nmaterial white type velvet\n", 2, "unknown 'velvet'"},
        {"mesh tiny.obj\nmaterial white kd 0.5 0.5\n", 2, "kd: expected 3 numbers"},
        {"mesh tiny.obj\nmaterial white kd 0.5 0.5 2\n", 2, "outside [0, 1]"},
        {"mesh tiny.obj\nmaterial white roughness 1.5\n", 2, "outside [0, 1]"},
        {"mesh tiny.obj\nmaterial white ior 0\n", 2, "outside (0, inf)"},
        {"mesh tiny.obj\nmaterial white shine 3\n", 2, "unknown key 'shine'"},
        {"mesh tiny.obj\nmaterial\n", 2, "missing name"},
        {"mesh \"tiny.obj\nsize 1 1\n", 1, "unterminated"},
        {"mesh\n", 1, "missing file name"},
        {"# empty\nsize 10 10\n", 0, "no mesh directive"},
        {"size 10 10\n\nmesh nowhere.obj\n", 3, "cannot open mesh"},
    };
    expect_bad_lines(cases, sizeof cases / sizeof cases[0], "t.scene", load_scene_text);
}

/* An error inside a mesh names the OBJ file and its line, not the scene file. */
TEST(scene_file_mesh_errors_point_into_the_obj)
{
    scene s;
    rerror e;
    char expect[1100];
    test_write_file("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");
    CHECK(load_scene_text(&s, "mesh broken.obj\n", &e) != 0);
    snprintf(expect, sizeof expect, "%s:4: vertex index 0", test_tmp_path("broken.obj"));
    CHECKF(!strncmp(e.msg, expect, strlen(expect)), "%s", e.msg);
}

/* ---- every OBJ of the shared data, against the expectation table ---- */

#define SHARED_DATA "../shared/data"
#define EXPECTATIONS "tests/data-expectations.txt"

typedef struct {
    char path[512];
    int loads;
    char message[256];
    int seen;
} expectation;

static size_t read_expectations(expectation *table, size_t max)
{
    FILE *f = fopen(EXPECTATIONS, "r");
    char line[1024];
    size_t n = 0;
    if (!f) return 0;
    while (fgets(line, sizeof line, f) && n < max) {
        char *path = line, *kind, *message;
        size_t len = strlen(line);
        while (len && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = '\0';
        if (!line[0] || line[0] == '#') continue;
        kind = strchr(path, '\t');
        if (!kind) continue;
        *kind++ = '\0';
        message = strchr(kind, '\t');
        if (message) *message++ = '\0';
        snprintf(table[n].path, sizeof table[n].path, "%s", path);
        table[n].loads = !strcmp(kind, "loads");
        snprintf(table[n].message, sizeof table[n].message, "%s", message ? message : "");
        table[n].seen = 0;
        n++;
    }
    fclose(f);
    return n;
}

static size_t find_objs(const char *dir, char (*out)[512], size_t n, size_t max)
{
    DIR *d = opendir(dir);
    struct dirent *entry;
    if (!d) return n;
    while ((entry = readdir(d)) != NULL && n < max) {
        char path[512];
        struct stat st;
        size_t len = strlen(entry->d_name);
        if (entry->d_name[0] == '.') continue;
        snprintf(path, sizeof path, "%s/%s", dir, entry->d_name);
        if (stat(path, &st)) continue;
        if (S_ISDIR(st.st_mode)) n = find_objs(path, out, n, max);
        else if (len > 4 && !strcmp(entry->d_name + len - 4, ".obj")) snprintf(out[n++], 512, "%s", path);
    }
    closedir(d);
    return n;
}

/* Every OBJ either loads (triangles > 0, indices in range, finite positions, known
 * materials and objects) or is rejected with one "path:line: ..." or "path: ..." line
 * containing the expected text. New files must be added to the table. */
TEST_LONG(shared_data_loads)
{
    static expectation table[256];
    static char files[256][512];
    size_t n_table, n_files, i, j, loaded = 0, rejected = 0;
    struct stat st;
    if (stat(SHARED_DATA, &st)) {
        printf("    %s absent: skipped\n", SHARED_DATA);
        return;
    }
    n_table = read_expectations(table, 256);
    CHECKF(n_table > 0, "cannot read %s", EXPECTATIONS);
    n_files = find_objs(SHARED_DATA, files, 0, 256);
    for (i = 0; i < n_files; ++i) {
        const char *rel = files[i] + strlen(SHARED_DATA) + 1;
        expectation *x = NULL;
        scene s;
        rerror e;
        int status;
        for (j = 0; j < n_table; ++j)
            if (!strcmp(table[j].path, rel)) x = &table[j];
        CHECKF(x != NULL, "%s is not in %s", rel, EXPECTATIONS);
        x->seen = 1;
        status = scene_load(&s, files[i], &e);
        if (!status) {
            size_t t;
            int k;
            CHECKF(x->loads, "%s loaded but is expected to be rejected (%s)", rel, x->message);
            CHECK(s.triangle_count > 0);
            for (t = 0; t < s.triangle_count; ++t) {
                const triangle *tr = &s.triangles[t];
                CHECK(tr->material < s.material_count && tr->object < s.object_count);
                for (k = 0; k < 3; ++k) {
                    CHECK(tr->v[k] < s.position_count);
                    CHECK(tr->n[k] < (int32_t)s.normal_count);
                }
            }
            for (t = 0; t < s.position_count; ++t)
                CHECK(isfinite(s.positions[t].x) && isfinite(s.positions[t].y) && isfinite(s.positions[t].z));
            loaded++;
            scene_free(&s);
        } else {
            size_t len = strlen(files[i]);
            const char *mtl_at;
            CHECKF(!x->loads, "%s rejected: %s", rel, e.msg);
            /* the error is at a line of the OBJ, or of one of its MTL files (a map statement) */
            mtl_at = strstr(e.msg, ".mtl:");
            CHECKF(((!strncmp(e.msg, files[i], len) && e.msg[len] == ':') ||
                    (mtl_at && !memchr(e.msg, ' ', (size_t)(mtl_at - e.msg)))) &&
                       !strchr(e.msg, '\n'),
                   "%s: message '%s'", rel, e.msg);
            CHECKF(strstr(e.msg, x->message) != NULL, "%s: message '%s' lacks '%s'", rel, e.msg, x->message);
            rejected++;
        }
    }
    for (j = 0; j < n_table; ++j) CHECKF(table[j].seen, "%s in the table but not in %s", table[j].path, SHARED_DATA);
    /* The fuzzer regression has no .obj name: read it as one (a NUL byte: rejected). */
    {
        FILE *in = fopen(SHARED_DATA "/tinyobjloader/fuzzer/regressions/"
                                     "clusterfuzz-testcase-minimized-fuzz_ParseFromString-4877060179886080",
                         "rb");
        char buf[4096], path[1024];
        size_t n = in ? fread(buf, 1, sizeof buf, in) : 0;
        FILE *out;
        scene s;
        rerror e;
        if (in) {
            fclose(in);
            snprintf(path, sizeof path, "%s", test_tmp_path("fuzz.obj"));
            out = fopen(path, "wb");
            CHECK(out && fwrite(buf, 1, n, out) == n);
            fclose(out);
            CHECK(scene_load(&s, path, &e) != 0);
            CHECKF(strstr(e.msg, "fuzz.obj:1: NUL byte") != NULL, "%s", e.msg);
        }
    }
    printf("    %zu OBJ files: %zu load, %zu rejected as expected\n", n_files, loaded, rejected);
}
