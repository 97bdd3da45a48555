/* Vector math.
 *
 * Two precisions live side by side (docs/design.md, Conventions):
 *   vec3f  float   geometry: vertices, BVH, rays, hit points (as GPUs do);
 *   vec3   real    estimator arithmetic: shading directions, throughputs, pdfs.
 * `real` is double by default and float with `make PRECISION=float`.
 * Colours are `rgb` (linear Rec. 709 primaries). */
#ifndef RESTIR_VEC_H
#define RESTIR_VEC_H

#include <math.h>

#ifdef RESTIR_REAL_FLOAT
typedef float real;
#define REAL_EPSILON 1.1920929e-7f
#define REAL_MAX 3.402823e38f
#else
typedef double real;
#define REAL_EPSILON 2.220446049250313e-16
#define REAL_MAX 1.7976931348623157e308
#endif

#define PI_R ((real)3.14159265358979323846)
#define INV_PI_R ((real)0.31830988618379067154)

typedef struct { float x, y, z; } vec3f;
typedef struct { real x, y, z; } vec3;
typedef struct { real r, g, b; } rgb;

/* ---- float geometry vectors ---- */
static inline vec3f v3f(float x, float y, float z) { vec3f v; v.x = x; v.y = y; v.z = z; return v; }
static inline vec3f v3f_add(vec3f a, vec3f b) { return v3f(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3f v3f_sub(vec3f a, vec3f b) { return v3f(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3f v3f_scale(vec3f a, float s) { return v3f(a.x * s, a.y * s, a.z * s); }
static inline float v3f_dot(vec3f a, vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3f v3f_cross(vec3f a, vec3f b)
{
    return v3f(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float v3f_length(vec3f a) { return sqrtf(v3f_dot(a, a)); }
static inline vec3f v3f_normalize(vec3f a) { return v3f_scale(a, 1.0f / v3f_length(a)); }
static inline vec3f v3f_min(vec3f a, vec3f b) { return v3f(fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z)); }
static inline vec3f v3f_max(vec3f a, vec3f b) { return v3f(fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)); }
static inline float v3f_axis(vec3f a, int axis) { return axis == 0 ? a.x : (axis == 1 ? a.y : a.z); }

/* ---- real vectors ---- */
static inline vec3 v3(real x, real y, real z) { vec3 v; v.x = x; v.y = y; v.z = z; return v; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_scale(vec3 a, real s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline real v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline real v3_length(vec3 a) { return (real)sqrt(v3_dot(a, a)); }
static inline vec3 v3_normalize(vec3 a) { return v3_scale(a, (real)1 / v3_length(a)); }
static inline vec3 v3_from_f(vec3f a) { return v3((real)a.x, (real)a.y, (real)a.z); }
static inline vec3f v3f_from(vec3 a) { return v3f((float)a.x, (float)a.y, (float)a.z); }

/* Orthonormal basis around unit n (Duff et al. 2017, "Building an orthonormal basis, revisited"). */
static inline void v3_basis(vec3 n, vec3 *t, vec3 *b)
{
    real sign = n.z >= 0 ? (real)1 : (real)-1;
    real a = (real)-1 / (sign + n.z);
    real c = n.x * n.y * a;
    *t = v3((real)1 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = v3(c, sign + n.y * n.y * a, -n.y);
}

/* ---- colours ---- */
static inline rgb rgb_make(real r, real g, real b) { rgb c; c.r = r; c.g = g; c.b = b; return c; }
static inline rgb rgb_gray(real v) { return rgb_make(v, v, v); }
static inline rgb rgb_add(rgb a, rgb b) { return rgb_make(a.r + b.r, a.g + b.g, a.b + b.b); }
static inline rgb rgb_mul(rgb a, rgb b) { return rgb_make(a.r * b.r, a.g * b.g, a.b * b.b); }
static inline rgb rgb_scale(rgb a, real s) { return rgb_make(a.r * s, a.g * s, a.b * s); }
static inline int rgb_is_black(rgb a) { return a.r == 0 && a.g == 0 && a.b == 0; }
static inline real rgb_max(rgb a) { return fmax(a.r, fmax(a.g, a.b)); }

/* The target function's scalarisation: Rec. 709 luminance (docs/design.md, Conventions). The one place it is written. */
static inline real luminance(rgb c) { return (real)0.2126 * c.r + (real)0.7152 * c.g + (real)0.0722 * c.b; }

#endif
