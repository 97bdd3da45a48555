/* Rigid per-object animation: keyframe evaluation, posing the scene at a frame, the
 * rest pose, deep copies and frame ranges (restir/scene/animation.h, docs/scene-format.md). */
#include "restir/scene/animation.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/sky.h"

typedef struct {
    uint32_t object;
    vec3 pivot;
    object_keyframe *keys;
    double (*quat)[4]; /* per key: unit quaternion (w, x, y, z) of its axis-angle */
    size_t count;
} object_track;

struct scene_animation {
    object_track *tracks;
    size_t track_count;
    /* The rest pose (all vertices, so indices match s->positions / s->normals) and, per
     * vertex, the track that moves it (-1: static). */
    vec3f *rest_positions, *rest_normals;
    int32_t *position_track, *normal_track;
    size_t position_count, normal_count;
    int posed; /* scene_pose_at was called: the rest pose is no longer in s->positions */
};

static const object_track *track_of(const scene *s, uint32_t object)
{
    size_t i;
    if (!s->animation) return NULL;
    for (i = 0; i < s->animation->track_count; ++i)
        if (s->animation->tracks[i].object == object) return &s->animation->tracks[i];
    return NULL;
}

int scene_is_animated(const scene *s) { return s->animation && s->animation->track_count > 0; }

/* ---- keyframe evaluation ---- */

static void quat_from_axis_angle(vec3 axis, real degrees, double q[4])
{
    double len = sqrt((double)axis.x * axis.x + (double)axis.y * axis.y + (double)axis.z * axis.z);
    double half = (double)degrees * 3.14159265358979323846 / 360.0, s = sin(half) / len;
    q[0] = cos(half);
    q[1] = axis.x * s;
    q[2] = axis.y * s;
    q[3] = axis.z * s;
}

/* Slerp from a to b (no flip to the shorter arc: same-axis keyframes interpolate the angle
 * linearly, also beyond 180 degrees; docs/scene-format.md). */
static void quat_slerp(const double a[4], const double b[4], double u, double out[4])
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3], wa, wb, len;
    int i;
    if (d > 1) d = 1;
    if (d > 1 - 1e-12) {
        wa = 1 - u;
        wb = u;
    } else {
        double omega = acos(d < -1 ? -1 : d), so = sin(omega);
        wa = sin((1 - u) * omega) / so;
        wb = sin(u * omega) / so;
    }
    for (i = 0; i < 4; ++i) out[i] = wa * a[i] + wb * b[i];
    len = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
    for (i = 0; i < 4; ++i) out[i] /= len;
}

static void quat_matrix(const double q[4], double m[3][3])
{
    double w = q[0], x = q[1], y = q[2], z = q[3];
    m[0][0] = 1 - 2 * (y * y + z * z);
    m[0][1] = 2 * (x * y - w * z);
    m[0][2] = 2 * (x * z + w * y);
    m[1][0] = 2 * (x * y + w * z);
    m[1][1] = 1 - 2 * (x * x + z * z);
    m[1][2] = 2 * (y * z - w * x);
    m[2][0] = 2 * (x * z - w * y);
    m[2][1] = 2 * (y * z + w * x);
    m[2][2] = 1 - 2 * (x * x + y * y);
}

/* p(f) = c + t(f) + R(f)(p - c): m = R(f), t = c + t(f) - R(f) c. */
static void track_transform(const object_track *tr, int frame, double m[3][3], double t[3])
{
    const object_keyframe *k = tr->keys;
    size_t n = tr->count, i = 0;
    double q[4], u = 0, tr3[3], c[3];
    int a;
    if (frame <= k[0].frame || n == 1) {
        memcpy(q, tr->quat[0], sizeof q);
        i = 0;
    } else if (frame >= k[n - 1].frame) {
        memcpy(q, tr->quat[n - 1], sizeof q);
        i = n - 1;
    } else {
        while (k[i + 1].frame <= frame) ++i;
        u = (double)(frame - k[i].frame) / (double)(k[i + 1].frame - k[i].frame);
        quat_slerp(tr->quat[i], tr->quat[i + 1], u, q);
    }
    tr3[0] = k[i].translate.x;
    tr3[1] = k[i].translate.y;
    tr3[2] = k[i].translate.z;
    if (u > 0) {
        tr3[0] += u * ((double)k[i + 1].translate.x - k[i].translate.x);
        tr3[1] += u * ((double)k[i + 1].translate.y - k[i].translate.y);
        tr3[2] += u * ((double)k[i + 1].translate.z - k[i].translate.z);
    }
    quat_matrix(q, m);
    c[0] = tr->pivot.x;
    c[1] = tr->pivot.y;
    c[2] = tr->pivot.z;
    for (a = 0; a < 3; ++a) t[a] = c[a] + tr3[a] - (m[a][0] * c[0] + m[a][1] * c[1] + m[a][2] * c[2]);
}

