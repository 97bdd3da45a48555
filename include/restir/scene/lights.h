/* Emissive triangles as lights (docs/scenes.md): every triangle whose material has
 * emission Ke > 0 in some channel is a one-sided area light that emits radiance Ke
 * from its FRONT face only, the side of the face normal (v1-v0)x(v2-v0).
 *
 * Light sampling for next-event estimation (NEE) is two discrete/continuous steps:
 *   1. pick a light l with probability P(l) proportional to its power
 *      Phi_l ∝ luminance(Ke_l) · area_l (Vose's alias table: O(1) per sample);
 *   2. pick a point y uniformly on its area (warp_uniform_triangle), pdf 1/area_l.
 * The area-measure pdf of y is P(l)/area_l. From a receiving point x the solid-angle
 * pdf of the direction towards y is
 *     p_light(x -> y) = P(l) / area_l · |x - y|^2 / |cos theta_l|,  cos theta_l = n_l · (x - y)/|x - y|
 * which is also the pdf the NEE strategy assigns to a BSDF-sampled path that HITS
 * the emitter at y (needed by the balance heuristic, GRIS §7.6 Eq. 49). */
#ifndef RESTIR_LIGHTS_H
#define RESTIR_LIGHTS_H

#include <stddef.h>
#include <stdint.h>
#include "restir/core/error.h"
#include "restir/scene/scene.h"
#include "restir/core/vec.h"
#include "restir/core/warp.h"

#define LIGHT_NONE UINT32_MAX
/* The triangle index of a vertex at infinity (a light_sample or surface_hit of the sky:
 * docs/environment.md). Such a vertex keeps its unit direction w (from the scene towards
 * the sky) in its position field and -w as its normal. */
#define LIGHT_TRIANGLE_DISTANT (UINT32_MAX - 1u)

/* A discrete distribution sampled in O(1) by Vose's alias method
 * (M. D. Vose, "A linear algorithm for generating random numbers with a given
 * distribution", IEEE TSE 17(9), 1991). */
typedef struct {
    size_t count;
    real *pmf;        /* the normalised probabilities p_i = w_i / sum w */
    real *threshold;  /* column i keeps i if the coin u < threshold[i], else alias[i] */
    uint32_t *alias;
} alias_table;

/* Builds the table for non-negative weights with a positive, finite sum. */
int alias_table_build(alias_table *t, const real *weights, size_t count, rerror *e);
void alias_table_free(alias_table *t);
/* u_column picks the column (uniformly), u_coin decides between it and its alias. */
uint32_t alias_table_sample(const alias_table *t, real u_column, real u_coin);

typedef struct {
    uint32_t triangle; /* index into scene.triangles */
    vec3f v0, v1, v2;  /* vertices (float geometry, docs/design.md, Conventions) */
    vec3f normal;      /* unit front-face normal (v1-v0)x(v2-v0)/|..| */
    real area;
    rgb emission;      /* Ke: radiance leaving the front face */
} light;

typedef struct {
    light *lights;
    size_t count;
    alias_table select;          /* P(l) ∝ luminance(Ke_l) · area_l */
    uint32_t *light_of_triangle; /* scene triangle -> light index, or LIGHT_NONE */
    size_t triangle_count;
    real total_power;            /* sum of luminance(Ke) · area (no factor pi) */
    /* Distant lights (docs/environment.md): the environment and the sun are entries
     * env_entry, sun_entry >= count of the selection table (LIGHT_NONE if absent or
     * without power), with power R^2 ∫ luminance(L) dω (R: the scene's bounding-sphere
     * radius; the power per π a disc of radius R intercepts). */
    const struct scene_sky *sky; /* NULL: no distant light */
    /* The scene, when some emitter has map_Ke: the emission of a light point is then Ke
     * times the map at its UV (light_emission_at); NULL: every light emits its Ke. The
     * selection table keeps P(l) ∝ lum(Ke) area (any P(l) > 0 where emission is stays exact). */
    const scene *maps;
    uint32_t env_entry, sun_entry;
} light_set;

