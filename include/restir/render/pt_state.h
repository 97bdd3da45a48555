/* The path tracer's accumulation state (src/render/pt_state.c): per-pixel sums of one or more
 * sample ranges, their mean, merging of disjoint ranges (restir merge), and the fingerprint
 * that says which scene and options a state belongs to. */
#ifndef RESTIR_RENDER_PT_STATE_H
#define RESTIR_RENDER_PT_STATE_H

#include "restir/render/pt.h"

/* ---- state, mean image, variance ---- */
int pt_state_alloc(pt_state *st, int width, int height, rerror *e);
void pt_state_free(pt_state *st);
/* out (allocated here) = sum / spp; all zero when spp = 0. */
int pt_state_mean(const pt_state *st, image *out, rerror *e);

/* 64-bit FNV-1a fingerprint of everything that defines the estimator's expectation and its
 * random numbers: geometry, materials, camera at o->frame, image size, seed, max depth,
 * strategy, roulette, jitter, ablations and the precision of `real`. Not: spp, sample
 * offset, threads, time limit. */
uint64_t pt_fingerprint(const scene *s, const pt_options *o);

/* ---- merging independent runs ---- */
/* acc += add: same size, seed and fingerprint, and add's sample range must start where
 * acc's ends or end where it starts (contiguous, disjoint), so the merged state is the
 * state of one run over the union of the sample ranges. */
int pt_state_merge(pt_state *acc, const pt_state *add, rerror *e);
/* out (allocated here) = sum_i counts[i] · images[i] / sum_i counts[i], accumulated in
 * double: the sample-count-weighted mean of runs given as mean images. */
int pt_merge_means(const image *images, const double *counts, int n, image *out, rerror *e);

#endif