void scene_object_transform_at_d(const scene *s, uint32_t object, int frame, double m[3][3], double t[3])
{
    const object_track *tr = track_of(s, object);
    int a, b;
    if (tr) {
        track_transform(tr, frame, m, t);
        return;
    }
    for (a = 0; a < 3; ++a) {
        t[a] = 0;
        for (b = 0; b < 3; ++b) m[a][b] = a == b;
    }
}

rigid_transform scene_object_transform_at(const scene *s, uint32_t object, int frame)
{
    rigid_transform r;
    double m[3][3], t[3];
    int a, b;
    scene_object_transform_at_d(s, object, frame, m, t);
    for (a = 0; a < 3; ++a)
        for (b = 0; b < 3; ++b) r.m[a][b] = (float)m[a][b];
    r.t = v3f((float)t[0], (float)t[1], (float)t[2]);
    return r;
}

/* ---- posing ---- */

int scene_pose_at(scene *s, int frame, rerror *e)
{
    struct scene_animation *an = s->animation;
    double (*m)[3][3], (*t)[3];
    size_t i, k;
    if (!scene_is_animated(s)) return 0;
    m = rmalloc(an->track_count, sizeof *m, e);
    t = rmalloc(an->track_count, sizeof *t, e);
    if (!m || !t) {
        free(m);
        free(t);
        return -1;
    }
    for (k = 0; k < an->track_count; ++k) track_transform(&an->tracks[k], frame, m[k], t[k]);
    for (i = 0; i < an->position_count && i < s->position_count; ++i) {
        int32_t tr = an->position_track[i];
        vec3f p = an->rest_positions[i];
        if (tr < 0) continue;
        s->positions[i] = v3f((float)(m[tr][0][0] * p.x + m[tr][0][1] * p.y + m[tr][0][2] * p.z + t[tr][0]),
                              (float)(m[tr][1][0] * p.x + m[tr][1][1] * p.y + m[tr][1][2] * p.z + t[tr][1]),
                              (float)(m[tr][2][0] * p.x + m[tr][2][1] * p.y + m[tr][2][2] * p.z + t[tr][2]));
    }
    for (i = 0; i < an->normal_count && i < s->normal_count; ++i) {
        int32_t tr = an->normal_track[i];
        vec3f n = an->rest_normals[i];
        if (tr < 0) continue;
        s->normals[i] = v3f((float)(m[tr][0][0] * n.x + m[tr][0][1] * n.y + m[tr][0][2] * n.z),
                            (float)(m[tr][1][0] * n.x + m[tr][1][1] * n.y + m[tr][1][2] * n.z),
                            (float)(m[tr][2][0] * n.x + m[tr][2][1] * n.y + m[tr][2][2] * n.z));
    }
    free(m);
    free(t);
    an->posed = 1;
    /* Rigid motion changes every box of the moving objects: rebuild rather than refit
     * (the cost is measured by `restir bench animation`). */
    return scene_prepare(s, e);
}

/* ---- adding an animation ---- */

static int grow(void **array, size_t count, size_t elem, rerror *e)
{
    void *p = realloc(*array, (count ? count : 1) * elem);
    if (!p) return rerror_set(e, "out of memory (%zu bytes)", count * elem);
    *array = p;
    return 0;
}

static struct scene_animation *animation_get(scene *s, rerror *e)
{
    if (!s->animation) s->animation = rcalloc(1, sizeof *s->animation, e);
    return s->animation;
}

/* Gives object `object` its own copy of every vertex (kind 0: position, 1: normal) it
 * shares with another object, then marks its vertices as moved by track `track`. */
