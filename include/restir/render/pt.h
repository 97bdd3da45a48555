/* The reference unidirectional path tracer: the ground truth every ReSTIR configuration
 * is tested against (docs/path-tracer.md).
 *
 * Estimator: per pixel, the mean over samples s of the path contribution L_s,
 *     L = Le(x1) + sum_{i>=1} beta_i [ w_nee · f|cos| Le / p_light  (NEE at x_i)
 *                                     + w_bsdf · Le(x_{i+1}) · f_l|cos|/(P(l) pdf_l) (BSDF hit) ]
 * with the balance heuristic of GRIS Eq. 49 (all-lobe BSDF pdf), max path length d,
 * optional Russian roulette. Paths are addressed: sample s of pixel p uses
 * rng_key_make(seed, p, s) (docs/rng.md), so any sample can be replayed alone, runs with
 * disjoint sample ranges are independent, and the result is identical for any thread count.
 *
 * State: per-pixel sums in double of L and L^2 for the samples [sample_offset,
 * sample_offset + spp). A checkpoint stores this state; resuming continues with the next
 * sample index, so an interrupted and resumed run equals an uninterrupted one bit for bit. */
#ifndef RESTIR_PT_H
#define RESTIR_PT_H

#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include "restir/core/error.h"
#include "restir/core/image.h"
#include "restir/render/light_ris.h"
#include "restir/render/vertex_sampling.h"
#include "restir/scene/scene.h"

#define PT_MAX_DEPTH_LIMIT 255 /* the RNG address has 8 bits for the vertex index */

/* NULL-terminated name tables for the CLI (index = enum value / bit position). */
extern const char *const pt_strategy_names[];  /* "mis", "nee", "bsdf" */
extern const char *const pt_ablation_names[];  /* "light-pdf", "mis-sum", "mis-lobe", "light-ris-pdf" */
/* The ablation bit for a name, or 0 if unknown. */
unsigned pt_ablation_from_name(const char *name);

/* Accumulated samples of one render (what a checkpoint holds). */
typedef struct {
    int width, height;
    double *sum;            /* 3 doubles per pixel: sum over samples of L (RGB) */
    double *sum_sq;         /* 3 doubles per pixel: sum of L^2 (per-pixel variance) */
    uint32_t seed;
    uint32_t sample_offset; /* sample index of the first accumulated sample */
    uint32_t spp;           /* samples per pixel accumulated: [sample_offset, sample_offset + spp) */
    uint64_t fingerprint;   /* scene + estimator options (pt_fingerprint) */
    uint64_t nonfinite;     /* samples whose L had a NaN/Inf channel (accumulated as 0) */
    uint32_t first_nonfinite_pixel, first_nonfinite_sample; /* smallest (sample, pixel) */
} pt_state;

typedef void (*pt_pass_callback)(void *ctx, const pt_state *st);

typedef struct {
    uint32_t spp;           /* target TOTAL samples per pixel (a resumed state counts); 0 = no target */
    double time_limit;      /* seconds; 0 = none. Whole 1-spp passes run until it is reached */
    uint32_t seed;          /* run seed of the addressed RNG */
    uint32_t sample_offset; /* first sample index of a fresh run (runs with disjoint ranges merge) */
    int max_depth;          /* maximum path length d in segments, 1..255 (1 = emission at x1 only) */
    int min_depth;          /* shortest path length d counted, 1..max_depth (default 1 = all light;
                               3 = indirect light only, what restir --paths indirect renders) */
    enum pt_strategy strategy;
    int russian_roulette;   /* 0 (default) or 1: unbiased roulette, see rr_min_depth */
    int rr_min_depth;       /* roulette decides continuation after vertex x_i for i >= this (default 3) */
    int jitter;             /* 1: sub-pixel jitter from RNG_CAMERA; 0: pixel centres (default) */
    unsigned ablations;     /* enum pt_ablation bits */
    light_ris_options light_ris; /* NEE by light RIS (light_ris.h; default: off, the plain sampler) */
    int frame;              /* camera keyframe time */
    int threads;            /* >= 1 */
    int quiet;              /* no progress bar */
    const char *checkpoint_path;  /* written at the end and when stopped (NULL: none) */
    double checkpoint_interval;   /* also every this many seconds (0: never) */
    const char *resume_path;      /* continue this checkpoint (NULL: fresh start) */
    volatile sig_atomic_t *stop_flag; /* checked between passes; nonzero ends the render */
    int callback_every;           /* call on_passes after every this many passes (0: never) */
    pt_pass_callback on_passes;
    void *callback_ctx;
} pt_options;

typedef struct {
    pt_state state;
    image mean;             /* float RGB: sum / spp (what the CLI writes) */
    double seconds;         /* wall time of this call's rendering */
    uint64_t paths;         /* paths traced in this call */
    uint64_t rays;          /* rays traced in this call (camera + bounce + shadow) */
    uint32_t spp_added;     /* samples per pixel added by this call */
    int stopped;            /* 1 if stop_flag ended the render before the target */
} pt_result;

void pt_options_default(pt_options *o);
/* Checks ranges (max depth, threads, sample range overflow, spp or time limit given). */
int pt_options_validate(const pt_options *o, rerror *e);

/* Renders s (prepared: BVH built) per o. On success fills *out (free with pt_result_free).
 * The light set is built inside. Frees everything on failure. */
int pt_render(const scene *s, const pt_options *o, pt_result *out, rerror *e);
void pt_result_free(pt_result *r);

#endif
