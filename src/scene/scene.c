/* scene_load: a scene file or a bare OBJ, then the checks and defaults every scene gets;
 * the camera at a frame; framing the bounds; freeing. */
#include "restir/scene/scene.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/animation.h"
#include "restir/scene/obj.h"
#include "restir/scene/scene_builder.h"
#include "restir/scene/scene_file.h"
#include "restir/scene/sky.h"

#define DEFAULT_IMAGE_SIZE 512
#define FRAMING_FOV_DEGREES 40.0

static int ends_with_obj(const char *path)
{
    size_t n = strlen(path);
    return n >= 4 && path[n - 4] == '.' && (path[n - 3] == 'o' || path[n - 3] == 'O') &&
           (path[n - 2] == 'b' || path[n - 2] == 'B') && (path[n - 1] == 'j' || path[n - 1] == 'J');
}

static int out_of_memory(rerror *e) { return rerror_set(e, "out of memory"); }

/* Materials still undefined after all files: the default, with a warning naming the
 * usemtl that asked for them. The implicit "default" (faces before any usemtl) is
 * silent unless a library or the scene file defined it. */
static int settle_materials(scene_builder *b, rerror *e)
{
    size_t i;
    for (i = 0; i < b->s->material_count; ++i) {
        if (b->material_origin[i] != MATERIAL_UNDEFINED || !b->material_first_use[i]) continue;
        if (builder_warn(b, b->material_first_use[i], 0,
                         "material '%s' is not defined by any material library or material line; using the default "
                         "(Lambertian, Kd 0.8)",
                         b->s->materials[i].name))
            return out_of_memory(e);
    }
    return 0;
}

/* A cut-out emitter (map_d and Ke > 0; an MTL refuses it, a scene file's `material ... ke`
 * could still make one): NEE would sample its cut-away points, which no ray can hit. */
static int refuse_cutout_emitters(const scene *s, rerror *e)
{
    size_t i;
    for (i = 0; i < s->material_count; ++i)
        if (s->materials[i].map_alpha && !rgb_is_black(s->materials[i].emission))
            return rerror_at(e, s->path, 0, "material '%s': map_d (cut-out) on an emitting material is not supported",
                             s->materials[i].name);
    return 0;
}

static int finish(scene_builder *b, rerror *e)
{
    scene *s = b->s;
    if (settle_materials(b, e) || refuse_cutout_emitters(s, e)) return -1;
    if (!s->triangle_count)
        return rerror_at(e, s->path, 0, "the scene has no triangles (%zu vertices%s)", s->position_count,
                         b->degenerate_triangles ? ", only degenerate faces" : "");
    if (b->degenerate_triangles &&
        builder_warn(b, s->path, 0, "%zu degenerate triangles (zero area, no normal) were dropped",
                     b->degenerate_triangles))
        return out_of_memory(e);
    if (b->suppressed_warnings) {
        /* The last slot says how many more there were. */
        char **w = &s->warnings[s->warning_count - 1];
        char msg[sizeof s->path + 64];
        size_t n;
        snprintf(msg, sizeof msg, "%s: ... and %zu more warnings", s->path, b->suppressed_warnings + 1);
        n = strlen(msg);
        free(*w);
        *w = malloc(n + 1);
        if (!*w) return out_of_memory(e);
        memcpy(*w, msg, n + 1);
    }
    if (!s->width) s->width = s->height = DEFAULT_IMAGE_SIZE;
    if (!s->has_camera) s->camera = scene_frame_bounds(s);
    return 0;
}

int scene_load_with_options(scene *s, const char *path, const scene_load_options *options, rerror *e)
{
    scene_builder b;
    int status;
    memset(s, 0, sizeof *s);
    if (strlen(path) >= sizeof s->path) return rerror_set(e, "%.200s...: path too long", path);
    memcpy(s->path, path, strlen(path) + 1);
    builder_init(&b, s, options, e);
    status = ends_with_obj(path) ? obj_load(&b, path, e) : scene_file_load(&b, path, e);
    if (!status) status = finish(&b, e);
    builder_finish(&b);
    if (status) scene_free(s);
    return status;
}

int scene_load(scene *s, const char *path, rerror *e) { return scene_load_with_options(s, path, NULL, e); }

void scene_free(scene *s)
{
    size_t i;
    free(s->positions);
    free(s->normals);
    free(s->texcoords);
    for (i = 0; i < s->texture_count; ++i) texture_free(&s->textures[i]);
    free(s->textures);
    free(s->triangles);
    free(s->materials);
    for (i = 0; i < s->object_count; ++i) free(s->object_names[i]);
    free(s->object_names);
    free(s->keyframes);
    scene_animation_free(s);
    sky_free(s->sky);
    free(s->sky);
    for (i = 0; i < s->warning_count; ++i) free(s->warnings[i]);
    free(s->warnings);
    bvh_free(&s->accel);
    free(s->face_normals);
    memset(s, 0, sizeof *s);
}

size_t scene_emitter_count(const scene *s)
{
    size_t i, n = 0;
    for (i = 0; i < s->triangle_count; ++i)
        if (!rgb_is_black(s->materials[s->triangles[i].material].emission)) n++;
    return n;
}

static vec3 lerp3(vec3 a, vec3 b, real t) { return v3_add(a, v3_scale(v3_sub(b, a), t)); }

