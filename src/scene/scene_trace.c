/* Ray queries on a scene: building the acceleration structure, closest hits with
 * surface data, visibility between two points and rays leaving a surface. Every ray
 * that starts on a surface is offset with offset_ray_origin (after Wächter & Binder
 * 2019) to the side it leaves to, so no epsilon in t is needed: spawned rays have
 * tmin = 0, and shadow segments are only shortened by the offsets themselves. */
#include "restir/scene/scene_trace.h"

#include "restir/scene/scene.h"
#include "restir/scene/surface_maps.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static vec3f face_normal(vec3f a, vec3f b, vec3f c);

/* face_normal of every triangle, once: a hit looks it up instead of recomputing it (the
 * same function, so the same bits; docs/performance.md). */
static int prepare_face_normals(scene *s, rerror *e)
{
    size_t i;
    free(s->face_normals);
    s->face_normals = rmalloc(s->triangle_count, sizeof *s->face_normals, e);
    if (!s->face_normals) return -1;
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle *t = &s->triangles[i];
        s->face_normals[i] = face_normal(s->positions[t->v[0]], s->positions[t->v[1]], s->positions[t->v[2]]);
    }
    return 0;
}

int scene_prepare(scene *s, rerror *e)
{
    vec3f *corners;
    size_t i;
    int k;
    if (s->triangle_count == 0) return rerror_at(e, s->path, 0, "scene has no triangles");
    for (i = 0; i < s->triangle_count; ++i)
        for (k = 0; k < 3; ++k)
            if (s->triangles[i].v[k] >= s->position_count)
                return rerror_at(e, s->path, 0, "triangle %zu refers to vertex %u of %zu", i,
                                 s->triangles[i].v[k], s->position_count);
    corners = rmalloc(3 * s->triangle_count, sizeof *corners, e);
    if (!corners) return -1;
    s->bounds_min = v3f(INFINITY, INFINITY, INFINITY);
    s->bounds_max = v3f(-INFINITY, -INFINITY, -INFINITY);
    for (i = 0; i < s->triangle_count; ++i) {
        for (k = 0; k < 3; ++k) {
            vec3f p = s->positions[s->triangles[i].v[k]];
            corners[3 * i + k] = p;
            if (isfinite(p.x) && isfinite(p.y) && isfinite(p.z)) {
                s->bounds_min = v3f_min(s->bounds_min, p);
                s->bounds_max = v3f_max(s->bounds_max, p);
            }
        }
    }
    bvh_free(&s->accel);
    if (bvh_build(&s->accel, corners, s->triangle_count, e)) {
        free(corners);
        return -1;
    }
    free(corners);
    return prepare_face_normals(s, e);
}

/* The true face normal (v1-v0)x(v2-v0), normalised. Computed in double: the cross
 * product of a tiny (but non-degenerate, hence hittable) triangle can underflow in
 * float. */
static vec3f face_normal(vec3f a, vec3f b, vec3f c)
{
    vec3 n = v3_cross(v3_sub(v3_from_f(b), v3_from_f(a)), v3_sub(v3_from_f(c), v3_from_f(a)));
    double len = sqrt((double)n.x * n.x + (double)n.y * n.y + (double)n.z * n.z);
    return v3f((float)(n.x / len), (float)(n.y / len), (float)(n.z / len));
}

/* Interpolated vertex normal, or ng when the triangle has none or the result is unusable. */
static vec3f shading_normal(const scene *s, const triangle *t, float b1, float b2, vec3f ng)
{
    vec3f n;
    float len;
    int k;
    for (k = 0; k < 3; ++k)
        if (t->n[k] < 0 || (size_t)t->n[k] >= s->normal_count) return ng;
    n = v3f_add(v3f_add(v3f_scale(s->normals[t->n[0]], 1.0f - b1 - b2), v3f_scale(s->normals[t->n[1]], b1)),
                v3f_scale(s->normals[t->n[2]], b2));
    len = v3f_length(n);
    if (!(len > 0) || !isfinite(len)) return ng;
    return v3f_scale(n, 1.0f / len);
}

