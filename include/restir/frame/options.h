/* The configuration of a ReSTIR PT run (offline driver, GRIS §6.5, and real-time
 * pipeline, GRIS §6.3), composed of the techniques' own option structs (each with its
 * default and its validation in its module: spatial_options.h, temporal.h,
 * stochastic_spatial.h, mutate.h, correlation.h, light_ris.h) and the frame's fields;
 * the defaults, the GRIS §8.3 presets, validation of the whole, and what each estimator
 * module is handed of it (restir_context_for, restir_initial_options_for). */
#ifndef RESTIR_FRAME_OPTIONS_H
#define RESTIR_FRAME_OPTIONS_H

#include <signal.h>
#include <stdio.h>
#include "restir/render/light_ris.h"
#include "restir/restir/correlation.h"
#include "restir/restir/initial.h"
#include "restir/restir/mis.h"
#include "restir/restir/mutate.h"
#include "restir/restir/neighbors.h"
#include "restir/restir/reuse_cells.h"
#include "restir/restir/spatial.h"
#include "restir/restir/spatial_options.h"
#include "restir/restir/stochastic_spatial.h"
#include "restir/restir/temporal.h"

#define RESTIR_MAX_SPATIAL_PASSES 16
#define RESTIR_MAX_DOMAINS 1024 /* 1 + neighbours per pixel and pass (box windows up to r = 15) */

enum restir_paths { RESTIR_PATHS_ALL = 0, RESTIR_PATHS_INDIRECT = 1 };
extern const char *const restir_paths_names[]; /* "all", "indirect" */
enum restir_shading { RESTIR_SHADING_SCALAR = 0, RESTIR_SHADING_VECTOR = 1 };
extern const char *const restir_shading_names[]; /* "scalar", "vector" */
/* The frame images: radiance (default), the duplicate count per pixel (Enhanced §5), or the
 * temporal history age per pixel (frames since its chain of temporal sources began: 0 = no
 * history this frame; sequences only) */
enum restir_output { RESTIR_OUTPUT_RADIANCE = 0, RESTIR_OUTPUT_DUPLICATES = 1, RESTIR_OUTPUT_AGE = 2 };

typedef struct {
    enum restir_shift shift;    /* enum restir_shift (default hybrid) */
    int spatial_passes;         /* K, 0..16 (0: initial resampling alone; default 0) */
    spatial_options spatial;    /* what each pass reuses, and with which GRIS step */
    int frames;                 /* independent frames averaged (GRIS Eq. 47), >= 1 */
    double time_limit;          /* > 0: render frames until this many seconds have passed
                                   (at least one; `frames` is then ignored) */
    int first_frame;            /* frame index of the first frame (disjoint ranges are independent) */
    int candidates;             /* N path trees per pixel (default 1) */
    int max_depth;              /* longest path in segments, 2..16 (3..16 with indirect); default 10 */
    double roughness_threshold; /* lobe roughness for reconnection (default 0.2, GRIS §8.3) */
    double distance_threshold;  /* d_min as a fraction of the scene's bounding-box diagonal
                                   (default 0.02; GRIS §8.3 uses 1-5% of the scene size) */
    enum restir_shading shading; /* enum restir_shading: scalar F(Y) W_Y (default) or vector (Enhanced §6.3) */
    int force_nee_reconnection; /* Enhanced §6.2.3 forced NEE light reconnection (hybrid; default 0) */
    enum rc_mode rc_criterion;  /* enum rc_mode: gris (default) or footprint (Enhanced §4, Eq. 5) */
    double footprint_c;         /* c of Enhanced Eq. 5 (default 0.02, Enhanced §7.2) */
    int no_pair_step;           /* paired reuse: 1 runs a full GRIS step per pixel (four shifts
                                   per pair) instead of the Enhanced §3 pair step (two) */
    enum restir_paths paths;    /* enum restir_paths */
    enum restir_ablation ablation; /* enum restir_ablation */
    int russian_roulette;       /* the path tracer's roulette in initial sampling only (default 0) */
    int rr_min_depth;           /* default 3 */
    uint32_t seed;              /* run seed of the addressed RNG (default 1) */
    int jitter;                 /* sub-pixel jitter per frame (default 0: pixel centres) */
    int threads;                /* >= 1 */
    int quiet;                  /* no progress bar */
    int keep_reservoirs;        /* return the last frame's final reservoirs */
    /* real-time pipeline only (restir_render_sequence; restir_render ignores them): */
    temporal_options temporal;  /* temporal reuse (GRIS §6.3 step 2) */
    /* stochastic pairwise MIS (spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE, or reuse
     * cells; naive_p is set from the ablation, not here): */
    stochastic_options stochastic;
    /* correlation under motion (issue 12, docs/correlation.md; real-time pipeline only): */
    correlation_options correlation;
    int output_aov;             /* enum restir_output: what the frame images hold (--aov duplicates|age) */
    int no_duplicate_stats;     /* 1: skip the per-frame duplication map and the Mutations Fig. 8
                                   duplicate count when nothing reads them (no dedup, no
                                   duplicate images): the "correlation" and mutation duplicate
                                   counters of restir_stats stay 0 (default 0: computed) */
    volatile sig_atomic_t *stop_flag; /* NULL: never. Nonzero (the CLI's SIGINT/SIGTERM) cancels the
                                         frame in progress at a tile boundary (threads_set_cancel)
                                         and ends the render with the frames complete so far, maybe
                                         none (result frames = 0) */
    mutation_options mutation;  /* MCMC mutations (Mutations Algorithm 3), real-time pipeline only */
    light_ris_options light_ris; /* light RIS for NEE (Enhanced §6.1) */
    /* the confidence form of pairwise-defensive MIS (mis.h; issue 31): 0 = stochastic (the
       Stochastic MIS Eq. 11 form, default), 1 = falcor (1/(k+1) per pair, c_c/k inside) */
    int pairwise_confidence;
} restir_options;

