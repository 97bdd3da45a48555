/* Private to src/cli. `restir render --sequence A..B --runs K` (render_sequence_runs.c): K
 * runs of the sequence with seeds seed..seed+K-1; per frame f the moments file set
 * PREFIX.FFFF.mean.pfm, .var.pfm, .moments.json, .blocks.bin (restir check reads each:
 * a per-frame verdict); with --dump-dir DIR, run k's stage dumps in DIR/run_KK (diff-dump
 * --stat pairs run k of A with run k of B). */
#ifndef RESTIR_CLI_RENDER_SEQUENCE_RUNS_H
#define RESTIR_CLI_RENDER_SEQUENCE_RUNS_H

#include "render_args.h"

int render_sequence_runs(const render_args *a, const scene *s, const char *out, render_timings *t);

#endif
