/* Ray-throughput benchmark: primary, diffuse secondary and shadow rays. */
#include "restir/bench/bench_rays.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "restir/core/json_text.h"
#include "restir/core/rng.h"
#include "restir/core/threads.h"
#include "restir/core/warp.h"
#include "restir/render/camera.h"
#include "restir/scene/scene_trace.h"

void bench_rays_default_options(bench_rays_options *o)
{
    o->width = 512;
    o->height = 512;
    o->repeats = 5;
    o->threads = 0;
    o->seed = 1;
}

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ------------------------------------------------------------------------------- */
/* Ray generation (untimed)                                                         */

typedef bench_ray_set ray_set;

static real random_at(const bench_rays_options *o, long pixel, uint32_t slot)
{
    return rng_uniform(rng_key_at(rng_key_make(o->seed, (uint32_t)pixel, 0), RNG_TEST, 0, slot));
}

static void make_primary_rays(const scene *s, const bench_rays_options *o, ray_set *out)
{
    camera cam;
    long x, y;
    camera_init(&cam, s->has_camera ? scene_camera_at(s, 0) : scene_frame_bounds(s), o->width, o->height);
    out->count = 0;
    for (y = 0; y < o->height; ++y) {
        for (x = 0; x < o->width; ++x) {
            long pixel = y * o->width + x;
            out->rays[out->count++] = camera_ray(&cam, x + random_at(o, pixel, 0), y + random_at(o, pixel, 1));
        }
    }
}

/* Cosine-distributed direction about n. */
static vec3f cosine_direction(vec3f n, vec2 u)
{
    vec3 t, b, nn = v3_from_f(n), l = warp_cosine_hemisphere(u);
    v3_basis(nn, &t, &b);
    return v3f_from(v3_add(v3_add(v3_scale(t, l.x), v3_scale(b, l.y)), v3_scale(nn, l.z)));
}

/* Emissive triangles, or NULL/0 when the scene has none. */
static uint32_t *emissive_triangles(const scene *s, long *count, rerror *e)
{
    uint32_t *list = rmalloc(s->triangle_count, sizeof *list, e);
    size_t i;
    *count = 0;
    if (!list) return NULL;
    for (i = 0; i < s->triangle_count; ++i) {
        uint32_t m = s->triangles[i].material;
        if (m < s->material_count && !rgb_is_black(s->materials[m].emission)) list[(*count)++] = (uint32_t)i;
    }
    return list;
}

/* A shadow-ray target: a uniform point on a random emitter, or on a random face of the
 * bounding box. Sets *has_normal when the target lies on a surface. */
static vec3f shadow_target(const scene *s, const uint32_t *emitters, long emitter_count, long pixel,
                           const bench_rays_options *o, vec3f *normal, int *has_normal)
{
    real u0 = random_at(o, pixel, 4), u1 = random_at(o, pixel, 5), u2 = random_at(o, pixel, 6);
    if (emitter_count > 0) {
        long pick = (long)(u0 * emitter_count);
        const triangle *t = &s->triangles[emitters[pick < emitter_count ? pick : emitter_count - 1]];
        vec3f a = s->positions[t->v[0]], b = s->positions[t->v[1]], c = s->positions[t->v[2]];
        vec2 bary = warp_uniform_triangle(v2(u1, u2));
        *normal = v3f_normalize(v3f_cross(v3f_sub(b, a), v3f_sub(c, a)));
        *has_normal = 1;
        return v3f_add(v3f_add(v3f_scale(a, (float)bary.x), v3f_scale(b, (float)bary.y)),
                       v3f_scale(c, (float)(1 - bary.x - bary.y)));
    } else {
        int face = (int)(u0 * 6) % 6, axis = face % 3;
        float p[3], lo[3], hi[3];
        memcpy(lo, &s->bounds_min, sizeof lo);
        memcpy(hi, &s->bounds_max, sizeof hi);
        p[axis] = face < 3 ? lo[axis] : hi[axis];
        p[(axis + 1) % 3] = lo[(axis + 1) % 3] + (float)u1 * (hi[(axis + 1) % 3] - lo[(axis + 1) % 3]);
        p[(axis + 2) % 3] = lo[(axis + 2) % 3] + (float)u2 * (hi[(axis + 2) % 3] - lo[(axis + 2) % 3]);
        *has_normal = 0;
        return v3f(p[0], p[1], p[2]);
    }
}

