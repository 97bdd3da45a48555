/* Benchmarks with machine-readable (JSON) output (`make bench`, docs/equal-time.md). */
#ifndef RESTIR_BENCH_BENCH_RAYS_H
#define RESTIR_BENCH_BENCH_RAYS_H

#include <stdint.h>
#include <stdio.h>
#include "restir/core/error.h"
#include "restir/scene/scene.h"

typedef struct {
    int width, height; /* primary ray grid: one jittered camera ray per pixel (512 x 512) */
    int repeats;       /* timed repetitions of every measurement; the MEDIAN is reported (5) */
    int threads;       /* thread count measured besides 1; 0 = threads_default() */
    uint32_t seed;     /* jitter, bounce directions and light points (RNG_TEST stream) */
} bench_rays_options;

void bench_rays_default_options(bench_rays_options *o);

/* The rays bench_rays times, for harnesses outside the build (tools/embree_bench). */
typedef struct {
    ray *rays;
    long count;
} bench_ray_set;
typedef struct {
    bench_ray_set primary, secondary, shadow;
} bench_ray_sets;
/* Generates the three ray sets described below (o->width x o->height primary rays). */
int bench_ray_sets_make(const scene *s, const bench_rays_options *o, bench_ray_sets *r, rerror *e);
void bench_ray_sets_free(bench_ray_sets *r);

/* Ray throughput of the scene's BVH (s must be prepared with scene_prepare) in Mrays/s:
 *   primary:   the camera's jittered rays through every pixel, closest hit;
 *   secondary: one cosine-distributed bounce about the geometric normal (turned to the
 *              side the camera ray came from) from every primary hit, closest hit;
 *   shadow:    from every primary hit to a uniform point on a uniformly chosen emissive
 *              triangle (or, without emitters, on a uniformly chosen face of the scene's
 *              bounding box), any hit, the very rays scene_visible traces
 *              (scene_visibility_ray).
 * All rays are generated before the clock starts: only traversal is timed. Each pass is
 * timed `repeats` times for 1 thread and for o->threads (if > 1); the BVH is also rebuilt
 * once to time the build. Writes one JSON object to json_out. */
int bench_rays(const scene *s, const bench_rays_options *o, FILE *json_out, rerror *e);

#endif
