/* The G-buffer: the primary hit x1 of every pixel (docs/design.md, Layout).
 * ReSTIR's reuse passes read it (neighbour rejection by normal/depth, reuse cells by
 * object id, the Enhanced footprint criterion by distance and cosine); `render --aov`
 * writes its channels as images. */
#ifndef RESTIR_GBUFFER_H
#define RESTIR_GBUFFER_H

#include "restir/render/camera.h"
#include "restir/render/vertex_sampling.h"
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

/* x1 of pixel p of G-buffer g (scene s) as the path sampler builds it from the frame's
 * primary ray: 0 if the primary ray missed. */
int gbuffer_primary_vertex(const scene *s, const gbuffer *g, long p, path_vertex *v);

static inline const gbuffer_texel *gbuffer_at(const gbuffer *g, int x, int y)
{
    return &g->texels[(long)y * g->width + x];
}

#endif