/* "stochastic", "falcor" (--pairwise-confidence) */
extern const char *const restir_pairwise_confidence_names[];
/* The mis_family a step with family `mis` (o->mis or o->temporal_mis) runs: pairwise-
 * defensive in the confidence form o->pairwise_confidence chooses, else mis itself. */
mis_family restir_step_mis(const restir_options *o, int mis);

void restir_options_default(restir_options *o);
/* 1 if o turns on a feature that is biased by design (correlation_options_biased): the
 * estimator is then no longer unbiased (docs/correlation.md); --stats says "biased". */
int restir_options_biased(const restir_options *o);
/* Each technique's validation (its message names the technique: "mutation: ..."), then
 * the frame's own fields and the rules between techniques ("restir: ..."). */
int restir_options_validate(const restir_options *o, rerror *e);

/* The context (shift, criterion with d_min in scene units, ablation, MIS strategy) that
 * restir_render uses for scene s; lights must outlive it. */
void restir_context_for(restir_context *c, const scene *s, const light_set *lights, const restir_options *o);
void restir_initial_options_for(initial_options *io, const restir_options *o);
/* Paired reuse: builds no->count reuse textures (sigma from the radius, pairing.h) into
 * `textures` (PAIRING_MAX_TEXTURES entries) and points no at them; other patterns: no-op.
 * restir_pairing_free releases them. */
int restir_pairing_build(neighbor_options *no, const restir_options *o, reuse_texture *textures, rerror *e);
void restir_pairing_free(neighbor_options *no);
/* Whether spatial passes run the Enhanced §3 pair step (pair_step.c): paired reuse, the
 * GRIS step (a deterministic MIS family), no reuse cells, no_pair_step off. */
int restir_pair_step_active(const restir_options *o);

/* The effective configuration as a JSON object (no trailing newline). */
void restir_options_write_json(FILE *out, const restir_options *o, const char *indent);
/* The GRIS offline preset (GRIS §8.3): 32 path trees, 3 spatial passes, 6 neighbours in
 * radius 10, defensive pairwise MIS for spatial reuse (GRIS Eq. 38); the other fields are kept. */
void restir_options_preset_gris_offline(restir_options *o);

/* The GRIS real-time preset (GRIS §8.3): 1 path tree, temporal reuse (Talbot, cap 20),
 * one spatial pass with 3 neighbours in a 20-pixel radius, pairwise-defensive spatial MIS. */
void restir_options_preset_gris_realtime(restir_options *o);

#endif
