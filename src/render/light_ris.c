/* Light RIS for NEE and light tiles (include/restir/render/light_ris.h; docs/enhanced.md §6). */
#include "restir/render/light_ris.h"
#include "restir/scene/scene_trace.h"
#include "restir/scene/sky.h"
#include "restir/scene/surface_maps.h"

int light_ris_count(const path_context *c, uint32_t vertex_index)
{
    int m;
    if (c->light_ris <= 0) return 0;
    if (vertex_index <= 1) return c->light_ris;
    if (vertex_index >= LIGHT_RIS_MAX) return 1; /* N / i^2 < 1 already; no overflow of i^2 */
    /* Enhanced §7: "max(1, 32/B^2)" candidates at bounce B (x_B). */
    m = c->light_ris / (int)(vertex_index * vertex_index);
    return m > 1 ? m : 1;
}

/* floor(u n), clamped (u = 1 - ulp rounds up in float builds). */
static uint32_t index_of(real u, uint32_t n)
{
    uint32_t k = (uint32_t)(u * (real)n);
    return k < n ? k : n - 1;
}

int light_tile_entry(const light_set *ls, uint32_t seed, uint32_t frame, uint32_t tile, uint32_t entry,
                     light_sample *out)
{
    real u[4];
    rng_u_slots(rng_key_make(seed, tile, frame), RNG_NEE, 0, 16u + 4u * entry, 4, u);
    return light_sample_point(ls, u, out);
}

uint32_t light_tile_of(const path_context *c, rng_key path)
{
    uint32_t w = c->image_width > 0 ? (uint32_t)c->image_width : 1u;
    uint32_t tiles_x = (w + LIGHT_TILE_SCREEN - 1) / LIGHT_TILE_SCREEN;
    uint32_t screen = (path.pixel / w / LIGHT_TILE_SCREEN) * tiles_x + (path.pixel % w) / LIGHT_TILE_SCREEN;
    return index_of(rng_u(rng_key_make(path.seed, screen, path.sample), RNG_NEE, 0, 0), LIGHT_TILE_COUNT);
}

/* What light RIS needs of one light point seen from x_i. */
typedef struct {
    vec3 wi;      /* unit x_i -> z */
    rgb f_cos;    /* all-lobe f|cos| at x_i towards z */
    rgb emitted;  /* Le(z -> x_i) */
    real phat;    /* p̂(z) = luminance(f|cos| Le), solid angle at x_i */
} light_eval;

/* p̂(z) / p_0(z), both in solid angle at x_i: the luminance of the unshadowed plain NEE
 * estimate f|cos| Le / p_0 (0 where either vanishes). */
static real target_ratio(const path_context *c, const path_vertex *v, uint32_t tri, vec3 z, vec3 nz, rgb ke,
                         light_eval *e)
{
    vec3 d = v3_sub(z, v->position);
    real dist = v3_length(d), p0;
    e->f_cos = e->emitted = rgb_gray(0);
    e->phat = 0;
    if (tri == LIGHT_TRIANGLE_DISTANT) { /* z is a direction (docs/environment.md) */
        e->wi = v3_normalize(z);
        e->emitted = ke;
    } else {
        if (!(dist > 0)) return 0;
        e->wi = v3_scale(d, 1 / dist);
        e->emitted = light_emitted(ke, nz, v3_neg(e->wi));
    }
    if (rgb_is_black(e->emitted)) return 0;
    e->f_cos = path_vertex_eval(v, e->wi);
    e->phat = luminance(rgb_mul(e->f_cos, e->emitted));
    p0 = path_light_pdf(c, tri, v->position, z, nz);
    return p0 > 0 && e->phat > 0 ? e->phat / p0 : 0;
}

static real sample_ratio(const path_context *c, const path_vertex *v, const light_sample *z, light_eval *e)
{
    return target_ratio(c, v, z->triangle, v3_from_f(z->position), v3_from_f(z->normal), z->emission, e);
}

/* The emission of the light point y on triangle tri (a light of the set), or of the
 * direction y at infinity (tri = LIGHT_TRIANGLE_DISTANT). 0 if it is no light. */
