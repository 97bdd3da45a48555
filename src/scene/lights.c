/* Emissive triangles, power-proportional light selection and uniform area sampling
 * (include/restir/scene/lights.h). */
#include "restir/scene/lights.h"

#include <stdlib.h>
#include <string.h>
#include "restir/scene/sky.h"
#include "restir/scene/surface_maps.h"

/* ---- Vose's alias method ------------------------------------------------------- */

void alias_table_free(alias_table *t)
{
    free(t->pmf);
    free(t->threshold);
    free(t->alias);
    memset(t, 0, sizeof *t);
}

/* Vose 1991: scale the probabilities by n; repeatedly pair one column that is below
 * 1 ("small") with one above ("large"); the large one donates the missing mass and
 * becomes the alias. Each column then holds at most two outcomes. */
static void alias_table_fill(alias_table *t, real *scaled, uint32_t *work)
{
    size_t n = t->count, small_top = 0, large_bottom = n, i;
    /* work[0 .. small_top) is the small stack, work[large_bottom .. n) the large one. */
    for (i = 0; i < n; ++i) {
        if (scaled[i] < 1) work[small_top++] = (uint32_t)i;
        else work[--large_bottom] = (uint32_t)i;
    }
    while (small_top > 0 && large_bottom < n) {
        uint32_t s = work[--small_top], l = work[large_bottom++];
        t->threshold[s] = scaled[s];
        t->alias[s] = l;
        scaled[l] = (scaled[l] + scaled[s]) - 1;
        if (scaled[l] < 1) work[small_top++] = l;
        else work[--large_bottom] = l;
    }
    /* Left-overs are 1 up to rounding: they keep their own column entirely. */
    while (large_bottom < n) {
        uint32_t l = work[large_bottom++];
        t->threshold[l] = 1;
        t->alias[l] = l;
    }
    while (small_top > 0) {
        uint32_t s = work[--small_top];
        t->threshold[s] = 1;
        t->alias[s] = s;
    }
}

int alias_table_build(alias_table *t, const real *weights, size_t count, rerror *e)
{
    real sum = 0, *scaled = NULL;
    uint32_t *work = NULL;
    size_t i;
    memset(t, 0, sizeof *t);
    if (count == 0 || count > UINT32_MAX) return rerror_set(e, "alias table: %lu entries", (unsigned long)count);
    for (i = 0; i < count; ++i) {
        if (!(weights[i] >= 0) || !isfinite(weights[i]))
            return rerror_set(e, "alias table: weight %lu is %g", (unsigned long)i, (double)weights[i]);
        sum += weights[i];
    }
    if (!(sum > 0) || !isfinite(sum)) return rerror_set(e, "alias table: the weights sum to %g", (double)sum);
    t->count = count;
    t->pmf = rmalloc(count, sizeof *t->pmf, e);
    t->threshold = rmalloc(count, sizeof *t->threshold, e);
    t->alias = rmalloc(count, sizeof *t->alias, e);
    scaled = rmalloc(count, sizeof *scaled, e);
    work = rmalloc(count, sizeof *work, e);
    if (!t->pmf || !t->threshold || !t->alias || !scaled || !work) {
        free(scaled);
        free(work);
        alias_table_free(t);
        return -1;
    }
    for (i = 0; i < count; ++i) {
        t->pmf[i] = weights[i] / sum;
        scaled[i] = t->pmf[i] * (real)count;
    }
    alias_table_fill(t, scaled, work);
    free(scaled);
    free(work);
    return 0;
}

uint32_t alias_table_sample(const alias_table *t, real u_column, real u_coin)
{
    size_t column = (size_t)(u_column * (real)t->count);
    if (column >= t->count) column = t->count - 1; /* u_column = 1 - ulp in float builds */
    return u_coin < t->threshold[column] ? (uint32_t)column : t->alias[column];
}

/* ---- the light set --------------------------------------------------------------- */

static int is_emissive(rgb ke) { return ke.r > 0 || ke.g > 0 || ke.b > 0; }

static void light_from_triangle(light *l, const scene *s, uint32_t tri)
{
    const triangle *t = &s->triangles[tri];
    vec3 e1, e2, c;
    real twice_area;
    l->triangle = tri;
    l->v0 = s->positions[t->v[0]];
    l->v1 = s->positions[t->v[1]];
    l->v2 = s->positions[t->v[2]];
    /* Area and normal in real precision from the float vertices. */
    e1 = v3_sub(v3_from_f(l->v1), v3_from_f(l->v0));
    e2 = v3_sub(v3_from_f(l->v2), v3_from_f(l->v0));
    c = v3_cross(e1, e2);
    twice_area = v3_length(c);
    l->area = twice_area / 2;
    l->normal = twice_area > 0 ? v3f_from(v3_scale(c, 1 / twice_area)) : v3f(0, 0, 0);
    l->emission = s->materials[t->material].emission;
}

