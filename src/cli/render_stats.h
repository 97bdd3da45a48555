/* Private to src/cli. `restir render --stats FILE`: timings and counters as JSON (docs/cli.md). */
#ifndef RESTIR_CLI_RENDER_STATS_H
#define RESTIR_CLI_RENDER_STATS_H

#include "render_args.h"

/* Writes the JSON atomically; 0, or 2 after printing the error. */
int write_stats(const char *path, const render_args *a, const scene *s, const render_timings *t);

#endif
