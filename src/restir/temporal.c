/* Temporal reuse at one pixel (include/restir/temporal.h). */
#include "restir/temporal.h"

#include <math.h>

void temporal_resample(const restir_context *cur, const restir_context *prev, mis_family mis,
                       const path_vertex *x1_cur, const path_vertex *x1_prev, const reservoir *cur_r,
                       const reservoir *prev_r, real mcap, const real *u, reservoir *out, spatial_workspace *w,
                       temporal_stats *st)
{
    const path_vertex *x1[2];
    const reservoir *in[2];
    reservoir capped;
    st->pixels++;
    if (!x1_prev || !prev_r) {
        st->no_history++;
        *out = *cur_r;
        return;
    }
    /* GRIS §6.2 M_c, §6.4: the history counts at most C times the new samples */
    capped = *prev_r;
    if (isfinite((double)mcap)) {
        real cap = mcap * cur_r->confidence;
        if (capped.confidence > cap) st->capped++;
        reservoir_cap_confidence(&capped, cap);
    }
    x1[0] = x1_cur;
    x1[1] = x1_prev;
    in[0] = cur_r;
    in[1] = &capped;
    /* domain 1's MIS shifts run in the previous frame (GRIS App. B) */
    gris_resample(cur, prev, mis, 2, x1, in, u, out, w, &st->step);
}

void temporal_stats_add(temporal_stats *acc, const temporal_stats *add)
{
    acc->pixels += add->pixels;
    acc->no_history += add->no_history;
    acc->capped += add->capped;
    spatial_stats_add(&acc->step, &add->step);
}
