/* The cost of light selection for NEE (`restir bench restir --light-ris N [--light-tiles]`;
 * docs/cli.md "bench", docs/enhanced.md §6). */
#ifndef RESTIR_LIGHT_BENCH_H
#define RESTIR_LIGHT_BENCH_H

#include <stdio.h>
#include "restir/core/error.h"
#include "restir/scene/scene.h"

/* One JSON object on `out`: ns per NEE sample at the primary hits of a 64 × 64 view
 * (selection, target evaluation and the one shadow ray), plain sampler vs light RIS with N
 * candidates (with tiles or not), the fraction of NEE samples that return light, and the
 * time to fill one frame's 128 × 1024 light tiles. Single thread; the minimum of interleaved
 * repetitions. */
int bench_light_selection(FILE *out, const scene *s, const char *name, int light_ris, int light_tiles, rerror *e);

#endif
