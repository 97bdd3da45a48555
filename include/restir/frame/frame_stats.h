/* Counters, timings and per-pixel memory of a ReSTIR PT run (offline or real-time), summed
 * over workers and frames, and written as JSON by `render --stats` and the benchmarks. */
#ifndef RESTIR_FRAME_FRAME_STATS_H
#define RESTIR_FRAME_FRAME_STATS_H

#include <stdio.h>
#include "restir/frame/options.h"
#include "restir/restir/duplication.h"

/* Bytes per pixel of every per-pixel buffer of a ReSTIR run (issue 17; docs/performance.md).
 * Per-thread workspaces and per-scene data are not per pixel and not counted. */
typedef struct {
    unsigned reservoir;          /* sizeof(reservoir) */
    unsigned reservoir_pss;      /* per reservoir buffer: its primary-sample rows (reservoir.h;
                                    --mutations only), counted in reservoirs_* */
    unsigned reservoirs_initial, reservoirs_spatial, reservoirs_previous; /* 0 when not allocated */
    unsigned gbuffer, gbuffer_previous;
    unsigned accumulation, vector_shade, reuse_cells;
    unsigned pair_step;          /* --pairing paired: the pair step's pre-pass records (Enhanced §3) */
    unsigned correlation;        /* sequences: duplication map and history ages (docs/correlation.md) */
    unsigned total;
} restir_memory;
/* The buffers restir_render (sequence = 0) or the real-time pipeline (sequence = 1) allocates. */
void restir_memory_per_pixel(const restir_options *o, int sequence, restir_memory *m);

typedef struct {
    initial_stats initial;
    spatial_stats spatial;     /* all passes */
    neighbor_stats neighbors;  /* verdict of every proposed neighbour */
    temporal_stats temporal;   /* temporal steps (sequences only) */
    mutate_stats mutate;       /* MCMC mutations (sequences only) */
    uint64_t frames;
    uint64_t nonfinite_pixels; /* output pixels with a NaN/Inf channel (kept in the image; an
                                  estimate beyond FLT_MAX becomes Inf in the float image) */
    int passes;                /* K */
    double ms_gbuffer, ms_initial, ms_shade;     /* summed over frames */
    double ms_temporal;                          /* temporal step incl. reprojection (sequences) */
    double ms_pose, ms_motion;                   /* posing + BVH rebuild; motion vectors (sequences) */
    double ms_mutate;                            /* MCMC mutations, all stages (sequences) */
    double ms_spatial[RESTIR_MAX_SPATIAL_PASSES]; /* pass p, summed over frames */
    /* correlation (sequences; docs/correlation.md): the duplication map of every frame's
     * final reservoirs, summed over frames; reservoirs the boiling filter cleared */
    duplication_summary correlation;
    uint64_t boiling_cleared;
    double ms_correlation;                       /* duplication map + boiling filter */
    restir_memory memory;      /* bytes per pixel of the run's buffers (set once per run) */
} restir_stats;

/* *acc += *add: every counter and timing (frames too; `passes` is kept). */
void restir_stats_add(restir_stats *acc, const restir_stats *add);

/* The statistics as a JSON object (no trailing newline), e.g. for `render --stats`:
 * candidates, selections by length and reconnection index, shifts by outcome. */
/* Guards that changed the estimate (docs/precision.md): initial + spatial + temporal
 * invalid_weights. --stats writes them with nonfinite_pixels as "guards". */
uint64_t restir_stats_invalid_weights(const restir_stats *st);
void restir_stats_write_json(FILE *out, const restir_stats *st, const char *indent);
#endif
