/* Rigid per-object animation (restir/scene/animation.h): the `animate` directive, keyframe
 * interpolation (translation linear, rotation slerp = linear angle about one axis,
 * clamping), posing the scene, vertices shared with a static object, deep copies, frame
 * ranges and every load error with its file:line. */
#include <stdio.h>
#include <string.h>
#include "restir/scene/animation.h"
#include "restir/scene/generate_rooms.h"
#include "restir/scene/scene.h"
#include "scene_text_util.h"
#include "test.h"
#include "text_util.h"
#include "restir/scene/scene_trace.h"

/* Two unit squares sharing an edge: "left" (x in [0,1]) and "right" (x in [1,2]), both in
 * z = 0 facing +z, plus a light above; the shared edge has shared vertices and normals. */
static const char *pair_obj = "mtllib pair.mtl\n"
                              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                              "v 0 0 3\nv 1 0 3\nv 1 1 3\n"
                              "vn 0 0 1\n"
                              "o left\nusemtl white\nf 1//1 2//1 3//1 4//1\n"
                              "o right\nusemtl white\nf 2//1 5//1 6//1 3//1\n"
                              "o light\nusemtl glow\nf 9 8 7\n";
static const char *pair_mtl = "newmtl white\nKd 0.7 0.7 0.7\nnewmtl glow\nKd 0 0 0\nKe 5 5 5\n";

static int load_pair(scene *s, const char *animation, rerror *e)
{
    char text[2048];
    test_write_file("pair.obj", pair_obj);
    test_write_file("pair.mtl", pair_mtl);
    snprintf(text, sizeof text, "mesh pair.obj\ncamera eye 1 0.5 5 target 1 0.5 0 up 0 1 0 fov 40\nsize 16 16\n%s",
             animation);
    return scene_from_text(s, "pair.scene", text, e);
}

static uint32_t object_id(const scene *s, const char *name)
{
    uint32_t i;
    for (i = 0; i < s->object_count; ++i)
        if (!strcmp(s->object_names[i], name)) return i;
    return UINT32_MAX;
}

static vec3 apply(rigid_transform r, vec3 p)
{
    return v3(r.m[0][0] * p.x + r.m[0][1] * p.y + r.m[0][2] * p.z + r.t.x,
              r.m[1][0] * p.x + r.m[1][1] * p.y + r.m[1][2] * p.z + r.t.y,
              r.m[2][0] * p.x + r.m[2][1] * p.y + r.m[2][2] * p.z + r.t.z);
}

TEST(animation_keyframes_interpolate_and_clamp)
{
    scene s;
    rerror e;
    uint32_t right;
    rigid_transform r;
    vec3 p;
    int first = 0, last = 0;
    /* "right" swings about the shared edge (pivot (1,0,0), axis y) from 0 to 200 degrees
     * (more than 180: slerp without the shorter-arc flip stays linear in the angle) while
     * moving 2 up. */
    CHECKF(!load_pair(&s,
                      "animate right 10 pivot 1 0 0\n"
                      "animate right 20 rotate 0 1 0 200 translate 0 2 0\n",
                      &e),
           "%s", e.msg);
    CHECK(scene_is_animated(&s) && scene_animated_object_count(&s) == 1);
    right = object_id(&s, "right");
    CHECK(right != UINT32_MAX);
    CHECK(!scene_frame_range(&s, &first, &last) && first == 10 && last == 20);
    /* Clamped before the first keyframe: identity. */
    r = scene_object_transform_at(&s, right, -5);
    p = apply(r, v3(2, 1, 0));
    CHECK_NEAR(p.x, 2, 1e-6);
    CHECK_NEAR(p.y, 1, 1e-6);
    CHECK_NEAR(p.z, 0, 1e-6);
    /* Frame 15: half-way, 100 degrees about y through (1, *, 0), 1 up. */
    r = scene_object_transform_at(&s, right, 15);
    p = apply(r, v3(2, 1, 0));
    CHECK_NEAR(p.x, 1 + cos(100 * PI_R / 180), 1e-6);
    CHECK_NEAR(p.y, 2, 1e-6);
    CHECK_NEAR(p.z, -sin(100 * PI_R / 180), 1e-6);
    /* Frame 12: 40 degrees. */
    p = apply(scene_object_transform_at(&s, right, 12), v3(2, 0, 0));
    CHECK_NEAR(p.x, 1 + cos(40 * PI_R / 180), 1e-6);
    CHECK_NEAR(p.z, -sin(40 * PI_R / 180), 1e-6);
    CHECK_NEAR(p.y, 0.4, 1e-6);
    /* Clamped after the last: 200 degrees. */
    p = apply(scene_object_transform_at(&s, right, 99), v3(2, 0, 0));
    CHECK_NEAR(p.x, 1 + cos(200 * PI_R / 180), 1e-6);
    CHECK_NEAR(p.z, -sin(200 * PI_R / 180), 1e-6);
    /* Static objects: the identity. */
    p = apply(scene_object_transform_at(&s, object_id(&s, "left"), 15), v3(0.5, 0.5, 0));
    CHECK(p.x == (real)0.5 && p.y == (real)0.5 && p.z == 0);
    scene_free(&s);
}

