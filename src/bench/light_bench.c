/* The cost of light selection for NEE, plain vs light RIS (include/restir/bench/light_bench.h;
 * docs/enhanced.md §6, docs/cli.md "bench"). */
#include "restir/bench/light_bench.h"

#include <stdlib.h>
#include "restir/core/progress.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/render/light_ris.h"
#include "restir/scene/scene_trace.h"

/* The primary hits of a 64 × 64 grid of the scene's camera (pixel centres). */
static int primary_vertices(const scene *s, path_vertex **out, rerror *e)
{
    const int n = 64;
    camera cam;
    int x, y, count = 0;
    *out = rmalloc((size_t)n * n, sizeof **out, e);
    if (!*out) return -1;
    camera_init(&cam, scene_camera_at(s, 0), n, n);
    for (y = 0; y < n; ++y)
        for (x = 0; x < n; ++x) {
            ray r = primary_ray(&cam, x, y, 0, 0, 0);
            surface_hit h;
            if (!scene_intersect(s, &r, &h)) continue;
            path_vertex_make(&(*out)[count], s, &h, v3_from_f(r.dir));
            if ((*out)[count].can_nee) ++count;
        }
    return count;
}

/* ns per NEE sample at x1 (selection, evaluation and the one shadow ray), `rounds` samples per
 * vertex; *lit: the fraction of samples that return light. */
static double ns_per_nee(const path_context *c, const path_vertex *v, int count, int rounds, double *lit)
{
    double t0 = now_seconds(), hits = 0;
    int i, k;
    for (k = 0; k < rounds; ++k)
        for (i = 0; i < count; ++i) {
            nee_sample n;
            { rng_key key = rng_key_make(7, (uint32_t)i, (uint32_t)k); hits += vertex_sample_light(c, &v[i], &key, 1, &n); }
        }
    *lit = hits / ((double)rounds * count);
    return 1e9 * (now_seconds() - t0) / ((double)rounds * count);
}

int bench_light_selection(FILE *out, const scene *s, const char *name, int light_ris, int light_tiles, rerror *e)
{
    light_set ls;
    path_context c = {0};
    path_vertex *v = NULL;
    light_sample *table;
    double plain_ns, ris_ns, plain_lit, ris_lit, t0, build_ms;
    uint32_t t, entry;
    int count, k;
    if (lights_build(&ls, s, e)) return -1;
    if ((count = primary_vertices(s, &v, e)) < 0) {
        lights_free(&ls);
        return -1;
    }
    table = rmalloc((size_t)LIGHT_TILE_COUNT * LIGHT_TILE_SIZE, sizeof *table, e);
    if (!table || count == 0 || ls.count == 0) {
        if (table && !count) rerror_set(e, "bench: %s: no primary hit can do NEE", name);
        if (table && count && !ls.count) rerror_set(e, "bench: %s: no emitters", name);
        free(table);
        free(v);
        lights_free(&ls);
        return -1;
    }
    c.scene = s;
    c.lights = &ls;
    c.strategy = PT_STRATEGY_MIS;
    c.image_width = 64;
    /* Interleaved repetitions, the minimum of each: the machine may be shared. */
    plain_ns = ris_ns = 1e300;
    for (t = 0; t < 5; ++t) {
        double ns;
        c.light_ris = c.light_tiles = 0;
        if ((ns = ns_per_nee(&c, v, count, 4, &plain_lit)) < plain_ns) plain_ns = ns;
        c.light_ris = light_ris;
        c.light_tiles = light_tiles;
        if ((ns = ns_per_nee(&c, v, count, 1, &ris_lit)) < ris_ns) ris_ns = ns;
    }
    /* What a per-frame table of the tiles would cost to fill (the code looks entries up by
     * address instead; docs/enhanced.md §6.4). */
    build_ms = 1e300;
    for (k = 0; k < 3; ++k) {
        t0 = now_seconds();
        for (t = 0; t < LIGHT_TILE_COUNT; ++t)
            for (entry = 0; entry < LIGHT_TILE_SIZE; ++entry)
                light_tile_entry(&ls, 1, (uint32_t)k, t, entry, &table[(size_t)t * LIGHT_TILE_SIZE + entry]);
        if (1e3 * (now_seconds() - t0) < build_ms) build_ms = 1e3 * (now_seconds() - t0);
    }
    fprintf(out,
            "  {\"bench\": \"light_selection\", \"scene\": \"%s\", \"lights\": %lu, \"vertices\": %d, "
            "\"light_ris\": %d, \"light_tiles\": %s,\n   \"ns_per_nee_sample\": {\"plain\": %.1f, \"light_ris\": %.1f}, "
            "\"unoccluded_nonzero\": {\"plain\": %.4f, \"light_ris\": %.4f}, \"tile_build_ms\": %.3f}",
            name, (unsigned long)ls.count, count, light_ris, light_tiles ? "true" : "false", plain_ns, ris_ns, plain_lit,
            ris_lit, build_ms);
    free(table);
    free(v);
    lights_free(&ls);
    return 0;
}
