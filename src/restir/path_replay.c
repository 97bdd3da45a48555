/* Paths from their random numbers, vertex by vertex (include/restir/restir/path_replay.h). */
#include "restir/restir/path_replay.h"

#include "restir/render/light_ris.h"
#include "restir/scene/scene_trace.h"

void trunk_begin(path_trunk *t, const path_vertex *x1)
{
    t->n = 1;
    t->v[1] = *x1;
    t->beta[1] = rgb_gray(1);
}

void path_bsdf_numbers(const path_sample *s, int vertex, real u[3])
{
    rng_key key = path_sample_key(s);
    int slot;
    /* Without explicit numbers at this vertex (the usual case): the three hashed side by side. */
    if ((vertex - 1) * PATH_PSS_PER_VERTEX >= s->n_pss) {
        rng_u_slots(key, RNG_BSDF, (uint32_t)vertex, 0, PATH_PSS_PER_VERTEX, u);
        return;
    }
    for (slot = 0; slot < PATH_PSS_PER_VERTEX; ++slot) {
        int i = (vertex - 1) * PATH_PSS_PER_VERTEX + slot; /* path_sample.h: pss[i] layout */
        u[slot] = i >= 0 && i < s->n_pss ? s->pss[i] : rng_u(key, RNG_BSDF, (uint32_t)vertex, (uint32_t)slot);
    }
}

void path_nee_numbers(const path_sample *s, real u[4])
{
    rng_key key = path_sample_key(s);
    int slot, base = (s->length - 2) * PATH_PSS_PER_VERTEX; /* vertex d-1 (path_sample.h) */
    for (slot = 0; slot < 4; ++slot) u[slot] = rng_u(key, RNG_NEE, (uint32_t)(s->length - 1), (uint32_t)slot);
    if (s->technique == PATH_TECH_NEE && base + PATH_PSS_PER_VERTEX <= s->n_pss) {
        u[2] = s->pss[base + 1];
        u[3] = s->pss[base + 2];
    }
}

enum shift_failure trunk_sample(path_trunk *t, const real u[3])
{
    int n = t->n;
    if (!vertex_sample_bsdf_numbers(&t->v[n], u[0], v2(u[1], u[2]), &t->b[n])) return SHIFT_FAIL_REPLAY_SAMPLE;
    /* The same product, in the same order, as the reference path tracer's throughput. */
    t->beta[n + 1] = rgb_mul(t->beta[n], t->b[n].weight);
    return rgb_is_black(t->beta[n + 1]) ? SHIFT_FAIL_REPLAY_ZERO : SHIFT_OK;
}

enum shift_failure path_trace_bounce(const scene *s, const light_set *sky, const path_vertex *v, const bsdf_bounce *b,
                                     path_vertex *next)
{
    ray r = scene_spawn_ray(v->hit.position, v->hit.ng, v3f_from(b->wi), v3f_from(v->wo));
    surface_hit h;
    if (scene_intersect(s, &r, &h)) path_vertex_make(next, s, &h, v3_from_f(r.dir));
    else if (sky && light_set_has_sky(sky)) path_vertex_make_distant(next, b->wi);
    else return SHIFT_FAIL_REPLAY_MISS;
    return SHIFT_OK;
}

enum shift_failure trunk_trace(path_trunk *t, const scene *s)
{
    enum shift_failure why = path_trace_bounce(s, NULL, &t->v[t->n], &t->b[t->n], &t->v[t->n + 1]);
    if (why == SHIFT_OK) t->n++;
    return why;
}

enum shift_failure trunk_trace_escape(path_trunk *t, const restir_context *c)
{
    enum shift_failure why = path_trace_bounce(c->path.scene, c->path.lights, &t->v[t->n], &t->b[t->n], &t->v[t->n + 1]);
    if (why == SHIFT_OK) t->n++;
    return why;
}

enum shift_failure trunk_replay(path_trunk *t, const restir_context *c, const path_vertex *x1, const path_sample *s,
                                int n)
{
    enum shift_failure why;
    trunk_begin(t, x1);
    while (t->n < n) {
        real u[3];
        path_bsdf_numbers(s, t->n, u);
        if ((why = trunk_sample(t, u)) != SHIFT_OK) return why;
        if ((why = trunk_trace(t, c->path.scene)) != SHIFT_OK) return why;
    }
    return SHIFT_OK;
}

/* GRIS Eq. 49 for an NEE path: w_nee = p_light / (p_light + p_bsdf). */
rgb nee_path_contribution(const path_context *c, rgb beta, const nee_sample *n)
{
    return rgb_mul(beta, rgb_scale(n->contribution, path_mis_weight_nee(c, n->pdf_light, n->pdf_bsdf)));
}

/* GRIS Eq. 49 for a BSDF path: w_bsdf = p_bsdf / (p_bsdf + p_light), with the all-lobe
 * BSDF pdf and the NEE pdf of the hit point seen from `from`. */
rgb emitter_path_contribution(const path_context *c, rgb beta_hit, const path_vertex *from, const path_vertex *hit,
                              const bsdf_bounce *b, rng_key path, int from_index, real *light_pdf)
{
    rgb le = path_vertex_emitted(c, hit);
    *light_pdf = 0;
    if (rgb_is_black(le)) return le;
    return emitted_path_contribution(c, le, beta_hit, from, hit, b, path, from_index, light_pdf);
}