static int split_vertices(scene *s, uint32_t object, int32_t track, int kind, rerror *e)
{
    struct scene_animation *an = s->animation;
    size_t count = kind ? s->normal_count : s->position_count, added = 0, i, n;
    unsigned char *shared = rcalloc(count ? count : 1, 1, e);
    int64_t *remap = rmalloc(count ? count : 1, sizeof *remap, e);
    int32_t **owner = kind ? &an->normal_track : &an->position_track;
    size_t *owned = kind ? &an->normal_count : &an->position_count;
    int k;
    if (!shared || !remap) goto fail;
    for (i = 0; i < count; ++i) remap[i] = -1;
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle *t = &s->triangles[i];
        if (t->object == object) continue;
        for (k = 0; k < 3; ++k) {
            int64_t v = kind ? t->n[k] : (int64_t)t->v[k];
            if (v >= 0 && (size_t)v < count) shared[v] = 1;
        }
    }
    /* Count the copies first, then grow the arrays once. */
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle *t = &s->triangles[i];
        if (t->object != object) continue;
        for (k = 0; k < 3; ++k) {
            int64_t v = kind ? t->n[k] : (int64_t)t->v[k];
            if (v >= 0 && (size_t)v < count && shared[v] && remap[v] < 0) remap[v] = (int64_t)(count + added++);
        }
    }
    n = count + added;
    if (kind) {
        if (grow((void **)&s->normals, n, sizeof *s->normals, e)) goto fail;
    } else if (grow((void **)&s->positions, n, sizeof *s->positions, e)) {
        goto fail;
    }
    if (grow((void **)owner, n, sizeof **owner, e)) goto fail;
    for (i = *owned; i < n; ++i) (*owner)[i] = -1;
    *owned = n;
    for (i = 0; i < count; ++i)
        if (remap[i] >= 0) {
            if (kind) s->normals[remap[i]] = s->normals[i];
            else s->positions[remap[i]] = s->positions[i];
        }
    if (kind) s->normal_count = n;
    else s->position_count = n;
    for (i = 0; i < s->triangle_count; ++i) {
        triangle *t = &s->triangles[i];
        if (t->object != object) continue;
        for (k = 0; k < 3; ++k) {
            int64_t v = kind ? t->n[k] : (int64_t)t->v[k];
            if (v < 0 || (size_t)v >= count) continue;
            if (remap[v] >= 0) v = remap[v];
            if (kind) t->n[k] = (int32_t)v;
            else t->v[k] = (uint32_t)v;
            (*owner)[v] = track;
        }
    }
    free(shared);
    free(remap);
    return 0;
fail:
    free(shared);
    free(remap);
    return -1;
}

static int check_keys(const scene *s, uint32_t object, const object_keyframe *keys, size_t count, double (*quat)[4],
                      rerror *e)
{
    size_t i;
    for (i = 0; i < count; ++i) {
        vec3 a = keys[i].axis;
        if (i && keys[i].frame <= keys[i - 1].frame)
            return rerror_set(e, "object '%s': keyframe %d after %d (frames must increase)", s->object_names[object],
                              keys[i].frame, keys[i - 1].frame);
        if (!(v3_dot(a, a) > 0) || !isfinite(v3_dot(a, a)))
            return rerror_set(e, "object '%s': keyframe %d: the rotation axis is zero", s->object_names[object],
                              keys[i].frame);
        if (!isfinite(keys[i].angle_degrees) || !isfinite(keys[i].translate.x) || !isfinite(keys[i].translate.y) ||
            !isfinite(keys[i].translate.z))
            return rerror_set(e, "object '%s': keyframe %d: non-finite transform", s->object_names[object],
                              keys[i].frame);
        quat_from_axis_angle(a, keys[i].angle_degrees, quat[i]);
        if (i) {
            const double *p = quat[i - 1], *q = quat[i];
            /* q = -p: the rotations differ by 360 degrees and slerp has no unique path. */
            if (p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3] < -1 + 1e-9)
                return rerror_set(e,
                                  "object '%s': keyframes %d and %d: rotations 360 degrees apart (the "
                                  "interpolation is undefined; add a keyframe in between)",
                                  s->object_names[object], keys[i - 1].frame, keys[i].frame);
        }
    }
    return 0;
}

static int object_emitter(const scene *s, uint32_t object, const char **name)
{
    size_t i;
    for (i = 0; i < s->triangle_count; ++i) {
        const material *m = &s->materials[s->triangles[i].material];
        if (s->triangles[i].object == object && !rgb_is_black(m->emission)) {
            *name = m->name;
            return 1;
        }
    }
    return 0;
}

/* The rest pose: a copy of every vertex (re-taken after each added object, which may have
 * duplicated vertices; the scene is still in its rest pose then). */
static int snapshot_rest(scene *s, rerror *e)
{
    struct scene_animation *an = s->animation;
    if (grow((void **)&an->rest_positions, s->position_count, sizeof(vec3f), e) ||
        grow((void **)&an->rest_normals, s->normal_count, sizeof(vec3f), e))
        return -1;
    if (s->position_count) memcpy(an->rest_positions, s->positions, s->position_count * sizeof(vec3f));
    if (s->normal_count) memcpy(an->rest_normals, s->normals, s->normal_count * sizeof(vec3f));
    return 0;
}

