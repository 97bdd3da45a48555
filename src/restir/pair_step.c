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
#include "restir/restir.h"

#include "restir/threads.h"
#include "frame_job.h"

static uint32_t pass_sample(const frame_job *j)
{
    return neighbor_sample_index(j->frame, (uint32_t)j->o->spatial_passes, (uint32_t)j->pass);
}

static long frame_pixels(const frame_job *j) { return (long)j->s->width * j->s->height; }

/* Pixel (x, y): its sample shifted to each accepted partner, filed by texture. Pixels
 * without a primary hit are nobody's neighbour: their slots are never read. */
static void prepass_pixel(frame_job *j, worker_state *w, int x, int y)
{
    long p = (long)y * j->s->width + x, N = frame_pixels(j);
    const reservoir *r = &j->src[p];
    int valid = path_sample_is_valid(&r->y) && r->W > 0, n, a;
    path_vertex to;
    if (!frame_primary_vertex(j->s, &j->g, p, &to)) return;
    n = neighbor_select_slots(&j->no, &j->g, j->o->seed, pass_sample(j), x, y, w->nbr, w->slot, j->max_domains - 1,
                              NULL, NULL);
    for (a = 0; a < n; ++a) {
        pair_shift *ps = &j->pair[(long)w->slot[a] * N + p];
        ps->ok = 0;
        if (!valid || !frame_primary_vertex(j->s, &j->g, (long)w->nbr[a], &to)) continue;
        ps->ok = spatial_counted_shift(&j->ctx, &to, &r->y, &ps->y, &ps->jacobian, &w->st.spatial) == SHIFT_OK;
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
    parallel_tiles(j->s->width, j->s->height, 16, j->o->threads, prepass_tile, j, NULL, NULL);
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
    spatial_resample_preshifted(&j->ctx, (mis_family)j->o->mis, n + 1, w->x1, w->in, &pre, w->u, out, &w->ws,
                                &w->st.spatial);
}
