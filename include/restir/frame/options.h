/* The configuration of a ReSTIR PT run (offline driver, GRIS §6.5, and real-time
 * pipeline, GRIS §6.3): one field per knob of the four papers' algorithms, the defaults,
 * the GRIS §8.3 presets, validation, and what each estimator module is handed of it
 * (restir_context_for, restir_initial_options_for, restir_neighbor_options_for). */
#ifndef RESTIR_FRAME_OPTIONS_H
#define RESTIR_FRAME_OPTIONS_H

#include <signal.h>
#include <stdio.h>
#include "restir/restir/initial.h"
#include "restir/restir/mis.h"
#include "restir/restir/mutate.h"
#include "restir/restir/neighbors.h"
#include "restir/restir/reuse_cells.h"
#include "restir/restir/spatial.h"
#include "restir/restir/stochastic_spatial.h"
#include "restir/restir/temporal.h"

#define RESTIR_MAX_SPATIAL_PASSES 16
#define RESTIR_MAX_DOMAINS 1024 /* 1 + neighbours per pixel and pass (box windows up to r = 15) */

enum restir_paths { RESTIR_PATHS_ALL = 0, RESTIR_PATHS_INDIRECT = 1 };
extern const char *const restir_paths_names[]; /* "all", "indirect" */
enum restir_shading { RESTIR_SHADING_SCALAR = 0, RESTIR_SHADING_VECTOR = 1 };
extern const char *const restir_shading_names[]; /* "scalar", "vector" */
enum restir_pairing { RESTIR_PAIRING_DISK = 0, RESTIR_PAIRING_PAIRED = 1 };
extern const char *const restir_pairing_names[]; /* "disk", "paired" */
enum restir_motion_vectors { RESTIR_MV_SINGLE = 0, RESTIR_MV_DUAL = 1 };
/* The frame images: radiance (default), the duplicate count per pixel (Enhanced §5), or the
 * temporal history age per pixel (frames since its chain of temporal sources began: 0 = no
 * history this frame; sequences only) */
enum restir_output { RESTIR_OUTPUT_RADIANCE = 0, RESTIR_OUTPUT_DUPLICATES = 1, RESTIR_OUTPUT_AGE = 2 };
extern const char *const restir_motion_vector_names[]; /* "single", "dual" */
/* --mis stochastic-pairwise: spatial passes only, not a mis_family (stochastic_spatial.h);
 * its name is restir_mis_names[RESTIR_MIS_STOCHASTIC_PAIRWISE] (mis.h). */
#define RESTIR_MIS_STOCHASTIC_PAIRWISE MIS_FAMILY_COUNT

