/* The stages of one ReSTIR PT frame (src/frame/stages.h), shared by the offline driver
 * (offline.c, independent frames, GRIS §6.5) and the real-time pipeline (pipeline.c, GRIS
 * §6.3 steps 1-4): G-buffer, initial resampling, K spatial passes, shading; every stage a
 * pass over the image in 16 x 16 tiles. */
#include "stages.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"
#include "pair_step.h"

/* ---- passes (stages.h) ------------------------------------------------ */

int pipeline_stage_skipped(const frame_job *j, const char *name)
{
    return j->hook && j->hook->skips && j->hook->skips(j->hook->user, name);
}

void pipeline_stage_done(frame_job *j, const char *name, reservoir *rs)
{
    /* a stage a restart skips did not write rs (the listener keeps the numbers it reads) */
    if (j->pss_rows && !pipeline_stage_skipped(j, name))
        reservoir_buffer_keep_pss(rs, (size_t)j->s->width * (size_t)j->s->height, j->o->threads);
    if (j->hook && j->hook->reservoirs) j->hook->reservoirs(j->hook->user, name, rs, j->s->width, j->s->height);
}

/* x1 of pixel p as the path sampler builds it from the frame's primary ray. */
static int primary_vertex(const frame_job *j, long p, path_vertex *v) { return gbuffer_primary_vertex(j->s, &j->g, p, v); }

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

/* `restir inspect --from-dump`: 1 if the listener traces pixel p (frame/pixel_trace.h). */
static int traced(const frame_job *j, long p) { return j->hook && j->hook->pixel && j->hook->trace_pixel == p; }

/* The domains' pixels of the step at p (domain 0 = p, then the accepted neighbours). */
static void domain_pixels(const worker_state *w, long p, int m, long *pixels)
{
    int d;
    for (d = 0; d < m && d < PIXEL_TRACE_MAX_DOMAINS; ++d) pixels[d] = d == 0 ? p : (long)w->nbr[d - 1];
}

/* The neighbour candidate that proposed each traced domain, then hands t to the listener. */
static void trace_done(const frame_job *j, const worker_state *w, pixel_trace *t)
{
    int d;
    if (!j->o->spatial.cells)
        for (d = 1; d < t->kept; ++d) t->d[d].candidate = w->slot[d - 1];
    t->neighbor_sample = neighbor_sample_index(j->frame, (uint32_t)j->o->spatial_passes, (uint32_t)j->pass) +
                         (j->ctx.ablation == RESTIR_ABLATE_NEIGHBOR_RNG);
    j->hook->pixel(j->hook->user, t);
}

/* The stochastic pairwise step (stochastic_spatial.h) over the domains spatial_pixel set
 * up. Pick k of pass p draws RNG_RIS vertex RNG_VERTEX_STOCHASTIC_PICK(p), slot k;
 * canonical pick k RNG_VERTEX_STOCHASTIC_CANONICAL(p), slot k (rng.h). */
