/* MTL material libraries (src/scene/mtl.c; docs/scene-format.md, "MTL mapping"): the raw
 * statements of each material and the documented mapping to the oracle's lobed materials. */
#ifndef RESTIR_SCENE_MTL_H
#define RESTIR_SCENE_MTL_H

#include "restir/scene/scene_builder.h"

/* The raw statements of one MTL material (`has_*` says whether the key was given). */
typedef struct {
    rgb kd, ks, ke;
    double ns, ni, d, tr, pr, pm;
    int illum;
    int has_kd, has_ks, has_ke, has_ns, has_ni, has_d, has_tr, has_pr, has_pm, has_illum;
    /* Image maps, loaded into the scene as they are read: 1 + index into scene.textures, 0 = none. */
    uint32_t map_kd, map_ke, map_pr, map_ns, map_d;
} mtl_record;

/* Loads an MTL library into b (mtl.c); skips a library loaded before (same path). */
int mtl_load(scene_builder *b, const char *path, rerror *e);

/* The documented MTL -> material mapping (docs/scene-format.md, "MTL mapping"; maps:
 * docs/materials.md, "Textures").
 * *dissolve_ignored is set when d < 1 or Tr > 0 was given but did not make the material
 * a dielectric. */
material mtl_to_material(const char *name, const mtl_record *r, int *dissolve_ignored);
/* GGX linear roughness r from a Phong/Blinn-Phong exponent: alpha = sqrt(2 / (Ns + 2))
 * (Walter et al. 2007, Sec. 5.2, the Phong-Beckmann correspondence), r = sqrt(alpha). */
real roughness_from_phong_exponent(double ns);

#endif
