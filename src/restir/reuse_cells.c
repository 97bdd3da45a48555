/* Screen-space reuse cells (include/restir/restir/reuse_cells.h; Stochastic MIS §5). */
#include "restir/restir/reuse_cells.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/rng.h"

uint32_t reuse_cell_hash(uint32_t tile, uint32_t object, uint32_t normal_bin)
{
    uint32_t v[4];
    v[0] = tile;
    v[1] = object;
    v[2] = normal_bin;
    v[3] = 0x9e3779b9u;
    rng_pcg4d(v);
    return v[0] | 1u; /* never 0: 0 marks "no hit" */
}

static vec3f facing_normal(const gbuffer_texel *t)
{
    return v3f_dot(t->hit.ng, t->view_dir) < 0 ? t->hit.ng : v3f_scale(t->hit.ng, -1);
}

static uint32_t bin4(float v)
{
    int b = (int)floorf((v + 1.0f) * 2.0f);
    return (uint32_t)(b < 0 ? 0 : b > 3 ? 3 : b);
}

uint32_t reuse_normal_bin(const gbuffer_texel *t)
{
    vec3f n = facing_normal(t);
    return bin4(n.x) | bin4(n.y) << 2 | bin4(n.z) << 4;
}

void reuse_cells_free(reuse_cells *rc)
{
    free(rc->cell_of);
    free(rc->start);
    free(rc->pixels);
    free(rc->nz_start);
    free(rc->nz_pixels);
    free(rc->confidence);
    free(rc->hash);
    memset(rc, 0, sizeof *rc);
}

int reuse_cells_alloc(reuse_cells *rc, int width, int height, rerror *e)
{
    size_t n = (size_t)width * (size_t)height;
    if (rc->cell_of && rc->width == width && rc->height == height) return 0;
    reuse_cells_free(rc);
    rc->width = width;
    rc->height = height;
    rc->cell_of = rcalloc(n, sizeof *rc->cell_of, e);
    rc->start = rcalloc(n + 1, sizeof *rc->start, e); /* at most one cell per pixel */
    rc->pixels = rcalloc(n, sizeof *rc->pixels, e);
    rc->nz_start = rcalloc(n + 1, sizeof *rc->nz_start, e);
    rc->nz_pixels = rcalloc(n, sizeof *rc->nz_pixels, e);
    rc->confidence = rcalloc(n, sizeof *rc->confidence, e);
    rc->hash = rcalloc(n, sizeof *rc->hash, e);
    if (!rc->cell_of || !rc->start || !rc->pixels || !rc->nz_start || !rc->nz_pixels || !rc->confidence || !rc->hash) {
        reuse_cells_free(rc);
        return -1;
    }
    return 0;
}

static int nonzero(const reservoir *r) { return path_sample_is_valid(&r->y) && r->y.target > 0 && r->W > 0; }

/* Dense cell indices: tiles in row-major order, within a tile the distinct hashes in
 * order of first appearance (a tile holds at most 64 cells). */
static void assign_cells(reuse_cells *rc, const gbuffer *g)
{
    int tx, ty, tw = (g->width + REUSE_TILE - 1) / REUSE_TILE, th = (g->height + REUSE_TILE - 1) / REUSE_TILE;
    rc->tiles = tw * th;
    rc->cell_count = 0;
    for (ty = 0; ty < th; ++ty)
        for (tx = 0; tx < tw; ++tx) {
            uint32_t seen[REUSE_CELL_MAX_PIXELS];
            int ids[REUSE_CELL_MAX_PIXELS], n_seen = 0, x, y, k;
            uint32_t tile = (uint32_t)(ty * tw + tx);
            for (y = ty * REUSE_TILE; y < (ty + 1) * REUSE_TILE && y < g->height; ++y)
                for (x = tx * REUSE_TILE; x < (tx + 1) * REUSE_TILE && x < g->width; ++x) {
                    long p = (long)y * g->width + x;
                    const gbuffer_texel *t = &g->texels[p];
                    uint32_t h;
                    if (!t->valid) {
                        rc->hash[p] = 0;
                        rc->cell_of[p] = -1;
                        continue;
                    }
                    h = reuse_cell_hash(tile, t->hit.object, reuse_normal_bin(t));
                    rc->hash[p] = h;
                    for (k = 0; k < n_seen && seen[k] != h; ++k) {}
                    if (k == n_seen) {
                        seen[n_seen] = h;
                        ids[n_seen++] = rc->cell_count++;
                    }
                    rc->cell_of[p] = ids[k];
                }
        }
}

