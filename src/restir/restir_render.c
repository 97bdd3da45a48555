/* The offline ReSTIR PT renderer (GRIS §6.5): initial resampling, K spatial passes
 * (GRIS §6.3 step 3), shading, frames averaged with GRIS Eq. 47 (include/restir/restir.h). */
#include "restir/restir.h"

#include "restir/light_ris.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/camera.h"
#include "restir/connectability.h"
#include "restir/gbuffer.h"
#include "restir/progress.h"
#include "restir/threads.h"
#include "frame_job.h"

const char *const restir_paths_names[] = {"all", "indirect", NULL};
const char *const restir_pairing_names[] = {"disk", "paired", NULL};
const char *const restir_motion_vector_names[] = {"single", "dual", NULL};
const char *const restir_shading_names[] = {"scalar", "vector", NULL};

void restir_options_default(restir_options *o)
{
    memset(o, 0, sizeof *o);
    o->shift = RESTIR_SHIFT_HYBRID;
    o->spatial_passes = 0;
    o->neighbors = 6;
    o->radius = 10;
    o->pattern = NEIGHBOR_R2;
    o->normal_cos = NEIGHBOR_DEFAULT_MIN_NORMAL_COS;
    o->depth_ratio = NEIGHBOR_DEFAULT_MAX_RELATIVE_DEPTH;
    o->mis = MIS_TALBOT;
    o->frames = 1;
    o->candidates = 1;
    o->max_depth = 10;
    o->roughness_threshold = 0.2;
    o->distance_threshold = 0.02;
    o->rc_criterion = RC_MODE_GRIS;
    o->footprint_c = 0.02;
    o->paths = RESTIR_PATHS_ALL;
    o->rr_min_depth = 3;
    o->seed = 1;
    o->threads = 1;
    o->quiet = 1;
    o->temporal = 1;
    o->temporal_mis = MIS_TALBOT;
    o->mcap = 20;
    o->stochastic_n = 1;
    o->stochastic_nc = 1;
    o->dedup_min = 1;    /* Enhanced §5: c_cap_min = 1, alpha = 0.1 */
    o->dedup_alpha = 0.1;
    o->mutate_after = MUTATE_AFTER_TEMPORAL;
}

void restir_neighbor_options_for(neighbor_options *no, const restir_options *o)
{
    neighbor_options_default(no);
    no->pattern = (enum neighbor_pattern)o->pattern;
    no->count = o->neighbors;
    no->radius = o->radius;
    no->reject_geometry = !o->no_reject;
    no->min_normal_cos = (float)o->normal_cos;
    no->max_relative_depth = (float)o->depth_ratio;
    if (o->pairing == RESTIR_PAIRING_PAIRED) no->pattern = NEIGHBOR_PAIRED;
}

int restir_pairing_build(neighbor_options *no, const restir_options *o, reuse_texture *textures, rerror *e)
{
    no->textures = NULL;
    if (no->pattern != NEIGHBOR_PAIRED) return 0;
    if (reuse_textures_build(textures, no->count, pairing_sigma_for_radius(o->radius), o->seed, e)) return -1;
    no->textures = textures;
    return 0;
}

int restir_pair_step_active(const restir_options *o)
{
    return o->pairing == RESTIR_PAIRING_PAIRED && !o->no_pair_step && o->mis != RESTIR_MIS_STOCHASTIC_PAIRWISE &&
           !o->cells && o->spatial_passes > 0;
}

void restir_pairing_free(neighbor_options *no)
{
    if (no->textures) reuse_textures_free((reuse_texture *)no->textures, no->count);
    no->textures = NULL;
}

/* GRIS §8.3: "we use defensive pairwise MIS for spatial reuse" (issue 9: the preset kept
 * Talbot before). */
void restir_options_preset_gris_offline(restir_options *o)
{
    o->candidates = 32;
    o->mis = MIS_PAIRWISE_DEFENSIVE;
    o->spatial_passes = 3;
    o->neighbors = 6;
    o->radius = 10;
    o->mis = MIS_PAIRWISE_DEFENSIVE;
}

void restir_options_preset_gris_realtime(restir_options *o)
{
    o->candidates = 1;
    o->temporal = 1;
    o->temporal_mis = MIS_TALBOT;
    o->mcap = 20;
    o->spatial_passes = 1;
    o->neighbors = 3;
    o->radius = 20;
    o->mis = MIS_PAIRWISE_DEFENSIVE;
}

int restir_options_biased(const restir_options *o) { return o->dedup || o->boiling_filter > 0; }

/* Issue 12 (docs/correlation.md): --dedup, --motion-vectors, --boiling-filter. */
static int correlation_options_validate(const restir_options *o, rerror *e)
{
    if (o->dedup && (isinf(o->mcap) || !(o->dedup_min > 0) || isinf(o->dedup_min)))
        return rerror_set(e, "restir: --dedup needs a finite --mcap and c_cap_min > 0 (got mcap %g, min %g)", o->mcap,
                          o->dedup_min);
    if (o->dedup && (!(o->dedup_alpha > 0) || isinf(o->dedup_alpha)))
        return rerror_set(e, "restir: --dedup-alpha %g (must be finite and > 0)", o->dedup_alpha);
    if (o->motion_vectors != RESTIR_MV_SINGLE && o->motion_vectors != RESTIR_MV_DUAL)
        return rerror_set(e, "restir: unknown motion vectors %d", o->motion_vectors);
    if (!(o->boiling_filter >= 0 && o->boiling_filter <= 1))
        return rerror_set(e, "restir: --boiling-filter %g (strength in (0, 1], 0 = off)", o->boiling_filter);
    return 0;
}