int scene_add_object_animation(scene *s, uint32_t object, vec3 pivot, const object_keyframe *keys, size_t count,
                               rerror *e)
{
    struct scene_animation *an;
    object_track *tr;
    const char *emitter;
    double (*quat)[4];
    object_keyframe *copy;
    if (object >= s->object_count) return rerror_set(e, "object id %u does not exist", object);
    if (!count) return rerror_set(e, "object '%s': no keyframes", s->object_names[object]);
    if (track_of(s, object)) return rerror_set(e, "object '%s' is animated twice", s->object_names[object]);
    if (s->animation && s->animation->posed)
        return rerror_set(e, "object '%s': animations are added in the rest pose (before scene_pose_at)",
                          s->object_names[object]);
    if (object_emitter(s, object, &emitter))
        return rerror_set(e, "object '%s' contains an emitter (material '%s'): only static lights are supported",
                          s->object_names[object], emitter);
    quat = rmalloc(count, sizeof *quat, e);
    copy = rmalloc(count, sizeof *copy, e);
    if (!quat || !copy || check_keys(s, object, keys, count, quat, e) || !(an = animation_get(s, e)) ||
        grow((void **)&an->tracks, an->track_count + 1, sizeof *an->tracks, e)) {
        free(quat);
        free(copy);
        return -1;
    }
    memcpy(copy, keys, count * sizeof *copy);
    tr = &an->tracks[an->track_count];
    tr->object = object;
    tr->pivot = pivot;
    tr->keys = copy;
    tr->quat = quat;
    tr->count = count;
    an->track_count++;
    if (split_vertices(s, object, (int32_t)(an->track_count - 1), 0, e) ||
        split_vertices(s, object, (int32_t)(an->track_count - 1), 1, e) || snapshot_rest(s, e))
        return -1;
    bvh_free(&s->accel); /* vertex indices changed */
    free(s->face_normals);
    s->face_normals = NULL;
    return 0;
}

size_t scene_animated_object_count(const scene *s) { return s->animation ? s->animation->track_count : 0; }

const object_keyframe *scene_animated_object(const scene *s, size_t i, uint32_t *object, vec3 *pivot, size_t *count)
{
    const object_track *tr;
    if (i >= scene_animated_object_count(s)) return NULL;
    tr = &s->animation->tracks[i];
    if (object) *object = tr->object;
    if (pivot) *pivot = tr->pivot;
    if (count) *count = tr->count;
    return tr->keys;
}

void scene_animation_free(scene *s)
{
    struct scene_animation *an = s->animation;
    size_t i;
    if (!an) return;
    for (i = 0; i < an->track_count; ++i) {
        free(an->tracks[i].keys);
        free(an->tracks[i].quat);
    }
    free(an->tracks);
    free(an->rest_positions);
    free(an->rest_normals);
    free(an->position_track);
    free(an->normal_track);
    free(an);
    s->animation = NULL;
}

int scene_frame_range(const scene *s, int *first, int *last)
{
    int lo = 0, hi = 0, any = 0;
    size_t i, k;
    for (i = 0; i < s->keyframe_count; ++i) {
        int f = s->keyframes[i].frame;
        if (!any || f < lo) lo = f;
        if (!any || f > hi) hi = f;
        any = 1;
    }
    for (k = 0; k < scene_animated_object_count(s); ++k) {
        const object_track *tr = &s->animation->tracks[k];
        for (i = 0; i < tr->count; ++i) {
            int f = tr->keys[i].frame;
            if (!any || f < lo) lo = f;
            if (!any || f > hi) hi = f;
            any = 1;
        }
    }
    if (!any) return -1;
    *first = lo;
    *last = hi;
    return 0;
}

/* ---- deep copy ---- */

static int copy_array(void **dst, const void *src, size_t count, size_t elem, rerror *e)
{
    *dst = NULL;
    if (!src || !count) return 0;
    *dst = rmalloc(count, elem, e);
    if (!*dst) return -1;
    memcpy(*dst, src, count * elem);
    return 0;
}

/* Deep copies of the image maps (scene_free frees each). */
static int copy_textures(scene *dst, const scene *src, rerror *e)
{
    size_t i;
    if (!src->texture_count) return 0;
    dst->textures = rmalloc(src->texture_count, sizeof *dst->textures, e);
    if (!dst->textures) return -1;
    for (i = 0; i < src->texture_count; ++i, ++dst->texture_count)
        if (texture_copy(&dst->textures[i], &src->textures[i], e)) return -1;
    return 0;
}

