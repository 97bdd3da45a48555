/* Distant lights: an environment (a constant colour or an equirectangular map) and a sun
 * (a cone of uniform radiance), the "vertex at infinity" of docs/environment.md.
 *
 * A direction w (unit, pointing from the scene towards the sky) is the whole vertex: the
 * radiance arriving along -w is L(w) = L_env(w) + L_sun(w), whatever point receives it.
 *
 * Map convention (docs/scene-format.md, `environment map`): +y is up; the map's row 0 is
 * the top (theta = 0, w = +y), texel (col, row) covers u in [col, col+1)/W, v in
 * [row, row+1)/H, with theta = pi v and phi = 2 pi u + rotation, and
 *     w = (sin theta sin phi, cos theta, sin theta cos phi)
 * so u = 0 looks along +z, u = 1/4 along +x, and `rotate DEG` turns the map right-handedly
 * about +y. The map is piecewise constant (the nearest texel), which is exactly the function
 * its sampling distribution integrates: the oracle's answer to "what is the sky", against
 * which a GPU's bilinear lookup is an approximation.
 *
 * Sampling (two numbers each):
 *   map:      a piecewise-constant 2-D distribution over (u, v) (marginal CDF over rows,
 *             conditional CDF over the columns of the row), texel weights luminance x texel
 *             solid angle; solid-angle pdf p(w) = p_uv(u, v) / (2 pi^2 sin theta)
 *             (dw = sin theta dtheta dphi = 2 pi^2 sin theta du dv);
 *   constant: uniform on the sphere, p = 1/(4 pi);
 *   sun:      uniform in the cone of half-angle alpha around the sun direction,
 *             p = 1/Omega, Omega = 2 pi (1 - cos alpha). */
#ifndef RESTIR_SKY_H
#define RESTIR_SKY_H

#include "restir/core/error.h"
#include "restir/core/vec.h"
#include "restir/core/warp.h"
#include "restir/scene/scene.h"

typedef struct scene_sky {
    /* ---- as given by the scene file */
    int has_env;
    int env_is_map;         /* 0: constant env_constant; 1: the map below */
    rgb env_constant;
    char env_path[4096];    /* the map's file (for messages and the fingerprint) */
    real rotate_degrees;    /* about +y */
    real scale;             /* multiplies the map's texels (applied when the map is set) */
    int width, height;
    float *texels;          /* width * height * 3, row 0 = top, already scaled */
    int has_sun;
    vec3 sun_direction;     /* unit, towards the sun */
    real sun_angle_degrees; /* angular radius alpha, 0 < alpha < 90 */
    rgb sun_radiance;
    /* ---- derived by sky_prepare */
    real rotate_cos, rotate_sin;
    real sun_cos_max;       /* cos alpha */
    real sun_solid_angle;   /* 2 pi (1 - cos alpha), computed as 4 pi sin^2(alpha/2) */
    vec3 sun_t, sun_b;      /* an orthonormal frame (sun_t, sun_b, sun_direction) */
    real *marginal_cdf;     /* height + 1 entries, 0 .. 1 */
    real *conditional_cdf;  /* height rows of width + 1 entries, 0 .. 1 */
    real *row_weight;       /* sum of the texel weights of each row */
    real weight_sum;        /* sum of all texel weights */
    real env_power;         /* integral of luminance(L_env) over the sphere */
    real sun_power;         /* luminance(L_sun) Omega */
} scene_sky;

/* An empty description (no environment, no sun, scale 1). */
void sky_init(scene_sky *k);
void sky_free(scene_sky *k);
/* A deep copy into a new allocation (*dst = NULL for src = NULL). */
int sky_clone(scene_sky **dst, const scene_sky *src, rerror *e);

/* The environment map from any float RGB image (row 0 = top), times `scale`: PFM today,
 * EXR when the images branch lands. Texels must be finite and >= 0. */
int sky_set_map(scene_sky *k, int width, int height, const float *rgb_texels, real scale, rerror *e);
/* Reads the map file by its extension: .pfm, .exr (linear radiance) or .png (sRGB-decoded,
 * image_read's rule); other extensions are reported as unsupported. */
int sky_load_map(scene_sky *k, const char *path, real scale, rerror *e);
/* Builds the derived fields. Call after the description is complete. */
int sky_prepare(scene_sky *k, rerror *e);

/* Radiance arriving from direction w (unit, towards the sky). */
rgb sky_env_radiance(const scene_sky *k, vec3 w);
rgb sky_sun_radiance(const scene_sky *k, vec3 w);
static inline rgb sky_radiance(const scene_sky *k, vec3 w)
{
    return rgb_add(sky_env_radiance(k, w), sky_sun_radiance(k, w));
}

/* Environment sampling from two numbers; returns the unit direction. */
vec3 sky_env_sample(const scene_sky *k, vec2 u);
/* Its solid-angle pdf at w (0 where the map is black). */
real sky_env_pdf(const scene_sky *k, vec3 w);
/* The map coordinates (u, v) of a direction and back (no pdf): for tests and inspection. */
vec2 sky_env_uv(const scene_sky *k, vec3 w);
vec3 sky_env_direction(const scene_sky *k, vec2 uv);

/* Sun sampling: uniform in the cone; pdf 1/Omega inside it, 0 outside. */
vec3 sky_sun_sample(const scene_sky *k, vec2 u);
real sky_sun_pdf(const scene_sky *k, vec3 w);

/* Is the direction w from the surface point p (geometric normal ng) free up to infinity?
 * The ray starts from p offset to w's side (offset_ray_origin) and has no end. */
int sky_visible(const scene *s, vec3f p, vec3f ng, vec3 w);

#endif