/* Collects the emissive triangles of s. Zero-area emissive triangles are skipped (they
 * carry no power and cannot be hit). A scene without lights is valid (count = 0). */
int lights_build(light_set *ls, const scene *s, rerror *e);
void lights_free(light_set *ls);

/* A sampled point on a light; for a distant light (triangle = LIGHT_TRIANGLE_DISTANT) the
 * point at infinity: position = the unit direction w, normal = -w, emission = the sky's
 * whole radiance L_env(w) + L_sun(w), pdf_area = the SOLID-ANGLE pdf light_pdf_distant(w)
 * (every distant light that can produce w, each with its selection probability). */
typedef struct {
    uint32_t light;     /* index into light_set.lights */
    uint32_t triangle;  /* scene triangle index */
    vec3f position;
    vec3f normal;       /* front-face normal of the light */
    vec2 barycentric;   /* (b0, b1) as returned by warp_uniform_triangle; b2 = 1 - b0 - b1 */
    rgb emission;
    real pdf_area;      /* P(l) / area_l */
} light_sample;

/* Samples a light point from four uniform numbers: u[0] column, u[1] alias coin,
 * u[2], u[3] the point on the triangle. Returns 0 if the set is empty. */
int light_sample_point(const light_set *ls, const real u[4], light_sample *out);

/* The radiance Ke of light l (an index into ls->lights) at barycentrics (b1, b2) of its
 * triangle: Ke, or Ke times its map_Ke there. */
rgb light_emission_at(const light_set *ls, uint32_t l, float b1, float b2);

/* Inverse of the point step: the (u[2], u[3]) that produce barycentrics b. */
vec2 light_sample_point_inverse(vec2 barycentric);

/* Selection probability P(l) of the light on scene triangle `tri` (0 if it is not a light). */
real light_select_pdf(const light_set *ls, uint32_t tri);
/* Area-measure pdf P(l)/area_l of a point on scene triangle `tri` (0 if not a light). */
real light_pdf_area(const light_set *ls, uint32_t tri);

/* Converts an area pdf at point y (unit normal ny) into the solid-angle pdf seen from x:
 * pdf_area · |x-y|^2 / |ny · (x-y)/|x-y||. Returns 0 if the direction is tangent or x == y. */
real pdf_area_to_solid_angle(real pdf_area, vec3 x, vec3 y, vec3 ny);
/* The same from d = y - x (or x - y: only |ny . d| enters) and dist2 = d . d, for NEE, which
 * has them already: bit for bit pdf_area_to_solid_angle(pdf_area, x, y, ny). */
real pdf_area_to_solid_angle_d(real pdf_area, vec3 d, real dist2, vec3 ny);

/* Solid-angle pdf with which NEE from x samples the point y on scene triangle `tri`
 * (normal ny). The MIS weight of a BSDF-sampled emitter hit uses it. */
real light_pdf_solid_angle(const light_set *ls, uint32_t tri, vec3 x, vec3 y, vec3 ny);

/* Solid-angle pdf with which the light sampler produces the direction w at infinity:
 * Σ over the distant lights P(l) p_l(w) (0 without distant lights). */
real light_pdf_distant(const light_set *ls, vec3 w);
/* The radiance arriving from direction w (0 without distant lights). */
rgb light_distant_radiance(const light_set *ls, vec3 w);
static inline int light_set_has_sky(const light_set *ls) { return ls->sky != NULL; }

/* Radiance emitted from point y of a light with front normal n towards direction
 * `to_receiver` (unit, pointing away from the light): Ke on the front side, 0 behind. */
static inline rgb light_emitted(rgb emission, vec3 normal, vec3 to_receiver)
{
    return v3_dot(normal, to_receiver) > 0 ? emission : rgb_gray(0);
}

#endif
