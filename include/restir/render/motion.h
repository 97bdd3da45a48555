/* Motion vectors and disocclusion between two frames' G-buffers (src/render/motion.c;
 * docs/correlation.md): the previous pixel of every texel under camera and rigid object
 * motion, and the dual motion vectors of Enhanced section 6.4. */
#ifndef RESTIR_RENDER_MOTION_H
#define RESTIR_RENDER_MOTION_H

#include "restir/render/gbuffer.h"

/* Disocclusion thresholds of gbuffer_motion (src/render/motion.c gives the defaults
 * and why): a reprojected point is accepted in the previous G-buffer's texel if that
 * texel's hit lies within max_relative_depth * (view depth) of the point's tangent plane
 * (previous pose) and the two geometric normals have cosine >= min_normal_cos. */
typedef struct {
    float max_relative_depth;
    float min_normal_cos;
} motion_thresholds;
void motion_thresholds_default(motion_thresholds *t);

/* Fills motion/prev_valid of cur (frame `frame`, scene s posed at `frame`) from the
 * previous frame's camera, the object transforms of frame `prev_frame` (evaluated from
 * s's keyframes) and the previous G-buffer: x1 is carried to its previous pose, projected
 * with prev_cam, and accepted when it lands on screen on a previous texel that is valid,
 * shows the same object and passes the depth (tangent-plane) and normal tests.
 * Pixels whose primary ray missed, and points behind the previous camera, get motion 0
 * and prev_valid 0. th = NULL: the defaults. In 16 x 16 tiles on `threads` workers (each
 * texel depends only on itself: the same bytes for any thread count). */
int gbuffer_motion(gbuffer *cur, const scene *s, int frame, const camera *prev_cam, int prev_frame,
                   const gbuffer *prev, const motion_thresholds *th, int threads, rerror *e);
/* The previous frame's pixel of a texel with motion: (floor(pixel + motion)). Returns
 * prev_valid (the pixel is then inside the previous image). */
static inline int gbuffer_previous_pixel(const gbuffer_texel *t, int *x, int *y)
{
    *x = (int)floorf(t->pixel[0] + t->motion[0]);
    *y = (int)floorf(t->pixel[1] + t->motion[1]);
    return t->prev_valid;
}

/* The G-buffer of frame `frame` with its motion vectors against frame - 1 (s posed at
 * `frame`; a copy of s is posed at frame - 1 for the previous G-buffer, built with the same
 * seed, jitter and sample = frame index as `render --method aov` uses). */
int gbuffer_build_with_motion(gbuffer *g, const scene *s, int frame, uint32_t seed, int jitter, int threads, rerror *e);
/* The previous-frame position of a current-frame point on object `object` (rigid motion
 * between the two frames' object transforms), in double. */
vec3 motion_previous_position(const scene *s, uint32_t object, int frame, int prev_frame, vec3 p);

/* Dual motion vectors (Enhanced §6.4, Zeng et al. 2021; the rule is in src/render/motion.c
 * and docs/correlation.md): for a texel t of frame `frame` (scene s, camera cam) whose
 * reprojection failed (valid, !prev_valid) onto a previous texel of another object (the
 * occluder), the previous pixel obtained by moving t's sample position against the
 * occluder's own screen motion (one pixel further if that texel still shows the
 * occluder). Returns 1 and (x, y) when that previous texel shows t's object with an
 * agreeing normal, else 0. */
int gbuffer_dual_previous_pixel(const gbuffer_texel *t, const scene *s, int frame, const camera *cam, int prev_frame,
                                const gbuffer *prev, int *x, int *y);

#endif