/* The alpha test of every ray query (docs/materials.md, "Cut-outs"): the one place where
 * a hit on a cut-away point is rejected. Scenes without map_d never call it. */
static int alpha_keeps(const void *ctx, uint32_t tri, float b1, float b2)
{
    return scene_alpha_keeps((const scene *)ctx, tri, b1, b2);
}

static int closest_hit(const scene *s, const ray *r, bvh_hit *bh)
{
    if (s->has_cutouts) return bvh_intersect_filtered(&s->accel, r, bh, alpha_keeps, s);
    return bvh_intersect(&s->accel, r, bh);
}

int scene_occluded(const scene *s, const ray *r)
{
    if (s->has_cutouts) return bvh_occluded_filtered(&s->accel, r, alpha_keeps, s);
    return bvh_occluded(&s->accel, r);
}

int scene_intersect(const scene *s, const ray *r, surface_hit *h)
{
    bvh_hit bh;
    const triangle *t;
    vec3f a, b, c;
    if (!closest_hit(s, r, &bh)) return 0;
    t = &s->triangles[bh.tri];
    a = s->positions[t->v[0]];
    b = s->positions[t->v[1]];
    c = s->positions[t->v[2]];
    /* The position from the barycentrics rather than origin + t dir: its error is
     * relative to the vertex magnitudes, which is what offset_ray_origin assumes. */
    h->position = v3f_add(v3f_add(v3f_scale(a, 1.0f - bh.b1 - bh.b2), v3f_scale(b, bh.b1)), v3f_scale(c, bh.b2));
    h->ng = s->face_normals ? s->face_normals[bh.tri] : face_normal(a, b, c);
    h->ns = shading_normal(s, t, bh.b1, bh.b2, h->ng);
    h->t = bh.t;
    h->b1 = bh.b1;
    h->b2 = bh.b2;
    h->triangle = bh.tri;
    h->material = t->material;
    h->object = t->object;
    return 1;
}

int scene_surface_point(const scene *s, uint32_t tri, float b1, float b2, surface_hit *h)
{
    const triangle *t;
    vec3f a, b, c;
    if (tri >= s->triangle_count) return 0;
    t = &s->triangles[tri];
    a = s->positions[t->v[0]];
    b = s->positions[t->v[1]];
    c = s->positions[t->v[2]];
    /* Exactly the arithmetic of scene_intersect, so a stored hit is rebuilt bit for bit. */
    h->position = v3f_add(v3f_add(v3f_scale(a, 1.0f - b1 - b2), v3f_scale(b, b1)), v3f_scale(c, b2));
    h->ng = s->face_normals ? s->face_normals[tri] : face_normal(a, b, c);
    h->ns = shading_normal(s, t, b1, b2, h->ng);
    h->t = 0;
    h->b1 = b1;
    h->b2 = b2;
    h->triangle = tri;
    h->material = t->material;
    h->object = t->object;
    return 1;
}

/* fmaxf(a, b) for a b that is never NaN: the larger, or b if a is NaN. */
static float max_not_nan(float a, float b) { return a > b ? a : b; }

/* fmaxf(|x|, fmaxf(|y|, fmaxf(|z|, 0))), bit for bit: the innermost 0 makes every second
 * argument a number, so the comparisons give fmaxf's answers (NaN coordinates count as 0)
 * without three libm calls per offset (docs/performance.md). */
static float max_abs(vec3f v) { return max_not_nan(fabsf(v.x), max_not_nan(fabsf(v.y), max_not_nan(fabsf(v.z), 0.0f))); }

