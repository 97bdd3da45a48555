/* A second yardstick harness, written the way an outside sceptic would measure restir's BVH
 * against Embree 3 (issue 28: two harnesses gave 0.95 and 0.70 for the same bunny view).
 * It shares no code with embree_bench.c by design (a few small helpers, median and the
 * Embree scene upload, are written again here on purpose), and differs in what was
 * suspected to decide the figure:
 *   - rays: its own pinhole camera through pixel centres (no jitter), scanline order; the
 *     bounce and shadow rays are spawned from EMBREE's primary hits (its t, its geometric
 *     normal) with its own xorshift RNG: a cosine bounce and a shadow ray towards a fixed
 *     point above the scene's bounding box;
 *   - timing: wall clock (CLOCK_MONOTONIC) around the whole loop, including each side's
 *     conversion of the shared ray record into its own ray type, and beside it the thread's
 *     CPU time (the figure that survives a loaded machine);
 *   - order: all repetitions of one tracer, then all of the other (not interleaved), then the
 *     median of each tracer's Mrays/s, and ratio = median(restir) / median(Embree).
 * Embree: rtcIntersect1 / rtcOccluded1, default build quality and flags, threads=1.
 * Not part of the restir build (needs libembree-dev); see Makefile and docs/performance.md. */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "restir/scene/scene.h"

typedef struct {
    float o[3], d[3], tfar;
} plain_ray;

/* Both clocks of a pass: wall (what a sceptic on an idle machine reads) and this thread's
 * CPU time (what survives a shared, loaded machine). */
typedef struct {
    double wall, cpu;
} stamp;

static stamp now(void)
{
    struct timespec w, c;
    stamp t;
    clock_gettime(CLOCK_MONOTONIC, &w);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c);
    t.wall = (double)w.tv_sec + 1e-9 * (double)w.tv_nsec;
    t.cpu = (double)c.tv_sec + 1e-9 * (double)c.tv_nsec;
    return t;
}