/* Secondary and shadow rays from the primary hits. */
static int make_hit_rays(const scene *s, const bench_rays_options *o, const ray_set *primary, ray_set *secondary,
                         ray_set *shadow, rerror *e)
{
    long i, emitter_count;
    uint32_t *emitters = emissive_triangles(s, &emitter_count, e);
    if (!emitters) return -1;
    secondary->count = shadow->count = 0;
    for (i = 0; i < primary->count; ++i) {
        surface_hit h;
        vec3f n, target, target_n;
        int has_n;
        if (!scene_intersect(s, &primary->rays[i], &h)) continue;
        n = v3f_dot(h.ng, primary->rays[i].dir) > 0 ? v3f_scale(h.ng, -1.0f) : h.ng;
        secondary->rays[secondary->count++] =
            scene_spawn_ray(h.position, h.ng, cosine_direction(n, v2(random_at(o, i, 2), random_at(o, i, 3))),
                            v3f_scale(primary->rays[i].dir, -1.0f));
        target = shadow_target(s, emitters, emitter_count, i, o, &target_n, &has_n);
        shadow->rays[shadow->count] = scene_visibility_ray(h.position, h.ng, target, has_n ? &target_n : NULL);
        shadow->count++;
    }
    free(emitters);
    return 0;
}

void bench_ray_sets_free(bench_ray_sets *r)
{
    free(r->primary.rays);
    free(r->secondary.rays);
    free(r->shadow.rays);
    memset(r, 0, sizeof *r);
}

int bench_ray_sets_make(const scene *s, const bench_rays_options *o, bench_ray_sets *r, rerror *e)
{
    size_t pixels = (size_t)o->width * (size_t)o->height;
    memset(r, 0, sizeof *r);
    r->primary.rays = rmalloc(pixels, sizeof(ray), e);
    r->secondary.rays = rmalloc(pixels, sizeof(ray), e);
    r->shadow.rays = rmalloc(pixels, sizeof(ray), e);
    if (!r->primary.rays || !r->secondary.rays || !r->shadow.rays) goto fail;
    make_primary_rays(s, o, &r->primary);
    if (make_hit_rays(s, o, &r->primary, &r->secondary, &r->shadow, e)) goto fail;
    return 0;
fail:
    bench_ray_sets_free(r);
    return -1;
}

/* ------------------------------------------------------------------------------- */
/* Timed passes                                                                     */

typedef struct {
    const bvh *accel;
    const ray *rays;
    unsigned char *answers; /* written so the work cannot be optimised away */
    int any_hit;
} pass;