rgb emitted_path_contribution(const path_context *c, rgb le, rgb beta_hit, const path_vertex *from,
                              const path_vertex *hit, const bsdf_bounce *b, rng_key path, int from_index,
                              real *light_pdf)
{
    *light_pdf = 0;
    if (!b->is_delta && c->strategy == PT_STRATEGY_MIS)
        *light_pdf = path_light_pdf_hit(c, from, hit, path, (uint32_t)from_index);
    return rgb_mul(beta_hit, rgb_scale(le, path_mis_weight_bsdf_hit(c, b, *light_pdf)));
}

enum shift_failure trunk_finish(path_trunk *t, const restir_context *c, const path_sample *s, path_end *end)
{
    int d = s->length;
    enum shift_failure why;
    if (s->technique == PATH_TECH_NEE) {
        const path_vertex *v = &t->v[d - 1];
        /* The path tracer draws NEE only where a non-Dirac lobe can receive it. */
        real u[4];
        int lit;
        path_nee_numbers(s, u);
        /* Light RIS: the candidates and the selection number are the path's own (its replay
         * identity); the selected index may differ at another x_{d-1}: that is the PSS map
         * (docs/enhanced.md §6, "Shifts"). */
        lit = v->can_nee && (c->path.light_ris > 0
                                 ? light_ris_sample(&c->path, v, path_sample_key(s), (uint32_t)(d - 1), &end->nee)
                                 : vertex_sample_light_numbers(&c->path, v, u, &end->nee));
        if (!lit) return SHIFT_FAIL_NEE;
        end->F = nee_path_contribution(&c->path, t->beta[d - 1], &end->nee);
        end->light_pdf = end->nee.pdf_light;
        return rgb_is_black(end->F) ? SHIFT_FAIL_NEE : SHIFT_OK;
    } else {
        real u[3];
        path_bsdf_numbers(s, d - 1, u);
        if ((why = trunk_sample(t, u)) != SHIFT_OK) return why;
        if ((why = trunk_trace_escape(t, c)) != SHIFT_OK) return why;
        end->F = emitter_path_contribution(&c->path, t->beta[d], &t->v[d - 1], &t->v[d], &t->b[d - 1],
                                           path_sample_key(s), d - 1, &end->light_pdf);
        return rgb_is_black(end->F) ? SHIFT_FAIL_REPLAY_NO_LIGHT : SHIFT_OK;
    }
}

enum shift_failure path_replay(path_trunk *t, const restir_context *c, const path_vertex *x1, const path_sample *s,
                               path_end *end)
{
    enum shift_failure why;
    if (s->length < 2 || s->length > PATH_MAX_LENGTH) return SHIFT_FAIL_EMPTY;
    if ((why = trunk_replay(t, c, x1, s, s->length - 1)) != SHIFT_OK) return why;
    return trunk_finish(t, c, s, end);
}

void trunk_lobes(const path_trunk *t, int d, int technique, uint8_t lobe[PATH_MAX_LENGTH])
{
    int j;
    for (j = 0; j < PATH_MAX_LENGTH; ++j) lobe[j] = PATH_LOBE_NONE;
    for (j = 1; j < d; ++j) lobe[j] = (uint8_t)t->b[j].lobe;
    if (technique == PATH_TECH_NEE) lobe[d - 1] = PATH_LOBE_NEE;
}

void trunk_rc_vertices(const path_trunk *t, const restir_context *c, const uint8_t lobe[PATH_MAX_LENGTH], int d,
                       const path_end *end, int technique, rc_vertex v[PATH_MAX_LENGTH + 1])
{
    int j;
    for (j = 1; j < d; ++j) {
        v[j].position = t->v[j].position;
        v[j].at_infinity = 0;
        v[j].rough = rc_vertex_is_rough(&t->v[j].b, lobe[j], c->rc.roughness_threshold);
        v[j].ng = t->v[j].ng;
        v[j].surface = &t->v[j];
        v[j].lobe = lobe[j];
        v[j].wi = lobe[j] == PATH_LOBE_NEE ? end->nee.wi : t->b[j].wi;
    }
    v[d].position = technique == PATH_TECH_NEE ? v3_from_f(end->nee.y.position) : t->v[d].position;
    v[d].at_infinity = technique == PATH_TECH_NEE ? end->nee.y.triangle == LIGHT_TRIANGLE_DISTANT
                                                  : path_vertex_is_distant(&t->v[d]);
    if (v[d].at_infinity) v[d].position = light_distant_direction(v3f_from(v[d].position));
    v[d].rough = rc_vertex_is_rough(NULL, PATH_LOBE_NONE, c->rc.roughness_threshold);
    v[d].ng = technique == PATH_TECH_NEE ? v3_from_f(end->nee.y.normal) : t->v[d].ng;
    v[d].surface = NULL; /* emissive: Enhanced footnote 6 */
    v[d].lobe = PATH_LOBE_NONE;
    v[d].wi = v3(0, 0, 0);
}
