/* Arbitrary output variables: the G-buffer channels as images (`render --aov`). */
#ifndef RESTIR_AOV_H
#define RESTIR_AOV_H

#include "restir/gbuffer.h"
#include "restir/image.h"

enum aov_kind { AOV_NORMAL, AOV_ALBEDO, AOV_DEPTH, AOV_OBJECT, AOV_MOTION };

/* Parses "normal|albedo|depth|object|motion"; returns -1 if unknown. */
int aov_parse(const char *name);
const char *aov_name(enum aov_kind kind);

/* normal: shading normal mapped to 0.5 + 0.5 n; albedo: Kd (or Ks for conductors and
 * dielectrics); depth: view-space depth in scene units (0 where nothing is hit);
 * object: a fixed pseudo-random colour per object id; motion: R, G = the motion vector in
 * pixels (gbuffer_motion: previous position minus current), B = prev_valid (0 or 1), all
 * 0 where nothing is hit. The image must be allocated. */
void aov_render(const gbuffer *g, const scene *s, enum aov_kind kind, image *out);

#endif
