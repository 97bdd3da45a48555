/* The pair step of paired spatial reuse (Enhanced §3; docs/enhanced.md §2).
 *
 * With reciprocal neighbours (--pairing paired: j is i's partner in reuse texture k exactly
 * when i is j's), pairwise MIS at pixel i needs, per neighbour j, two shifts: the forward
 * T_{j->i}(X_j) (the candidate) and T_{i->j}(X_i) (p̂_{<-j}(X_i), the canonical sample's
 * MIS entry, GRIS Eqs. 35, 37-38). Pixel j needs the same two with the roles swapped. So a
 * pre-pass shifts every pixel's sample once to each of its partners, and the resampling
 * pass reads both directions of each pair from it: two shifts per pair instead of four.
 * The values are those the per-pixel step would compute (the same function of the same
 * inputs), so the output is bit-identical to --no-pair-step (test_restir_pairing.c). */

#include "pair_step.h"

#include <stdlib.h>

#include "restir/core/threads.h"
#include "restir/frame/options.h"

static uint32_t pass_sample(const frame_job *j)
{
    return neighbor_sample_index(j->frame, (uint32_t)j->o->spatial_passes, (uint32_t)j->pass);
}

static long frame_pixels(const frame_job *j) { return (long)j->s->width * j->s->height; }

int frame_pair_alloc(frame_job *j, rerror *e)
{
    size_t N = (size_t)frame_pixels(j), k = (size_t)j->o->spatial.neighbors;
    /* one shift per pixel and texture */
    j->pair = rcalloc(k * N, sizeof *j->pair, e);
    j->pair_n = rmalloc(N, sizeof *j->pair_n, e);
    j->pair_nbr = rmalloc(k * N, sizeof *j->pair_nbr, e);
    j->pair_slot = rmalloc(k * N, sizeof *j->pair_slot, e);
    j->pair_x1 = rmalloc(N, sizeof *j->pair_x1, e);
    return j->pair && j->pair_n && j->pair_nbr && j->pair_slot && j->pair_x1 ? 0 : -1;
}

void frame_pair_free(frame_job *j)
{
    free(j->pair);
    free(j->pair_n);
    free(j->pair_nbr);
    free(j->pair_slot);
    free(j->pair_x1);
    j->pair = NULL;
    j->pair_n = NULL;
    j->pair_nbr = NULL;
    j->pair_slot = NULL;
    j->pair_x1 = NULL;
}

/* Pass 0 of a frame: every pixel's x1 (the G-buffer is the frame's), and -1 neighbours
 * where the primary ray missed. */
static void vertex_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    int x, y;
    (void)worker;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            long p = (long)y * j->s->width + x;
            j->pair_n[p] = gbuffer_primary_vertex(j->s, &j->g, p, &j->pair_x1[p]) ? 0 : -1;
        }
}

/* Pixel (x, y): its neighbours (kept for the resampling pass; counted here, once) and its
 * sample shifted to each partner, filed by texture. Pixels without a primary hit are
 * nobody's neighbour: their slots are never read. */
static void prepass_pixel(frame_job *j, worker_state *w, int x, int y)
{
    long p = (long)y * j->s->width + x, N = frame_pixels(j), k = j->o->spatial.neighbors;
    const reservoir *r = &j->src[p];
    int valid = path_sample_is_valid(&r->y) && r->W > 0, n, a;
    uint32_t *nbr = &j->pair_nbr[p * k];
    if (j->pair_n[p] < 0) return;
    n = neighbor_select_slots(&j->no, &j->g, j->o->seed, pass_sample(j), x, y, nbr, w->slot, j->max_domains - 1,
                              &w->st.neighbors, NULL);
    j->pair_n[p] = n < 0 ? 0 : n;
    for (a = 0; a < n; ++a) {
        pair_shift *ps = &j->pair[(long)w->slot[a] * N + p];
        j->pair_slot[p * k + a] = (unsigned char)w->slot[a];
        ps->ok = valid && spatial_counted_shift(&j->ctx, &j->pair_x1[nbr[a]], &r->y, &ps->y, &ps->jacobian,
                                                &w->st.spatial) == SHIFT_OK;
    }
}

static void prepass_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) prepass_pixel(j, &j->workers[worker], x, y);
}

void frame_pair_prepass(frame_job *j)
{
    if (j->pass == 0) parallel_tiles(j->s->width, j->s->height, 16, j->o->threads, vertex_tile, j, NULL, NULL);
    parallel_tiles(j->s->width, j->s->height, 16, j->o->threads, prepass_tile, j, NULL, NULL);
}

int frame_pair_domains(frame_job *j, worker_state *w, long p)
{
    long k = j->o->spatial.neighbors;
    int n = j->pair_n[p], a;
    w->x1[0] = &j->pair_x1[p];
    for (a = 0; a < n; ++a) {
        w->nbr[a] = j->pair_nbr[p * k + a];
        w->slot[a] = j->pair_slot[p * k + a];
        w->x1[a + 1] = &j->pair_x1[w->nbr[a]];
    }
    return n;
}

void frame_pair_resample(frame_job *j, worker_state *w, long p, int n, reservoir *out)
{
    long N = frame_pixels(j);
    pair_shifts pre;
    int d;
    for (d = 1; d <= n; ++d) {
        long k = w->slot[d - 1];
        w->fwd[d] = &j->pair[k * N + (long)w->nbr[d - 1]]; /* partner -> p */
        w->rev[d] = &j->pair[k * N + p];                   /* p -> partner */
    }
    pre.forward = w->fwd;
    pre.reverse = w->rev;
    pre.drop_reverse = j->ctx.ablation == RESTIR_ABLATE_PAIR_MIS;
    spatial_resample_preshifted(&j->ctx, restir_step_mis(j->o, j->o->spatial.mis), n + 1, w->x1, w->in, &pre, w->u, out, &w->ws,
                                &w->st.spatial);
}