int restir_options_validate(const restir_options *o, rerror *e)
{
    int min_depth = o->paths == RESTIR_PATHS_INDIRECT ? 3 : 2;
    if (o->shift < 0 || o->shift >= RESTIR_SHIFT_COUNT) return rerror_set(e, "restir: unknown shift %d", o->shift);
    neighbor_options no;
    if (o->spatial_passes < 0 || o->spatial_passes > RESTIR_MAX_SPATIAL_PASSES)
        return rerror_set(e, "restir: %d spatial passes (0..%d)", o->spatial_passes, RESTIR_MAX_SPATIAL_PASSES);
    if (o->mis < 0 || o->mis > RESTIR_MIS_STOCHASTIC_PAIRWISE) return rerror_set(e, "restir: unknown MIS family %d", o->mis);
    if (o->stochastic_n < 1 || o->stochastic_n > STOCHASTIC_MAX_PICKS || o->stochastic_nc < 1 ||
        o->stochastic_nc > STOCHASTIC_MAX_PICKS)
        return rerror_set(e, "restir: --stochastic-n %d / --stochastic-nc %d outside 1..%d", o->stochastic_n,
                          o->stochastic_nc, STOCHASTIC_MAX_PICKS);
    if (!(o->radius >= 1) || !(o->radius <= 4096)) return rerror_set(e, "restir: radius %g outside [1, 4096]", o->radius);
    restir_neighbor_options_for(&no, o);
    if (neighbor_options_validate(&no, e)) return -1;
    if (neighbor_candidate_count(&no) + 1 > RESTIR_MAX_DOMAINS)
        return rerror_set(e, "restir: %d neighbour candidates per pixel (at most %d)", neighbor_candidate_count(&no),
                          RESTIR_MAX_DOMAINS - 1);
    if (!(o->time_limit >= 0) || !(o->time_limit < 1e9)) return rerror_set(e, "restir: time limit %g", o->time_limit);
    if (o->frames < 1) return rerror_set(e, "restir: %d frames", o->frames);
    if (o->first_frame < 0) return rerror_set(e, "restir: first frame %d < 0", o->first_frame);
    if (o->candidates < 1 || o->candidates > 1 << 16)
        return rerror_set(e, "restir: %d path trees (1..65536)", o->candidates);
    if ((uint64_t)(o->first_frame + (uint64_t)o->frames) * (uint64_t)o->candidates > UINT32_MAX)
        return rerror_set(e, "restir: frame range x path trees exceeds 2^32 sample indices");
    if (o->max_depth < min_depth || o->max_depth > PATH_MAX_LENGTH)
        return rerror_set(e, "restir: max depth %d outside %d..%d", o->max_depth, min_depth, PATH_MAX_LENGTH);
    if (!(o->roughness_threshold >= 0) || !(o->distance_threshold >= 0))
        return rerror_set(e, "restir: negative (or NaN) roughness or distance threshold");
    if (o->shading != RESTIR_SHADING_SCALAR && o->shading != RESTIR_SHADING_VECTOR)
        return rerror_set(e, "restir: unknown shading %d", o->shading);
    if (o->shading == RESTIR_SHADING_VECTOR && o->mis == RESTIR_MIS_STOCHASTIC_PAIRWISE)
        return rerror_set(e, "restir: --shading vector needs a deterministic spatial MIS family (the stochastic "
                             "pairwise step keeps no per-input weights to sum)");
    if (o->pairing != RESTIR_PAIRING_DISK && o->pairing != RESTIR_PAIRING_PAIRED)
        return rerror_set(e, "restir: unknown pairing %d", o->pairing);
    if (o->rc_criterion != RC_MODE_GRIS && o->rc_criterion != RC_MODE_FOOTPRINT)
        return rerror_set(e, "restir: unknown reconnection criterion %d", o->rc_criterion);
    if (!(o->footprint_c >= 0) || isinf(o->footprint_c))
        return rerror_set(e, "restir: footprint constant c %g (must be finite and >= 0)", o->footprint_c);
    if (o->paths != RESTIR_PATHS_ALL && o->paths != RESTIR_PATHS_INDIRECT)
        return rerror_set(e, "restir: unknown --paths %d", o->paths);
    if (o->ablation < 0 || o->ablation >= RESTIR_ABLATION_COUNT)
        return rerror_set(e, "restir: unknown ablation %d", o->ablation);
    if (o->ablation == RESTIR_ABLATE_PAIR_MIS && !restir_pair_step_active(o))
        return rerror_set(e, "restir: --ablate pair-mis needs the pair step (--pairing paired, a deterministic --mis, "
                             "no --reuse-cells, no --no-pair-step)");
    if (o->threads < 1) return rerror_set(e, "restir: %d threads", o->threads);
    if (o->temporal_mis < 0 || o->temporal_mis >= MIS_FAMILY_COUNT)
        return rerror_set(e, "restir: unknown temporal MIS family %d", o->temporal_mis);
    if (o->mutations < 0 || o->mutations > MUTATE_MAX_ITERATIONS)
        return rerror_set(e, "restir: --mutations %d (must be 0..%d)", o->mutations, MUTATE_MAX_ITERATIONS);
    if (o->mutation < 0 || o->mutation >= MUTATE_STRATEGY_COUNT)
        return rerror_set(e, "restir: unknown mutation strategy %d", o->mutation);
    if (o->mutate_after & ~(MUTATE_AFTER_INITIAL | MUTATE_AFTER_TEMPORAL | MUTATE_AFTER_SPATIAL))
        return rerror_set(e, "restir: unknown mutation stage bits %#x", (unsigned)o->mutate_after);
    if (!(o->mcap > 0)) return rerror_set(e, "restir: M-cap %g (must be > 0, or inf)", o->mcap);
    if (o->light_ris < 0 || o->light_ris > LIGHT_RIS_MAX)
        return rerror_set(e, "restir: --light-ris %d is outside 0..%d candidates", o->light_ris, LIGHT_RIS_MAX);
    if (o->light_tiles && o->light_ris == 0) return rerror_set(e, "restir: --light-tiles needs --light-ris N");
    /* The MCMC mutations perturb the light point's two numbers (path_nee_numbers); under
     * light RIS the NEE vertex is a discrete choice among candidates, which they do not
     * define a mutation of (docs/enhanced.md §6). */
    if (o->light_ris > 0 && o->mutations > 0)
        return rerror_set(e, "restir: --mutations cannot be combined with --light-ris (no mutation of a light-RIS "
                             "NEE vertex is defined; docs/enhanced.md section 6)");
    return correlation_options_validate(o, e);
}