static void trace_one(void *ctx, long i, int worker)
{
    pass *p = ctx;
    (void)worker;
    if (p->any_hit) {
        p->answers[i] = (unsigned char)bvh_occluded(p->accel, &p->rays[i]);
    } else {
        bvh_hit h;
        p->answers[i] = (unsigned char)bvh_intersect(p->accel, &p->rays[i], &h);
    }
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof v[0], compare_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* CPU time of the whole process (all threads). */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct {
    double mrays;          /* rays per wall-clock second: the throughput */
    double mrays_per_core; /* rays per CPU second: insensitive to other load on the machine */
} rate;

/* Medians over `repeats` runs. */
static rate time_pass(const bvh *accel, const ray_set *set, int any_hit, int threads, int repeats,
                      unsigned char *answers)
{
    double wall[64], cpu[64];
    rate result = {0, 0};
    pass p;
    int r;
    if (set->count == 0) return result;
    if (repeats > 64) repeats = 64;
    p.accel = accel;
    p.rays = set->rays;
    p.answers = answers;
    p.any_hit = any_hit;
    for (r = 0; r < repeats; ++r) {
        double w0 = wall_seconds(), c0 = cpu_seconds();
        parallel_items(set->count, threads, trace_one, &p);
        wall[r] = set->count / (wall_seconds() - w0) * 1e-6;
        cpu[r] = set->count / (cpu_seconds() - c0) * 1e-6;
    }
    result.mrays = median(wall, repeats);
    result.mrays_per_core = median(cpu, repeats);
    return result;
}

/* Times a fresh build of the scene's BVH (single-threaded, as scene_prepare does it). */
static int time_build(const scene *s, double *seconds, rerror *e)
{
    vec3f *corners = rmalloc(3 * s->triangle_count, sizeof *corners, e);
    bvh fresh;
    size_t i;
    int k;
    double t0;
    if (!corners) return -1;
    for (i = 0; i < s->triangle_count; ++i)
        for (k = 0; k < 3; ++k) corners[3 * i + k] = s->positions[s->triangles[i].v[k]];
    t0 = wall_seconds();
    if (bvh_build(&fresh, corners, s->triangle_count, e)) {
        free(corners);
        return -1;
    }
    *seconds = wall_seconds() - t0;
    bvh_free(&fresh);
    free(corners);
    return 0;
}

int bench_rays(const scene *s, const bench_rays_options *o, FILE *json_out, rerror *e)
{
    long pixels = (long)o->width * o->height;
    ray_set primary, secondary, shadow;
    unsigned char *answers;
    double build_seconds = 0;
    int thread_counts[2], runs = 1, t;
    int repeats = o->repeats < 1 ? 1 : o->repeats;

    if (o->width < 1 || o->height < 1) return rerror_set(e, "bench rays: image size must be positive");
    if (s->triangle_count == 0) return rerror_at(e, s->path, 0, "scene has no triangles");
    if (s->accel.node_count == 0)
        return rerror_at(e, s->path, 0, "scene has no BVH (not prepared, or only degenerate triangles)");
    primary.rays = rmalloc((size_t)pixels, sizeof(ray), e);
    secondary.rays = rmalloc((size_t)pixels, sizeof(ray), e);
    shadow.rays = rmalloc((size_t)pixels, sizeof(ray), e);
    answers = rmalloc((size_t)pixels, 1, e);
    if (!primary.rays || !secondary.rays || !shadow.rays || !answers) goto fail;
    make_primary_rays(s, o, &primary);
    if (make_hit_rays(s, o, &primary, &secondary, &shadow, e)) goto fail;
    if (threads_cancelled()) { /* a stop (SIGINT): skip the timed BVH build (1M triangles: 1 s) */
        rerror_set(e, "bench rays: cancelled");
        goto fail;
    }
    if (time_build(s, &build_seconds, e)) goto fail;

    thread_counts[0] = 1;
    thread_counts[1] = o->threads > 0 ? o->threads : threads_default();
    if (thread_counts[1] > 1) runs = 2;

    fprintf(json_out, "{\"scene\": ");
    json_put_string(json_out, s->path);
    fprintf(json_out,
            ", \"triangles\": %zu,\n \"bvh\": {\"nodes\": %zu, \"depth\": %d, \"sah_cost\": %.4f, "
            "\"leaf_triangles\": %zu, \"build_seconds\": %.4f, \"wide_nodes\": %zu, \"leaf_blocks\": %zu, "
            "\"bytes_per_triangle\": %.1f, \"wide_sah_cost\": %.4f},\n",
            s->triangle_count, s->accel.node_count, s->accel.depth, s->accel.sah_cost, s->accel.prim_count,
            build_seconds, s->accel.wide_count, s->accel.block_count,
            (double)bvh_memory_bytes(&s->accel) / (double)(s->accel.prim_count ? s->accel.prim_count : 1),
            bvh_wide_sah_cost(&s->accel));
    fprintf(json_out,
            " \"image\": [%d, %d], \"repeats\": %d, \"statistic\": \"median\", \"primary_rays\": %ld, "
            "\"secondary_rays\": %ld, \"shadow_rays\": %ld,\n \"results\": [",
            o->width, o->height, repeats, primary.count, secondary.count, shadow.count);
    for (t = 0; t < runs; ++t) {
        int threads = thread_counts[t];
        rate p = time_pass(&s->accel, &primary, 0, threads, repeats, answers);
        rate q = time_pass(&s->accel, &secondary, 0, threads, repeats, answers);
        rate r = time_pass(&s->accel, &shadow, 1, threads, repeats, answers);
        fprintf(json_out,
                "%s\n  {\"threads\": %d, \"primary_mrays\": %.3f, \"secondary_mrays\": %.3f, \"shadow_mrays\": %.3f,"
                "\n   \"per_core\": {\"primary_mrays\": %.3f, \"secondary_mrays\": %.3f, \"shadow_mrays\": %.3f}}",
                t ? "," : "", threads, p.mrays, q.mrays, r.mrays, p.mrays_per_core, q.mrays_per_core, r.mrays_per_core);
    }
    fprintf(json_out, "\n ]}\n");
    free(primary.rays);
    free(secondary.rays);
    free(shadow.rays);
    free(answers);
    return 0;
fail:
    free(primary.rays);
    free(secondary.rays);
    free(shadow.rays);
    free(answers);
    return -1;
}