camera_pose scene_camera_at(const scene *s, int frame)
{
    const camera_keyframe *k = s->keyframes;
    size_t n = s->keyframe_count, i;
    camera_pose pose;
    real t;
    if (!n) return s->camera;
    if (frame <= k[0].frame) return k[0].pose;
    if (frame >= k[n - 1].frame) return k[n - 1].pose;
    for (i = 0; k[i + 1].frame <= frame; ++i) {
    }
    /* Linear in every component between the keyframes around the frame. */
    t = (real)(frame - k[i].frame) / (real)(k[i + 1].frame - k[i].frame);
    pose.eye = lerp3(k[i].pose.eye, k[i + 1].pose.eye, t);
    pose.target = lerp3(k[i].pose.target, k[i + 1].pose.target, t);
    pose.up = lerp3(k[i].pose.up, k[i + 1].pose.up, t);
    pose.fov_y_degrees = k[i].pose.fov_y_degrees + (k[i + 1].pose.fov_y_degrees - k[i].pose.fov_y_degrees) * t;
    return pose;
}

/* Where the framing camera looks from: +z (the historical view) unless the mesh shows
 * much less of itself that way than from another direction. What a direction d shows is the
 * mesh's projected area sum_i A_i |n_i . d| (both sides, occlusion ignored): 0 for flat
 * geometry seen edge-on (a floor in y = 0 from +z). The candidates are +z, then views
 * raised 45 degrees over the y and x axes and the four diagonals (+-1, +-1, 1); they do not
 * all lie in one plane, so every plane is seen by one of them at more than 45 degrees from
 * edge-on. None is parallel to +y, so up = +y always works. */
static vec3 framing_direction(const scene *s)
{
    static const double dirs[7][3] = {{0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 1}, {-1, 1, 1}, {1, -1, 1}, {-1, -1, 1}};
    double shown[7] = {0};
    size_t i;
    int k, best = 0;
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle *t = &s->triangles[i];
        vec3f p0 = s->positions[t->v[0]], p1 = s->positions[t->v[1]], p2 = s->positions[t->v[2]];
        double a[3], b[3], n[3];
        a[0] = (double)p1.x - p0.x, a[1] = (double)p1.y - p0.y, a[2] = (double)p1.z - p0.z;
        b[0] = (double)p2.x - p0.x, b[1] = (double)p2.y - p0.y, b[2] = (double)p2.z - p0.z;
        n[0] = a[1] * b[2] - a[2] * b[1]; /* twice the area times the unit normal */
        n[1] = a[2] * b[0] - a[0] * b[2];
        n[2] = a[0] * b[1] - a[1] * b[0];
        for (k = 0; k < 7; ++k) {
            double len = sqrt(dirs[k][0] * dirs[k][0] + dirs[k][1] * dirs[k][1] + dirs[k][2] * dirs[k][2]);
            shown[k] += fabs(n[0] * dirs[k][0] + n[1] * dirs[k][1] + n[2] * dirs[k][2]) / len;
        }
    }
    /* +z stays unless another view shows more than twice as much (ordinary meshes keep
     * their framing; only nearly edge-on ones change). */
    for (k = 1; k < 7; ++k)
        if (shown[k] > shown[best] && shown[k] > 2 * shown[0]) best = k;
    {
        double len = sqrt(dirs[best][0] * dirs[best][0] + dirs[best][1] * dirs[best][1] + dirs[best][2] * dirs[best][2]);
        return v3((real)(dirs[best][0] / len), (real)(dirs[best][1] / len), (real)(dirs[best][2] / len));
    }
}

camera_pose scene_frame_bounds(const scene *s)
{
    camera_pose pose;
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX}, c[3], radius2 = 0;
    double half_y = FRAMING_FOV_DEGREES * 0.5 * 3.14159265358979323846 / 180, half, aspect, distance;
    size_t i;
    int k, axis;
    vec3 dir;
    for (i = 0; i < s->triangle_count; ++i)
        for (k = 0; k < 3; ++k) {
            vec3f p = s->positions[s->triangles[i].v[k]];
            double q[3];
            q[0] = p.x;
            q[1] = p.y;
            q[2] = p.z;
            for (axis = 0; axis < 3; ++axis) {
                if (q[axis] < lo[axis]) lo[axis] = q[axis];
                if (q[axis] > hi[axis]) hi[axis] = q[axis];
            }
        }
    if (!s->triangle_count) lo[0] = lo[1] = lo[2] = hi[0] = hi[1] = hi[2] = 0;
    for (axis = 0; axis < 3; ++axis) {
        c[axis] = 0.5 * (lo[axis] + hi[axis]);
        radius2 += 0.25 * (hi[axis] - lo[axis]) * (hi[axis] - lo[axis]);
    }
    /* The bounding sphere (radius = half the diagonal) fits the narrower of the vertical
     * and horizontal fields of view at distance radius / sin(half angle). */
    aspect = s->width > 0 && s->height > 0 ? (double)s->width / s->height : 1;
    half = aspect >= 1 ? half_y : atan(tan(half_y) * aspect);
    distance = radius2 > 0 ? sqrt(radius2) / sin(half) : 1;
    dir = framing_direction(s);
    pose.target = v3((real)c[0], (real)c[1], (real)c[2]);
    if (dir.x == 0 && dir.y == 0) pose.eye = v3((real)c[0], (real)c[1], (real)(c[2] + distance)); /* as always */
    else pose.eye = v3((real)(c[0] + distance * dir.x), (real)(c[1] + distance * dir.y), (real)(c[2] + distance * dir.z));
    pose.up = v3(0, 1, 0);
    pose.fov_y_degrees = (real)FRAMING_FOV_DEGREES;
    return pose;
}