void restir_context_for(restir_context *c, const scene *s, const light_set *lights, const restir_options *o)
{
    memset(c, 0, sizeof *c);
    c->path.scene = s;
    c->path.lights = lights;
    c->path.strategy = PT_STRATEGY_MIS;
    c->path.ablations = o->ablation == RESTIR_ABLATE_LIGHT_RIS_PDF ? PT_ABLATE_LIGHT_RIS_PDF : 0;
    c->path.light_ris = o->light_ris;
    c->path.light_tiles = o->light_tiles;
    c->path.image_width = s->width;
    c->shift = o->shift;
    c->rc.roughness_threshold = (real)o->roughness_threshold;
    c->rc.min_distance = rc_min_distance_for_scene(s, (real)o->distance_threshold);
    c->rc.mode = o->rc_criterion;
    c->rc.footprint_c = (real)o->footprint_c;
    c->rc.force_nee = o->force_nee_reconnection != 0;
    c->ablation = o->ablation;
}

void restir_initial_options_for(initial_options *io, const restir_options *o)
{
    io->trees = o->candidates;
    io->max_depth = o->max_depth;
    io->indirect_only = o->paths == RESTIR_PATHS_INDIRECT;
    io->russian_roulette = o->russian_roulette;
    io->rr_min_depth = o->rr_min_depth;
}

/* ---- passes (the stages: frame_job.h) ------------------------------------------------ */

int frame_primary_vertex(const scene *s, const gbuffer *g, long p, path_vertex *v)
{
    const gbuffer_texel *t = &g->texels[p];
    if (!t->valid) return 0;
    path_vertex_make(v, s, &t->hit, v3_from_f(t->view_dir));
    return 1;
}

/* x1 of pixel p as the path sampler builds it from the frame's primary ray. */
static int primary_vertex(const frame_job *j, long p, path_vertex *v) { return frame_primary_vertex(j->s, &j->g, p, v); }

static void initial_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            long p = (long)y * j->s->width + x;
            path_vertex v;
            if (!primary_vertex(j, p, &v)) {
                reservoir_init(&j->initial[p]);
                continue;
            }
            initial_sample_pixel(&j->ctx, &j->io, &v, j->o->seed, (uint32_t)p, j->frame, &j->initial[p],
                                 &j->workers[worker].st.initial);
        }
}

/* stochastic_workspace.vertex: domain i's primary vertex, built on first use. */
static const path_vertex *lazy_vertex(void *user, int i)
{
    worker_state *w = user;
    if (!w->x1[i]) {
        primary_vertex(w->lazy_job, (long)w->nbr[i - 1], &w->verts[i]);
        w->x1[i] = &w->verts[i];
    }
    return w->x1[i];
}

/* The stochastic pairwise step (stochastic_spatial.h) over the domains spatial_pixel set
 * up. Pick k of pass p draws RNG_RIS vertex 64 + p, slot k; canonical pick k vertex
 * 80 + p, slot k (passes < 16, so no clash with 32 + p or the temporal vertex 48). */
static void stochastic_spatial_pixel(frame_job *j, worker_state *w, rng_key key, int m, reservoir *out)
{
    stochastic_options so;
    int k;
    so.n_picks = j->o->stochastic_n;
    so.n_canonical_picks = j->o->stochastic_nc;
    so.confidence_scaling = !j->o->no_confidence_scaling;
    so.naive_p = j->ctx.ablation == RESTIR_ABLATE_STOCHASTIC_P;
    for (k = 0; k < so.n_picks; ++k) w->up[k] = rng_u(key, RNG_RIS, 64u + (uint32_t)j->pass, (uint32_t)k);
    for (k = 0; k < so.n_canonical_picks; ++k) w->uc[k] = rng_u(key, RNG_RIS, 80u + (uint32_t)j->pass, (uint32_t)k);
    w->sw.vertex = lazy_vertex;
    w->sw.vertex_user = w;
    stochastic_pairwise_resample(&j->ctx, &so, m, w->x1, w->in, w->u, w->up, w->uc, out, &w->sw, &w->st.spatial);
}

/* Enhanced §6.3: sum_i m_i(Y_i) F(Y_i) W_{X_i} |dT_i/dX_i| over the inputs of the GRIS step
 * just run (their shifts, MIS weights and Jacobians are in the workspace). It is the
 * expectation of the scalar estimate F(Y) W_Y over the selection among the same inputs
 * (w_i = m_i p̂(Y_i) W_i J_i selects Y_i with probability w_i / sum w, and W_Y =
 * sum w / p̂(Y)), so it is unbiased wherever the scalar estimate is. */
static rgb vector_estimate(const spatial_workspace *ws, const reservoir *const *in, int m, spatial_stats *st)
{
    rgb L = rgb_gray(0);
    int i;
    for (i = 0; i < m; ++i) {
        real weight;
        if (!ws->valid[i]) continue;
        weight = ws->mis[i] * in[i]->W * ws->jacobian[i];
        if (!isfinite(weight)) st->invalid_weights++; /* skipped, like wrs_update skips it */
        if (weight > 0 && isfinite(weight)) L = rgb_add(L, rgb_scale(ws->cand[i]->F, weight));
    }
    return L;
}

/* One pixel of spatial pass j->pass (GRIS §6.3 step 3): its own reservoir (canonical,
 * domain 0) and the accepted neighbours (domains 1..M-1) of the previous pass's output
 * resampled into dst[p] with the chosen MIS family (spatial.h). The neighbours depend only
 * on the G-buffer and RNG_NEIGHBOR, never on the reservoirs (neighbors.h). */
