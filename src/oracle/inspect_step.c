/* The two-domain GRIS steps `restir inspect` shows (inspect_step.h): the library's own
 * spatial_resample and temporal_resample on two reservoirs, so that the printed numbers are
 * the renderer's. */
#include "inspect_step.h"

#include <string.h>
#include "restir/core/rng.h"
#include "restir/frame/options.h"
#include "restir/oracle/dump_diff.h"
#include "restir/restir/temporal.h"

/* The common set-up: g cleared, the two inputs, the selection numbers (RNG_RIS, `vertex`);
 * g->shown = 0 (and nothing else) for a step without a two-domain form (stochastic pairwise
 * MIS: has_family = 0). */
static int step_begin(inspect_step *g, int temporal, int has_family, const reservoir *ra, const reservoir *rb,
                      rng_key key, uint32_t vertex, rerror *e)
{
    int j;
    memset(g, 0, sizeof *g);
    g->temporal = temporal;
    g->selected = -1;
    if (!has_family) return 0;
    if (spatial_workspace_alloc(&g->ws, 2, e)) return -1;
    g->shown = 1;
    g->in[0] = *ra;
    g->in[1] = *rb;
    for (j = 0; j < 2; ++j) g->u[j] = rng_u(key, RNG_RIS, vertex, (uint32_t)j);
    return 0;
}

/* After the step: the resampling weights w_j (GRIS Eq. 19) and the selected candidate. */
static void step_end(inspect_step *g)
{
    int j;
    for (j = 0; j < 2; ++j) {
        g->w[j] = g->ws.valid[j] ? gris_resampling_weight(g->ws.mis[j], g->ws.ptarget[j], g->in[j].W, g->ws.jacobian[j])
                                 : 0;
        if (g->ws.valid[j] && dump_same_sample(g->ws.cand[j], &g->out.y)) g->selected = j;
    }
}

int inspect_spatial_step(const restir_context *c, const restir_options *o, const initial_options *io,
                         const path_vertex *xa, const path_vertex *xb, const reservoir *ra, const reservoir *rb,
                         uint32_t p, inspect_step *g, rerror *e)
{
    const path_vertex *x1[2];
    const reservoir *in[2];
    spatial_stats st;
    rng_key key = initial_pixel_key(io, o->seed, (uint32_t)o->first_frame, p);
    if (step_begin(g, 0, o->spatial.algorithm == SPATIAL_GRIS_STEP, ra, rb, key, RNG_VERTEX_SPATIAL_RIS(0), e)) return -1; /* spatial pass 1 */
    if (!g->shown) return 0;
    x1[0] = xa;
    x1[1] = xb;
    in[0] = &g->in[0];
    in[1] = &g->in[1];
    memset(&st, 0, sizeof st);
    spatial_resample(c, restir_step_mis(o, o->spatial.mis), 2, x1, in, g->u, &g->out, &g->ws, &st);
    step_end(g);
    return 0;
}

/* The temporal GRIS step of pixel p (GRIS §6.3 step 2, temporal.h) in a static scene:
 * domain 0 = p's initial reservoir of frame f, domain 1 = p's initial reservoir of frame
 * f - 1 (the real-time pipeline feeds the previous frame's FINAL reservoir, after its
 * spatial passes, at the motion-reprojected pixel: the same arithmetic on other inputs),
 * capped at --mcap times the current confidence, --temporal-mis, the selection numbers of
 * RNG_RIS vertex RNG_VERTEX_TEMPORAL_RIS (pipeline.c temporal_pixel). */
int inspect_temporal_step(const restir_context *c, const restir_options *o, const initial_options *io,
                          const path_vertex *xa, const path_vertex *xprev, const reservoir *ra, const reservoir *rprev,
                          uint32_t p, inspect_step *g, rerror *e)
{
    temporal_stats st;
    rng_key key = initial_pixel_key(io, o->seed, (uint32_t)o->first_frame, p);
    if (step_begin(g, 1, 1, ra, rprev, key, RNG_VERTEX_TEMPORAL_RIS, e)) return -1;
    if (!g->shown) return 0;
    memset(&st, 0, sizeof st);
    temporal_resample_mode(c, c, NULL, restir_step_mis(o, o->temporal.mis), xa, xprev, &g->in[0], &g->in[1],
                           (real)o->temporal.mcap, o->temporal.mcap_mode, g->u, &g->out, &g->ws, &st);
    step_end(g);
    return 0;
}