void lights_free(light_set *ls)
{
    free(ls->lights);
    free(ls->light_of_triangle);
    alias_table_free(&ls->select);
    memset(ls, 0, sizeof *ls);
}

/* R^2: the squared radius of the scene's bounding sphere (1 if the bounds are unknown). */
static real scene_radius2(const scene *s)
{
    vec3 d = v3_sub(v3_from_f(s->bounds_max), v3_from_f(s->bounds_min));
    real r2 = v3_dot(d, d) / 4;
    return isfinite(r2) && r2 > 0 ? r2 : 1;
}

static int lights_fill_table(light_set *ls, const scene *s, rerror *e)
{
    real *power;
    size_t i, n = ls->count;
    int status;
    const scene_sky *k = ls->sky;
    real env = k ? k->env_power * scene_radius2(s) : 0, sun = k ? k->sun_power * scene_radius2(s) : 0;
    ls->env_entry = ls->sun_entry = LIGHT_NONE;
    if (env > 0) ls->env_entry = (uint32_t)n++;
    if (sun > 0) ls->sun_entry = (uint32_t)n++;
    if (n == 0) return 0;
    power = rmalloc(n, sizeof *power, e);
    if (!power) return -1;
    ls->total_power = 0;
    for (i = 0; i < ls->count; ++i) {
        power[i] = luminance(ls->lights[i].emission) * ls->lights[i].area;
        ls->total_power += power[i];
    }
    if (ls->env_entry != LIGHT_NONE) ls->total_power += power[ls->env_entry] = env;
    if (ls->sun_entry != LIGHT_NONE) ls->total_power += power[ls->sun_entry] = sun;
    status = alias_table_build(&ls->select, power, n, e);
    free(power);
    return status;
}

int lights_build(light_set *ls, const scene *s, rerror *e)
{
    size_t i;
    memset(ls, 0, sizeof *ls);
    ls->sky = s->sky;
    ls->maps = scene_has_emission_maps(s) ? s : NULL;
    ls->triangle_count = s->triangle_count;
    ls->light_of_triangle = rmalloc(s->triangle_count ? s->triangle_count : 1, sizeof *ls->light_of_triangle, e);
    ls->lights = rmalloc(s->triangle_count ? s->triangle_count : 1, sizeof *ls->lights, e);
    if (!ls->light_of_triangle || !ls->lights) {
        lights_free(ls);
        return -1;
    }
    for (i = 0; i < s->triangle_count; ++i) {
        light l;
        ls->light_of_triangle[i] = LIGHT_NONE;
        if (s->triangles[i].material >= s->material_count) {
            lights_free(ls);
            return rerror_set(e, "%s: triangle %lu has material %u of %lu", s->path, (unsigned long)i,
                              s->triangles[i].material, (unsigned long)s->material_count);
        }
        if (!is_emissive(s->materials[s->triangles[i].material].emission)) continue;
        light_from_triangle(&l, s, (uint32_t)i);
        /* A light with no power is never chosen by NEE; a BSDF hit on it must then carry
         * no emission either, or the two strategies would estimate different images.
         * Luminance is positive for any positive RGB, so only zero area qualifies. */
        if (!(l.area > 0) || !(luminance(l.emission) > 0)) continue;
        ls->light_of_triangle[i] = (uint32_t)ls->count;
        ls->lights[ls->count++] = l;
    }
    if (lights_fill_table(ls, s, e)) {
        lights_free(ls);
        return -1;
    }
    return 0;
}

/* Kept out of line: scenes without a sky must not pay for it in light_sample_point (gcc
 * inlined it and the path tracer's cornell A/B dropped to 0.96-0.98). */
#ifdef __GNUC__
#define SKY_COLD __attribute__((noinline, cold))
#else
#define SKY_COLD
#endif

/* The point at infinity of a distant light's two numbers (lights.h, light_sample). */
static SKY_COLD int distant_sample(const light_set *ls, const real u[4], light_sample *out)
{
    vec3 w = out->light == ls->env_entry ? sky_env_sample(ls->sky, v2(u[2], u[3])) : sky_sun_sample(ls->sky, v2(u[2], u[3]));
    /* The vertex is stored in float like every vertex; its pdf and radiance are those of
     * the stored direction, so that every later evaluation sees the same vertex. */
    out->position = v3f_from(w);
    w = v3_normalize(v3_from_f(out->position));
    out->triangle = LIGHT_TRIANGLE_DISTANT;
    out->normal = v3f_from(v3_neg(w));
    out->barycentric = v2(u[2], u[3]);
    out->emission = light_distant_radiance(ls, w);
    out->pdf_area = light_pdf_distant(ls, w);
    return out->pdf_area > 0;
}

