/* Evidence for light RIS's NEE/BSDF MIS (issue 26; light_ris.h, docs/enhanced.md §6): the
 * direct light at single shading points, integrated by the path sampler's two techniques
 * combined with the balance heuristic, where a BSDF-sampled emitter hit takes the RIS pdf
 * estimate p̃(y; {y} ∪ Z') of light_ris_pdf_hit. For every candidate count N, with and
 * without light tiles, the RIS combination must integrate to the same value as the plain
 * combination (light_ris = 0), per channel. The two are paired on the same numbers (the
 * BSDF side is identical, NEE candidate 0 is the plain sampler's light): batch k of A and
 * of B use the same path keys. A wrong MIS pdf at BSDF hits (the next bounce's candidate
 * count: mutant light-ris-pdf-hit-next-count; the NEE side's own candidates instead of fresh
 * ones: light-ris-pdf-hit-reuses-nee-candidates) breaks the partition of unity of the two
 * weights in expectation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "restir/scene/lights.h"
#include "restir/render/light_ris.h"
#include "restir/frame/options.h"
#include "pt_util.h"
#include "restir_util.h"
#include "test.h"
#include "restir/scene/scene_trace.h"

/* Shading points: primary hits of a few pixels of many-lights (glossy floor, pillars,
 * copper) at 32 x 32. For each (N, tiles): `batches` batches of `per_batch` samples per
 * point; batch k of A (RIS) and B (plain) use the same keys. */
static void integrate(int n, int tiles, int batches, int per_batch, bench_paired *p, char *name, size_t name_size)
{
    static const int px[][2] = {{16, 28}, {8, 26}, {24, 22}, {12, 18}};
    scene s;
    light_set lights;
    restir_context ca, cb;
    restir_options o;
    path_vertex v[4];
    uint32_t point_id[4];
    int nv = 0, i;
    snprintf(name, name_size, "light RIS N %d%s vs plain NEE, MIS at 4 shading points of many-lights", n,
             tiles ? " tiles" : "");
    bench_paired_init(p, name);
    if (rt_load_scene_lights("scenes/many-lights.scene", 32, &s, &lights)) return;
    restir_options_default(&o);
    restir_context_for(&cb, &s, &lights, &o);
    o.light_ris.candidates = n;
    o.light_ris.tiles = tiles;
    restir_context_for(&ca, &s, &lights, &o);
    for (i = 0; i < 4; ++i)
        if (rt_primary_vertex(&s, px[i][0], px[i][1], &v[nv])) ++nv;
    CHECKF(nv >= 3, "only %d shading points", nv);
    for (i = 0; i < nv; ++i) point_id[i] = (uint32_t)(px[i][1] * 32 + px[i][0]);
    test_direct_mis_paired_batches(p, &ca.path, &cb.path, v, point_id, nv, test_seed() * 7u + 3u, batches, per_batch);
    bench_paired_finish(p);
    lights_free(&lights);
    scene_free(&s);
}

static void matrix(const int *counts, int nc, int batches, int per_batch, int with_tiles)
{
    int i, tiles;
    for (tiles = 0; tiles <= with_tiles && !test_has_failed(); ++tiles)
        for (i = 0; i < nc && !test_has_failed(); ++i) {
            bench_paired p;
            char name[160];
            integrate(counts[i], tiles, batches, per_batch, &p, name, sizeof name);
            if (!test_has_failed()) bench_paired_expect_consistent(&p, BENCH_Z_CONSISTENT);
        }
}

/* 10^6 samples per configuration (64 x 4096 at each of the 4 points), every candidate count 1..64. */
TEST_LONG(evidence_light_ris_mis_pdf_single_points_long)
{
    static const int counts[] = {1, 2, 4, 8, 16, 32, 64};
    matrix(counts, 7, 64, 4096, 1);
}

/* ---- the BSDF side's pdf estimate against its definition, exact ---------------------------- */

/* p̂(z)/p_0(z) at v (solid angle), recomputed from the public pieces; *phat = p̂(z). */
static double ratio_at(const path_context *c, const path_vertex *v, const light_sample *z, double *phat)
{
    vec3 p = v3_from_f(z->position), n = v3_from_f(z->normal), d = v3_sub(p, v->position), wi;
    double dist = (double)v3_length(d), p0, ph;
    *phat = 0;
    if (!(dist > 0)) return 0;
    wi = v3_scale(d, (real)(1 / dist));
    ph = (double)luminance(rgb_mul(path_vertex_eval(v, wi), light_emitted(z->emission, n, v3_neg(wi))));
    p0 = (double)path_light_pdf(c, z->triangle, v->position, p, n);
    *phat = ph;
    return p0 > 0 && ph > 0 ? ph / p0 : 0;
}

/* docs/enhanced.md §6: p̃(y; {y} ∪ Z') = p̂(y) M / (r(y) + sum over the M - 1 candidates z'_j
 * of r(z'_j)), M = max(1, N / i^2) at x_i (N at x_1), the z'_j fresh samples of p_0 from the
 * path's RNG_NEE slots 8192 + 4j (with tiles: slot 8192 + 4j picks an entry e of the virtual
 * tile; e = 0 is y itself, else the sample of slots 16384 + 4e). */
