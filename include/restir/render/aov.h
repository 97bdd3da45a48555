/* Arbitrary output variables: the G-buffer channels as images (`render --aov`). */
#ifndef RESTIR_AOV_H
#define RESTIR_AOV_H

#include "restir/render/gbuffer.h"
#include "restir/core/image.h"

enum aov_kind { AOV_NORMAL, AOV_ALBEDO, AOV_DEPTH, AOV_OBJECT, AOV_MOTION };

/* "normal", "albedo", "depth", "object", "motion" (index = enum aov_kind), NULL-terminated. */
extern const char *const aov_names[];

/* normal: shading normal mapped to 0.5 + 0.5 n; albedo: Kd (or Ks for conductors and
 * dielectrics); depth: view-space depth in scene units (0 where nothing is hit);
 * object: a fixed pseudo-random colour per object id; motion: R, G = the motion vector in
 * pixels (gbuffer_motion: previous position minus current), B = prev_valid (0 or 1), all
 * 0 where nothing is hit. The image must be allocated. */
void aov_render(const gbuffer *g, const scene *s, enum aov_kind kind, image *out);

/* The PNG preview of an AOV image (allocated here): depth divided by the largest depth in
 * the image, so the farthest hit is 1 (white) and misses stay 0 (black) whatever the
 * scene's scale; the other channels are already in [0, 1] (normal, albedo, object) or
 * are signed pixel offsets (motion) and are copied unchanged. */
int aov_preview(const image *aov, enum aov_kind kind, image *out, rerror *e);

#endif
