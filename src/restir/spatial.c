/* One spatial GRIS step (include/restir/restir/spatial.h). */
#include "restir/restir/spatial.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/invariant.h"

int spatial_workspace_alloc(spatial_workspace *w, int max_domains, rerror *e)
{
    size_t m = (size_t)max_domains;
    memset(w, 0, sizeof *w);
    if (max_domains < 1) return rerror_set(e, "spatial: %d domains", max_domains);
    w->max_domains = max_domains;
    w->ptarget = rcalloc(m * m, sizeof *w->ptarget, e);
    w->confidence = rcalloc(m, sizeof *w->confidence, e);
    w->jacobian = rcalloc(m, sizeof *w->jacobian, e);
    w->shifted = rcalloc(m, sizeof *w->shifted, e);
    w->cand = rcalloc(m, sizeof *w->cand, e);
    w->valid = rcalloc(m, 1, e);
    w->mis = rcalloc(m, sizeof *w->mis, e);
    w->check_confidence = rcalloc(m, sizeof *w->check_confidence, e);
    if (!w->ptarget || !w->confidence || !w->jacobian || !w->shifted || !w->cand || !w->valid || !w->mis || !w->check_confidence) {
        spatial_workspace_free(w);
        return -1;
    }
    return 0;
}

void spatial_workspace_free(spatial_workspace *w)
{
    free(w->ptarget);
    free(w->confidence);
    free(w->jacobian);
    free(w->shifted);
    free(w->cand);
    free(w->valid);
    free(w->mis);
    free(w->check_confidence);
    memset(w, 0, sizeof *w);
}

/* One counted shift of x to the pixel of `to` into *y with |dT/dx| in *jacobian; the
 * jacobian ablation drops |dT/dx| wherever it enters (weights and MIS). Returns the
 * shift's outcome (SHIFT_OK or why it failed), counted in st. */
enum shift_failure spatial_counted_shift(const restir_context *c, const path_vertex *to, const path_sample *x,
                                         path_sample *y, real *jacobian, spatial_stats *st)
{
    enum shift_failure why = shift_path(c, to, x, y, jacobian, NULL);
    st->shifts++;
    st->outcome[why]++;
    if (c->ablation == RESTIR_ABLATE_JACOBIAN && *jacobian > 0) *jacobian = 1;
    return why;
}

/* rf's step before a shift from domain `from` to `to`, counted like a failed shift when it
 * fails; *x is then the sample to shift. */
static int refreshed(const domain_refresh *rf, int from, int to, const path_sample *y, path_sample *tmp,
                     const path_sample **x, spatial_stats *st)
{
    enum shift_failure why;
    *x = y;
    if (!rf) return 1;
    why = rf->fn(rf->user, from, to, y, tmp);
    if (why == SHIFT_OK) {
        *x = tmp;
        return 1;
    }
    st->shifts++;
    st->outcome[why]++;
    return 0;
}

/* p̂_{<-i}(y) = p̂_i(T_i^{-1}(y)) |dT_i^{-1}/dy| (GRIS Eq. 35): y shifted out into domain i. */
static real ptarget_from(const restir_context *c, const domain_refresh *rf, int i, const path_vertex *xi,
                         const path_sample *y, spatial_stats *st)
{
    path_sample back, tmp;
    const path_sample *x;
    real jacobian;
    st->mis_shifts++;
    if (!refreshed(rf, 0, i, y, &tmp, &x, st)) return 0;
    if (spatial_counted_shift(c, xi, x, &back, &jacobian, st) != SHIFT_OK) return 0;
    return back.target * jacobian;
}

/* Whether family f reads p̂_{<-i}(y_j) for i >= 1, i != j (mis.h: Talbot reads every
 * entry; pairwise reads only the canonical column; constant none). */
static int needs_entry(mis_family f, int i, int j)
{
    (void)i;
    if (f == MIS_TALBOT) return 1;
    if (f == MIS_PAIRWISE_UNIFORM || f == MIS_PAIRWISE_DEFENSIVE || f == MIS_PAIRWISE_DEFENSIVE_FALCOR) return j == 0;
    return 0;
}

/* Candidates shifted in: y_j = T_j(X_j), J_j, and the matrix's row 0 and diagonal; with
 * pre (the pair step) the neighbours' shifts are read instead of made. */