static double pdf_hit_by_definition(const path_context *c, const path_vertex *v, rng_key key, uint32_t i,
                                    const light_sample *y)
{
    int n = c->light_ris, m = i <= 1 ? n : n / (int)(i * i), j;
    double phat, r_y = ratio_at(c, v, y, &phat), sum = r_y;
    if (m < 1) m = 1;
    if (!(r_y > 0)) return 0;
    for (j = 0; j + 1 < m; ++j) {
        uint32_t slot = 8192u + 4u * (uint32_t)j;
        light_sample z;
        real u[4];
        double ph;
        if (c->light_tiles) {
            uint32_t e = (uint32_t)(rng_u(key, RNG_NEE, i, slot) * (real)LIGHT_TILE_SIZE);
            if (e >= LIGHT_TILE_SIZE) e = LIGHT_TILE_SIZE - 1;
            if (e == 0) {
                sum += r_y;
                continue;
            }
            slot = 16384u + 4u * e;
        }
        rng_u_slots(key, RNG_NEE, i, slot, 4, u);
        if (light_sample_point(c->lights, u, &z)) sum += ratio_at(c, v, &z, &ph);
    }
    return phat * m / sum;
}

/* light_ris_pdf_hit (what a BSDF-sampled emitter hit's MIS weight uses) equals its definition
 * at 4 shading points of many-lights, for every candidate count 1..64 of the schedule at
 * vertices x_1..x_3, with and without tiles, 300 light points y each: relative 1e-9
 * (double; 1e-4 float). Catches a wrong candidate count and a candidate set other than the
 * fresh one exactly. */
TEST(evidence_light_ris_pdf_hit_by_definition_exact)
{
    static const int px[][2] = {{16, 28}, {8, 26}, {24, 22}, {12, 18}};
    static const int counts[] = {1, 2, 3, 4, 8, 16, 32, 64};
    scene s;
    light_set lights;
    double tol = sizeof(real) == 4 ? 1e-4 : 1e-9, worst = 0;
    long checked = 0;
    int p, ci, tiles, k;
    uint32_t i;
    if (rt_load_scene_lights("scenes/many-lights.scene", 32, &s, &lights)) return;
    for (p = 0; p < 4 && !test_has_failed(); ++p) {
        path_vertex v;
        if (!rt_primary_vertex(&s, px[p][0], px[p][1], &v)) continue;
        for (tiles = 0; tiles < 2; ++tiles)
            for (ci = 0; ci < 8; ++ci)
                for (i = 1; i <= 3; ++i) {
                    restir_options o;
                    restir_context c;
                    restir_options_default(&o);
                    o.light_ris.candidates = counts[ci];
                    o.light_ris.tiles = tiles;
                    restir_context_for(&c, &s, &lights, &o);
                    for (k = 0; k < 300; ++k) {
                        rng_key key = rng_key_make(test_seed() + 5u, (uint32_t)(px[p][1] * 32 + px[p][0]), (uint32_t)k);
                        light_sample y;
                        real u[4];
                        double want, got;
                        rng_u_slots(key, RNG_TEST, i, 0, 4, u);
                        if (!light_sample_point(&lights, u, &y)) continue;
                        want = pdf_hit_by_definition(&c.path, &v, key, i, &y);
                        got = (double)light_ris_pdf_hit(&c.path, &v, key, i, y.triangle, v3_from_f(y.position),
                                                        v3_from_f(y.normal));
                        if (want == 0 && got == 0) continue;
                        ++checked;
                        if (fabs(got - want) > worst * fabs(want)) worst = fabs(got - want) / fabs(want);
                        CHECKF(fabs(got - want) <= tol * fabs(want),
                               "point %d, N %d%s, x_%u: light_ris_pdf_hit %.12g, by definition %.12g", p, counts[ci],
                               tiles ? " tiles" : "", i, got, want);
                    }
                }
    }
    lights_free(&lights);
    scene_free(&s);
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  %ld pdfs compared, worst relative difference %.3g\n", checked, worst);
    CHECKF(checked >= 10000, "only %ld pdfs compared", checked);
}

/* ---- the path tracer with light RIS, paired against plain NEE ---------------------------- */

typedef struct {
    const scene *s;
    pt_options o;
} pt_config;

static int run_pt(void *user, uint32_t seed, double mean[3])
{
    pt_config *c = user;
    pt_options o = c->o;
    pt_result r;
    rerror e;
    o.seed = seed;
    if (pt_render(c->s, &o, &r, &e)) {
        test_fail(__FILE__, __LINE__, "pt_render: %s", e.msg);
        return -1;
    }
    bench_image_mean(&r.mean, mean);
    pt_result_free(&r);
    return 0;
}

/* The whole path tracer (paths up to 3 segments: light RIS at x_1 and x_2) on many-lights,
 * N = 8 (x_2: 2 candidates) with and without tiles, against plain NEE on the same seeds
 * (weak: det. bias ~5 %; the single-point tests above are the sharp ones). */
TEST(evidence_light_ris_pt_paired)
{
    scene s;
    pt_config a, b;
    int tiles;
    if (rt_load_scene("scenes/many-lights.scene", 16, &s)) return;
    for (tiles = 0; tiles < 2 && !test_has_failed(); ++tiles) {
        bench_paired p;
        pt_options_default(&b.o);
        b.s = a.s = &s;
        b.o.spp = 16;
        b.o.max_depth = 3;
        b.o.threads = 2;
        a.o = b.o;
        a.o.light_ris.candidates = 8;
        a.o.light_ris.tiles = tiles;
        bench_paired_init(&p, tiles ? "path tracer light RIS N 8 tiles vs plain NEE, many-lights"
                                    : "path tracer light RIS N 8 vs plain NEE, many-lights");
        if (bench_paired_run(&p, 16, test_seed() * 97u + 13u, run_pt, &a, run_pt, &b)) break;
        bench_paired_expect_consistent(&p, BENCH_Z_CONSISTENT);
    }
    scene_free(&s);
}
