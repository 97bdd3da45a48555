/* Private to src/scene. the five lobe kinds, each seen from wo's side of the surface.
 *
 * bsdf.c flips the local frame (z -> -z) when wo.z < 0 so that every lobe
 * function below sees wo.z > 0; `eta` is then the index ratio n(other side) /
 * n(wo's side) (dielectrics), or the coat's ior (plastic, two-sided). The lobe
 * functions never see the flip. */
#ifndef RESTIR_SCENE_LOBES_H
#define RESTIR_SCENE_LOBES_H

#include "restir/scene/bsdf.h"

typedef struct {
    const bsdf *b;
    vec3 wo;  /* unit, wo.z > 0 */
    real eta; /* n_other / n_wo_side, or the plastic coat's ior */
} lobe_view;

typedef struct {
    rgb (*eval)(const lobe_view *v, vec3 wi);             /* f |wi.z|; 0 for delta */
    real (*pdf)(const lobe_view *v, vec3 wi);             /* solid angle; 0 for delta */
    int (*sample)(const lobe_view *v, vec2 u, vec3 *wi);  /* direction only */
    int (*inverse)(const lobe_view *v, vec3 wi, vec2 *u); /* NULL for delta */
    rgb (*delta_coefficient)(const lobe_view *v);         /* NULL for non-delta */
    /* eval and pdf of one direction in one pass, bit for bit the two above (a sampled
     * direction needs both); NULL where the two share no work. */
    void (*eval_pdf)(const lobe_view *v, vec3 wi, rgb *f_cos, real *pdf);
} lobe_ops;

#endif
