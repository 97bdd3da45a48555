/* The §5.1 reuse-cell search of Stochastic MIS (src/restir/reuse_cells.c; issue 26: it had no
 * test of its radius, growth, iteration count or weighting). A synthetic G-buffer (three
 * objects in vertical stripes, a band of tilted normals, holes, one tile of zero confidence)
 * and the search written out again here from the paper's §5.1 and reuse_cells.h's contract:
 *   iteration k = 0..11 draws q = x + round(r cos phi), r = 30 * 1.25^k * sqrt(u0),
 *   phi = 2 pi u1 (a uniform point of the disk), rejects q outside the image, without a hit,
 *   of another object or with dot(n_q, n_x) < min_cos, or of a cell with confidence sum 0,
 *   and streams q's cell by weighted reservoir sampling with weight = the cell's confidence
 *   sum (u2 * wsum < w replaces the choice).
 * The library must agree with it at every pixel for several samples and thresholds; the
 * planted bugs of tests/mutants/reuse-cell-search-*.patch each change the choice of many
 * pixels. Hand-checked limits: the largest radius 30 * 1.25^11 = 349.2 reaches a cell
 * 300 px away only in the last iteration; a pixel whose object has no other hit returns -1. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/rng.h"
#include "restir/restir/reuse_cells.h"
#include "test.h"

#define CW 200
#define CH 120

static vec3f facing(const gbuffer_texel *t)
{
    return v3f_dot(t->hit.ng, t->view_dir) < 0 ? t->hit.ng : v3f_scale(t->hit.ng, -1);
}

/* Objects: stripes of 40 px (object x / 40 mod 3); normals (0, 0, 1) except rows 60..89 of
 * x >= 100, tilted to (0.8, 0, 0.6) (dot 0.6); holes where (7x + 3y) mod 29 = 0; the view
 * looks down -z. Confidences 1..5 by a hash of the pixel, 0 in the tile at (16..23, 8..15). */
static int build_case(gbuffer *g, reservoir **res)
{
    int x, y;
    g->width = CW;
    g->height = CH;
    g->texels = calloc((size_t)CW * CH, sizeof *g->texels);
    *res = calloc((size_t)CW * CH, sizeof **res);
    if (!g->texels || !*res) return -1;
    for (y = 0; y < CH; ++y)
        for (x = 0; x < CW; ++x) {
            long p = (long)y * CW + x;
            gbuffer_texel *t = &g->texels[p];
            reservoir *r = &(*res)[p];
            reservoir_init(r);
            t->valid = (7 * x + 3 * y) % 29 != 0;
            t->hit.object = (uint32_t)((x / 40) % 3);
            t->hit.ng = x >= 100 && y >= 60 && y < 90 ? v3f(0.8f, 0, 0.6f) : v3f(0, 0, 1);
            t->view_dir = v3f(0, 0, -1);
            r->confidence = (real)(1 + (uint32_t)(p * 2654435761u) % 5u);
            if (x >= 16 && x < 24 && y >= 8 && y < 16) r->confidence = 0;
        }
    return 0;
}

/* The search as §5.1 and reuse_cells.h describe it (see the top). */
static int reference_search(const reuse_cells *rc, const gbuffer *g, float min_cos, uint32_t seed, uint32_t sample,
                            int x, int y)
{
    long p = (long)y * g->width + x;
    const gbuffer_texel *t = &g->texels[p];
    rng_key key = rng_key_make(seed, (uint32_t)p, sample);
    double wsum = 0;
    int k, chosen = -1;
    if (!t->valid) return -1;
    for (k = 0; k < 12; ++k) {
        double radius = 30.0 * pow(1.25, k);
        double r = radius * sqrt((double)rng_u(key, RNG_NEIGHBOR, 128u + (uint32_t)k, 0));
        double phi = 2 * 3.14159265358979323846 * (double)rng_u(key, RNG_NEIGHBOR, 128u + (uint32_t)k, 1);
        int qx = x + (int)floor(r * cos(phi) + 0.5), qy = y + (int)floor(r * sin(phi) + 0.5), c;
        const gbuffer_texel *s;
        double w;
        if (qx < 0 || qy < 0 || qx >= g->width || qy >= g->height) continue;
        s = &g->texels[(long)qy * g->width + qx];
        c = rc->cell_of[(long)qy * g->width + qx];
        if (!s->valid || c < 0 || s->hit.object != t->hit.object || v3f_dot(facing(s), facing(t)) < min_cos) continue;
        w = rc->confidence[c];
        if (!(w > 0)) continue;
        wsum += w;
        if ((double)rng_u(key, RNG_NEIGHBOR, 128u + (uint32_t)k, 2) * wsum < w) chosen = c;
    }
    return chosen;
}