/* Mrays per second of n rays since t0, by both clocks. */
static stamp rate_since(stamp t0, long n)
{
    stamp t = now(), r;
    r.wall = n / (t.wall - t0.wall) * 1e-6;
    r.cpu = n / (t.cpu - t0.cpu) * 1e-6;
    return r;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static uint32_t xorshift(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

static float unit(uint32_t *s) { return (float)(xorshift(s) >> 8) * (1.0f / 16777216.0f); }

static void normalize(float *v)
{
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross(const float *a, const float *b, float *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static RTCScene embree_scene(RTCDevice dev, const scene *s)
{
    RTCScene sc = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                       s->position_count);
    unsigned *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                           s->triangle_count);
    size_t i;
    for (i = 0; i < s->position_count; ++i)
        v[3 * i] = s->positions[i].x, v[3 * i + 1] = s->positions[i].y, v[3 * i + 2] = s->positions[i].z;
    for (i = 0; i < s->triangle_count; ++i)
        ix[3 * i] = s->triangles[i].v[0], ix[3 * i + 1] = s->triangles[i].v[1], ix[3 * i + 2] = s->triangles[i].v[2];
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    return sc;
}

/* Pixel-centre primary rays of the scene's camera, scanline order from the top row. */
static plain_ray *primary_rays(const scene *s, int w, int h)
{
    camera_pose c = scene_camera_at(s, 0);
    float eye[3] = {(float)c.eye.x, (float)c.eye.y, (float)c.eye.z};
    float fwd[3] = {(float)(c.target.x - c.eye.x), (float)(c.target.y - c.eye.y), (float)(c.target.z - c.eye.z)};
    float up[3] = {(float)c.up.x, (float)c.up.y, (float)c.up.z}, right[3], cam_up[3];
    float th = (float)tan(c.fov_y_degrees * 3.14159265358979 / 360.0), aspect = (float)w / (float)h;
    plain_ray *r = malloc((size_t)w * (size_t)h * sizeof *r);
    int x, y, k;
    normalize(fwd);
    cross(fwd, up, right);
    normalize(right);
    cross(right, fwd, cam_up);
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) {
            plain_ray *q = &r[(size_t)y * w + x];
            float sx = (2.0f * (x + 0.5f) / w - 1.0f) * th * aspect, sy = (1.0f - 2.0f * (y + 0.5f) / h) * th;
            for (k = 0; k < 3; ++k) q->o[k] = eye[k], q->d[k] = fwd[k] + sx * right[k] + sy * cam_up[k];
            normalize(q->d);
            q->tfar = INFINITY;
        }
    return r;
}

/* One Embree closest hit; returns 1 and the hit point and unit geometric normal (facing the ray). */
static int embree_hit(RTCScene sc, const plain_ray *q, float *p, float *n)
{
    struct RTCIntersectContext ctx;
    struct RTCRayHit rh;
    float d;
    int k;
    rtcInitIntersectContext(&ctx);
    memset(&rh, 0, sizeof rh);
    rh.ray.org_x = q->o[0], rh.ray.org_y = q->o[1], rh.ray.org_z = q->o[2];
    rh.ray.dir_x = q->d[0], rh.ray.dir_y = q->d[1], rh.ray.dir_z = q->d[2];
    rh.ray.tfar = q->tfar;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(sc, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    n[0] = rh.hit.Ng_x, n[1] = rh.hit.Ng_y, n[2] = rh.hit.Ng_z;
    normalize(n);
    d = n[0] * q->d[0] + n[1] * q->d[1] + n[2] * q->d[2];
    for (k = 0; k < 3; ++k) {
        if (d > 0) n[k] = -n[k];
        p[k] = q->o[k] + rh.ray.tfar * q->d[k] + 1e-4f * n[k];
    }
    return 1;
}

/* From every primary hit: a cosine-distributed bounce and a shadow ray to light_pos. */
static void secondary_rays(RTCScene sc, const plain_ray *prim, long n_prim, const float *light_pos, plain_ray **bounce,
                           plain_ray **shadow, long *count)
{
    uint32_t rng = 0x9e3779b9u;
    long i, m = 0;
    *bounce = malloc((size_t)n_prim * sizeof **bounce);
    *shadow = malloc((size_t)n_prim * sizeof **shadow);
    for (i = 0; i < n_prim; ++i) {
        float p[3], n[3], t[3], b[3], a[3] = {1, 0, 0}, u1, u2, r, phi, len;
        plain_ray *bo = &(*bounce)[m], *sh = &(*shadow)[m];
        int k;
        if (!embree_hit(sc, &prim[i], p, n)) continue;
        if (fabsf(n[0]) > 0.9f) a[0] = 0, a[1] = 1;
        cross(n, a, t);
        normalize(t);
        cross(n, t, b);
        u1 = unit(&rng), u2 = unit(&rng), r = sqrtf(u1), phi = 6.2831853f * u2;
        for (k = 0; k < 3; ++k) {
            bo->o[k] = sh->o[k] = p[k];
            bo->d[k] = r * cosf(phi) * t[k] + r * sinf(phi) * b[k] + sqrtf(1 - u1) * n[k];
            sh->d[k] = light_pos[k] - p[k];
        }
        normalize(bo->d);
        bo->tfar = INFINITY;
        len = sqrtf(sh->d[0] * sh->d[0] + sh->d[1] * sh->d[1] + sh->d[2] * sh->d[2]);
        normalize(sh->d);
        sh->tfar = len * 0.999f;
        ++m;
    }
    *count = m;
}

/* A point one box height above the centre of the top of the scene's bounding box. */
static void scene_light_above(const scene *s, float *light)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    size_t i;
    for (i = 0; i < s->position_count; ++i) {
        const float p[3] = {(float)s->positions[i].x, (float)s->positions[i].y, (float)s->positions[i].z};
        int k;
        for (k = 0; k < 3; ++k) lo[k] = p[k] < lo[k] ? p[k] : lo[k], hi[k] = p[k] > hi[k] ? p[k] : hi[k];
    }
    light[0] = 0.5f * (lo[0] + hi[0]);
    light[1] = hi[1] + (hi[1] - lo[1]);
    light[2] = 0.5f * (lo[2] + hi[2]);
}

/* "shuffled": the primary rays in a random order (Fisher-Yates, fixed seed), i.e. without the
 * coherence of scanline order, which both tracers otherwise enjoy. */
static void shuffle_rays(plain_ray *r, long n)
{
    uint32_t rng = 0x2545f491u;
    long i;
    for (i = n - 1; i > 0; --i) {
        long j = (long)(xorshift(&rng) % (uint32_t)(i + 1));
        plain_ray t = r[i];
        r[i] = r[j], r[j] = t;
    }
}

static stamp time_restir(const scene *s, const plain_ray *q, long n, int any, long *hits)
{
    stamp t0 = now();
    long i, h = 0;
    for (i = 0; i < n; ++i) {
        ray r;
        bvh_hit hit;
        r.origin.x = q[i].o[0], r.origin.y = q[i].o[1], r.origin.z = q[i].o[2];
        r.dir.x = q[i].d[0], r.dir.y = q[i].d[1], r.dir.z = q[i].d[2];
        r.tmin = 0, r.tmax = q[i].tfar;
        h += any ? bvh_occluded(&s->accel, &r) : bvh_intersect(&s->accel, &r, &hit);
    }
    *hits = h;
    return rate_since(t0, n);
}

static stamp time_embree(RTCScene sc, const plain_ray *q, long n, int any, long *hits)
{
    struct RTCIntersectContext ctx;
    stamp t0 = now();
    long i, h = 0;
    rtcInitIntersectContext(&ctx);
    for (i = 0; i < n; ++i) {
        struct RTCRayHit rh;
        rh.ray.org_x = q[i].o[0], rh.ray.org_y = q[i].o[1], rh.ray.org_z = q[i].o[2];
        rh.ray.dir_x = q[i].d[0], rh.ray.dir_y = q[i].d[1], rh.ray.dir_z = q[i].d[2];
        rh.ray.tnear = 0, rh.ray.tfar = q[i].tfar, rh.ray.time = 0, rh.ray.mask = 0xffffffffu;
        rh.ray.id = 0, rh.ray.flags = 0;
        if (any) {
            rtcOccluded1(sc, &ctx, &rh.ray);
            h += rh.ray.tfar < 0;
        } else {
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(sc, &ctx, &rh);
            h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    *hits = h;
    return rate_since(t0, n);
}

static void report(const char *kind, const scene *s, RTCScene sc, const plain_ray *q, long n, int any, int reps,
                   int last)
{
    double aw[64], bw[64], ac[64], bc[64];
    long ha = 0, hb = 0;
    int i;
    for (i = 0; i < reps; ++i) {
        stamp r = time_restir(s, q, n, any, &ha);
        aw[i] = r.wall, ac[i] = r.cpu;
    }
    for (i = 0; i < reps; ++i) {
        stamp r = time_embree(sc, q, n, any, &hb);
        bw[i] = r.wall, bc[i] = r.cpu;
    }
    printf("  {\"rays\": \"%s\", \"count\": %ld, \"restir_hits\": %ld, \"embree_hits\": %ld, "
           "\"wall\": {\"restir_mrays\": %.3f, \"embree_mrays\": %.3f, \"ratio\": %.3f}, "
           "\"cpu\": {\"restir_mrays\": %.3f, \"embree_mrays\": %.3f, \"ratio\": %.3f}}%s\n",
           kind, n, ha, hb, median(aw, reps), median(bw, reps), median(aw, reps) / median(bw, reps), median(ac, reps),
           median(bc, reps), median(ac, reps) / median(bc, reps), last ? "" : ",");
    fflush(stdout);
}

int main(int argc, char **argv)
{
    scene s;
    rerror e;
    int w = 1024, h = 1024, reps = 7, shuffled = 0;
    RTCDevice dev;
    RTCScene sc;
    plain_ray *prim, *bounce, *shadow;
    long n2;
    float light[3];
    if (argc < 2 || (argc > 2 && sscanf(argv[2], "%dx%d", &w, &h) != 2) || (argc > 3 && (reps = atoi(argv[3])) < 1) ||
        reps > 64 || (argc > 4 && !(shuffled = !strcmp(argv[4], "shuffled"))) || argc > 5) {
        fprintf(stderr, "usage: sceptic_bench SCENE [WxH] [REPEATS 1..64] [shuffled]\n");
        return 2;
    }
    memset(&s, 0, sizeof s);
    if (scene_load(&s, argv[1], &e) || (s.accel.node_count == 0 && scene_prepare(&s, &e))) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    dev = rtcNewDevice("threads=1");
    sc = embree_scene(dev, &s);
    prim = primary_rays(&s, w, h);
    scene_light_above(&s, light);
    secondary_rays(sc, prim, (long)w * h, light, &bounce, &shadow, &n2);
    if (shuffled) shuffle_rays(prim, (long)w * h);
    printf("{\"harness\": \"sceptic_bench\", \"scene\": \"%s\", \"image\": [%d, %d], \"repeats\": %d, \"primary_order\": \"%s\", "
           "\"timing\": \"wall clock and thread CPU time, each tracer's repetitions in a row, medians\",\n"
           " \"embree\": \"%d.%d.%d rtcIntersect1/rtcOccluded1, default build quality, threads=1\",\n \"results\": [\n",
           argv[1], w, h, reps, shuffled ? "shuffled" : "scanline", RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH);
    report("primary", &s, sc, prim, (long)w * h, 0, reps, 0);
    report("diffuse_bounce", &s, sc, bounce, n2, 0, reps, 0);
    report("shadow", &s, sc, shadow, n2, 1, reps, 1);
    printf(" ]}\n");
    free(prim), free(bounce), free(shadow);
    rtcReleaseScene(sc);
    rtcReleaseDevice(dev);
    scene_free(&s);
    return 0;
}
