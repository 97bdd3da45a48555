/* Offline ReSTIR PT in the benchmark and the equal-time harness (docs/restir-pt.md,
 * "Benchmark"): `make bench` prints per-pass milliseconds (initial, each spatial pass,
 * shade), shifts per pixel, shift failure reasons and an equal-time comparison with the
 * reference path tracer as JSON. */
#ifndef RESTIR_RESTIR_BENCH_H
#define RESTIR_RESTIR_BENCH_H

#include <stdio.h>
#include "restir/bench/equal_time.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"

/* Offline ReSTIR PT as an equal_time method: unit u = frame options.first_frame + u
 * (independent frames; the harness averages them, GRIS Eq. 47). ctx must outlive m. */
typedef struct {
    const scene *s;
    restir_options options;
} equal_time_restir_ctx;
void equal_time_restir_method(equal_time_restir_ctx *ctx, const scene *s, const restir_options *o, const char *name,
                              equal_time_method *m);

/* One timed frame of o on s per (shift, MIS family) in {reconnection, replay, hybrid} x
 * {talbot, pairwise-defensive}: writes a JSON array element per configuration (name,
 * configuration, milliseconds per pass, shifts per pixel per pass, failure reasons). */
int bench_restir(FILE *out, const scene *s, const char *name, const restir_options *o, int *first, rerror *e);

/* Equal time against the path tracer: a reference of ref_spp samples per pixel, then PT
 * and o for `seconds` each; prints one JSON element with both curves' last MAPE and the
 * time each needs to reach the larger of the two final MAPEs (equal_time_time_to_reach). */
int bench_restir_equal_time(FILE *out, const scene *s, const char *name, const restir_options *o, uint32_t ref_spp,
                            double seconds, int *first, rerror *e);

/* The real-time pipeline (restir_render_sequence) over frames first_frame..last_frame of s
 * with o: one JSON element with the per-frame milliseconds of every stage (pose + BVH
 * rebuild, G-buffer, motion vectors, initial, temporal, each spatial pass, shading),
 * temporal and spatial shifts per pixel, the temporal history / cap / selection rates and
 * shift outcomes, and the bytes of reservoir state per pixel. */
int bench_realtime(FILE *out, const scene *s, const char *name, const restir_options *o, int first_frame,
                   int last_frame, int *first, rerror *e);

/* MCMC mutations (docs/mutations.md): the sequence f0..f1 of s (hybrid shift) without
 * mutations and, per strategy (rv, pp, fp), with o->mutations (>= 1) mutations after temporal
 * reuse; one JSON object per strategy: ms per mutation iteration, frame times and their
 * ratio, acceptance rate, rejections by reason, bytes per pixel. */
int bench_mutations(FILE *out, const scene *s, const char *name, const restir_options *o, int f0, int f1, int *first,
                    rerror *e);

#endif
