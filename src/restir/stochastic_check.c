/* The debug build's invariants after one stochastic pairwise MIS step
 * (stochastic_spatial.h, stochastic_check_step). Everything is recomputed from the step's
 * inputs with other code than the step's own: the pick probabilities straight from Eq. 17,
 * the deterministic pairwise weights from mis.c (GRIS Eq. 38), so that a slip in
 * stochastic_mis.c or stochastic_spatial.c cannot agree with itself here. */
#include "restir/restir/stochastic_check.h"

#include "restir/restir/reconnection.h"
#include "restir/restir/stochastic_spatial.h"

#include <math.h>
#include <stdio.h>

/* Relative agreement in the estimator precision (the two sides sum in other orders). */
static int agree(real a, real b)
{
    double tol = sizeof(real) == 4 ? 1e-4 : 1e-9;
    return fabs((double)(a - b)) <= tol * fmax(1.0, fmax(fabs((double)a), fabs((double)b)));
}

static int usable(const reservoir *r) { return path_sample_is_valid(&r->y) && r->W > 0; }

/* The scaled confidences c_0, min(1, Ñ/M) c_i (§4.3) into w->check_conf; returns C. */
static real scaled_confidences(const stochastic_options *so, int m, const reservoir *const *in, real *conf)
{
    int n = m - 1, i;
    real scale = 1, C = 0;
    if (so->confidence_scaling && n > 0 && so->n_picks < n) scale = (real)so->n_picks / (real)n;
    for (i = 0; i < m; ++i) {
        conf[i] = i == 0 ? in[0]->confidence : scale * in[i]->confidence;
        C += conf[i];
    }
    return C;
}

/* The deterministic defensive pairwise weight m_i(y) of mis.c for a non-canonical i, from
 * p̂_c(y) and p̂_{<-i}(y) (the only two entries of the matrix it reads). */
static real pairwise_m(const stochastic_workspace *w, int m, int i, real p_canonical, real q)
{
    mis_input mi;
    real *P = w->check_ptarget;
    P[i] = p_canonical;  /* p̂_{<-0}(y_i): row 0, column i */
    P[i * m + i] = q;    /* p̂_{<-i}(y_i) */
    mi.m = m;
    mi.n_canonical = 1;
    mi.confidence = w->check_conf;
    mi.ptarget = P;
    return mis_pairwise_defensive(&mi, i, i, NULL);
}

static int check_counts(const stochastic_options *so, int n, const stochastic_workspace *w, int canonical_done,
                        char *why, size_t why_size)
{
    int i, k = 0, kc = 0;
    for (i = 0; i < n; ++i) {
        k += w->K[i];
        kc += w->Kc[i];
    }
    if (k != so->n_picks) {
        snprintf(why, why_size, "%d picks made, Ñ = %d (M = %d)", k, so->n_picks, n);
        return 1;
    }
    if (canonical_done && kc != so->n_canonical_picks) {
        snprintf(why, why_size, "%d canonical picks made, Ñ_c = %d (M = %d)", kc, so->n_canonical_picks, n);
        return 1;
    }
    return 0;
}

/* One picked domain i (index i + 1 among the inputs): Eq. 17's P(i) > 0, the P in its
 * weight, m̃_i against mis.c, and the reconnection segment. */
static int check_pick(const restir_context *c, const stochastic_options *so, int m, const path_vertex *const *x1,
                      const reservoir *const *in, stochastic_workspace *w, real a_sum, int i, char *why, size_t n)
{
    const reservoir *r = in[i + 1];
    real a = usable(r) ? r->confidence * r->y.target * r->W : 0, P = a_sum > 0 ? a / a_sum : 0, expect;
    if (!(P > 0)) {
        snprintf(why, n, "domain %d picked %d times with P(i) = %g by Eq. 17", i + 1, w->K[i], (double)P);
        return 1;
    }
    if (!so->naive_p && !agree(w->P_used[i], P)) {
        snprintf(why, n, "domain %d: P(i) in m~_i %.17g, Eq. 17 gives %.17g", i + 1, (double)w->P_used[i], (double)P);
        return 1;
    }
    if (!(w->jacobian[i] > 0)) return 0; /* the shift in failed: no candidate */
    expect = (real)w->K[i] / ((real)so->n_picks * w->P_used[i]) *
             pairwise_m(w, m, i + 1, w->shifted[i].target, r->y.target / w->jacobian[i]);
    if (!(w->m_used[i] >= 0) || !agree(w->m_used[i], expect)) {
        snprintf(why, n, "domain %d: m~_i used %.17g, K/(Ñ P) m_i by mis.c %.17g", i + 1, (double)w->m_used[i],
                 (double)expect);
        return 1;
    }
    if (!rc_segment_visible(c, x1[0], &w->shifted[i])) {
        snprintf(why, n, "domain %d: successful reconnection to x_%d, but the segment is occluded", i + 1,
                 w->shifted[i].rc_k);
        return 1;
    }
    return 0;
}

/* m̃_c = c_c/C + sum K'(i)/(Ñ_c P_c) b_i(Y_c) with b_i = c_i/C - m_i(Y_c) (Eq. 19), P_c = 1/M. */
static int check_canonical(const stochastic_options *so, int m, const reservoir *const *in, stochastic_workspace *w,
                           real C, char *why, size_t n)
{
    int i;
    real expect = w->check_conf[0] / C, p = in[0]->y.target;
    for (i = 0; i + 1 < m; ++i) {
        real b;
        if (!w->Kc[i]) continue;
        b = w->check_conf[i + 1] / C - pairwise_m(w, m, i + 1, p, w->q_back[i]);
        expect += (real)w->Kc[i] * (real)(m - 1) / (real)so->n_canonical_picks * b;
    }
    if (!(w->m_c_used >= 0) || !agree(w->m_c_used, expect)) {
        snprintf(why, n, "m~_c used %.17g, Eqs. 18-19 by mis.c %.17g", (double)w->m_c_used, (double)expect);
        return 1;
    }
    return 0;
}

int stochastic_check_step(const restir_context *c, const stochastic_options *so, int m, const path_vertex *const *x1,
                          const reservoir *const *in, const reservoir *out, stochastic_workspace *w, char *why,
                          size_t why_size)
{
    int n = m - 1, i, canonical_done;
    real C, a_sum = 0;
    for (i = 0; i < m; ++i)
        if (!(in[i]->confidence >= 0)) {
            snprintf(why, why_size, "input %d has confidence %g < 0", i, (double)in[i]->confidence);
            return 1;
        }
    C = scaled_confidences(so, m, in, w->check_conf);
    if (!(out->W >= 0) || !isfinite((double)out->W)) {
        snprintf(why, why_size, "output W = %g is not finite and >= 0", (double)out->W);
        return 1;
    }
    if (!agree(out->confidence, C)) {
        snprintf(why, why_size, "output confidence %.17g, c_c + sum min(1, Ñ/M) c_i = %.17g", (double)out->confidence,
                 (double)C);
        return 1;
    }
    if (n == 0) return 0;
    canonical_done = usable(in[0]) && C > 0;
    for (i = 1; i < m; ++i) a_sum += usable(in[i]) ? in[i]->confidence * in[i]->y.target * in[i]->W : 0;
    if (a_sum > 0 && check_counts(so, n, w, canonical_done, why, why_size)) return 1;
    for (i = 0; i < n; ++i)
        if (w->K[i] && check_pick(c, so, m, x1, in, w, a_sum, i, why, why_size)) return 1;
    return canonical_done && check_canonical(so, m, in, w, C, why, why_size);
}