static void spatial_pixel(frame_job *j, worker_state *w, int x, int y)
{
    long p = (long)y * j->s->width + x;
    rng_key key = rng_key_make(j->o->seed, (uint32_t)p, initial_tree_sample(&j->io, j->frame, 0));
    uint32_t nsample = neighbor_sample_index(j->frame, (uint32_t)j->o->spatial_passes, (uint32_t)j->pass);
    int n, d;
    if (j->pair ? j->pair_n[p] < 0 : !primary_vertex(j, p, &w->verts[0])) {
        reservoir_init(&j->dst[p]);
        if (j->vector_shade) j->vector_shade[p] = rgb_gray(0);
        return;
    }
    /* capacity is checked by restir_options_validate, so this cannot fail */
    if (j->pair) {
        n = frame_pair_domains(j, w, p); /* the pre-pass's neighbours and cached vertices */
    } else if (j->o->cells) {
        /* Stochastic MIS §5.1: a reuse cell; its pixels except p are the domains */
        int c = reuse_cell_search(&j->cells, &j->g, (float)j->o->normal_cos, j->o->seed, nsample, x, y);
        n = c >= 0 ? reuse_cell_domains(&j->cells, c, (uint32_t)p, w->nbr) : 0;
    } else {
        n = neighbor_select_slots(&j->no, &j->g, j->o->seed, nsample, x, y, w->nbr, w->slot, j->max_domains - 1,
                                  &w->st.neighbors, NULL);
        if (n < 0) n = 0;
    }
    w->lazy_job = j;
    for (d = 0; d <= n; ++d) {
        long q = d == 0 ? p : (long)w->nbr[d - 1];
        /* accepted neighbours have a primary hit; the stochastic step builds them on demand */
        if (!j->pair) {
            if (d > 0 && j->o->mis != RESTIR_MIS_STOCHASTIC_PAIRWISE) primary_vertex(j, q, &w->verts[d]);
            w->x1[d] = d > 0 && j->o->mis == RESTIR_MIS_STOCHASTIC_PAIRWISE ? NULL : &w->verts[d];
        }
        w->in[d] = &j->src[q];
        /* vertex 32 + p: initial sampling uses vertices 2..16 of RNG_RIS (the key packs
         * vertex < 256 and slot < 65536, so the pass must not go into the slot) */
        w->u[d] = rng_u(key, RNG_RIS, 32u + (uint32_t)j->pass, (uint32_t)d);
    }
    if (j->o->mis == RESTIR_MIS_STOCHASTIC_PAIRWISE) {
        stochastic_spatial_pixel(j, w, key, n + 1, &j->dst[p]);
        return;
    }
    if (j->pair)
        frame_pair_resample(j, w, p, n, &j->dst[p]); /* Enhanced §3: the pair's shifts from the pre-pass */
    else
        spatial_resample(&j->ctx, (mis_family)j->o->mis, n + 1, w->x1, w->in, w->u, &j->dst[p], &w->ws,
                         &w->st.spatial);
    if (j->vector_shade && j->pass == j->o->spatial_passes - 1)
        j->vector_shade[p] = vector_estimate(&w->ws, w->in, n + 1, &w->st.spatial);
}

static void spatial_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) spatial_pixel(j, &j->workers[worker], x, y);
}

static void shade_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    int x, y;
    (void)worker;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            long p = (long)y * j->s->width + x;
            path_vertex v;
            rgb L;
            if (!primary_vertex(j, p, &v)) continue;
            /* Emission at x1 is added, never resampled (docs/design.md, Conventions); F(Y) W_Y is GRIS Eq. 3. */
            L = j->vector_shade && j->o->spatial_passes > 0 ? j->vector_shade[p] : reservoir_estimate(&j->final[p]);
            if (j->o->paths == RESTIR_PATHS_ALL) L = rgb_add(path_vertex_emitted(&j->ctx.path, &v), L);
            j->sum[3 * p + 0] += (double)L.r;
            j->sum[3 * p + 1] += (double)L.g;
            j->sum[3 * p + 2] += (double)L.b;
        }
}

double frame_lap_ms(double *t)
{
    double now = now_seconds(), ms = 1000 * (now - *t);
    *t = now;
    return ms;
}

int frame_stage_gbuffer(frame_job *j, const camera *cam, restir_stats *times, double *t, rerror *e)
{
    const restir_options *o = j->o;
    if (gbuffer_build(&j->g, j->s, cam, o->seed, initial_tree_sample(&j->io, j->frame, 0), o->jitter, o->threads, e))
        return -1;
    times->ms_gbuffer += frame_lap_ms(t);
    return 0;
}

void frame_stage_initial(frame_job *j, restir_stats *times, double *t)
{
    parallel_tiles(j->s->width, j->s->height, 16, j->o->threads, initial_tile, j, NULL, NULL);
    times->ms_initial += frame_lap_ms(t);
}

reservoir *frame_stage_spatial(frame_job *j, reservoir *a, reservoir *b, restir_stats *times, double *t)
{
    reservoir *final = a;
    for (j->pass = 0; j->pass < j->o->spatial_passes && !threads_cancelled(); ++j->pass) {
        char name[32];
        snprintf(name, sizeof name, "spatial%d", j->pass + 1);
        /* ping-pong: a -> b -> a -> ... */
        j->src = j->pass % 2 == 0 ? a : b;
        j->dst = j->pass % 2 == 0 ? b : a;
        if (!pipeline_stage_skipped(j, name)) {
            if (j->o->cells) reuse_cells_build(&j->cells, &j->g, j->src, NULL); /* allocated: cannot fail */
            if (j->no.textures) { /* paired: the pass's texture placements, drawn once */
                neighbor_place(&j->no, j->o->seed,
                               neighbor_sample_index(j->frame, (uint32_t)j->o->spatial_passes, (uint32_t)j->pass),
                               j->placed);
                j->no.placements = j->placed;
            }
            if (j->pair) frame_pair_prepass(j); /* Enhanced §3: each pair's two shifts, once */
            parallel_tiles(j->s->width, j->s->height, 16, j->o->threads, spatial_tile, j, NULL, NULL);
            j->no.placements = NULL;
        }
        if (threads_cancelled()) break; /* an incomplete pass is neither dumped nor used */
        final = j->dst;
        times->ms_spatial[j->pass] += frame_lap_ms(t);
        pipeline_stage_done(j, name, j->dst);
    }
    return final;
}

/* Shading adds the frame to the sum, so it is all or nothing: not started once the frame
 * was cancelled (j->shade_cancelled), and not cancellable itself (one estimate per pixel). */
void frame_stage_shade(frame_job *j, const reservoir *final, restir_stats *times, double *t)
{
    volatile sig_atomic_t *cancel;
    j->final = final;
    j->shade_cancelled = threads_cancelled();
    if (j->shade_cancelled) return;
    cancel = threads_set_cancel(NULL);
    parallel_tiles(j->s->width, j->s->height, 16, j->o->threads, shade_tile, j, NULL, NULL);
    threads_set_cancel(cancel);
    times->ms_shade += frame_lap_ms(t);
}

/* One independent offline frame: G-buffer, initial resampling, K spatial passes, shading
 * (GRIS §6.3 steps 1, 3, 4; no temporal reuse: GRIS §6.5). */
/* Returns 0, -1 on failure, or 1 if SIGINT/SIGTERM cancelled it at a tile boundary
 * (threads_set_cancel): then nothing of the frame reached the sum. */