static void stochastic_spatial_pixel(frame_job *j, worker_state *w, rng_key key, int m, reservoir *out)
{
    stochastic_options so = j->o->stochastic;
    int k;
    so.naive_p = j->ctx.ablation == RESTIR_ABLATE_STOCHASTIC_P;
    for (k = 0; k < so.n_picks; ++k) w->up[k] = rng_u(key, RNG_RIS, RNG_VERTEX_STOCHASTIC_PICK(j->pass), (uint32_t)k);
    for (k = 0; k < so.n_canonical_picks; ++k) w->uc[k] = rng_u(key, RNG_RIS, RNG_VERTEX_STOCHASTIC_CANONICAL(j->pass), (uint32_t)k);
    w->sw.vertex = lazy_vertex;
    w->sw.vertex_user = w;
    stochastic_pairwise_resample(&j->ctx, &so, m, w->x1, w->in, w->u, w->up, w->uc, out, &w->sw, &w->st.spatial);
    if (traced(j, (long)key.pixel)) {
        pixel_trace t;
        long pixels[PIXEL_TRACE_MAX_DOMAINS];
        char name[32];
        snprintf(name, sizeof name, "spatial%d", j->pass + 1);
        domain_pixels(w, (long)key.pixel, m, pixels);
        pixel_trace_stochastic(&t, name, j->frame, (long)key.pixel, j->pass, key, &so, m, pixels, w->in, w->u, w->up,
                               w->uc, &w->sw, out);
        trace_done(j, w, &t);
    }
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
    rng_key key = initial_pixel_key(&j->io, j->o->seed, j->frame, (uint32_t)p);
    uint32_t nsample = neighbor_sample_index(j->frame, (uint32_t)j->o->spatial_passes, (uint32_t)j->pass) +
                       (j->ctx.ablation == RESTIR_ABLATE_NEIGHBOR_RNG); /* the planted off-by-one */
    int n, d;
    if (j->pair ? j->pair_n[p] < 0 : !primary_vertex(j, p, &w->verts[0])) {
        reservoir_init(&j->dst[p]);
        if (j->vector_shade) j->vector_shade[p] = rgb_gray(0);
        return;
    }
    /* capacity is checked by restir_options_validate, so this cannot fail */
    if (j->pair) {
        n = frame_pair_domains(j, w, p); /* the pre-pass's neighbours and cached vertices */
    } else if (j->o->spatial.cells) {
        /* Stochastic MIS §5.1: a reuse cell; its pixels except p are the domains */
        int c = reuse_cell_search(&j->cells, &j->g, (float)j->o->spatial.normal_cos, j->o->seed, nsample, x, y);
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
            if (d > 0 && j->o->spatial.algorithm != SPATIAL_STOCHASTIC_PAIRWISE) primary_vertex(j, q, &w->verts[d]);
            w->x1[d] = d > 0 && j->o->spatial.algorithm == SPATIAL_STOCHASTIC_PAIRWISE ? NULL : &w->verts[d];
        }
        w->in[d] = &j->src[q];
        /* the pass goes into the vertex, never the slot (the f5df7f5 collision; rng.h) */
        w->u[d] = rng_u(key, RNG_RIS, RNG_VERTEX_SPATIAL_RIS(j->pass), (uint32_t)d);
    }
    if (j->o->spatial.algorithm == SPATIAL_STOCHASTIC_PAIRWISE) {
        stochastic_spatial_pixel(j, w, key, n + 1, &j->dst[p]);
        return;
    }
    if (j->pair)
        frame_pair_resample(j, w, p, n, &j->dst[p]); /* Enhanced §3: the pair's shifts from the pre-pass */
    else
        spatial_resample(&j->ctx, restir_step_mis(j->o, j->o->spatial.mis), n + 1, w->x1, w->in, w->u, &j->dst[p], &w->ws,
                         &w->st.spatial);
    if (traced(j, p)) {
        pixel_trace t;
        long pixels[PIXEL_TRACE_MAX_DOMAINS];
        char name[32];
        snprintf(name, sizeof name, "spatial%d", j->pass + 1);
        domain_pixels(w, p, n + 1, pixels);
        pixel_trace_gris(&t, j->pair ? PIXEL_TRACE_PAIR : PIXEL_TRACE_SPATIAL, name, j->frame, p, j->pass, key,
                         RNG_VERTEX_SPATIAL_RIS(j->pass), (int)restir_step_mis(j->o, j->o->spatial.mis), n + 1, pixels,
                         w->in, w->u, &w->ws, &j->dst[p]);
        trace_done(j, w, &t);
    }
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

static void sky_background_add(frame_job *j, long p)
{
    rgb L = light_distant_radiance(j->ctx.path.lights, v3_normalize(v3_from_f(j->g.texels[p].view_dir)));
    j->sum[3 * p + 0] += (double)L.r;
    j->sum[3 * p + 1] += (double)L.g;
    j->sum[3 * p + 2] += (double)L.b;
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
            if (!primary_vertex(j, p, &v)) {
                /* The primary ray left the scene: the sky seen directly (docs/environment.md). */
                if (j->o->paths == RESTIR_PATHS_ALL && light_set_has_sky(j->ctx.path.lights))
                    sky_background_add(j, p);
                continue;
            }
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
            if (j->o->spatial.cells) reuse_cells_build(&j->cells, &j->g, j->src, NULL); /* allocated: cannot fail */
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

void frame_sum_stats(const frame_job *j, restir_stats *st)
{
    int t;
    for (t = 0; t < j->o->threads; ++t) restir_stats_add(st, &j->workers[t].st);
}

int frame_workers_alloc(frame_job *j, rerror *e)
{
    int t;
    size_t m = (size_t)j->max_domains;
    if (j->o->spatial.cells) {
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
        if (j->o->spatial.algorithm == SPATIAL_STOCHASTIC_PAIRWISE && stochastic_workspace_alloc(&w->sw, j->max_domains, e))
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
