/* Initial resampling over N path trees per pixel (GRIS §8.3, Enhanced §2.3 and §6.1;
 * docs/restir-pt.md "Initial sampling").
 *
 * Each tree is exactly the reference path tracer's path (same per-vertex steps, same
 * random-number addresses: tree t of frame f uses sample index f*N + t, so with N = 1 the
 * tree of frame f IS the path tracer's sample f): NEE at every vertex, one BSDF
 * continuation per vertex with one lobe per bounce. Every complete path of the tree is a
 * RIS candidate of the lobe-extended PSS path space (GRIS Eq. 50, technique NEE or BSDF):
 *   - an NEE path (x_0..x_i, light point) of length d = i + 1,
 *   - a BSDF path whose bounce at x_i hits an emitter x_{i+1}, length d = i + 1,
 * for 2 <= d <= max depth (3 <= d with --paths indirect). Candidates stream through one
 * reservoir with the weight of GRIS Eq. 1 with constant MIS 1/N (reservoir.h):
 *     w = p̂(x) W_x / N,   p̂ = luminance(F),   W_x = 1 / P(Russian roulette survival)
 * (Enhanced §6.2.4: roulette only in the source pdf; F never contains it), then
 *     W = sum w / p̂(Y)  (GRIS Eq. 22),   c = N.
 * The selection number of a candidate is RNG_RIS at (tree sample, vertex d, slot technique).
 * The selected path is then recorded (reconnection.h, path_record) from its identity. */
#ifndef RESTIR_INITIAL_H
#define RESTIR_INITIAL_H

#include "restir/restir/reservoir.h"
#include "restir/restir/restir_context.h"

typedef struct {
    int trees;            /* N path trees per pixel and frame (GRIS §8.3: 32 offline, 1 real-time) */
    int max_depth;        /* longest candidate path, in segments, 2..PATH_MAX_LENGTH */
    int indirect_only;    /* 1: only paths with d >= 3 (GRIS's figures measure indirect light) */
    int russian_roulette; /* 1: the path tracer's roulette (continue with min(1, max beta)) */
    int rr_min_depth;     /* roulette after vertex x_i for i >= this (the path tracer's default 3) */
} initial_options;

typedef struct {
    uint64_t pixels;          /* pixels with a primary hit */
    uint64_t trees;
    uint64_t candidates;      /* candidates with a nonzero weight */
    uint64_t selected;        /* reservoirs holding a sample */
    uint64_t record_failed;   /* the selected path could not be replayed (must stay 0) */
    uint64_t record_mismatch; /* replayed F differs from the streamed F (must stay 0) */
    uint64_t unshiftable;     /* selected samples flagged PATH_RC_FLAG_UNSHIFTABLE */
    uint64_t length[PATH_MAX_LENGTH + 1];   /* selected samples by length d */
    uint64_t rc_index[PATH_MAX_LENGTH + 1]; /* selected samples by reconnection index (0: none) */
    uint64_t invalid_weights; /* candidate weights skipped as NaN, Inf or < 0 (reservoir n_invalid) */
} initial_stats;

/* Fills r with the initial reservoir of `pixel` in `frame`, whose primary hit is x1. */
void initial_sample_pixel(const restir_context *c, const initial_options *o, const path_vertex *x1, uint32_t seed,
                          uint32_t pixel, uint32_t frame, reservoir *r, initial_stats *st);

/* The sample index of tree t of frame f: f * N + t (also the jitter's sample index of the
 * frame's primary rays, with t = 0). */
uint32_t initial_tree_sample(const initial_options *o, uint32_t frame, int tree);

/* The key of pixel `pixel` in `frame`: (seed, pixel, the frame's tree-0 sample). Every
 * per-pixel number of a frame after initial sampling (temporal, spatial and stochastic
 * selection numbers at the RNG_VERTEX_* of rng.h, mutations) and the primary ray's jitter
 * are addressed from it, by the frame and by the oracle alike. */
rng_key initial_pixel_key(const initial_options *o, uint32_t seed, uint32_t frame, uint32_t pixel);

void initial_stats_add(initial_stats *acc, const initial_stats *add);

#endif