static int render_frame(frame_job *j, const camera *cam, restir_stats *times, rerror *e)
{
    double t = now_seconds();
    reservoir *final;
    if (frame_stage_gbuffer(j, cam, times, &t, e)) return -1;
    if (!threads_cancelled()) frame_stage_initial(j, times, &t);
    final = threads_cancelled() ? NULL : frame_stage_spatial(j, j->initial, j->pong, times, &t);
    if (final) frame_stage_shade(j, final, times, &t); /* it checks the cancel flag itself */
    gbuffer_free(&j->g);
    return j->shade_cancelled || !final ? 1 : 0;
}

void restir_stats_add(restir_stats *st, const restir_stats *w)
{
    int i;
    initial_stats_add(&st->initial, &w->initial);
    spatial_stats_add(&st->spatial, &w->spatial);
    temporal_stats_add(&st->temporal, &w->temporal);
    mutate_stats_add(&st->mutate, &w->mutate);
    st->neighbors.candidates += w->neighbors.candidates;
    for (i = 0; i < NEIGHBOR_VERDICT_COUNT; ++i) st->neighbors.verdict[i] += w->neighbors.verdict[i];
    st->frames += w->frames;
    st->nonfinite_pixels += w->nonfinite_pixels;
    st->ms_gbuffer += w->ms_gbuffer;
    st->ms_initial += w->ms_initial;
    st->ms_temporal += w->ms_temporal;
    st->ms_pose += w->ms_pose;
    st->ms_motion += w->ms_motion;
    st->ms_mutate += w->ms_mutate;
    st->ms_shade += w->ms_shade;
    for (i = 0; i < RESTIR_MAX_SPATIAL_PASSES; ++i) st->ms_spatial[i] += w->ms_spatial[i];
    duplication_summary_add(&st->correlation, &w->correlation);
    st->boiling_cleared += w->boiling_cleared;
    st->ms_correlation += w->ms_correlation;
}

void frame_sum_stats(const frame_job *j, restir_stats *st)
{
    int t;
    for (t = 0; t < j->o->threads; ++t) restir_stats_add(st, &j->workers[t].st);
}

void restir_result_free(restir_result *r)
{
    image_free(&r->mean);
    free(r->reservoirs);
    memset(r, 0, sizeof *r);
}

/* Frames f = first_frame, first_frame + 1, ...: `frames` of them, or (time_limit > 0)
 * until the time is up; a set stop_flag cancels the frame in progress at a tile boundary
 * (threads_set_cancel) and ends the render with the frames complete so far (maybe none).
 * Returns the number rendered, -1 on failure. */
static long render_frames(frame_job *j, restir_stats *times, double t0, rerror *e)
{
    const restir_options *o = j->o;
    camera cam;
    progress bar;
    long f;
    uint64_t max_frames = (uint64_t)UINT32_MAX / (uint64_t)o->candidates - (uint64_t)o->first_frame;
    volatile sig_atomic_t *old_cancel;
    int status = 0;
    camera_init(&cam, scene_camera_at(j->s, 0), j->s->width, j->s->height);
    old_cancel = threads_set_cancel(o->stop_flag);
    progress_begin(&bar, "restir", o->quiet || o->time_limit > 0);
    progress_expect(&bar, o->frames);
    for (f = 0;; ++f) {
        if (o->time_limit > 0 ? (f > 0 && now_seconds() - t0 >= o->time_limit) : f >= o->frames) break;
        if ((uint64_t)f >= max_frames || (o->stop_flag && *o->stop_flag)) break;
        j->frame = (uint32_t)(o->first_frame + f);
        status = render_frame(j, &cam, times, e);
        if (status) break; /* -1: failed; 1: cancelled, the frame is not counted */
        if (o->time_limit <= 0) progress_update(&bar, (int)f + 1, o->frames);
    }
    progress_end(&bar);
    threads_set_cancel(old_cancel);
    return status < 0 ? -1 : f;
}

static int run_frames(frame_job *j, restir_result *out, double t0, rerror *e)
{
    const restir_options *o = j->o;
    size_t pixels = (size_t)j->s->width * (size_t)j->s->height, i;
    long frames = render_frames(j, &out->stats, t0, e);
    if (frames < 0) return -1;
    out->stats.frames = (uint64_t)frames;
    if (image_alloc(&out->mean, j->s->width, j->s->height, e)) return -1;
    /* GRIS Eq. 47; no frame (stopped during the first): a black image with frames = 0,
     * which the caller must not present as a result */
    for (i = 0; i < 3 * pixels; ++i) out->mean.px[i] = frames ? (float)(j->sum[i] / (double)frames) : 0.0f;
    out->stats.nonfinite_pixels = image_nonfinite_pixels(&out->mean); /* kept, counted (docs/precision.md) */
    if (o->keep_reservoirs) {
        out->reservoirs = rmalloc(pixels, sizeof *out->reservoirs, e);
        if (!out->reservoirs) return -1;
        memcpy(out->reservoirs, j->final, pixels * sizeof *out->reservoirs);
    }
    return 0;
}

int frame_workers_alloc(frame_job *j, rerror *e)
{
    int t;
    size_t m = (size_t)j->max_domains;
    if (j->o->cells) {
        if (j->max_domains < REUSE_CELL_MAX_PIXELS + 1) j->max_domains = REUSE_CELL_MAX_PIXELS + 1;
        m = (size_t)j->max_domains;
        if (reuse_cells_alloc(&j->cells, j->s->width, j->s->height, e)) return -1;
    }
    j->workers = rcalloc((size_t)j->o->threads, sizeof *j->workers, e);
    if (!j->workers) return -1;
    if (j->o->spatial_passes == 0 && !j->temporal) return 0;
    for (t = 0; t < j->o->threads; ++t) {
        worker_state *w = &j->workers[t];
        /* temporal reuse needs 2 domains */
        if (spatial_workspace_alloc(&w->ws, j->max_domains > 2 ? j->max_domains : 2, e)) return -1;
        if (j->o->mis == RESTIR_MIS_STOCHASTIC_PAIRWISE && stochastic_workspace_alloc(&w->sw, j->max_domains, e))
            return -1;
        w->nbr = rmalloc(m, sizeof *w->nbr, e);
        w->x1 = rmalloc(m, sizeof *w->x1, e);
        w->verts = rmalloc(m, sizeof *w->verts, e);
        w->in = rmalloc(m, sizeof *w->in, e);
        w->u = rmalloc(m, sizeof *w->u, e);
        w->slot = rmalloc(m, sizeof *w->slot, e);
        w->fwd = rmalloc(m, sizeof *w->fwd, e);
        w->rev = rmalloc(m, sizeof *w->rev, e);
        if (!w->nbr || !w->x1 || !w->verts || !w->in || !w->u || !w->slot || !w->fwd || !w->rev) return -1;
    }
    if (restir_pair_step_active(j->o) && frame_pair_alloc(j, e)) return -1;
    return 0;
}