static int ris_emission(const path_context *c, uint32_t tri, vec3 y, rgb *ke)
{
    uint32_t l;
    if (tri == LIGHT_TRIANGLE_DISTANT) {
        *ke = light_distant_radiance(c->lights, v3_normalize(y));
        return light_set_has_sky(c->lights);
    }
    if (tri >= c->lights->triangle_count || (l = c->lights->light_of_triangle[tri]) == LIGHT_NONE) return 0;
    *ke = c->lights->lights[l].emission;
    if (c->lights->maps) { /* map_Ke: the emission at y's own barycentrics */
        float b1, b2;
        scene_barycentrics(c->scene, tri, y, &b1, &b2);
        *ke = light_emission_at(c->lights, l, b1, b2);
    }
    return 1;
}

/* Candidate j of the NEE side (numbers at first_slot = 4j): a sample of p_0, directly or
 * as a uniformly chosen entry of the path's light tile (whose entries are samples of p_0). */
static int nee_candidate(const path_context *c, rng_key path, uint32_t vertex, uint32_t first_slot, uint32_t tile,
                         light_sample *z)
{
    real u[4];
    if (c->light_tiles)
        return light_tile_entry(c->lights, path.seed, path.sample, tile,
                                index_of(rng_u(path, RNG_NEE, vertex, first_slot), LIGHT_TILE_SIZE), z);
    rng_u_slots(path, RNG_NEE, vertex, first_slot, 4, u);
    return light_sample_point(c->lights, u, z);
}

/* RIS (Talbot et al. 2005; Enhanced §6.1): M candidates of p_0, w_j = p̂(z_j)/(M p_0(z_j)),
 * z_s selected with probability w_s/Σw, W = Σw / p̂(z_s); the estimate is f(z_s) V Le W
 * (in the notation of the seeds: Mutations Eqs. 5-6, 8, with q = p_0). */
int light_ris_sample(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                     nee_sample *out)
{
    real r[LIGHT_RIS_MAX], sum = 0, u;
    int m = light_ris_count(c, vertex_index), j, s;
    uint32_t tile = c->light_tiles ? light_tile_of(c, path) : 0;
    light_eval e;
    out->contribution = rgb_gray(0);
    out->shadow_ray = 0;
    if (m > LIGHT_RIS_MAX) m = LIGHT_RIS_MAX;
    for (j = 0; j < m; ++j) {
        light_sample z;
        r[j] = nee_candidate(c, path, vertex_index, 4u * (uint32_t)j, tile, &z) ? sample_ratio(c, v, &z, &e) : 0;
        sum += r[j]; /* Σ_j p̂(z_j)/p_0(z_j) = M Σw */
    }
    if (!(sum > 0)) return 0;
    /* s = the first index whose running sum of r exceeds u Σr: P(s) = r_s / Σr = w_s / Σw. */
    u = rng_u(path, RNG_NEE, vertex_index, LIGHT_RIS_SLOT_SELECT) * sum;
    for (s = 0; s < m - 1 && !(u < r[s]); ++s) u -= r[s];
    while (s > 0 && !(r[s] > 0)) --s; /* rounding at the end of the running sum */
    /* The candidate is addressed: regenerate it instead of keeping M of them. */
    nee_candidate(c, path, vertex_index, 4u * (uint32_t)s, tile, &out->y);
    sample_ratio(c, v, &out->y, &e);
    out->wi = e.wi;
    out->emitted = e.emitted;
    out->f_cos = e.f_cos;
    out->pdf_bsdf = path_vertex_pdf(v, e.wi);
    /* 1/W = p̃(z_s; Z) = p̂(z_s) / ((1/M) Σ_j p̂(z_j)/p_0(z_j)): the NEE pdf of every MIS weight. */
    out->pdf_light = e.phat * (real)m / sum;
    if (!(out->pdf_light > 0)) return 0;
    out->shadow_ray = 1;
    if (out->y.triangle == LIGHT_TRIANGLE_DISTANT ? !sky_visible(c->scene, v->hit.position, v->hit.ng, e.wi)
                                                  : !scene_visible(c->scene, v->hit.position, v->hit.ng, out->y.position,
                                                                   &out->y.normal))
        return 0;
    out->contribution = rgb_scale(rgb_mul(out->f_cos, out->emitted), 1 / out->pdf_light);
    return 1;
}

