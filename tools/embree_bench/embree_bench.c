/* Yardstick: restir's BVH (bvh_intersect / bvh_occluded) against Embree 3
 * (rtcIntersect1 / rtcOccluded1) on the very same rays (bench_ray_sets_make: the rays of
 * `restir bench rays`), one thread, in one process. Repetitions alternate A, B, A, B, ...
 * so that both see the same load on a shared machine; every repetition gives a ratio
 * restir/Embree, and the median ratio with its min..max spread is reported, next to the
 * median Mrays/s of each (per CPU second of the thread). Also counts the rays on which the two disagree about hit/miss
 * (watertightness and the conservative boxes make restir's answer the exact one; Embree's
 * default build is not watertight, so a handful of edge rays may differ).
 *
 * Not part of the restir build (needs libembree-dev); see Makefile and docs/performance.md. */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "restir/bench/bench_rays.h"
#include "restir/scene/generate.h"
#include "restir/scene/scene.h"

/* CPU time of this thread (both tracers run on it: Embree's device has threads=1 and
 * rtcIntersect1/rtcOccluded1 run in the caller): time spent waiting for a core on a
 * shared machine is not counted. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
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

static RTCScene embree_scene(RTCDevice dev, const scene *s)
{
    RTCScene sc = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                       s->position_count);
    unsigned *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                           s->triangle_count);
    size_t i;
    for (i = 0; i < s->position_count; ++i) {
        v[3 * i] = s->positions[i].x;
        v[3 * i + 1] = s->positions[i].y;
        v[3 * i + 2] = s->positions[i].z;
    }
    for (i = 0; i < s->triangle_count; ++i) {
        ix[3 * i] = s->triangles[i].v[0];
        ix[3 * i + 1] = s->triangles[i].v[1];
        ix[3 * i + 2] = s->triangles[i].v[2];
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    return sc;
}

static void to_embree(const ray *r, struct RTCRay *e)
{
    e->org_x = r->origin.x, e->org_y = r->origin.y, e->org_z = r->origin.z;
    e->dir_x = r->dir.x, e->dir_y = r->dir.y, e->dir_z = r->dir.z;
    e->tnear = r->tmin;
    e->tfar = r->tmax;
    e->time = 0;
    e->mask = 0xffffffffu;
    e->id = 0;
    e->flags = 0;
}

/* One timed pass; returns Mrays/s and writes hit flags. */
static double pass_restir(const scene *s, const bench_ray_set *set, int any, unsigned char *hit)
{
    double t0 = now();
    long i;
    for (i = 0; i < set->count; ++i) {
        bvh_hit h;
        hit[i] = (unsigned char)(any ? bvh_occluded(&s->accel, &set->rays[i]) : bvh_intersect(&s->accel, &set->rays[i], &h));
    }
    return set->count / (now() - t0) * 1e-6;
}

static double pass_embree(RTCScene sc, const bench_ray_set *set, int any, unsigned char *hit)
{
    struct RTCIntersectContext ctx;
    double t0;
    long i;
    rtcInitIntersectContext(&ctx);
    t0 = now();
    for (i = 0; i < set->count; ++i) {
        if (any) {
            struct RTCRay r;
            to_embree(&set->rays[i], &r);
            rtcOccluded1(sc, &ctx, &r);
            hit[i] = r.tfar < 0;
        } else {
            struct RTCRayHit rh;
            to_embree(&set->rays[i], &rh.ray);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(sc, &ctx, &rh);
            hit[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return set->count / (now() - t0) * 1e-6;
}

int main(int argc, char **argv)
{
    scene s;
    rerror e;
    bench_rays_options o;
    bench_ray_sets rs;
    const char *kinds[3] = {"primary", "diffuse_bounce", "shadow"};
    int repeats = 9, i, k, generated = 0;
    const char *path = NULL;
    RTCDevice dev;
    RTCScene sc;
    double tb;

    bench_rays_default_options(&o);
    o.width = o.height = 1024;
    for (i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--size") && i + 1 < argc && sscanf(argv[i + 1], "%dx%d", &o.width, &o.height) == 2) ++i;
        else if (!strcmp(argv[i], "--repeats") && i + 1 < argc) repeats = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--generated") && i + 1 < argc) generated = atoi(argv[++i]);
        else if (argv[i][0] != '-') path = argv[i];
        else {
            fprintf(stderr, "usage: embree_bench SCENE|--generated N [--size WxH] [--repeats N]\n");
            return 2;
        }
    }
    if (repeats < 1 || repeats > 64 || (!path && !generated)) {
        fprintf(stderr, "usage: embree_bench SCENE|--generated N [--size WxH] [--repeats 1..64]\n");
        return 2;
    }
    memset(&s, 0, sizeof s);
    if (generated ? generate_displaced_sphere(&s, generated, &e) || scene_prepare(&s, &e)
                  : scene_load(&s, path, &e) || (s.accel.node_count == 0 && scene_prepare(&s, &e))) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (bench_ray_sets_make(&s, &o, &rs, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    dev = rtcNewDevice("threads=1");
    tb = now();
    sc = embree_scene(dev, &s);
    tb = now() - tb;
    printf("{\"scene\": \"%s\", \"triangles\": %zu, \"image\": [%d, %d], \"repeats\": %d, \"threads\": 1,\n"
           " \"embree\": \"%d.%d.%d rtcIntersect1/rtcOccluded1, default build quality, build %.3f s CPU\",\n"
           " \"statistic\": \"median of per-repetition ratios (A/B interleaved), min..max\",\n \"results\": [",
           generated ? "generated:displaced_sphere" : path, s.triangle_count, o.width, o.height, repeats,
           RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH, tb);
    for (k = 0; k < 3; ++k) {
        const bench_ray_set *set = k == 0 ? &rs.primary : (k == 1 ? &rs.secondary : &rs.shadow);
        unsigned char *ha = malloc((size_t)set->count + 1), *hb = malloc((size_t)set->count + 1);
        double ra[64], rb[64], ratio[64], lo, hi, m;
        long differ = 0, hits = 0, j;
        for (i = 0; i < repeats; ++i) {
            /* Alternate which one goes first, too. */
            if (i % 2) {
                rb[i] = pass_embree(sc, set, k == 2, hb);
                ra[i] = pass_restir(&s, set, k == 2, ha);
            } else {
                ra[i] = pass_restir(&s, set, k == 2, ha);
                rb[i] = pass_embree(sc, set, k == 2, hb);
            }
            ratio[i] = ra[i] / rb[i];
        }
        for (j = 0; j < set->count; ++j) {
            differ += ha[j] != hb[j];
            hits += ha[j];
        }
        m = median(ratio, repeats);
        lo = ratio[0];
        hi = ratio[repeats - 1];
        printf("%s\n  {\"rays\": \"%s\", \"count\": %ld, \"hits\": %ld, \"hit_disagreements\": %ld, "
               "\"restir_mrays\": %.3f, \"embree_mrays\": %.3f, \"ratio\": %.3f, \"ratio_min\": %.3f, \"ratio_max\": %.3f}",
               k ? "," : "", kinds[k], set->count, hits, differ, median(ra, repeats), median(rb, repeats), m, lo, hi);
        fflush(stdout);
        free(ha);
        free(hb);
    }
    printf("\n ]}\n");
    rtcReleaseScene(sc);
    rtcReleaseDevice(dev);
    bench_ray_sets_free(&rs);
    scene_free(&s);
    return 0;
}
