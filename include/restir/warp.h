/* Sampling warps: u in [0,1)^2 -> a point in a domain, each with its density
 * and its inverse u = warp^-1(x) (the MCMC mutations work on u).
 * Densities are with respect to area on the disk/triangle and solid angle on
 * spheres/hemispheres. Inverses are exact up to rounding on the open domain. */
#ifndef RESTIR_WARP_H
#define RESTIR_WARP_H

#include "restir/vec.h"

typedef struct { real x, y; } vec2;

static inline vec2 v2(real x, real y) { vec2 v; v.x = x; v.y = y; return v; }

/* Concentric (Shirley-Chiu) map of the unit square to the unit disk; pdf 1/pi. */
vec2 warp_disk_concentric(vec2 u);
vec2 warp_disk_concentric_inverse(vec2 p);
real warp_disk_pdf(void);

/* Cosine-weighted hemisphere about +z (Malley: concentric disk lifted); pdf cos/pi. */
vec3 warp_cosine_hemisphere(vec2 u);
vec2 warp_cosine_hemisphere_inverse(vec3 w);
real warp_cosine_hemisphere_pdf(real cos_theta);

/* Uniform sphere; pdf 1/(4 pi). */
vec3 warp_uniform_sphere(vec2 u);
vec2 warp_uniform_sphere_inverse(vec3 w);
real warp_uniform_sphere_pdf(void);

/* Uniform hemisphere about +z; pdf 1/(2 pi). */
vec3 warp_uniform_hemisphere(vec2 u);
vec2 warp_uniform_hemisphere_inverse(vec3 w);
real warp_uniform_hemisphere_pdf(void);

/* Uniform cone about +z with half-angle acos(cos_max); pdf 1/(2 pi (1 - cos_max)). */
vec3 warp_uniform_cone(vec2 u, real cos_max);
vec2 warp_uniform_cone_inverse(vec3 w, real cos_max);
real warp_uniform_cone_pdf(real cos_max);

/* Uniform triangle: barycentrics (b0, b1), b2 = 1 - b0 - b1; pdf 1/area. */
vec2 warp_uniform_triangle(vec2 u);
vec2 warp_uniform_triangle_inverse(vec2 b);

#endif