void frame_workers_free(frame_job *j)
{
    int t;
    reuse_cells_free(&j->cells);
    frame_pair_free(j);
    if (!j->workers) return;
    for (t = 0; t < j->o->threads; ++t) {
        worker_state *w = &j->workers[t];
        spatial_workspace_free(&w->ws);
        stochastic_workspace_free(&w->sw);
        free(w->nbr);
        free(w->x1);
        free(w->verts);
        free(w->in);
        free(w->u);
        free(w->slot);
        free(w->fwd);
        free(w->rev);
    }
    free(j->workers);
}

int restir_render(const scene *s, const restir_options *o, restir_result *out, rerror *e)
{
    reuse_texture textures[PAIRING_MAX_TEXTURES];
    frame_job j;
    light_set lights;
    size_t pixels;
    double t0 = now_seconds();
    int status = 0;
    memset(out, 0, sizeof *out);
    if (restir_options_validate(o, e)) return -1;
    if (s->width < 1 || s->height < 1) return rerror_set(e, "%s: image size %dx%d", s->path, s->width, s->height);
    if (lights_build(&lights, s, e)) return -1;
    memset(&j, 0, sizeof j);
    j.s = s;
    j.o = o;
    restir_context_for(&j.ctx, s, &lights, o);
    restir_initial_options_for(&j.io, o);
    restir_neighbor_options_for(&j.no, o);
    if (restir_pairing_build(&j.no, o, textures, e)) {
        lights_free(&lights);
        return -1;
    }
    j.max_domains = neighbor_candidate_count(&j.no) + 1;
    pixels = (size_t)s->width * (size_t)s->height;
    j.initial = rmalloc(pixels, sizeof *j.initial, e);
    j.pong = o->spatial_passes > 0 ? rmalloc(pixels, sizeof *j.pong, e) : NULL;
    j.sum = rcalloc(3 * pixels, sizeof *j.sum, e);
    if (o->shading == RESTIR_SHADING_VECTOR && o->spatial_passes > 0 &&
        !(j.vector_shade = rcalloc(pixels, sizeof *j.vector_shade, e)))
        status = -1;
    if (!j.initial || (o->spatial_passes > 0 && !j.pong) || !j.sum || frame_workers_alloc(&j, e)) status = -1;
    if (!status) status = run_frames(&j, out, t0, e);
    if (!status) {
        frame_sum_stats(&j, &out->stats);
        out->stats.passes = o->spatial_passes;
        restir_memory_per_pixel(o, 0, &out->stats.memory);
        out->seconds = now_seconds() - t0;
    }
    free(j.initial);
    free(j.pong);
    free(j.sum);
    free(j.vector_shade);
    frame_workers_free(&j);
    restir_pairing_free(&j.no);
    lights_free(&lights);
    if (status) restir_result_free(out);
    return status;
}

/* ---- statistics ---------------------------------------------------------------------- */

static void write_histogram(FILE *out, const uint64_t *h, int n)
{
    int i;
    fputc('[', out);
    for (i = 0; i < n; ++i) fprintf(out, "%s%llu", i ? ", " : "", (unsigned long long)h[i]);
    fputc(']', out);
}

/* "temporal": steps, reprojection failures, capped histories, outputs from frame t-1,
 * shifts (forward and reverse) by outcome; rates per step. */
static void temporal_stats_write_json(FILE *out, const temporal_stats *t, const char *indent)
{
    double steps = t->pixels > 0 ? (double)t->pixels : 1;
    int i;
    fprintf(out, "%s  \"temporal\": {\"pixels\": %llu, \"no_history\": %llu, \"capped\": %llu, "
                 "\"selected_previous\": %llu, \"shifts\": %llu, \"mis_shifts\": %llu, \"dual_mv\": %llu, "
                 "\"dedup_lowered\": %llu, ",
            indent, (unsigned long long)t->pixels, (unsigned long long)t->no_history, (unsigned long long)t->capped,
            (unsigned long long)t->step.selected_neighbor, (unsigned long long)t->step.shifts,
            (unsigned long long)t->step.mis_shifts, (unsigned long long)t->dual,
            (unsigned long long)t->dedup_lowered);
    fprintf(out, "\"history_rate\": %.6f, \"shifts_per_pixel\": %.3f, \"shift_success_rate\": %.6f,\n%s    \"shift_outcomes\": {",
            (double)(t->pixels - t->no_history) / steps, (double)t->step.shifts / steps,
            t->step.shifts > 0 ? (double)t->step.outcome[SHIFT_OK] / (double)t->step.shifts : 0.0, indent);
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", shift_failure_names[i], (unsigned long long)t->step.outcome[i]);
    fprintf(out, "}}");
}

/* "correlation" (sequences; docs/correlation.md): the duplication maps of the final
 * reservoirs summed over frames (mean duplicate count per pixel, share of pixels holding a
 * duplicated sample, the largest count) and the boiling filter's clears. */
static void correlation_stats_write_json(FILE *out, const restir_stats *st, const char *indent)
{
    const duplication_summary *c = &st->correlation;
    double px = c->pixels > 0 ? (double)c->pixels : 1;
    fprintf(out, ",\n%s  \"correlation\": {\"pixels\": %llu, \"duplicated_pixels\": %llu, \"duplicates\": %llu, "
                 "\"mean_duplicates\": %.6f, \"mean_duplication_score\": %.8f, \"duplicated_fraction\": %.6f, "
                 "\"max_duplicates\": %u, \"boiling_cleared\": %llu, \"milliseconds\": %.3f}",
            indent, (unsigned long long)c->pixels, (unsigned long long)c->duplicated,
            (unsigned long long)c->count_sum, (double)c->count_sum / px,
            (double)c->count_sum / px / duplication_score_denominator(DUPLICATION_RADIUS),
            (double)c->duplicated / px, c->count_max, (unsigned long long)st->boiling_cleared, st->ms_correlation);
}

