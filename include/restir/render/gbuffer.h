/* The G-buffer: the primary hit x1 of every pixel (docs/design.md, Layout).
 * ReSTIR's reuse passes read it (neighbour rejection by normal/depth, reuse cells by
 * object id, the Enhanced footprint criterion by distance and cosine); `render --aov`
 * writes its channels as images. */
#ifndef RESTIR_GBUFFER_H
#define RESTIR_GBUFFER_H

#include "restir/render/camera.h"
#include "restir/render/path_sampler.h"
#include "restir/scene/scene.h"

typedef struct {
    int valid;           /* 0: the primary ray left the scene */
    surface_hit hit;     /* x1: position, geometric and shading normal, material, object */
    vec3f view_dir;      /* unit direction of the primary ray (x0 -> x1) */
    float distance;      /* ||x1 - x0||: primary-ray footprint input */
    float cos_theta;     /* |cos| between the primary ray and the geometric normal at x1 */
    float depth;         /* view-space depth: distance along the camera's forward axis */
    float pixel[2];      /* the primary ray's sample position in continuous pixel coordinates (origin
                            top-left; pixel (x, y) covers [x, x+1) x [y, y+1)): centre or jittered */
    /* Filled by gbuffer_motion (0 and 0 until then): */
    float motion[2];     /* where x1 was in the previous frame's image minus pixel[] (pixels) */
    int prev_valid;      /* 1: x1 was on screen in the previous frame and not occluded there */
} gbuffer_texel;

typedef struct {
    int width, height;
    gbuffer_texel *texels; /* row 0 = top */
} gbuffer;

/* Pixel (x, y) of frame `frame`: the primary ray goes through the pixel centre, or a
 * jittered point (RNG_CAMERA stream, vertex 0, slots 0-1) when jitter != 0. */
ray primary_ray(const camera *c, int x, int y, uint32_t seed, uint32_t sample, int jitter);

/* The sample position of pixel (x, y) that primary_ray uses (continuous pixel coordinates). */
void primary_sample_position(const camera *c, int x, int y, uint32_t seed, uint32_t sample, int jitter, real *px,
                             real *py);

int gbuffer_build(gbuffer *g, const scene *s, const camera *c, uint32_t seed, uint32_t sample, int jitter,
                  int threads, rerror *e);
void gbuffer_free(gbuffer *g);

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

/* x1 of pixel p of G-buffer g (scene s) as the path sampler builds it from the frame's
 * primary ray: 0 if the primary ray missed. */
int gbuffer_primary_vertex(const scene *s, const gbuffer *g, long p, path_vertex *v);

static inline const gbuffer_texel *gbuffer_at(const gbuffer *g, int x, int y)
{
    return &g->texels[(long)y * g->width + x];
}

#endif