typedef struct {
    enum restir_shift shift;    /* enum restir_shift (default hybrid) */
    int spatial_passes;         /* K, 0..16 (0: initial resampling alone; default 0) */
    int neighbors;              /* n candidates per pixel and pass (disk patterns; default 6) */
    double radius;              /* neighbour disk radius in pixels (default 10, GRIS §8.3 offline) */
    enum neighbor_pattern pattern; /* enum neighbor_pattern (default r2) */
    enum restir_pairing pairing; /* enum restir_pairing: disk (default: `pattern`) or paired (Enhanced §3) */
    int no_reject;              /* 1: no normal/depth rejection of neighbours */
    double normal_cos;          /* reject if dot(n_i, n_j) < this (default 0.5) */
    double depth_ratio;         /* reject if |d_i - d_j| > this * min(d_i, d_j) (default 0.1) */
    mis_family mis;             /* mis_family (default MIS_TALBOT, GRIS Eq. 36) */
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
    int no_pair_step;           /* --pairing paired: 1 runs a full GRIS step per pixel (four shifts
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
    int temporal;               /* temporal reuse (GRIS §6.3 step 2; default 1 in sequences) */
    mis_family temporal_mis;    /* mis_family of the temporal step (default MIS_TALBOT, GRIS §8.3) */
    double mcap;                /* C > 0: c_prev <= C c_cur (GRIS §6.2, §6.4; default 20; may be inf) */
    /* stochastic pairwise MIS (mis = RESTIR_MIS_STOCHASTIC_PAIRWISE; stochastic_spatial.h): */
    int stochastic_n;           /* Ñ picks per pixel and pass (default 1) */
    int stochastic_nc;          /* Ñ_c canonical picks (default 1) */
    int no_confidence_scaling;  /* 1: no c_i <- c_i min(1, Ñ/M) (Stochastic MIS §4.3) */
    int cells;                  /* spatial domains = a reuse cell found by the §5.1 search
                                   (reuse_cells.h) instead of neighbor_select; any --mis */
    /* correlation under motion (issue 12, docs/correlation.md; real-time pipeline only): */
    int dedup;                  /* duplication-map adaptive cap (Enhanced §5): BIASED */
    double dedup_min;           /* c_cap_min (default 1) */
    double dedup_alpha;         /* alpha of lerp(mcap, c_cap_min, D^alpha) (default 0.1) */
    int motion_vectors;         /* enum restir_motion_vectors (default single; dual: Enhanced §6.4) */
    double boiling_filter;      /* RTXDI boiling filter strength s in (0, 1], 0 = off: BIASED */
    int output_aov;             /* enum restir_output: what the frame images hold (--aov duplicates|age) */
    int no_duplicate_stats;     /* 1: skip the per-frame duplication map and the Mutations Fig. 8
                                   duplicate count when nothing reads them (no --dedup, no
                                   --aov duplicates): the "correlation" and mutation duplicate
                                   counters of restir_stats stay 0 (default 0: computed) */
    volatile sig_atomic_t *stop_flag; /* checked between frames (NULL: never): nonzero ends the
                                         render after at least one frame (the CLI's SIGINT/SIGTERM) */
    /* MCMC mutations (mutate.h; Mutations Algorithm 3), real-time pipeline only: */
    int mutations;              /* N Metropolis-Hastings iterations per pixel and stage (default 0: off) */
    int mutation;               /* enum mutate_strategy (default rv, Mutations §4.3) */
    int mutate_after;           /* enum mutate_stage bits (default MUTATE_AFTER_TEMPORAL, Mutations §3) */
    /* light RIS for NEE (light_ris.h; Enhanced §6.1): */
    int light_ris;              /* N candidates at x1 (0: the plain light sampler, default) */
    int light_tiles;            /* 1: candidates from light tiles */
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
/* 1 if o turns on a feature that is biased by design (--dedup, --boiling-filter): the
 * estimator is then no longer unbiased (docs/correlation.md); --stats says "biased". */
int restir_options_biased(const restir_options *o);
int restir_options_validate(const restir_options *o, rerror *e);

/* The context (shift, criterion with d_min in scene units, ablation, MIS strategy) that
 * restir_render uses for scene s; lights must outlive it. */
void restir_context_for(restir_context *c, const scene *s, const light_set *lights, const restir_options *o);
void restir_initial_options_for(initial_options *io, const restir_options *o);
/* --pairing paired: builds no->count reuse textures (sigma from the radius, pairing.h) into
 * `textures` (PAIRING_MAX_TEXTURES entries) and points no at them; other patterns: no-op.
 * restir_pairing_free releases them. */
int restir_pairing_build(neighbor_options *no, const restir_options *o, reuse_texture *textures, rerror *e);
void restir_pairing_free(neighbor_options *no);
/* Whether spatial passes run the Enhanced §3 pair step (pair_step.c): --pairing paired, a
 * deterministic MIS family, no reuse cells, no --no-pair-step. */
int restir_pair_step_active(const restir_options *o);

/* The neighbour selection options of o (neighbors.h). */
void restir_neighbor_options_for(neighbor_options *no, const restir_options *o);
/* The effective configuration as a JSON object (no trailing newline). */
void restir_options_write_json(FILE *out, const restir_options *o, const char *indent);
/* The GRIS offline preset (GRIS §8.3): 32 path trees, 3 spatial passes, 6 neighbours in
 * radius 10, defensive pairwise MIS for spatial reuse (GRIS Eq. 38); the other fields are kept. */
void restir_options_preset_gris_offline(restir_options *o);

/* The GRIS real-time preset (GRIS §8.3): 1 path tree, temporal reuse (Talbot, cap 20),
 * one spatial pass with 3 neighbours in a 20-pixel radius, pairwise-defensive spatial MIS. */
void restir_options_preset_gris_realtime(restir_options *o);

#endif
