/* Private to src/cli. `restir render --runs K`: K independent renders reduced to per-pixel
 * mean, variance and the moments file of `restir check` (docs/statistics.md). */
#ifndef RESTIR_CLI_RENDER_RUNS_H
#define RESTIR_CLI_RENDER_RUNS_H

#include "render_args.h"

/* One image with the chosen method and seed (cmd_render.c's render_one). */
typedef int (*render_one_fn)(const render_args *a, const scene *s, uint32_t seed, const char *progressive_pfm,
                             image *img, render_timings *t);

/* The K runs of a->runs, each by render_one with seeds a->seed, a->seed + 1, ...: writes
 * PREFIX.mean.pfm, PREFIX.var.pfm, PREFIX.moments.json for `out` and returns the mean in
 * img; 0, 2 after printing the error, or 128 + signal when interrupted before two runs. */
/* 1 after printing why, if --method pt's --time-limit ended before its first pass was
 * complete (0 spp: a black image is no result), else 0. */
int pt_time_limit_empty(const render_args *a, const render_timings *t);

int render_runs(const render_args *a, const scene *s, const char *out, image *img, render_timings *t,
                render_one_fn render_one);

#endif
