/* Sampling warps: u in [0,1)^2 -> a point in a domain, each with its density
 * and its inverse u = warp^-1(x) (the MCMC mutations work on u).
 * Densities are with respect to area on the disk/triangle and solid angle on
 * spheres/hemispheres. Inverses are exact up to rounding on the open domain. */
#ifndef RESTIR_WARP_H
#define RESTIR_WARP_H

#include "restir/core/vec.h"

typedef struct { real x, y; } vec2;

static inline vec2 v2(real x, real y) { vec2 v; v.x = x; v.y = y; return v; }

/* Concentric (Shirley-Chiu) map of the unit square to the unit disk; pdf 1/pi.
 * (Inline, like warp_cosine_hemisphere: every diffuse bounce calls it, and a call passes
 * and returns its vectors through memory; docs/performance.md, round 2.) */
static inline vec2 warp_disk_concentric(vec2 u)
{
    real a = 2 * u.x - 1, b = 2 * u.y - 1, r, phi;
    if (a == 0 && b == 0) return v2(0, 0);
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (PI_R / 4) * (b / a);
    } else {
        r = b;
        phi = PI_R / 2 - (PI_R / 4) * (a / b);
    }
    return v2(r * cos(phi), r * sin(phi));
}
vec2 warp_disk_concentric_inverse(vec2 p);
real warp_disk_pdf(void);

/* Cosine-weighted hemisphere about +z (Malley: concentric disk lifted); pdf cos/pi. */
static inline vec3 warp_cosine_hemisphere(vec2 u)
{
    vec2 d = warp_disk_concentric(u);
    real z2 = 1 - d.x * d.x - d.y * d.y;
    return v3(d.x, d.y, z2 > 0 ? sqrt(z2) : 0);
}
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
static inline vec2 warp_uniform_triangle(vec2 u)
{
    /* b0 = 1 - sqrt(u1), b1 = u2 sqrt(u1): uniform over the triangle (PBRT 3rd ed. §13.6.5). */
    real s = sqrt(u.x);
    return v2(1 - s, u.y * s);
}
vec2 warp_uniform_triangle_inverse(vec2 b);

#endif