uint64_t restir_stats_invalid_weights(const restir_stats *st)
{
    return st->initial.invalid_weights + st->spatial.invalid_weights + st->temporal.step.invalid_weights;
}

/* "mutations": proposals, acceptances, rejections by reason (Mutations §3, mutate.h). */
static void mutate_stats_write_json(FILE *out, const mutate_stats *m, double ms, const char *indent)
{
    int i;
    fprintf(out, "%s  \"mutations\": {\"pixels\": %llu, \"skipped\": %llu, \"proposals\": %llu, \"accepted\": %llu, "
                 "\"rejected_mh\": %llu, \"acceptance_rate\": %.6f, \"milliseconds\": %.3f,\n%s    \"rejected\": {",
            indent, (unsigned long long)m->pixels, (unsigned long long)m->skipped, (unsigned long long)m->proposals,
            (unsigned long long)m->accepted, (unsigned long long)m->rejected_mh,
            m->proposals ? (double)m->accepted / (double)m->proposals : 0.0, ms, indent);
    for (i = 0; i < MUTATE_REJECT_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i > 0 ? ", " : "", mutate_reject_names[i], (unsigned long long)m->rejected[i]);
    fprintf(out, "}, \"duplicates\": %llu, \"final_valid\": %llu, \"pss_bytes_per_pixel\": %.1f, \"skip\": {",
            (unsigned long long)m->duplicates, (unsigned long long)m->final_valid,
            m->pixels ? (double)m->pss_numbers / (double)m->pixels * (double)sizeof(real) : 0.0);
    for (i = 0; i < MUTATE_REASON_SKIP_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i > 0 ? ", " : "", mutate_skip_names[i], (unsigned long long)m->skip[i]);
    fprintf(out, "}}");
}

void restir_memory_per_pixel(const restir_options *o, int sequence, restir_memory *m)
{
    unsigned per_buffer;
    memset(m, 0, sizeof *m);
    m->reservoir = (unsigned)sizeof(reservoir);
    /* the primary-sample rows of every buffer (reservoir.h), allocated by mutation runs only
     * (and by sequences that read a checkpoint or a stage dump) */
    m->reservoir_pss = sequence && o->mutations > 0 ? (unsigned)(PATH_MAX_PSS * sizeof(real)) : 0;
    per_buffer = m->reservoir + m->reservoir_pss;
    m->reservoirs_initial = per_buffer;
    m->reservoirs_spatial = sequence || o->spatial_passes > 0 ? per_buffer : 0; /* ping-pong */
    m->reservoirs_previous = sequence ? per_buffer : 0;                         /* temporal input */
    m->gbuffer = (unsigned)sizeof(gbuffer_texel);
    m->gbuffer_previous = sequence ? m->gbuffer : 0;
    m->accumulation = (unsigned)(3 * sizeof(double));
    m->vector_shade = o->shading == RESTIR_SHADING_VECTOR && o->spatial_passes > 0 ? (unsigned)sizeof(rgb) : 0;
    /* reuse_cells.h: cell_of, start, pixels, nz_start, nz_pixels, hash per pixel, and at most
     * one confidence per pixel (one cell per pixel at worst). */
    m->reuse_cells = o->cells ? (unsigned)(3 * sizeof(int) + 3 * sizeof(uint32_t) + sizeof(double)) : 0;
    /* pair_step.c: one pre-pass shift, partner pixel and texture per neighbour, the accepted
     * count and x1 of every pixel (Enhanced §3) */
    m->pair_step = restir_pair_step_active(o) && o->spatial_passes > 0
                       ? (unsigned)((size_t)o->neighbors * (sizeof(pair_shift) + sizeof(uint32_t) + 1) + sizeof(int) +
                                    sizeof(path_vertex))
                       : 0;
    /* pipeline.c: the duplication map and the history ages of frames t and t-1 (issue 12) */
    m->correlation = sequence ? (unsigned)(3 * sizeof(uint16_t)) : 0;
    m->total = m->reservoirs_initial + m->reservoirs_spatial + m->reservoirs_previous + m->gbuffer +
               m->gbuffer_previous + m->accumulation + m->vector_shade + m->reuse_cells + m->pair_step +
               m->correlation;
}

static void restir_memory_write_json(FILE *out, const restir_memory *m, const char *indent)
{
    fprintf(out, ",\n%s  \"bytes_per_pixel\": {\"reservoir\": %u, \"reservoir_pss\": %u, \"reservoirs_initial\": %u, "
                 "\"reservoirs_spatial\": %u, \"reservoirs_previous\": %u,\n%s    \"gbuffer\": %u, "
                 "\"gbuffer_previous\": %u, \"accumulation\": %u, \"vector_shade\": %u, \"reuse_cells\": %u, "
                 "\"pair_step\": %u, \"correlation\": %u, \"total\": %u}",
            indent, m->reservoir, m->reservoir_pss, m->reservoirs_initial, m->reservoirs_spatial,
            m->reservoirs_previous, indent, m->gbuffer, m->gbuffer_previous, m->accumulation, m->vector_shade,
            m->reuse_cells, m->pair_step, m->correlation, m->total);
}

