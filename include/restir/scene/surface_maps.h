/* What a surface point is once its material's image maps are applied (src/scene/surface_maps.c;
 * docs/materials.md, "Textures"): the UV from the triangle and barycentrics, the textured
 * material and BSDF, the cut-out test of every ray query and the textured emission.
 *
 * Everything is a function of (triangle, b1, b2) only: a vertex rebuilt from its stored
 * triangle and barycentrics (a reconnection vertex in an offset path) shades exactly as it
 * did where it was found. Untextured materials return their constants unchanged. */
#ifndef RESTIR_SCENE_SURFACE_MAPS_H
#define RESTIR_SCENE_SURFACE_MAPS_H

#include "restir/scene/bsdf.h"
#include "restir/scene/scene.h"

/* The alpha below which a cut-out (map_d) surface is absent: a hit there is not a hit. */
#define SCENE_ALPHA_CUTOFF 0.5

/* (u, v) interpolated from the triangle's vt (1 - b1 - b2, b1, b2); (0, 0) if it has none. */
vec2 scene_uv(const scene *s, uint32_t tri, float b1, float b2);
/* 1 if the material has a map that changes its BSDF (map_Kd, map_Pr / map_Ns). */
int material_has_bsdf_maps(const material *m);
/* The material at the point with map_Kd and the roughness map applied. */
material scene_material_at(const scene *s, uint32_t tri, float b1, float b2);
/* bsdf_from_material of scene_material_at (for untextured materials bit for bit
 * bsdf_from_material of the scene's material). */
bsdf scene_bsdf_at(const scene *s, const surface_hit *h);
/* 1 if the point is part of the surface: no map_d, or its alpha >= SCENE_ALPHA_CUTOFF.
 * The ray queries (scene_trace.c, sky.c) reject every other hit. */
int scene_alpha_keeps(const scene *s, uint32_t tri, float b1, float b2);
/* The emission Ke of triangle tri's material at the point, times map_Ke there (if any). */
rgb scene_emission_at(const scene *s, uint32_t tri, float b1, float b2, rgb ke);
/* The barycentrics (b1, b2) of the point p of triangle tri (projected onto its plane, in
 * real arithmetic): for light points known only by position (light RIS). */
void scene_barycentrics(const scene *s, uint32_t tri, vec3 p, float *b1, float *b2);
/* 1 if some material of the scene has map_Ke (emission varies over its triangles). */
int scene_has_emission_maps(const scene *s);

#endif