/* The BSDF side's candidate set for a light point y it hit: y plus M-1 fresh samples of p_0,
 * distributed as the NEE side's set given that it selected y (docs/enhanced.md §6). With
 * tiles the NEE side's other candidates share y's tile, so the match is a virtual tile with
 * y in entry 0 and fresh p_0 samples in the other entries, candidates picking entries uniformly. */
real light_ris_pdf_hit(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                       uint32_t tri, vec3 y, vec3 ny)
{
    int m = light_ris_count(c, vertex_index), j;
    rgb ke;
    real r_y, sum, phat;
    light_eval e;
    if (!(ris_emission(c, tri, y, &ke))) return 0;
    if (m > LIGHT_RIS_MAX) m = LIGHT_RIS_MAX;
    r_y = target_ratio(c, v, tri, y, ny, ke, &e);
    phat = e.phat;
    if (!(r_y > 0)) return 0; /* NEE's RIS never selects a point of p̂ = 0 */
    sum = r_y;
    for (j = 0; j + 1 < m; ++j) {
        uint32_t slot = LIGHT_RIS_SLOT_FRESH + 4u * (uint32_t)j;
        light_sample z;
        real u[4];
        if (c->light_tiles) {
            uint32_t entry = index_of(rng_u(path, RNG_NEE, vertex_index, slot), LIGHT_TILE_SIZE);
            if (entry == 0) { /* the candidate picked y's own entry */
                sum += r_y;
                continue;
            }
            slot = LIGHT_RIS_SLOT_VIRTUAL + 4u * entry; /* the same entry gives the same sample */
        }
        rng_u_slots(path, RNG_NEE, vertex_index, slot, 4, u);
        if (light_sample_point(c->lights, u, &z)) sum += sample_ratio(c, v, &z, &e);
    }
    return phat * (real)m / sum; /* p̃(y; {y} ∪ Z') */
}

/* Σ_j p̂(z_j)/p_0(z_j) over the NEE candidates at x_i, in candidate order (the same sum as
 * light_ris_sample, so that a shift to the sample's own vertex reproduces 1/W exactly). */
static real nee_candidate_sum(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                              int m)
{
    uint32_t tile = c->light_tiles ? light_tile_of(c, path) : 0;
    real sum = 0;
    int j;
    for (j = 0; j < m; ++j) {
        light_sample z;
        light_eval e;
        sum += nee_candidate(c, path, vertex_index, 4u * (uint32_t)j, tile, &z) ? sample_ratio(c, v, &z, &e) : 0;
    }
    return sum;
}

real light_ris_pdf_nee(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                       uint32_t tri, vec3 y, vec3 ny)
{
    int m = light_ris_count(c, vertex_index);
    rgb ke;
    real sum;
    light_eval e;
    if (!ris_emission(c, tri, y, &ke)) return 0;
    if (m > LIGHT_RIS_MAX) m = LIGHT_RIS_MAX;
    if (!(target_ratio(c, v, tri, y, ny, ke, &e) > 0)) return 0;
    sum = nee_candidate_sum(c, v, path, vertex_index, m);
    return sum > 0 ? e.phat * (real)m / sum : 0;
}

int light_ris_candidate_towards(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                                vec3 wi, light_sample *out)
{
    int m = light_ris_count(c, vertex_index), j;
    uint32_t tile = c->light_tiles ? light_tile_of(c, path) : 0;
    if (m > LIGHT_RIS_MAX) m = LIGHT_RIS_MAX;
    for (j = 0; j < m; ++j) {
        light_eval e;
        if (!nee_candidate(c, path, vertex_index, 4u * (uint32_t)j, tile, out)) continue;
        if (!(sample_ratio(c, v, out, &e) > 0)) continue; /* never selected */
        if (e.wi.x == wi.x && e.wi.y == wi.y && e.wi.z == wi.z) return 1;
    }
    return 0;
}

void light_ris_options_default(light_ris_options *o)
{
    o->candidates = 0;
    o->tiles = 0;
}

int light_ris_options_validate(const light_ris_options *o, rerror *e)
{
    if (o->candidates < 0 || o->candidates > LIGHT_RIS_MAX)
        return rerror_set(e, "light RIS: %d candidates (must be 0..%d)", o->candidates, LIGHT_RIS_MAX);
    if (o->tiles && o->candidates == 0) return rerror_set(e, "light RIS: tiles need candidates (N >= 1)");
    return 0;
}