void restir_stats_write_json(FILE *out, const restir_stats *st, const char *indent)
{
    const initial_stats *in = &st->initial;
    const spatial_stats *sp = &st->spatial;
    double px = in->pixels > 0 ? (double)in->pixels : 1;
    int i;
    fprintf(out, "{\n%s  \"frames\": %llu,\n", indent, (unsigned long long)st->frames);
    fprintf(out, "%s  \"milliseconds\": {\"gbuffer\": %.3f, \"initial\": %.3f, \"spatial\": [", indent, st->ms_gbuffer,
            st->ms_initial);
    for (i = 0; i < st->passes && i < RESTIR_MAX_SPATIAL_PASSES; ++i)
        fprintf(out, "%s%.3f", i ? ", " : "", st->ms_spatial[i]);
    fprintf(out, "], \"temporal\": %.3f, \"shade\": %.3f, \"pose\": %.3f, \"motion\": %.3f},\n", st->ms_temporal,
            st->ms_shade, st->ms_pose, st->ms_motion);
    fprintf(out, "%s  \"initial\": {\"pixels\": %llu, \"trees\": %llu, \"candidates\": %llu, \"selected\": %llu, ",
            indent, (unsigned long long)in->pixels, (unsigned long long)in->trees,
            (unsigned long long)in->candidates, (unsigned long long)in->selected);
    fprintf(out, "\"record_failed\": %llu, \"record_mismatch\": %llu, \"unshiftable\": %llu,\n",
            (unsigned long long)in->record_failed, (unsigned long long)in->record_mismatch,
            (unsigned long long)in->unshiftable);
    fprintf(out, "%s    \"selected_by_length\": ", indent);
    write_histogram(out, in->length, PATH_MAX_LENGTH + 1);
    fprintf(out, ",\n%s    \"selected_by_reconnection_index\": ", indent);
    write_histogram(out, in->rc_index, PATH_MAX_LENGTH + 1);
    fprintf(out, "},\n%s  \"spatial\": {\"passes\": %d, \"steps\": %llu, \"domains\": %llu, \"shifts\": %llu, "
                 "\"mis_shifts\": %llu, \"shifts_per_pixel_per_frame\": %.3f, \"selected_neighbor\": %llu,\n",
            indent, st->passes, (unsigned long long)sp->pixels, (unsigned long long)sp->domains,
            (unsigned long long)sp->shifts, (unsigned long long)sp->mis_shifts, (double)sp->shifts / px,
            (unsigned long long)sp->selected_neighbor);
    fprintf(out, "%s    \"shift_outcomes\": {", indent);
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", shift_failure_names[i], (unsigned long long)sp->outcome[i]);
    fprintf(out, "},\n%s    \"neighbor_verdicts\": {", indent);
    for (i = 0; i < NEIGHBOR_VERDICT_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", neighbor_verdict_names[i],
                (unsigned long long)st->neighbors.verdict[i]);
    fprintf(out, "}},\n");
    temporal_stats_write_json(out, &st->temporal, indent);
    correlation_stats_write_json(out, st, indent);
    fprintf(out, ",\n%s  \"guards\": {\"invalid_weights\": %llu, \"nonfinite_pixels\": %llu}", indent,
            (unsigned long long)restir_stats_invalid_weights(st), (unsigned long long)st->nonfinite_pixels);
    fprintf(out, ",\n");
    mutate_stats_write_json(out, &st->mutate, st->ms_mutate, indent);
    if (st->memory.total) restir_memory_write_json(out, &st->memory, indent);
    fprintf(out, "\n%s}", indent);
}

void restir_options_write_json(FILE *out, const restir_options *o, const char *indent)
{
    fprintf(out, "{\"shift\": \"%s\", \"mis\": \"%s\", \"candidates\": %d, \"spatial_passes\": %d, ",
            restir_shift_names[o->shift], restir_mis_names[o->mis], o->candidates, o->spatial_passes);
    fprintf(out, "\"neighbors\": %d, \"radius\": %g, \"pattern\": \"%s\", \"reject\": %s, \"normal_cos\": %g, "
                 "\"depth_ratio\": %g,\n%s  ",
            o->neighbors, o->radius, neighbor_pattern_names[o->pattern], o->no_reject ? "false" : "true",
            o->normal_cos, o->depth_ratio, indent);
    fprintf(out, "\"frames\": %d, \"first_frame\": %d, \"time_limit\": %g, \"max_depth\": %d, "
                 "\"roughness_threshold\": %g, \"distance_threshold\": %g, \"paths\": \"%s\", \"ablate\": \"%s\", ",
            o->frames, o->first_frame, o->time_limit, o->max_depth, o->roughness_threshold, o->distance_threshold,
            restir_paths_names[o->paths], restir_ablation_names[o->ablation]);
    fprintf(out, "\"pairing\": \"%s\", \"pair_step\": %s, \"shading\": \"%s\", ", restir_pairing_names[o->pairing],
            restir_pair_step_active(o) ? "true" : "false", restir_shading_names[o->shading]);
    fprintf(out, "\"force_nee_reconnection\": %s, ", o->force_nee_reconnection ? "true" : "false");
    fprintf(out, "\"rc_criterion\": \"%s\", \"footprint_c\": %g, ", rc_mode_names[o->rc_criterion], o->footprint_c);
    fprintf(out, "\"russian_roulette\": %s, \"jitter\": %s, \"seed\": %u, \"threads\": %d,\n%s  ",
            o->russian_roulette ? "true" : "false", o->jitter ? "true" : "false", o->seed, o->threads, indent);
    if (o->mis == RESTIR_MIS_STOCHASTIC_PAIRWISE || o->cells) /* issue 14 (only when used) */
        fprintf(out, "\"stochastic_n\": %d, \"stochastic_nc\": %d, \"confidence_scaling\": %s, \"reuse_cells\": %s,\n%s  ",
                o->stochastic_n, o->stochastic_nc, o->no_confidence_scaling ? "false" : "true", o->cells ? "true" : "false",
                indent);
    if (o->dedup || o->motion_vectors || o->boiling_filter > 0) /* issue 12 (only when used) */
        fprintf(out, "\"dedup\": %s, \"dedup_min\": %g, \"dedup_alpha\": %g, \"motion_vectors\": \"%s\", "
                     "\"boiling_filter\": %g, \"biased\": %s,\n%s  ",
                o->dedup ? "true" : "false", o->dedup_min, o->dedup_alpha, restir_motion_vector_names[o->motion_vectors],
                o->boiling_filter, restir_options_biased(o) ? "true" : "false", indent);
    if (isinf(o->mcap))
        fprintf(out, "\"temporal\": %s, \"temporal_mis\": \"%s\", \"mcap\": \"inf\"", o->temporal ? "true" : "false",
                restir_mis_names[o->temporal_mis]);
    else
        fprintf(out, "\"temporal\": %s, \"temporal_mis\": \"%s\", \"mcap\": %g", o->temporal ? "true" : "false",
                restir_mis_names[o->temporal_mis], o->mcap);
    fprintf(out, ", \"mutations\": %d, \"mutation\": \"%s\", \"mutate_after\": %d, \"light_ris\": %d, \"light_tiles\": %s}", o->mutations,
            mutate_strategy_names[o->mutation], o->mutate_after, o->light_ris, o->light_tiles ? "true" : "false");
}
