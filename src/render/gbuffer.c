/* Primary hits for every pixel, traced in parallel tiles (deterministic). */
#include "restir/render/gbuffer.h"

#include <stdlib.h>
#include "restir/core/rng.h"
#include "restir/core/threads.h"
#include "restir/scene/scene_trace.h"

void primary_sample_position(const camera *c, int x, int y, uint32_t seed, uint32_t sample, int jitter, real *px,
                             real *py)
{
    real dx = (real)0.5, dy = (real)0.5;
    if (jitter) {
        rng_key k = rng_key_make(seed, (uint32_t)(y * c->width + x), sample);
        dx = rng_u(k, RNG_CAMERA, 0, 0);
        dy = rng_u(k, RNG_CAMERA, 0, 1);
    }
    *px = (real)x + dx;
    *py = (real)y + dy;
}

ray primary_ray(const camera *c, int x, int y, uint32_t seed, uint32_t sample, int jitter)
{
    real px, py;
    primary_sample_position(c, x, y, seed, sample, jitter, &px, &py);
    return camera_ray(c, px, py);
}

typedef struct {
    gbuffer *g;
    const scene *s;
    const camera *c;
    uint32_t seed, sample;
    int jitter;
} gbuffer_job;

static void fill_texel(const gbuffer_job *job, int x, int y)
{
    gbuffer_texel *t = &job->g->texels[(long)y * job->g->width + x];
    real px, py;
    ray r;
    primary_sample_position(job->c, x, y, job->seed, job->sample, job->jitter, &px, &py);
    r = camera_ray(job->c, px, py);
    t->pixel[0] = (float)px;
    t->pixel[1] = (float)py;
    t->motion[0] = t->motion[1] = 0;
    t->prev_valid = 0;
    t->valid = scene_intersect(job->s, &r, &t->hit);
    t->view_dir = r.dir;
    if (!t->valid) {
        t->distance = t->depth = INFINITY;
        t->cos_theta = 0;
        return;
    }
    t->distance = t->hit.t; /* the ray direction is unit length */
    t->cos_theta = fabsf(v3f_dot(t->hit.ng, r.dir));
    t->depth = t->hit.t * (float)v3_dot(v3_from_f(r.dir), job->c->forward);
}

static void gbuffer_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    int x, y;
    (void)worker;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) fill_texel(ctx, x, y);
}

int gbuffer_build(gbuffer *g, const scene *s, const camera *c, uint32_t seed, uint32_t sample, int jitter,
                  int threads, rerror *e)
{
    gbuffer_job job;
    g->width = c->width;
    g->height = c->height;
    g->texels = rcalloc((size_t)c->width * (size_t)c->height, sizeof *g->texels, e);
    if (!g->texels) return -1;
    job.g = g;
    job.s = s;
    job.c = c;
    job.seed = seed;
    job.sample = sample;
    job.jitter = jitter;
    parallel_tiles(c->width, c->height, 16, threads, gbuffer_tile, &job, NULL, NULL);
    return 0;
}

void gbuffer_free(gbuffer *g)
{
    free(g->texels);
    g->texels = NULL;
}

/* x1 of pixel p as the path sampler builds it from the frame's primary ray. */
int gbuffer_primary_vertex(const scene *s, const gbuffer *g, long p, path_vertex *v)
{
    const gbuffer_texel *t = &g->texels[p];
    if (!t->valid) return 0;
    path_vertex_make(v, s, &t->hit, v3_from_f(t->view_dir));
    return 1;
}