TEST(animation_pose_moves_only_the_object_and_its_copies)
{
    scene s, c;
    rerror e;
    uint32_t left, right;
    size_t i;
    surface_hit h;
    ray r;
    CHECKF(!load_pair(&s, "animate right 0\nanimate right 4 translate 0 0 -2 rotate 1 0 0 90 pivot 1.5 0.5 0\n", &e),
           "%s", e.msg);
    left = object_id(&s, "left");
    right = object_id(&s, "right");
    /* The shared edge's two positions and the shared normal were copied for "right". */
    CHECK(s.position_count == 9 + 2 && s.normal_count == 2);
    CHECKF(!scene_pose_at(&s, 2, &e), "%s", e.msg);
    for (i = 0; i < s.triangle_count; ++i) {
        const triangle *t = &s.triangles[i];
        int k;
        for (k = 0; k < 3; ++k) {
            vec3f p = s.positions[t->v[k]];
            if (t->object == left) CHECK(p.z == 0 && p.x <= 1); /* unmoved */
            if (t->object == right) {
                /* 45 degrees about x through (1.5, 0.5, 0), then 1 back: y - 0.5 = (y0 - 0.5) cos 45. */
                CHECK_NEAR(p.z, -1 + ((p.y - 0.5) > 0 ? 1 : -1) * 0.5 * sin(PI_R / 4), 1e-5);
                CHECK_NEAR(fabs(p.y - 0.5), 0.5 * cos(PI_R / 4), 1e-5);
                CHECK_NEAR(s.normals[t->n[k]].y, -sin(PI_R / 4), 1e-6);
                CHECK_NEAR(s.normals[t->n[k]].z, cos(PI_R / 4), 1e-6);
            }
        }
    }
    /* The BVH follows: a ray down the z axis through (1.5, 0.5) hits "right" at z = -1. */
    r.origin = v3f(1.5f, 0.5f, 5);
    r.dir = v3f(0, 0, -1);
    r.tmin = 0;
    r.tmax = INFINITY;
    CHECK(scene_intersect(&s, &r, &h) && h.object == right);
    CHECK_NEAR(h.position.z, -1, 1e-5);
    /* A clone is independent and identical (BVH included). */
    CHECKF(!scene_clone(&c, &s, &e), "%s", e.msg);
    CHECK(c.position_count == s.position_count && !memcmp(c.positions, s.positions, s.position_count * sizeof(vec3f)));
    CHECK(scene_intersect(&c, &r, &h) && h.object == right);
    CHECKF(!scene_pose_at(&c, 0, &e), "%s", e.msg);
    CHECK(scene_intersect(&c, &r, &h) && h.object == right && h.position.z == 0);
    CHECK(scene_intersect(&s, &r, &h) && fabsf(h.position.z + 1) < 1e-5f);
    /* Posing is from the rest pose: frame 2 again gives the same bits. */
    CHECKF(!scene_pose_at(&c, 2, &e), "%s", e.msg);
    CHECK(!memcmp(c.positions, s.positions, s.position_count * sizeof(vec3f)));
    CHECK(!memcmp(c.normals, s.normals, s.normal_count * sizeof(vec3f)));
    scene_free(&c);
    scene_free(&s);
}

TEST(animation_static_scene_untouched)
{
    scene s;
    rerror e;
    int first = 7, last = 8;
    CHECKF(!load_pair(&s, "", &e), "%s", e.msg);
    CHECK(!scene_is_animated(&s) && scene_frame_range(&s, &first, &last) == -1 && first == 7 && last == 8);
    CHECK(s.position_count == 9);
    CHECK(scene_pose_at(&s, 3, &e) == 0);
    scene_free(&s);
}