TEST(evidence_reuse_cell_search_exact)
{
    gbuffer g;
    reservoir *res = NULL;
    reuse_cells rc;
    rerror e;
    static const float cosines[] = {0.5f, 0.7f};
    long checked = 0, found = 0, mismatches = 0, zero_chosen = 0, tilted_mixed = 0;
    int x, y, i;
    uint32_t sample;
    memset(&rc, 0, sizeof rc);
    memset(&g, 0, sizeof g);
    CHECK(build_case(&g, &res) == 0);
    CHECK(reuse_cells_build(&rc, &g, res, &e) == 0);
    if (test_has_failed()) goto done;
    /* the cells of the case: 25 x 15 tiles, one cell per tile and object/normal bin */
    CHECK(rc.tiles == 25 * 15);
    for (i = 0; i < 2; ++i)
        for (sample = 0; sample < 3; ++sample)
            for (y = 0; y < CH; y += 2)
                for (x = 0; x < CW; x += 3) {
                    uint32_t seed = 1 + (uint32_t)test_seed();
                    int want = reference_search(&rc, &g, cosines[i], seed, sample, x, y);
                    int got = reuse_cell_search(&rc, &g, cosines[i], seed, sample, x, y);
                    long q;
                    ++checked;
                    if (got != want) {
                        if (!mismatches)
                            test_fail(__FILE__, __LINE__, "pixel %d,%d sample %u min_cos %.1f: cell %d, §5.1 gives %d",
                                      x, y, sample, (double)cosines[i], got, want);
                        ++mismatches;
                    }
                    if (got < 0) continue;
                    ++found;
                    q = rc.pixels[rc.start[got]];
                    zero_chosen += !(rc.confidence[got] > 0);
                    /* with min_cos 0.7 a flat pixel never takes a tilted cell (dot 0.6) */
                    tilted_mixed += cosines[i] > 0.6f &&
                                    (g.texels[q].hit.ng.x != 0) != (g.texels[(long)y * CW + x].hit.ng.x != 0);
                }
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %ld searches, %ld found a cell, %ld differ from §5.1\n", checked, found, mismatches);
    CHECKF(mismatches == 0, "%ld of %ld searches differ from §5.1", mismatches, checked);
    CHECKF(zero_chosen == 0 && tilted_mixed == 0, "a cell of confidence 0 chosen %ld times, a dissimilar normal %ld",
           zero_chosen, tilted_mixed);
    CHECKF(found > checked / 2, "only %ld of %ld searches found a cell", found, checked);
done:
    reuse_cells_free(&rc);
    free(g.texels);
    free(res);
}

/* Hand-checked limits of the radius, its growth and the iteration count: a 700 x 8 strip,
 * every pixel object 0 with confidence 0 except one tile 300..307 px to the right of the
 * pixel (x = 4): the first 11 radii (30 .. 279.4) cannot reach it (|dx| >= 296 > 279.4 +
 * 0.5), only the 12th (349.2) can, so the search finds that cell in some samples and never
 * anything else. A pixel of an object with no other hit finds nothing (-1). */
TEST(evidence_reuse_cell_search_last_radius)
{
    gbuffer g;
    reservoir *res;
    reuse_cells rc;
    rerror e;
    int x, y, found = 0, other = 0, far_cell;
    uint32_t sample;
    const int w = 700, h = 8;
    memset(&rc, 0, sizeof rc);
    g.width = w;
    g.height = h;
    g.texels = calloc((size_t)w * h, sizeof *g.texels);
    res = calloc((size_t)w * h, sizeof *res);
    CHECK(g.texels && res);
    if (test_has_failed()) goto done;
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) {
            gbuffer_texel *t = &g.texels[(long)y * w + x];
            reservoir_init(&res[(long)y * w + x]);
            t->valid = 1;
            t->hit.object = x == 690 && y == 4 ? 7 : 0; /* a lone object */
            t->hit.ng = v3f(0, 0, 1);
            t->view_dir = v3f(0, 0, -1);
            res[(long)y * w + x].confidence = x >= 304 && x < 312 ? 1 : 0;
        }
    CHECK(reuse_cells_build(&rc, &g, res, &e) == 0);
    if (test_has_failed()) goto done;
    far_cell = rc.cell_of[4 * w + 304];
    for (sample = 0; sample < 200000; ++sample) {
        int c = reuse_cell_search(&rc, &g, 0.5f, 1, sample, 4, 4);
        if (c == far_cell) ++found;
        else if (c >= 0) ++other;
    }
    /* P(iteration 11 lands in the 8 x 8 tile) = 64 / (pi 349.2^2) = 1.67e-4 per sample,
     * the strip is 8 rows high, so
     * the tile is the strip's full height and every landing at dx in [300, 307] counts: ~33 expected in 200000 */
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  far tile found %d of 200000, other %d\n", found, other);
    CHECKF(other == 0, "%d searches chose a cell of confidence 0", other);
    CHECKF(found > 0, "the 12th radius (349.2) never reached the tile at dx 300..307 in 200000 samples");
    CHECK(reuse_cell_search(&rc, &g, 0.5f, 1, 0, 690, 4) == -1);
done:
    reuse_cells_free(&rc);
    free(g.texels);
    free(res);
}
