/* One GRIS step with stochastic pairwise MIS (include/restir/restir/stochastic_spatial.h;
 * docs/stochastic-mis.md). */
#include "restir/restir/stochastic_spatial.h"

#include "restir/core/invariant.h"
#include "restir/restir/stochastic_check.h"
#include "restir/restir/stochastic_picks_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int stochastic_workspace_alloc(stochastic_workspace *w, int max_domains, rerror *e)
{
    size_t m = (size_t)(max_domains > 1 ? max_domains : 1);
    memset(w, 0, sizeof *w);
    w->max_domains = (int)m;
    w->a = rcalloc(m, sizeof *w->a, e);
    w->P = rcalloc(m, sizeof *w->P, e);
    w->K = rcalloc(m, sizeof *w->K, e);
    w->Kc = rcalloc(m, sizeof *w->Kc, e);
    w->shifted = rcalloc(m, sizeof *w->shifted, e);
    w->jacobian = rcalloc(m, sizeof *w->jacobian, e);
    w->P_used = rcalloc(m, sizeof *w->P_used, e);
    w->m_used = rcalloc(m, sizeof *w->m_used, e);
    w->q_back = rcalloc(m, sizeof *w->q_back, e);
    w->check_conf = rcalloc(m, sizeof *w->check_conf, e);
    w->check_ptarget = rcalloc(m * m, sizeof *w->check_ptarget, e);
    if (!w->a || !w->P || !w->K || !w->Kc || !w->shifted || !w->jacobian || !w->P_used || !w->m_used || !w->q_back ||
        !w->check_conf || !w->check_ptarget) {
        stochastic_workspace_free(w);
        return -1;
    }
    return 0;
}

void stochastic_workspace_free(stochastic_workspace *w)
{
    free(w->a);
    free(w->P);
    free(w->K);
    free(w->Kc);
    free(w->shifted);
    free(w->jacobian);
    free(w->P_used);
    free(w->m_used);
    free(w->q_back);
    free(w->check_conf);
    free(w->check_ptarget);
    memset(w, 0, sizeof *w);
}

static int usable(const reservoir *r) { return path_sample_is_valid(&r->y) && r->W > 0; }

/* Stochastic MIS Eq. 17 over the n = m - 1 non-canonical domains (index i - 1), or the ablation's
 * uniform choice among the non-zero samples. */
static void selection(const stochastic_options *so, int n, const reservoir *const *in, stochastic_workspace *w,
                      spatial_stats *st)
{
    int i;
    for (i = 0; i < n; ++i) {
        const reservoir *r = in[i + 1];
        real a = usable(r) ? r->confidence * r->y.target * r->W : 0; /* c_i p̂(X_i) W_i */
        /* stochastic_selection_p gives a NaN/Inf (overflowing) a_i probability 0: counted */
        if (!isfinite((double)a)) st->invalid_weights++;
        w->a[i] = so->naive_p ? (a > 0 ? 1 : 0) : a;
    }
    stochastic_selection_p(w->a, n, w->P);
}

/* m̃_c (Stochastic MIS Eqs. 18-19): Ñ_c uniform picks among the n non-canonical domains, one shift of
 * the canonical sample out into each distinct pick. */
static real canonical_weight(const restir_context *c, const stochastic_options *so, int n,
                             const path_vertex *const *x1, const reservoir *const *in, const real *uc, real c_c,
                             real c_S, real scale, stochastic_workspace *w, spatial_stats *st)
{
    real C = c_c + c_S, m_c, p = in[0]->y.target;
    int i;
    if (n == 0) return 1;
    if (!(C > 0)) return 1; /* no confidence anywhere: all weight to the canonical side */
    m_c = c_c / C;          /* the defensive share, exact */
    stochastic_canonical_picks(n, so->n_canonical_picks, uc, w->Kc);
    for (i = 0; i < n; ++i) {
        path_sample back;
        const path_vertex *xi;
        real jac, q = 0, c_i = scale * in[i + 1]->confidence;
        if (!w->Kc[i]) continue;
        st->mis_shifts++;
        xi = w->vertex ? w->vertex(w->vertex_user, i + 1) : x1[i + 1];
        if (spatial_counted_shift(c, xi, &in[0]->y, &back, &jac, st) == SHIFT_OK) q = back.target * jac; /* Eq. 10 */
        w->q_back[i] = q;
        m_c += stochastic_canonical_term(w->Kc[i], so->n_canonical_picks, n, c_c, c_S, c_i, q, p); /* Eq. 18 */
    }
    return w->m_c_used = m_c;
}

