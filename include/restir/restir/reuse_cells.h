/* Screen-space reuse cells (Stochastic MIS §5; docs/stochastic-mis.md §6).
 *
 * The image is cut into 8 x 8 TILES; a CELL is the set of pixels of one tile with the
 * same hash of (tile id, object id, quantised facing normal) (PCG hash, rng_pcg4d). The
 * GPU version inserts every pixel into a "cellPixelIndices" multimap and every pixel with
 * a non-zero sample into "cellReservoirs" (Algorithm 1); the CPU equivalent here is a
 * counting sort of the pixels by dense cell index (stable: row-major within a cell),
 * once for all pixels and once for those with a non-zero sample.
 *
 * Neighbour-cell search (§5.1): 12 iterations of weighted reservoir sampling; iteration k
 * draws a uniform pixel in the disk of radius 30 * 1.25^k around the pixel, rejects it if
 * outside the image, without a hit, or of a different object or a facing normal with
 * dot < min_cos, and otherwise streams its cell with weight = the cell's confidence sum.
 * The choice reads only the G-buffer, the confidences and RNG_NEIGHBOR: in this renderer
 * confidences never depend on sample values (initial c = N, every step's output c is a
 * function of the input c), so the chosen cell is independent of the samples.
 *
 * Random numbers: key (seed, pixel, sample, RNG_NEIGHBOR, vertex 128 + k, slots 0-2). */
#ifndef RESTIR_REUSE_CELLS_H
#define RESTIR_REUSE_CELLS_H

#include <stdint.h>
#include "restir/core/error.h"
#include "restir/render/gbuffer.h"
#include "restir/restir/reservoir.h"

#define REUSE_TILE 8
#define REUSE_CELL_MAX_PIXELS (REUSE_TILE * REUSE_TILE)
#define REUSE_SEARCH_ITERATIONS 12
#define REUSE_SEARCH_RADIUS 30.0
#define REUSE_SEARCH_GROWTH 1.25
#define REUSE_SEARCH_VERTEX 128u

typedef struct {
    int width, height, tiles;
    int cell_count;
    int *cell_of;        /* per pixel: dense cell index, -1 without a primary hit */
    int *start;          /* cell_count + 1: cell c holds pixels[start[c] .. start[c+1]) */
    uint32_t *pixels;    /* all pixels, sorted by cell ("cellPixelIndices") */
    int *nz_start;       /* the same for the pixels with a non-zero sample ("cellReservoirs") */
    uint32_t *nz_pixels;
    double *confidence;  /* per cell: sum of the pixels' confidences */
    uint32_t *hash;      /* per pixel: the PCG cell hash (0 without a hit) */
} reuse_cells;

/* The cell hash of Stochastic MIS §5: PCG of (tile id, object id, normal bin). */
uint32_t reuse_cell_hash(uint32_t tile, uint32_t object, uint32_t normal_bin);
/* The quantised facing normal: each component in 4 bins (64 bins). */
uint32_t reuse_normal_bin(const gbuffer_texel *t);

/* Allocates for a width x height image (nothing to do if already so). */
int reuse_cells_alloc(reuse_cells *rc, int width, int height, rerror *e);
/* Builds (or rebuilds, reusing the allocation) the cells of G-buffer g with reservoirs
 * res (one per pixel; "non-zero" = a valid sample with p̂ > 0 and W > 0). */
int reuse_cells_build(reuse_cells *rc, const gbuffer *g, const reservoir *res, rerror *e);
void reuse_cells_free(reuse_cells *rc);

static inline int reuse_cell_size(const reuse_cells *rc, int c) { return rc->start[c + 1] - rc->start[c]; }
static inline int reuse_cell_nonzero(const reuse_cells *rc, int c) { return rc->nz_start[c + 1] - rc->nz_start[c]; }

/* §5.1: the neighbour cell of pixel (x, y), or -1 if every iteration was rejected. */
int reuse_cell_search(const reuse_cells *rc, const gbuffer *g, float min_cos, uint32_t seed, uint32_t sample, int x,
                      int y);

/* The non-canonical domains of pixel p in cell c: the cell's pixels except p itself
 * (docs/stochastic-mis.md §6: the canonical pixel is excluded, M = |cell| - [p in c]).
 * Writes them to out (capacity >= REUSE_CELL_MAX_PIXELS) and returns M. */
int reuse_cell_domains(const reuse_cells *rc, int c, uint32_t p, uint32_t *out);

#endif
