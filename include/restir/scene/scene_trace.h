/* Ray queries against a prepared scene (src/scene/scene_trace.c): closest hit, a surface point
 * from barycentrics, visibility between two points, and the offset rays every shift and the
 * path tracer spawn. */
#ifndef RESTIR_SCENE_SCENE_TRACE_H
#define RESTIR_SCENE_SCENE_TRACE_H

#include "restir/scene/scene.h"

/* Every query below honours alpha cut-outs (map_d): a hit where the interpolated alpha is
 * below SCENE_ALPHA_CUTOFF (surface_maps.h) is no hit, for every kind of ray alike.
 * Closest hit along a ray; returns 1 and fills *h if something is hit. */
int scene_intersect(const scene *s, const ray *r, surface_hit *h);
/* The surface point of triangle `tri` at barycentrics (b1, b2), exactly as scene_intersect
 * reports a hit there (t = 0): shift mappings rebuild a stored vertex from its triangle
 * and barycentrics. Returns 0 if tri is out of range. */
int scene_surface_point(const scene *s, uint32_t tri, float b1, float b2, surface_hit *h);
/* 1 if anything the ray hits in (tmin, tmax) is kept by the alpha test (bvh_occluded with
 * cut-outs): what every shadow and visibility ray uses. */
int scene_occluded(const scene *s, const ray *r);
/* 1 if the segment from a point on surface `from` (normal ng_from) to point `to`
 * (normal ng_to, or NULL for a non-surface point) is unoccluded. Origins are offset
 * robustly and scale-invariantly on both ends. */
int scene_visible(const scene *s, vec3f from, vec3f ng_from, vec3f to, const vec3f *ng_to);
/* The shadow ray scene_visible traces (any hit in (tmin, tmax) means occluded):
 * between the two offset end points with the unnormalised direction (t = 1 at the
 * far end), the range shortened at each surface end by its offset distance, traced
 * from the lexicographically smaller end so that (a, b) and (b, a) give the same ray. */
ray scene_visibility_ray(vec3f from, vec3f ng_from, vec3f to, const vec3f *ng_to);
/* Ray leaving a surface point in direction dir. The origin is moved a few ulps along the
 * surface towards wo (the unit direction back to where the path came from; zero if none)
 * and then off the surface to the side dir points to, so that a point on a concave edge
 * leaves from the open side of both faces (scene_trace.c). */
ray scene_spawn_ray(vec3f p, vec3f ng, vec3f dir, vec3f wo);

#endif
