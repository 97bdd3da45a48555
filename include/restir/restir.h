/* ReSTIR PT renderer, part 1 (docs/restir-pt.md): per frame, initial resampling over N
 * path trees per pixel (initial.h), optionally one spatial pass that merges every pixel
 * with one random neighbour (merge.h, GRIS Eq. 36 / Mutations Eqs. 31-32), and shading
 *     I_frame = Le(x1) + F(Y) W_Y        (emission at x1 is added, never resampled)
 * averaged over independent frames with the explicit mean of GRIS Eq. 47 (GRIS §6.5).
 * With --paths indirect the image holds only paths of length d >= 3 (no Le(x1)).
 *
 * Random numbers (docs/restir-pt.md, "Random numbers"): tree t of frame f uses the path
 * tracer's addresses with sample index f*N + t; the frame's primary rays (jitter) sample
 * f*N; the neighbour of pass p is RNG_NEIGHBOR (sample f, vertex p, slots 0-1); the
 * merge's selection numbers are RNG_RIS (sample f*N, vertex 0, slots 2p and 2p+1). The
 * result is byte-identical for any thread count. */
#ifndef RESTIR_RESTIR_H
#define RESTIR_RESTIR_H

#include <stdio.h>
#include "restir/image.h"
#include "restir/initial.h"
#include "restir/merge.h"
#include "restir/mis.h"

enum restir_paths { RESTIR_PATHS_ALL = 0, RESTIR_PATHS_INDIRECT = 1 };
extern const char *const restir_paths_names[]; /* "all", "indirect" */
extern const char *const restir_mis_names[];   /* the families restir_render accepts: "talbot" */

typedef struct {
    int shift;                  /* enum restir_shift (default hybrid) */
    int spatial_passes;         /* 0: initial resampling alone; 1: merge with one neighbour */
    int neighbors;              /* neighbours per pass: 1 */
    double radius;              /* neighbour disk radius in pixels (default 10, GRIS §8.3 offline) */
    int mis;                    /* index into restir_mis_names: 0 = talbot (GRIS Eq. 36) */
    int frames;                 /* independent frames averaged (GRIS Eq. 47), >= 1 */
    int first_frame;            /* frame index of the first frame (disjoint ranges are independent) */
    int candidates;             /* N path trees per pixel (default 1) */
    int max_depth;              /* longest path in segments, 2..16 (3..16 with indirect); default 10 */
    double roughness_threshold; /* lobe roughness for reconnection (default 0.2, GRIS §8.3) */
    double distance_threshold;  /* d_min as a fraction of the scene's bounding-box diagonal
                                   (default 0.02; GRIS §8.3 uses 1-5% of the scene size) */
    int paths;                  /* enum restir_paths */
    int ablation;               /* enum restir_ablation */
    int russian_roulette;       /* the path tracer's roulette in initial sampling only (default 0) */
    int rr_min_depth;           /* default 3 */
    uint32_t seed;              /* run seed of the addressed RNG (default 1) */
    int jitter;                 /* sub-pixel jitter per frame (default 0: pixel centres) */
    int threads;                /* >= 1 */
    int quiet;                  /* no progress bar */
    int keep_reservoirs;        /* return the last frame's final reservoirs */
} restir_options;

typedef struct {
    initial_stats initial;
    merge_stats merge;
    uint64_t frames;
} restir_stats;

typedef struct {
    image mean;            /* float RGB: the frame average */
    reservoir *reservoirs; /* width * height reservoirs of the last frame (keep_reservoirs), else NULL */
    restir_stats stats;
    double seconds;
} restir_result;

void restir_options_default(restir_options *o);
int restir_options_validate(const restir_options *o, rerror *e);

/* The context (shift, criterion with d_min in scene units, ablation, MIS strategy) that
 * restir_render uses for scene s; lights must outlive it. */
void restir_context_for(restir_context *c, const scene *s, const light_set *lights, const restir_options *o);
void restir_initial_options_for(initial_options *io, const restir_options *o);

/* Renders s (prepared: BVH built). Deterministic for any thread count. On success fills
 * *out (free with restir_result_free); frees everything on failure. */
int restir_render(const scene *s, const restir_options *o, restir_result *out, rerror *e);
void restir_result_free(restir_result *r);

/* The statistics as a JSON object (no trailing newline), e.g. for `render --stats`:
 * candidates, selections by length and reconnection index, shifts by outcome. */
void restir_stats_write_json(FILE *out, const restir_stats *st, const char *indent);

/* One pixel, for `restir inspect` (docs/restir-pt.md): prints the selected path of pixel
 * (x, y) in frame o->first_frame (vertices, lobes, k, technique, F, W), then shifts it to
 * pixel (nx, ny) with o->shift (failure reason, or J with its factors, F(y) and the round
 * trip back). */
int restir_inspect(FILE *out, const scene *s, const restir_options *o, int x, int y, int nx, int ny, rerror *e);

#endif