/* Every bad animate line: file:line and what is wrong. */
TEST(animation_load_errors_name_the_line)
{
    static const bad_input cases[] = {
        {"animate right 5\nanimate right 5 translate 1 0 0\n", "pair.scene:5: animate 'right': frame 5 after frame 5"},
        {"animate right 5\nanimate left 1\nanimate right 2\n", "pair.scene:6: animate 'right': frame 2 after frame 5"},
        {"animate nobody 0\n", "pair.scene:4: animate: no object named 'nobody'"},
        {"animate light 0 translate 0 1 0\n", "pair.scene:4: animate: object 'light' contains an emitter"},
        {"animate right 0 rotate 0 0 0 10\n", "pair.scene:4: animate: rotate: the axis is zero"},
        {"animate right 0 rotate 0 1 0\n", "pair.scene:4: rotate: expected 4 numbers"},
        {"animate right 0 translate 1 x 0\n", "pair.scene:4: translate:"},
        {"animate right 0 spin 3\n", "pair.scene:4: animate: unknown key 'spin'"},
        {"animate right 0 translate 1 0 0 translate 1 0 0\n", "pair.scene:4: animate: 'translate' given twice"},
        {"animate right\n", "pair.scene:4: animate: expected an integer"},
        {"animate right 1.5\n", "pair.scene:4: animate:"},
        {"animate\n", "pair.scene:4: animate: missing object name"},
        {"animate right 0 pivot 0 0 0\nanimate right 1 pivot 1 0 0\n", "pair.scene:5: animate 'right': pivot differs"},
        {"animate right 0\nanimate right 1 rotate 0 1 0 360\n", "pair.scene:4: animate: object 'right': keyframes 0 and 1"},
        {"animate right 0 translate 1 0 nan\n", "pair.scene:4: translate: "},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        scene s;
        rerror e;
        const char *msg;
        CHECKF(load_pair(&s, cases[i].input, &e) != 0, "case %zu loaded", i);
        msg = strstr(e.msg, "pair.scene:");
        CHECKF(msg && !strncmp(msg, cases[i].expect, strlen(cases[i].expect)), "case %zu: '%s' does not start with '%s'",
               i, e.msg, cases[i].expect);
    }
}

/* scenes/{pillars,shadow,ajar-swing,ajar-swing-still}.* are what `restir generate` writes:
 * same triangles, camera keyframes and object animation as the generators' scenes. */
static int same_animation(const scene *a, const scene *b, char *why, size_t n)
{
    size_t i, j, ca, cb;
    if (a->triangle_count != b->triangle_count || a->keyframe_count != b->keyframe_count ||
        scene_animated_object_count(a) != scene_animated_object_count(b))
        return snprintf(why, n, "counts differ"), 0;
    for (i = 0; i < a->triangle_count; ++i)
        for (j = 0; j < 3; ++j) {
            vec3f p = a->positions[a->triangles[i].v[j]], q = b->positions[b->triangles[i].v[j]];
            if (fabsf(p.x - q.x) + fabsf(p.y - q.y) + fabsf(p.z - q.z) > 1e-5f)
                return snprintf(why, n, "triangle %zu differs", i), 0;
        }
    for (i = 0; i < a->keyframe_count; ++i)
        if (a->keyframes[i].frame != b->keyframes[i].frame ||
            fabs(a->keyframes[i].pose.eye.x - b->keyframes[i].pose.eye.x) > 1e-9)
            return snprintf(why, n, "camera keyframe %zu differs", i), 0;
    for (i = 0; i < scene_animated_object_count(a); ++i) {
        uint32_t oa, ob;
        vec3 pa, pb;
        const object_keyframe *ka = scene_animated_object(a, i, &oa, &pa, &ca);
        const object_keyframe *kb = scene_animated_object(b, i, &ob, &pb, &cb);
        if (strcmp(a->object_names[oa], b->object_names[ob]) || ca != cb || fabs(pa.x - pb.x) + fabs(pa.z - pb.z) > 1e-9)
            return snprintf(why, n, "animated object %zu differs", i), 0;
        for (j = 0; j < ca; ++j)
            if (ka[j].frame != kb[j].frame || fabs(ka[j].angle_degrees - kb[j].angle_degrees) > 1e-9 ||
                fabs(ka[j].translate.x - kb[j].translate.x) > 1e-9)
                return snprintf(why, n, "object keyframe %zu differs", j), 0;
    }
    return 1;
}

TEST(animation_shipped_scenes_are_the_generated_ones)
{
    static const char *const files[] = {"scenes/pillars.scene", "scenes/shadow.scene", "scenes/ajar-swing.scene",
                                        "scenes/ajar-swing-still.scene"};
    int i;
    for (i = 0; i < 4; ++i) {
        scene g, f;
        rerror e;
        char why[256];
        int status = i == 0 ? generate_pillars(&g, &e) : i == 1 ? generate_shadow(&g, &e) : generate_ajar_swing(&g, i == 3, &e);
        CHECKF(!status, "%s", e.msg);
        CHECKF(!scene_load(&f, files[i], &e), "%s", e.msg);
        CHECKF(same_animation(&g, &f, why, sizeof why), "%s: %s", files[i], why);
        CHECK(g.width == f.width && g.has_camera && f.has_camera);
        scene_free(&g);
        scene_free(&f);
    }
}