real light_pdf_distant(const light_set *ls, vec3 w)
{
    real p = 0;
    if (!ls->sky) return 0;
    if (ls->env_entry != LIGHT_NONE) p += ls->select.pmf[ls->env_entry] * sky_env_pdf(ls->sky, w);
    if (ls->sun_entry != LIGHT_NONE) p += ls->select.pmf[ls->sun_entry] * sky_sun_pdf(ls->sky, w);
    return p;
}

rgb light_distant_radiance(const light_set *ls, vec3 w) { return ls->sky ? sky_radiance(ls->sky, w) : rgb_gray(0); }

rgb light_emission_at(const light_set *ls, uint32_t l, float b1, float b2)
{
    const light *x = &ls->lights[l];
    return ls->maps ? scene_emission_at(ls->maps, x->triangle, b1, b2, x->emission) : x->emission;
}

int light_sample_point(const light_set *ls, const real u[4], light_sample *out)
{
    const light *l;
    vec2 b;
    real b2;
    vec3 p;
    if (ls->select.count == 0) return 0;
    out->light = alias_table_sample(&ls->select, u[0], u[1]);
    if (out->light >= ls->count) return distant_sample(ls, u, out);
    l = &ls->lights[out->light];
    b = warp_uniform_triangle(v2(u[2], u[3]));
    b2 = 1 - b.x - b.y;
    /* p = b0 v0 + b1 v1 + b2 v2, evaluated in real and rounded once to float geometry. */
    p = v3_add(v3_add(v3_scale(v3_from_f(l->v0), b.x), v3_scale(v3_from_f(l->v1), b.y)),
               v3_scale(v3_from_f(l->v2), b2));
    out->triangle = l->triangle;
    out->position = v3f_from(p);
    out->normal = l->normal;
    out->barycentric = b;
    out->emission = ls->maps ? light_emission_at(ls, out->light, (float)b.y, (float)b2) : l->emission;
    out->pdf_area = ls->select.pmf[out->light] / l->area;
    return 1;
}

vec2 light_sample_point_inverse(vec2 barycentric) { return warp_uniform_triangle_inverse(barycentric); }

real light_select_pdf(const light_set *ls, uint32_t tri)
{
    uint32_t l;
    if (tri >= ls->triangle_count) return 0;
    l = ls->light_of_triangle[tri];
    return l == LIGHT_NONE ? 0 : ls->select.pmf[l];
}

real light_pdf_area(const light_set *ls, uint32_t tri)
{
    uint32_t l;
    if (tri >= ls->triangle_count) return 0;
    l = ls->light_of_triangle[tri];
    return l == LIGHT_NONE ? 0 : ls->select.pmf[l] / ls->lights[l].area;
}

/* dA -> dω: dω = |cos θ_y| dA / |x-y|^2 (e.g. Veach 1997 Eq. 8.10), so p_ω = p_A |x-y|^2 / |cos θ_y|. */
real pdf_area_to_solid_angle(real pdf_area, vec3 x, vec3 y, vec3 ny)
{
    vec3 d = v3_sub(x, y);
    return pdf_area_to_solid_angle_d(pdf_area, d, v3_dot(d, d), ny);
}

/* y - x = -(x - y) exactly, and so are the dot products: the sign of d cannot change a bit. */
real pdf_area_to_solid_angle_d(real pdf_area, vec3 d, real dist2, vec3 ny)
{
    real cos_y;
    if (!(dist2 > 0)) return 0;
    cos_y = fabs(v3_dot(ny, d)) / sqrt(dist2);
    if (!(cos_y > 0)) return 0;
    return pdf_area * dist2 / cos_y;
}

real light_pdf_solid_angle(const light_set *ls, uint32_t tri, vec3 x, vec3 y, vec3 ny)
{
    real pa = light_pdf_area(ls, tri);
    if (pa > 0) return pdf_area_to_solid_angle(pa, x, y, ny);
    /* a vertex at infinity: y is its direction; no conversion (docs/environment.md) */
    return tri == LIGHT_TRIANGLE_DISTANT ? light_pdf_distant(ls, v3_normalize(y)) : 0;
}