static void shift_in(const restir_context *c, const domain_refresh *rf, const pair_shifts *pre, int m,
                     const path_vertex *const *x1, const reservoir *const *in, spatial_workspace *w,
                     spatial_stats *st)
{
    int j;
    for (j = 0; j < m; ++j) {
        const reservoir *r = in[j];
        real *P = w->ptarget;
        path_sample tmp;
        const path_sample *x = &r->y;
        w->confidence[j] = r->confidence;
        w->valid[j] = path_sample_is_valid(&r->y) && r->W > 0;
        w->jacobian[j] = 0;
        w->cand[j] = &w->shifted[j];
        P[j] = 0;
        if (j > 0) P[j * m + j] = 0;
        if (!w->valid[j]) continue;
        if (j == 0) {
            w->cand[0] = &r->y; /* canonical: identity shift */
            w->jacobian[0] = 1;
        } else if (pre) {
            if (!pre->forward[j]->ok) {
                w->valid[j] = 0;
                continue;
            }
            w->cand[j] = &pre->forward[j]->y; /* read in place: no copy */
            w->jacobian[j] = pre->forward[j]->jacobian;
            P[j * m + j] = r->y.target / w->jacobian[j];
        } else if (!refreshed(rf, j, 0, &r->y, &tmp, &x, st) ||
                   spatial_counted_shift(c, x1[0], x, &w->shifted[j], &w->jacobian[j], st) != SHIFT_OK) {
            w->valid[j] = 0;
            continue;
        } else {
            P[j * m + j] = r->y.target / w->jacobian[j]; /* p̂_j(X_j) / |dT_j/dX_j| */
        }
        P[j] = w->cand[j]->target; /* p̂(y_j) */
    }
}

/* p̂_{<-i}(y_j) for the entries family `mis` reads beyond row 0 and the diagonal. */
static void mis_entries(const restir_context *away, const domain_refresh *rf, const pair_shifts *pre,
                        mis_family mis, int m, const path_vertex *const *x1, spatial_workspace *w, spatial_stats *st)
{
    int i, j;
    for (j = 0; j < m; ++j) {
        if (!w->valid[j]) continue;
        for (i = 1; i < m; ++i) {
            real *P = &w->ptarget[i * m + j];
            if (i == j) continue;
            if (!needs_entry(mis, i, j))
                *P = 0;
            else if (pre && j == 0) /* the pair step: X_0 was shifted into i by the pre-pass */
                *P = pre->reverse[i]->ok && !pre->drop_reverse ? pre->reverse[i]->y.target * pre->reverse[i]->jacobian : 0;
            else
                *P = ptarget_from(away, rf, i, x1[i], w->cand[j], st);
        }
    }
}

void spatial_resample(const restir_context *c, mis_family mis, int m, const path_vertex *const *x1,
                      const reservoir *const *in, const real *u, reservoir *out, spatial_workspace *w,
                      spatial_stats *st)
{
    gris_resample(c, c, NULL, mis, m, x1, in, u, out, w, st);
}

/* The GRIS step once the candidates are in (shift_in) and the MIS matrix is filled. */
static void select_candidate(const restir_context *c, mis_family mis, int m, const path_vertex *const *x1,
                             const reservoir *const *in, const real *u, reservoir *out, spatial_workspace *w,
                             spatial_stats *st)
{
    mis_input mi;
    int j;
    long unused = 0;
    int chosen = -1;
    mi.m = m;
    mi.n_canonical = 1;
    mi.confidence = w->confidence;
    mi.ptarget = w->ptarget;
    for (j = 0; j < m; ++j) {
        real mj, wj;
        w->mis[j] = 0;
        if (w->valid[j]) {
            /* m_j(y_j): GRIS Eqs. 36-38 / Stochastic MIS Eqs. 9-12 (mis.c) */
            mj = mis_weight(mis, &mi, j, j, &unused);
            w->mis[j] = mj;
            wj = gris_resampling_weight(mj, w->ptarget[j], in[j]->W, w->jacobian[j]); /* GRIS Eq. 19 */
            if (reservoir_stream(out, w->cand[j], wj, u[j])) chosen = j;
        }
        reservoir_add_confidence(out, w->confidence[j]); /* GRIS §6.2: c = sum of the inputs */
    }
    if (chosen > 0) st->selected_neighbor++;
    reservoir_finalize(out); /* GRIS Eq. 22 */
    st->invalid_weights += out->n_invalid;
    if (RESTIR_DEBUG_ENABLED) {
        char why[512];
        if (spatial_check_step(c, mis, m, x1, in, out, w, why, sizeof why)) restir_invariant_failed(__FILE__, __LINE__, why);
    }
}

/* One GRIS step: shift the candidates in, fill the "p̂ from i" entries of the MIS weights
 * (GRIS Eq. 35; Stochastic MIS Eq. 10), then select by the resampling weights of GRIS
 * Eq. 19 with the MIS weights of GRIS Eqs. 36-38 (Stochastic MIS Eqs. 9-12) and finalise W
 * by GRIS Eq. 22 (select_candidate). */