/* The normal n of the surface at p, turned to the side where `toward` lies. When
 * `toward` lies in p's tangent plane up to rounding (two points on one planar face:
 * their hit positions carry errors of a few ulps, so the sign of the distance is
 * noise), n is kept as it is: both ends of such a segment then move to the same side
 * of their common plane instead of to opposite sides, where the segment would cross
 * the plane and be falsely occluded. The tolerance, 2^-18 (|p| + |toward|) in the max
 * norm, is above those rounding errors and below the offset itself (256 ulps of the
 * largest coordinate, i.e. 2^-16 to 2^-15 of |p|). */
static vec3f facing(vec3f n, vec3f p, vec3f toward)
{
    float d = v3f_dot(n, v3f_sub(toward, p));
    float tolerance = (max_abs(p) + max_abs(toward)) * (1.0f / 262144.0f);
    return d < -tolerance ? v3f_scale(n, -1.0f) : n;
}

/* Lexicographic order of points, used to trace a segment always in the same direction. */
static int point_before(vec3f a, vec3f b)
{
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

/* The shadow ray between a point `from` on a surface and a point `to` (on a surface
 * when ng_to is given).
 * 1. Both ends are offset off their surfaces toward each other (Wächter & Binder).
 * 2. The ray runs between the two offset points with the UNNORMALISED direction
 *    end - start, so t in [0, 1] spans the segment and no length enters the test.
 * 3. The t range is also shortened at each surface end by that end's offset distance
 *    (t in (delta_start/L, 1 - delta_end/L), L the segment length). This covers what a
 *    normal offset cannot: a point on a concave edge lies on two surfaces, and when its
 *    position rounds to the outside of the surface it was not hit on, the normal offset
 *    (along the other surface's normal) does not bring it back; stepping along the
 *    segment into the free space does. Occluders closer to an end than its offset are
 *    ignored, the same tolerance the normal offset already implies.
 * 4. The segment is always traced from the lexicographically smaller offset point:
 *    (a, b) and (b, a) give the very same ray, so visibility is exactly symmetric
 *    (shift mappings and MIS rely on that). Ends closer than their offsets give an
 *    empty range: visible. */
ray scene_visibility_ray(vec3f from, vec3f ng_from, vec3f to, const vec3f *ng_to)
{
    vec3f a = offset_ray_origin(from, facing(ng_from, from, to));
    vec3f b = ng_to ? offset_ray_origin(to, facing(*ng_to, to, from)) : to;
    float delta_a = v3f_length(v3f_sub(a, from)), delta_b = v3f_length(v3f_sub(b, to)), length;
    ray r;
    if (point_before(b, a)) {
        vec3f t = a;
        float d = delta_a;
        a = b;
        b = t;
        delta_a = delta_b;
        delta_b = d;
    }
    r.origin = a;
    r.dir = v3f_sub(b, a);
    length = v3f_length(r.dir);
    r.tmin = length > 0 ? delta_a / length : 0;
    r.tmax = length > 0 ? 1 - delta_b / length : 0;
    return r;
}

int scene_visible(const scene *s, vec3f from, vec3f ng_from, vec3f to, const vec3f *ng_to)
{
    ray r = scene_visibility_ray(from, ng_from, to, ng_to);
    /* Coincident points (zero direction, empty range): bvh_occluded returns 0. */
    return !scene_occluded(s, &r);
}

ray scene_spawn_ray(vec3f p, vec3f ng, vec3f dir, vec3f wo)
{
    ray r;
    vec3f n = v3f_dot(ng, dir) < 0 ? v3f_scale(ng, -1.0f) : ng;
    /* Step first along the surface towards where the path came from (the tangential part
     * of wo), then off the surface. A hit on a concave edge lies on two faces at once; the
     * normal offset leaves only one of them, and the origin may still sit on (or, by
     * rounding, behind) the other face, so rays towards it would pass through it. The
     * incoming segment crossed free space, so its side of the edge is the open side. */
    vec3f tangent = v3f_sub(wo, v3f_scale(ng, v3f_dot(wo, ng)));
    r.origin = offset_ray_origin(offset_ray_origin(p, tangent), n);
    r.dir = dir;
    r.tmin = 0;
    r.tmax = INFINITY;
    return r;
}
