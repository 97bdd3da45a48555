/* `restir inspect`: one pixel's path sample, shift and GRIS step with every number
 * (src/oracle/inspect.c text, inspect_json.c JSON, inspect_step.c the steps). */
#ifndef RESTIR_ORACLE_INSPECT_H
#define RESTIR_ORACLE_INSPECT_H

#include <stdio.h>
#include "restir/frame/options.h"
#include "restir/scene/scene.h"

/* One pixel, for `restir inspect` (docs/restir-pt.md, docs/tour.md): prints the selected path
 * of pixel (x, y) in frame o->first_frame (vertices, lobes, k, technique, F, W), shifts it to
 * pixel (nx, ny) with o->shift (failure reason, or J with its factors, F(y) and the round
 * trip back), then one spatial GRIS step with M = 2 (the pixel's and the neighbour's initial
 * reservoirs, o->mis): every p̂, J, m_j, w_j and the resulting W. temporal (static scenes,
 * first_frame >= 1): also the temporal step with the pixel's initial reservoir of frame
 * first_frame - 1 as the previous domain (o->temporal_mis, o->mcap). json: one JSON object
 * with the same numbers at 17 significant digits instead of the text. */
int restir_inspect(FILE *out, const scene *s, const restir_options *o, int x, int y, int nx, int ny, int json,
                   int temporal, rerror *e);

#endif
