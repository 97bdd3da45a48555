/* `restir bench stochastic [SCENE]` (issue 14; docs/stochastic-mis.md): at the scene's
 * size (256 x 256 from the CLI), one JSON element per configuration of one spatial pass
 * after initial sampling: stochastic pairwise MIS over reuse cells for Ñ in
 * {1, 2, 4, 8, 16} (Ñ_c = 1, confidence scaling), the deterministic all-M comparator over
 * the same cells (pairwise-defensive), and stochastic pairwise over the default r2
 * neighbours; each with ms per spatial pass, shifts and MIS shifts per pixel and domains
 * per pixel. First, one element with the cell construction: ms per build (median of 9),
 * cells, tiles, cells per tile, mean pixels per cell, fraction of pixels with a non-zero
 * sample. */
#ifndef RESTIR_STOCHASTIC_BENCH_H
#define RESTIR_STOCHASTIC_BENCH_H

#include <stdio.h>
#include "restir/core/error.h"
#include "restir/scene/scene.h"

int bench_stochastic(FILE *out, const scene *s, const char *name, int threads, int *first, rerror *e);

#endif