void gris_resample(const restir_context *c, const restir_context *away, const domain_refresh *rf, mis_family mis,
                   int m, const path_vertex *const *x1, const reservoir *const *in, const real *u, reservoir *out,
                   spatial_workspace *w, spatial_stats *st)
{
    reservoir_init(out);
    st->pixels++;
    st->domains += (uint64_t)m;
    shift_in(c, rf, NULL, m, x1, in, w, st);
    mis_entries(away, rf, NULL, mis, m, x1, w, st);
    select_candidate(c, mis, m, x1, in, u, out, w, st);
}

void spatial_resample_preshifted(const restir_context *c, mis_family mis, int m, const path_vertex *const *x1,
                                 const reservoir *const *in, const pair_shifts *pre, const real *u, reservoir *out,
                                 spatial_workspace *w, spatial_stats *st)
{
    reservoir_init(out);
    st->pixels++;
    st->domains += (uint64_t)m;
    shift_in(c, NULL, pre, m, x1, in, w, st);
    mis_entries(c, NULL, pre, mis, m, x1, w, st);
    select_candidate(c, mis, m, x1, in, u, out, w, st);
}

/* ---- invariants (spatial.h, spatial_check_step) -------------------------------------- */

/* Agreement of two weights computed in the estimator precision by different sums. */
static int weights_agree(real a, real b)
{
    real tol = sizeof(real) == 4 ? (real)1e-4 : (real)1e-9;
    return fabs((double)(a - b)) <= (double)tol;
}

/* Sum_i m_i(y_j) = 1 over the true input confidences, and the used m_j(y_j) equals them. */
static int check_mis_column(mis_family mis, int m, const reservoir *const *in, const spatial_workspace *w, int j,
                            real *conf, char *why, size_t n)
{
    mis_input mi;
    real sum = 0, mj = 0;
    int i;
    for (i = 0; i < m; ++i) conf[i] = in[i]->confidence;
    mi.m = m;
    mi.n_canonical = 1;
    mi.confidence = conf;
    mi.ptarget = w->ptarget;
    for (i = 0; i < m; ++i) {
        real mij = mis_weight(mis, &mi, i, j, NULL);
        if (!(mij >= 0)) {
            snprintf(why, n, "MIS weight m_%d(y_%d) = %g < 0 (%s, M = %d)", i, j, (double)mij, mis_family_name(mis), m);
            return 1;
        }
        sum += mij;
        if (i == j) mj = mij;
    }
    if (!weights_agree(sum, 1)) {
        snprintf(why, n, "sum_i m_i(y_%d) = %.17g, not 1 (%s, M = %d)", j, (double)sum, mis_family_name(mis), m);
        return 1;
    }
    if (!weights_agree(w->mis[j], mj)) {
        snprintf(why, n, "m_%d(y_%d) used %.17g, over the input confidences %.17g (%s, M = %d)", j, j, (double)w->mis[j],
                 (double)mj, mis_family_name(mis), m);
        return 1;
    }
    return 0;
}

int spatial_check_step(const restir_context *c, mis_family mis, int m, const path_vertex *const *x1,
                       const reservoir *const *in, const reservoir *out, spatial_workspace *w, char *why,
                       size_t why_size)
{
    real csum = 0;
    int j;
    for (j = 0; j < m; ++j) {
        if (!(in[j]->confidence >= 0)) {
            snprintf(why, why_size, "input %d has confidence %g < 0", j, (double)in[j]->confidence);
            return 1;
        }
        csum += in[j]->confidence;
    }
    if (!(out->W >= 0) || !isfinite((double)out->W)) {
        snprintf(why, why_size, "output W = %g is not finite and >= 0", (double)out->W);
        return 1;
    }
    if (!(out->confidence >= 0) || out->confidence != csum) {
        snprintf(why, why_size, "output confidence %.17g, the %d inputs sum to %.17g", (double)out->confidence, m,
                 (double)csum);
        return 1;
    }
    for (j = 0; j < m; ++j) {
        if (!w->valid[j]) continue;
        if (check_mis_column(mis, m, in, w, j, w->check_confidence, why, why_size)) return 1;
        if (j > 0 && !rc_segment_visible(c, x1[0], w->cand[j])) {
            snprintf(why, why_size, "candidate %d: successful reconnection to x_%d, but the segment is occluded", j,
                     w->cand[j]->rc_k);
            return 1;
        }
    }
    return 0;
}

void spatial_stats_add(spatial_stats *acc, const spatial_stats *add)
{
    int i;
    acc->pixels += add->pixels;
    acc->domains += add->domains;
    acc->shifts += add->shifts;
    acc->mis_shifts += add->mis_shifts;
    acc->selected_neighbor += add->selected_neighbor;
    acc->invalid_weights += add->invalid_weights;
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i) acc->outcome[i] += add->outcome[i];
}