static int copy_strings(char ***dst, char *const *src, size_t count, rerror *e)
{
    size_t i;
    *dst = NULL;
    if (!count) return 0;
    *dst = rcalloc(count, sizeof **dst, e);
    if (!*dst) return -1;
    for (i = 0; i < count; ++i)
        if (copy_array((void **)&(*dst)[i], src[i], strlen(src[i]) + 1, 1, e)) return -1;
    return 0;
}

static int copy_animation(scene *dst, const struct scene_animation *src, rerror *e)
{
    struct scene_animation *an;
    size_t i;
    if (!src) return 0;
    an = dst->animation = rcalloc(1, sizeof *an, e);
    if (!an) return -1;
    *an = *src;
    an->tracks = NULL;
    an->rest_positions = an->rest_normals = NULL;
    an->position_track = an->normal_track = NULL;
    an->track_count = 0;
    if (copy_array((void **)&an->rest_positions, src->rest_positions, src->position_count, sizeof(vec3f), e) ||
        copy_array((void **)&an->rest_normals, src->rest_normals, src->normal_count, sizeof(vec3f), e) ||
        copy_array((void **)&an->position_track, src->position_track, src->position_count, sizeof(int32_t), e) ||
        copy_array((void **)&an->normal_track, src->normal_track, src->normal_count, sizeof(int32_t), e))
        return -1;
    if (src->track_count && !(an->tracks = rcalloc(src->track_count, sizeof *an->tracks, e))) return -1;
    for (i = 0; i < src->track_count; ++i) {
        const object_track *a = &src->tracks[i];
        object_track *b = &an->tracks[i];
        *b = *a;
        b->keys = NULL;
        b->quat = NULL;
        an->track_count = i + 1; /* so that scene_free frees what was copied so far */
        if (copy_array((void **)&b->keys, a->keys, a->count, sizeof *a->keys, e) ||
            copy_array((void **)&b->quat, a->quat, a->count, sizeof *a->quat, e))
            return -1;
    }
    return 0;
}

int scene_clone(scene *dst, const scene *src, rerror *e)
{
    const bvh *b = &src->accel;
    memcpy(dst, src, sizeof *dst);
    dst->positions = NULL;
    dst->normals = NULL;
    dst->texcoords = NULL;
    dst->textures = NULL;
    dst->texture_count = 0;
    dst->triangles = NULL;
    dst->materials = NULL;
    dst->object_names = NULL;
    dst->object_count = 0;
    dst->keyframes = NULL;
    dst->animation = NULL;
    dst->sky = NULL;
    dst->warnings = NULL;
    dst->warning_count = 0;
    memset(&dst->accel, 0, sizeof dst->accel);
    dst->face_normals = NULL;
    if (copy_array((void **)&dst->positions, src->positions, src->position_count, sizeof(vec3f), e) ||
        copy_array((void **)&dst->face_normals, src->face_normals, src->triangle_count, sizeof(vec3f), e) ||
        copy_array((void **)&dst->normals, src->normals, src->normal_count, sizeof(vec3f), e) ||
        copy_array((void **)&dst->texcoords, src->texcoords, src->texcoord_count, sizeof *src->texcoords, e) ||
        copy_array((void **)&dst->triangles, src->triangles, src->triangle_count, sizeof(triangle), e) ||
        copy_array((void **)&dst->materials, src->materials, src->material_count, sizeof(material), e) ||
        copy_array((void **)&dst->keyframes, src->keyframes, src->keyframe_count, sizeof(camera_keyframe), e))
        goto fail;
    dst->object_count = src->object_count;
    if (copy_strings(&dst->object_names, src->object_names, src->object_count, e)) goto fail;
    dst->warning_count = src->warning_count;
    if (copy_strings(&dst->warnings, src->warnings, src->warning_count, e)) goto fail;
    if (copy_textures(dst, src, e)) goto fail;
    if (copy_animation(dst, src->animation, e)) goto fail;
    if (sky_clone(&dst->sky, src->sky, e)) goto fail;
    dst->accel = *b;
    dst->accel.nodes = NULL;
    dst->accel.prim_order = NULL;
    dst->accel.blocks = NULL;
    dst->accel.wide = NULL;
    if (copy_array((void **)&dst->accel.nodes, b->nodes, b->node_count, sizeof *b->nodes, e) ||
        copy_array((void **)&dst->accel.wide, b->wide, b->wide_count, sizeof *b->wide, e) ||
        copy_array((void **)&dst->accel.prim_order, b->prim_order, b->prim_count, sizeof *b->prim_order, e) ||
        copy_array((void **)&dst->accel.blocks, b->blocks, b->block_count, sizeof *b->blocks, e))
        goto fail;
    return 0;
fail:
    scene_free(dst);
    return -1;
}
