/* Thread scaling of the real-time ReSTIR pipeline (issue 17; docs/performance.md, "ReSTIR
 * thread scaling"): `restir bench scaling [SCENE]`. */
#ifndef RESTIR_SCALING_BENCH_H
#define RESTIR_SCALING_BENCH_H

#include <stdio.h>
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"

/* Frames 0..frames-1 of s with o (restir_render_sequence, no output), `rounds` times with
 * 1 thread and with `threads` threads, alternately (1 T, T 1, ...). One JSON element: per
 * thread count the wall and CPU seconds of every round, the CPU the workers spent inside
 * parallel regions (threads_parallel_cpu_seconds) and the rest (serial: setup, stage
 * glue, statistics), the stage milliseconds; the wall speed-up (median, min, max over
 * rounds), the CPU ratio T/1, and the serial fraction s of the 1-thread runs with its
 * Amdahl bound 1 / (s + (1 - s) / T). Wall figures are only meaningful on an idle machine;
 * the CPU figures are not (much) disturbed by load. */
int bench_scaling(FILE *out, const scene *s, const char *name, const restir_options *o, int frames, int threads,
                  int rounds, int *first, rerror *e);

#endif