void stochastic_pairwise_resample(const restir_context *c, const stochastic_options *so, int m,
                                  const path_vertex *const *x1, const reservoir *const *in, const real *u,
                                  const real *up, const real *uc, reservoir *out, stochastic_workspace *w,
                                  spatial_stats *st)
{
    int n = m - 1, i, chosen = -1, distinct;
    real scale = so->confidence_scaling ? stochastic_confidence_scale(so->n_picks, n) : 1;
    real c_c = in[0]->confidence, c_S = 0;
    spatial_stats before;
    if (RESTIR_DEBUG_ENABLED) before = *st;
    reservoir_init(out);
    st->pixels++;
    st->domains += (uint64_t)m;
    if (n > 0) {
        memset(w->jacobian, 0, (size_t)n * sizeof *w->jacobian);
        memset(w->m_used, 0, (size_t)n * sizeof *w->m_used);
        memset(w->q_back, 0, (size_t)n * sizeof *w->q_back);
        memset(w->P_used, 0, (size_t)n * sizeof *w->P_used);
    }
    w->m_c_used = 0;
    for (i = 1; i < m; ++i) c_S += scale * in[i]->confidence; /* Eq. 12 over the scaled c_i */
    /* the canonical candidate: identity shift, J = 1 */
    if (usable(in[0])) {
        real m_c = canonical_weight(c, so, n, x1, in, uc, c_c, c_S, scale, w, st);
        if (reservoir_stream(out, &in[0]->y, gris_resampling_weight(m_c, in[0]->y.target, in[0]->W, 1), u[0]))
            chosen = 0;
    }
    /* the Ñ picks (Stochastic MIS Eq. 16): only these are shifted in */
    if (n > 0) {
        selection(so, n, in, w, st);
        distinct = stochastic_pick(w->P, n, so->n_picks, up, w->K);
        (void)distinct;
        for (i = 0; i < n; ++i) {
            const reservoir *r = in[i + 1];
            path_sample *y = &w->shifted[i];
            real jac, q, mi, P = so->naive_p ? (real)1 / (real)n : w->P[i];
            if (!w->K[i]) continue;
            w->P_used[i] = P;
            if (spatial_counted_shift(c, x1[0], &r->y, y, &jac, st) != SHIFT_OK) continue;
            q = r->y.target / jac; /* p̂_{<-i}(Y_i) = p̂_i(X_i) / |dT_i/dX_i| (Eq. 10) */
            mi = stochastic_mis_weight(w->K[i], so->n_picks, P,
                                       stochastic_pairwise_m(c_c, c_S, scale * r->confidence, q, y->target));
            w->jacobian[i] = jac;
            w->m_used[i] = mi;
            /* Stochastic MIS Eq. 14 */
            if (reservoir_stream(out, y, gris_resampling_weight(mi, y->target, r->W, jac), u[i + 1])) chosen = i + 1;
        }
    }
    reservoir_add_confidence(out, c_c + c_S);
    if (chosen > 0) st->selected_neighbor++;
    reservoir_finalize(out); /* GRIS Eq. 22 */
    if (RESTIR_DEBUG_ENABLED) {
        char why[512];
        if (stochastic_check_step(c, so, m, x1, in, out, w, why, sizeof why) ||
            stochastic_check_pick_counts(so, m, in, w, &before, st, why, sizeof why))
            restir_invariant_failed(__FILE__, __LINE__, why);
    }
    st->invalid_weights += out->n_invalid;
}

void stochastic_options_default(stochastic_options *so)
{
    so->n_picks = 1;
    so->n_canonical_picks = 1;
    so->confidence_scaling = 1;
    so->naive_p = 0;
}

int stochastic_options_validate(const stochastic_options *so, rerror *e)
{
    if (so->n_picks < 1 || so->n_picks > STOCHASTIC_MAX_PICKS)
        return rerror_set(e, "stochastic: %d picks (N~ must be 1..%d)", so->n_picks, STOCHASTIC_MAX_PICKS);
    if (so->n_canonical_picks < 1 || so->n_canonical_picks > STOCHASTIC_MAX_PICKS)
        return rerror_set(e, "stochastic: %d canonical picks (N~_c must be 1..%d)", so->n_canonical_picks,
                          STOCHASTIC_MAX_PICKS);
    return 0;
}
