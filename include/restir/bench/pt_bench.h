/* restir bench pt (src/bench/pt_bench.c): path-tracer throughput of a scene as JSON. */
#ifndef RESTIR_BENCH_PT_BENCH_H
#define RESTIR_BENCH_PT_BENCH_H

#include "restir/bench/bench_rays.h"

/* Renders s with the path tracer, `spp` samples per pixel on `threads` threads (MIS,
 * default options otherwise) and writes one JSON object to out: samples/s, rays/s,
 * seconds, counts (src/bench/pt_bench.c). */
int bench_pt(FILE *out, const scene *s, const char *name, uint32_t spp, int threads, rerror *e);

#endif
