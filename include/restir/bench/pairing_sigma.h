/* `restir bench pairing-sigma` (src/bench/pairing_sigma.c; docs/enhanced.md §2, "Eq. 3,
 * measured"): the standard deviation a reuse texture's offsets actually reach for each
 * reading of Enhanced Eq. 3 over a grid of target sigmas. */
#ifndef RESTIR_BENCH_PAIRING_SIGMA_H
#define RESTIR_BENCH_PAIRING_SIGMA_H

#include <stdint.h>
#include <stdio.h>
#include "restir/core/error.h"

/* One JSON element (after a comma unless *first) per (sigma, reading): the pass count n of
 * the reading, and per axis the mean over `textures` independent textures of size `size`
 * (ids 0..textures-1 of `seed`) of the offsets' standard deviation, with its 99% t-interval,
 * and the relative error against sigma. */
int bench_pairing_sigma(FILE *out, int textures, int size, uint32_t seed, int *first, rerror *e);

#endif
