/* One pixel's reuse steps, copied out of the steps' own workspaces (pixel_trace.h). */
#include "restir/frame/pixel_trace.h"

#include <stdio.h>
#include <string.h>

/* The same sample by initial-candidate id (docs/oracle.md "Same sample"). */
static int same_id(const path_sample *a, const path_sample *b)
{
    int ea = !path_sample_is_valid(a), eb = !path_sample_is_valid(b);
    if (ea || eb) return ea && eb;
    return a->seed == b->seed && a->pixel == b->pixel && a->sample == b->sample && a->length == b->length &&
           a->technique == b->technique;
}

static void trace_begin(pixel_trace *t, int step, const char *stage, uint32_t frame, long pixel, int pass,
                        rng_key key, int m, const long *pixels, const reservoir *const *in, const real *u,
                        const reservoir *out)
{
    int i;
    memset(t, 0, sizeof *t);
    t->step = step;
    snprintf(t->stage, sizeof t->stage, "%s", stage);
    t->frame = frame;
    t->pixel = pixel;
    t->pass = pass;
    t->key = key;
    t->m = m;
    t->kept = m < PIXEL_TRACE_MAX_DOMAINS ? m : PIXEL_TRACE_MAX_DOMAINS;
    t->selected = -1;
    t->out = *out;
    for (i = 0; i < t->kept; ++i) {
        t->d[i].pixel = pixels[i];
        t->d[i].candidate = -1;
        t->d[i].u = u[i];
        if (in[i]) t->d[i].in = *in[i];
        else reservoir_init(&t->d[i].in);
    }
}

void pixel_trace_gris(pixel_trace *t, int step, const char *stage, uint32_t frame, long pixel, int pass, rng_key key,
                      uint32_t vertex, int mis, int m, const long *pixels, const reservoir *const *in, const real *u,
                      const spatial_workspace *ws, const reservoir *out)
{
    int i;
    trace_begin(t, step, stage, frame, pixel, pass, key, m, pixels, in, u, out);
    t->vertex = vertex;
    t->mis = mis;
    if (!ws) { /* no reuse (temporal without history): the output is the input */
        t->d[0].valid = path_sample_is_valid(&t->d[0].in.y);
        t->d[0].confidence = t->d[0].in.confidence;
        t->d[0].jacobian = 1;
        t->d[0].target = t->d[0].target_own = t->d[0].in.y.target;
        t->d[0].m = 1;
        t->d[0].w = t->d[0].in.wsum;
        t->selected = t->d[0].valid ? 0 : -1;
        return;
    }
    for (i = 0; i < t->kept; ++i) {
        pixel_trace_domain *d = &t->d[i];
        d->valid = ws->valid[i];
        d->confidence = ws->confidence[i];
        if (!d->valid) continue;
        d->jacobian = ws->jacobian[i];
        d->target = ws->ptarget[i];                  /* row 0: p̂(y_i) */
        d->target_own = ws->ptarget[i * m + i];      /* p̂_i(X_i) / J_i */
        d->target_back = i ? ws->ptarget[i * m] : 0; /* p̂_{<-i}(y_0) */
        d->m = ws->mis[i];
        d->w = gris_resampling_weight(d->m, d->target, d->in.W, d->jacobian); /* GRIS Eq. 19 */
        if (t->selected < 0 && same_id(ws->cand[i], &out->y) && path_sample_is_valid(&out->y)) t->selected = i;
    }
}

void pixel_trace_stochastic(pixel_trace *t, const char *stage, uint32_t frame, long pixel, int pass, rng_key key,
                            const stochastic_options *so, int m, const long *pixels, const reservoir *const *in,
                            const real *u, const real *up, const real *uc, const stochastic_workspace *sw,
                            const reservoir *out)
{
    int i, n = m - 1;
    real scale = so->confidence_scaling ? stochastic_confidence_scale(so->n_picks, n) : 1;
    trace_begin(t, PIXEL_TRACE_STOCHASTIC, stage, frame, pixel, pass, key, m, pixels, in, u, out);
    t->vertex = RNG_VERTEX_SPATIAL_RIS(pass);
    t->mis = -1;
    t->n_picks = so->n_picks;
    t->n_canonical = so->n_canonical_picks;
    memcpy(t->up, up, (size_t)so->n_picks * sizeof *up);
    memcpy(t->uc, uc, (size_t)so->n_canonical_picks * sizeof *uc);
    t->m_c = sw->m_c_used;
    /* the canonical candidate: identity shift (Stochastic MIS Eq. 18) */
    t->d[0].valid = path_sample_is_valid(&t->d[0].in.y) && t->d[0].in.W > 0;
    t->d[0].confidence = t->d[0].in.confidence;
    t->d[0].jacobian = 1;
    t->d[0].target = t->d[0].target_own = t->d[0].in.y.target;
    t->d[0].m = sw->m_c_used;
    t->d[0].w = t->d[0].valid ? gris_resampling_weight(sw->m_c_used, t->d[0].target, t->d[0].in.W, 1) : 0;
    if (t->d[0].valid && same_id(&t->d[0].in.y, &out->y)) t->selected = 0;
    for (i = 1; i < t->kept; ++i) {
        pixel_trace_domain *d = &t->d[i];
        d->confidence = scale * d->in.confidence;
        d->picks = sw->K[i - 1];
        d->P = so->naive_p ? (real)1 / (real)n : sw->P[i - 1]; /* Eq. 17 (as the picks used it) */
        d->valid = d->picks > 0 && sw->jacobian[i - 1] > 0;
        if (!d->valid) continue;
        d->jacobian = sw->jacobian[i - 1];
        d->target = sw->shifted[i - 1].target;
        d->target_own = d->in.y.target / d->jacobian; /* Eq. 10 */
        d->m = sw->m_used[i - 1];
        d->w = gris_resampling_weight(d->m, d->target, d->in.W, d->jacobian); /* Eq. 14 */
        if (same_id(&sw->shifted[i - 1], &out->y) && path_sample_is_valid(&out->y)) t->selected = i;
    }
}
