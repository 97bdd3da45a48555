/* The G-buffer: the primary hit x1 of every pixel (DESIGN §2, "render/gbuffer").
 * ReSTIR's reuse passes read it (neighbour rejection by normal/depth, reuse cells by
 * object id, the Enhanced footprint criterion by distance and cosine); `render --aov`
 * writes its channels as images. */
#ifndef RESTIR_GBUFFER_H
#define RESTIR_GBUFFER_H

#include "restir/camera.h"
#include "restir/scene.h"

typedef struct {
    int valid;           /* 0: the primary ray left the scene */
    surface_hit hit;     /* x1: position, geometric and shading normal, material, object */
    vec3f view_dir;      /* unit direction of the primary ray (x0 -> x1) */
    float distance;      /* ||x1 - x0||: primary-ray footprint input */
    float cos_theta;     /* |cos| between the primary ray and the geometric normal at x1 */
    float depth;         /* view-space depth: distance along the camera's forward axis */
} gbuffer_texel;

typedef struct {
    int width, height;
    gbuffer_texel *texels; /* row 0 = top */
} gbuffer;

/* Pixel (x, y) of frame `frame`: the primary ray goes through the pixel centre, or a
 * jittered point (RNG_CAMERA stream, vertex 0, slots 0-1) when jitter != 0. */
ray primary_ray(const camera *c, int x, int y, uint32_t seed, uint32_t sample, int jitter);

int gbuffer_build(gbuffer *g, const scene *s, const camera *c, uint32_t seed, uint32_t sample, int jitter,
                  int threads, rerror *e);
void gbuffer_free(gbuffer *g);

static inline const gbuffer_texel *gbuffer_at(const gbuffer *g, int x, int y)
{
    return &g->texels[(long)y * g->width + x];
}

#endif