/* Counting sort by cell of the pixels with a cell (only_nonzero: and a non-zero sample);
 * stable, so each cell's pixels stay in row-major order. */
static void counting_sort(reuse_cells *rc, const reservoir *res, int only_nonzero, int *start, uint32_t *out)
{
    long n = (long)rc->width * rc->height, p;
    int c;
    memset(start, 0, (size_t)(rc->cell_count + 1) * sizeof *start);
    for (p = 0; p < n; ++p)
        if (rc->cell_of[p] >= 0 && (!only_nonzero || nonzero(&res[p]))) start[rc->cell_of[p] + 1]++;
    for (c = 0; c < rc->cell_count; ++c) start[c + 1] += start[c];
    for (p = 0; p < n; ++p) {
        int cp = rc->cell_of[p];
        if (cp < 0 || (only_nonzero && !nonzero(&res[p]))) continue;
        out[start[cp]++] = (uint32_t)p; /* start[c] advances to the end of cell c */
    }
    for (c = rc->cell_count; c > 0; --c) start[c] = start[c - 1]; /* shift back: start[c] = begin */
    start[0] = 0;
}

int reuse_cells_build(reuse_cells *rc, const gbuffer *g, const reservoir *res, rerror *e)
{
    long n = (long)g->width * g->height, p;
    if (reuse_cells_alloc(rc, g->width, g->height, e)) return -1;
    assign_cells(rc, g);
    counting_sort(rc, res, 0, rc->start, rc->pixels);
    counting_sort(rc, res, 1, rc->nz_start, rc->nz_pixels);
    memset(rc->confidence, 0, (size_t)rc->cell_count * sizeof *rc->confidence);
    for (p = 0; p < n; ++p)
        if (rc->cell_of[p] >= 0) rc->confidence[rc->cell_of[p]] += (double)res[p].confidence;
    return 0;
}

int reuse_cell_search(const reuse_cells *rc, const gbuffer *g, float min_cos, uint32_t seed, uint32_t sample, int x,
                      int y)
{
    long p = (long)y * g->width + x;
    const gbuffer_texel *t = &g->texels[p];
    rng_key key = rng_key_make(seed, (uint32_t)p, sample);
    double radius = REUSE_SEARCH_RADIUS, wsum = 0;
    int k, chosen = -1;
    if (!t->valid) return -1;
    for (k = 0; k < REUSE_SEARCH_ITERATIONS; ++k, radius *= REUSE_SEARCH_GROWTH) {
        uint32_t v = REUSE_SEARCH_VERTEX + (uint32_t)k;
        double r = radius * sqrt((double)rng_u(key, RNG_NEIGHBOR, v, 0));
        double phi = 6.283185307179586 * (double)rng_u(key, RNG_NEIGHBOR, v, 1);
        int qx = x + (int)floor(r * cos(phi) + 0.5), qy = y + (int)floor(r * sin(phi) + 0.5), c;
        const gbuffer_texel *s;
        double w;
        if (qx < 0 || qy < 0 || qx >= g->width || qy >= g->height) continue;
        s = &g->texels[(long)qy * g->width + qx];
        c = rc->cell_of[(long)qy * g->width + qx];
        if (c < 0 || !s->valid) continue;
        if (s->hit.object != t->hit.object || v3f_dot(facing_normal(s), facing_normal(t)) < min_cos) continue;
        w = rc->confidence[c]; /* §5.1: weighted by the cell's confidence sum */
        if (!(w > 0)) continue;
        wsum += w;
        if ((double)rng_u(key, RNG_NEIGHBOR, v, 2) * wsum < w) chosen = c; /* WRS (Chao 1982) */
    }
    return chosen;
}

int reuse_cell_domains(const reuse_cells *rc, int c, uint32_t p, uint32_t *out)
{
    int i, n = 0;
    for (i = rc->start[c]; i < rc->start[c + 1]; ++i)
        if (rc->pixels[i] != p) out[n++] = rc->pixels[i];
    return n;
}
