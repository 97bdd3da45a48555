/* Rigid per-object animation (issue 10; docs/scene-format.md "animate").
 *
 * An animated object has a pivot c (a rest-pose point) and keyframes, each a translation
 * t and a rotation R given as axis-angle. At frame f the object's rest-pose points p are at
 *
 *     p(f) = c + t(f) + R(f) (p - c),
 *
 * t(f) linear between the keyframes around f, R(f) the spherical linear interpolation
 * (slerp) of the keyframes' unit quaternions, without flipping to the shorter arc: for two
 * keyframes about the same axis this is exactly the angle interpolated linearly (a door
 * swinging from 10 to 80 degrees passes through 45). Outside the keyframes the pose is
 * clamped to the first or last one, as the camera's is (scene_camera_at). Lights are
 * static: an animated object containing an emitter is rejected when the scene is loaded.
 *
 * The scene keeps the rest pose of every animated object's vertices and normals;
 * scene_pose_at writes the pose of a frame into s->positions / s->normals and rebuilds the
 * BVH. Vertices shared between an animated object and another object are duplicated when
 * the animation is added, so every vertex belongs to at most one animated object. */
#ifndef RESTIR_ANIMATION_H
#define RESTIR_ANIMATION_H

#include <stddef.h>
#include <stdint.h>
#include "restir/core/error.h"
#include "restir/scene/scene.h"
#include "restir/core/vec.h"

typedef struct {
    float m[3][3]; /* rotation, row-major: p'_i = sum_j m[i][j] p_j + t_i */
    vec3f t;
} rigid_transform; /* p' = m p + t (rotation + translation) */

typedef struct {
    int frame;
    vec3 translate;      /* t at this frame */
    vec3 axis;           /* rotation axis (any non-zero length) */
    real angle_degrees;  /* rotation angle about axis, right-handed */
} object_keyframe;

/* 1 if any object has keyframes. */
int scene_is_animated(const scene *s);

/* The transform taking an object's rest-pose points to their pose at `frame` (the
 * identity for static objects and object ids out of range). */
rigid_transform scene_object_transform_at(const scene *s, uint32_t object, int frame);
/* The same in double precision (m row-major, p' = m p + t); what the motion vectors use. */
void scene_object_transform_at_d(const scene *s, uint32_t object, int frame, double m[3][3], double t[3]);

/* Sets the animated objects' positions and normals to their pose at `frame` (computed
 * from the rest pose the scene keeps, so posing is exact and order-independent), then
 * rebuilds bounds and BVH (scene_prepare). Returns 0 and does nothing for a static scene. */
int scene_pose_at(scene *s, int frame, rerror *e);

/* Deep copy of src into dst (dst is overwritten, not freed); the BVH is copied if src is
 * prepared. Free dst with scene_free. */
int scene_clone(scene *dst, const scene *src, rerror *e);

/* The range of frames covered by camera keyframes and object keyframes: *first = the
 * smallest keyframe frame, *last = the largest. Returns -1 (and leaves them alone) if the
 * scene has no keyframes at all, else 0. */
int scene_frame_range(const scene *s, int *first, int *last);

/* Adds keyframes (frames strictly increasing, axes non-zero, consecutive rotations not
 * 360 degrees apart) for object `object` with pivot `pivot`. Must be called while the
 * scene is in its rest pose (before scene_pose_at) and once per object. Fails with a
 * message (no file:line: the scene-file parser adds that) if the object contains an
 * emitter, the object does not exist or the keyframes are invalid. Invalidates the BVH
 * (call scene_prepare or scene_pose_at afterwards). */
int scene_add_object_animation(scene *s, uint32_t object, vec3 pivot, const object_keyframe *keys, size_t count,
                               rerror *e);

/* Introspection for the scene-file writer and tests: number of animated objects, and the
 * i-th one's object id, pivot and keyframes (pointer into the scene). */
size_t scene_animated_object_count(const scene *s);
const object_keyframe *scene_animated_object(const scene *s, size_t i, uint32_t *object, vec3 *pivot, size_t *count);

/* Frees the animation data (scene_free calls it). */
void scene_animation_free(scene *s);

#endif
