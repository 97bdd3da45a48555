/* Golden vectors of whole steps through the real code path (vectors_step.h). Every case
 * builds its reservoirs with initial_sample_pixel on the shift vectors' scene (cornell at
 * 24 x 18, frame 0, default ReSTIR options) and calls the step the pipeline calls; the
 * outputs are the step's own results and the workspace entries it used. */
#include "vectors_step.h"

#include <math.h>
#include <string.h>
#include "restir/frame/options.h"
#include "restir/restir/initial.h"
#include "restir/restir/mutate.h"
#include "restir/restir/path_replay.h"
#include "restir/restir/stochastic_spatial.h"
#include "restir/restir/temporal.h"

#define STEP_MAX_NEIGHBORS 8

typedef struct {
    const scene *s;
    const light_set *lights;
    const gbuffer *g;
    int w, h;
} step_scene;

static int load(step_scene *sc) { return vectors_scene(&sc->s, &sc->lights, &sc->g, &sc->w, &sc->h); }

static int pixel_ok(const step_scene *sc, double x, double y)
{
    return x >= 0 && y >= 0 && x < sc->w && y < sc->h && x == (int)x && y == (int)y;
}

/* The initial reservoir of pixel (x, y) (seed, frame 0) and its primary vertex; 0 if the pixel
 * has no primary hit. */
static int initial_at(const step_scene *sc, const restir_context *c, const restir_options *o, uint32_t seed, int x,
                      int y, path_vertex *x1, reservoir *r)
{
    initial_options io;
    initial_stats st;
    long p = (long)y * sc->w + x;
    restir_initial_options_for(&io, o);
    memset(&st, 0, sizeof st);
    reservoir_init(r);
    if (!gbuffer_primary_vertex(sc->s, sc->g, p, x1)) return 0;
    initial_sample_pixel(c, &io, x1, seed, (uint32_t)p, 0, r, &st);
    return 1;
}

/* valid, d, k, p̂, W, c of a reservoir (6 outputs) */
static int out_reservoir(double *out, const reservoir *r)
{
    out[0] = path_sample_is_valid(&r->y);
    out[1] = r->y.length;
    out[2] = r->y.rc_k;
    out[3] = (double)r->y.target;
    out[4] = (double)r->W;
    out[5] = (double)r->confidence;
    return 6;
}

/* ---- the temporal step (GRIS §6.2-6.4, App. B; temporal.h) ---------------------------- */

/* mis (0..3), mcap, seed_t, seed_{t-1}, x, y (frame t), qx, qy (frame t-1; -1: no history),
 * c_t, c_{t-1}, u_0, u_1 -> the output reservoir (valid, d, k, p̂, W, c), from_history,
 * capped, the 2 x 2 matrix p̂_{<-i}(y_j) (row i), m_0(y_0), m_1(y_1), J_1. Frame t-1 is a
 * restir_context of its own on the same scene (a still camera): the MIS shift of the
 * current candidate back into q runs there (GRIS Eq. 35), the history's diagonal entry is
 * p̂_{t-1}(X_1) / J_1. */
int vectors_eval_temporal_step(const double *in, int n_in, double *out)
{
    step_scene sc;
    restir_options o;
    restir_context cur, prev;
    path_vertex x1c, x1p;
    reservoir rc, rp, res;
    spatial_workspace w;
    temporal_stats st;
    real u[2];
    int mis = (int)in[0], history, i, n = 0;
    rerror e;
    if (n_in != 12 || load(&sc) || mis < 0 || mis > 3 || !pixel_ok(&sc, in[4], in[5])) return -1;
    history = in[6] >= 0;
    if (history && !pixel_ok(&sc, in[6], in[7])) return -1;
    restir_options_default(&o);
    restir_context_for(&cur, sc.s, sc.lights, &o);
    restir_context_for(&prev, sc.s, sc.lights, &o);
    if (!initial_at(&sc, &cur, &o, (uint32_t)in[2], (int)in[4], (int)in[5], &x1c, &rc)) return -1;
    rc.confidence = (real)in[8];
    if (history) {
        if (!initial_at(&sc, &prev, &o, (uint32_t)in[3], (int)in[6], (int)in[7], &x1p, &rp)) return -1;
        rp.confidence = (real)in[9];
    }
    u[0] = (real)in[10];
    u[1] = (real)in[11];
    if (spatial_workspace_alloc(&w, 2, &e)) return -1;
    memset(&st, 0, sizeof st);
    temporal_resample(&cur, &prev, NULL, (mis_family)mis, &x1c, history ? &x1p : NULL, &rc, history ? &rp : NULL,
                      (real)in[1], u, &res, &w, &st);
    n = out_reservoir(out, &res);
    out[n++] = (double)st.step.selected_neighbor;
    out[n++] = (double)st.capped;
    for (i = 0; i < 4; ++i) out[n++] = history ? (double)w.ptarget[i] : 0;
    out[n++] = history ? (double)w.mis[0] : 0;
    out[n++] = history ? (double)w.mis[1] : 0;
    out[n++] = history ? (double)w.jacobian[1] : 0;
    spatial_workspace_free(&w);
    return n;
}

void vectors_cases_temporal(vectors_emit_fn emit, void *g)
{
    static const struct {
        double mis, mcap, seed_t, seed_p, x, y, qx, qy, c_t, c_p, u0, u1;
        const char *label;
    } cases[] = {
        {1, 20, 1, 2, 12, 9, 13, 9, 1, 5, 0.5, 0.5, "Talbot, history one pixel to the left, not capped"},
        {1, 20, 3, 4, 6, 12, 8, 11, 1, 19, 0.5, 0.25, "Talbot, history two pixels away"},
        {1, 2, 1, 2, 12, 9, 13, 9, 1, 5, 0.5, 0.5, "Talbot, C = 2 caps the history's 5 to 2 (input, not output)"},
        {1, 2, 5, 6, 16, 5, 15, 6, 2, 30, 0.9, 0.1, "Talbot, C = 2, c_t = 2: history 30 capped to 4"},
        {1, INFINITY, 1, 2, 12, 9, 13, 9, 1, 50, 0.5, 0.5, "Talbot, no cap (C = inf)"},
        {3, 20, 1, 2, 12, 9, 13, 9, 1, 5, 0.5, 0.5, "pairwise defensive"},
        {3, 2, 7, 8, 4, 4, 5, 5, 1, 9, 0.3, 0.7, "pairwise defensive, capped"},
        {2, 20, 9, 10, 20, 14, 19, 14, 1, 5, 0.5, 0.5, "pairwise uniform"},
        {0, 20, 9, 10, 20, 14, 19, 14, 1, 5, 0.5, 0.5, "constant"},
        {1, 20, 11, 11, 12, 9, 12, 9, 1, 5, 0.5, 0.5, "Talbot, same pixel, same seed (J = 1, one sample twice)"},
        {1, 20, 12, 13, 2, 16, 3, 16, 1, 5, 0.999, 0.001, "Talbot, extreme selection numbers"},
        {1, 20, 1, 2, 12, 9, -1, -1, 1, 0, 0.5, 0.5, "no history (disoccluded): the current reservoir"},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        double v[12] = {cases[i].mis, cases[i].mcap, cases[i].seed_t, cases[i].seed_p, cases[i].x, cases[i].y,
                        cases[i].qx, cases[i].qy, cases[i].c_t, cases[i].c_p, cases[i].u0, cases[i].u1};
        emit(g, "temporal_resample", "GRIS 35;GRIS 36;GRIS 38;GRIS 19;GRIS 22", cases[i].label, v, 12);
    }
}

/* ---- mutations (Mutations Algorithm 3, Eqs. 14, 16, 19, 20, 23; mutate.h) ------------- */

/* strategy (0 rv, 1 pp, 2 fp), seed, x, y, stage (1, 2, 4), iterations -> before: valid, d,
 * k, p̂, W, c; after: valid, d, k, p̂, W, c, F rgb, n_pss; proposals, accepted, rejected_mh,
 * skipped (mutate_reservoir: the pipeline's per-pixel call, numbers from RNG_MUTATE at the
 * pixel's key initial_pixel_key(seed, frame 0, pixel)). */
int vectors_eval_mutate_chain(const double *in, int n_in, double *out)
{
    step_scene sc;
    restir_options o;
    restir_context c;
    initial_options io;
    path_vertex x1;
    reservoir r;
    mutate_stats st;
    real home[PATH_MAX_PSS];
    int strategy = (int)in[0], stage = (int)in[4], it = (int)in[5], n;
    long p;
    if (n_in != 6 || load(&sc) || strategy < 0 || strategy >= MUTATE_STRATEGY_COUNT || !pixel_ok(&sc, in[2], in[3]) ||
        (stage != 1 && stage != 2 && stage != 4) || it < 1 || it > 64)
        return -1;
    restir_options_default(&o);
    o.mutation.strategy = (enum mutate_strategy)strategy;
    o.mutation.count = it;
    restir_context_for(&c, sc.s, sc.lights, &o);
    restir_initial_options_for(&io, &o);
    if (!initial_at(&sc, &c, &o, (uint32_t)in[1], (int)in[2], (int)in[3], &x1, &r)) return -1;
    p = (long)in[3] * sc.w + (long)in[2];
    n = out_reservoir(out, &r);
    memset(&st, 0, sizeof st);
    memset(home, 0, sizeof home);
    mutate_reservoir(&c, &x1, initial_pixel_key(&io, (uint32_t)in[1], 0, (uint32_t)p), stage, strategy, it, &r, home,
                     &st);
    n += out_reservoir(out + n, &r);
    out[n++] = (double)r.y.F.r;
    out[n++] = (double)r.y.F.g;
    out[n++] = (double)r.y.F.b;
    out[n++] = r.y.n_pss;
    out[n++] = (double)st.proposals;
    out[n++] = (double)st.accepted;
    out[n++] = (double)st.rejected_mh;
    out[n++] = (double)st.skipped;
    return n;
}

/* strategy, seed, x, y, xi (every perturbation number), xi_lobe[2] (proposal), xi_lobe[2]
 * (current) -> explicit (0, or enum mutate_reason + 1), A(y) terms p(w_{k-1}, w_k),
 * G(x_k -> x_{k+1}), p(w_k, w_{k+1}) (mutate_rv_terms on the replayed current path; 1 where
 * absent), result (-1 ok, else enum mutate_reject), T(z->y)/T(y->z) (Eq. 20 for rv/pp, 1
 * for fp), p̂(z), z's d, k. The current sample is the pixel's initial sample. */
int vectors_eval_mutate_propose(const double *in, int n_in, double *out)
{
    step_scene sc;
    restir_options o;
    restir_context c;
    path_vertex x1;
    reservoir r;
    path_sample u, z;
    path_trunk t;
    path_end end;
    real un[PATH_MAX_PSS], zn[PATH_MAX_PSS], xi[PATH_MAX_PSS], xl[2], xc[2], terms[3] = {1, 1, 1}, ratio = 0;
    int strategy = (int)in[0], why, res = -2, i;
    if (n_in != 9 || load(&sc) || strategy < 0 || strategy >= MUTATE_STRATEGY_COUNT || !pixel_ok(&sc, in[2], in[3]))
        return -1;
    restir_options_default(&o);
    restir_context_for(&c, sc.s, sc.lights, &o);
    if (!initial_at(&sc, &c, &o, (uint32_t)in[1], (int)in[2], (int)in[3], &x1, &r) || !path_sample_is_valid(&r.y))
        return -1;
    for (i = 0; i < PATH_MAX_PSS; ++i) xi[i] = (real)in[4];
    xl[0] = (real)in[5];
    xl[1] = (real)in[6];
    xc[0] = (real)in[7];
    xc[1] = (real)in[8];
    u.pss = un;
    z.pss = zn;
    path_sample_clear(&z);
    z.pss = zn;
    why = mutate_explicit(&c, &x1, &r.y, xc, &u);
    if (!why && u.rc_k != PATH_RC_NONE && path_replay(&t, &c, &x1, &u, &end) == SHIFT_OK)
        mutate_rv_terms(&t, u.rc_k, mutate_bsdf_vertices(&u), terms);
    if (!why) res = mutate_propose(&c, &x1, &u, strategy, xi, xl, &z, &ratio);
    out[0] = why;
    for (i = 0; i < 3; ++i) out[1 + i] = (double)terms[i];
    out[4] = res;
    out[5] = res == -1 ? (double)ratio : 0;
    out[6] = res == -1 ? (double)z.target : 0;
    out[7] = res == -1 ? z.length : 0;
    out[8] = res == -1 ? z.rc_k : 0;
    return 9;
}

void vectors_cases_mutate_step(vectors_emit_fn emit, void *g)
{
    /* pixels whose initial sample (seed) has a reconnection vertex with a BSDF-sampled
     * x_{k+1} (Eq. 20's three terms), direct light (k = d = 2), longer chains, an empty pixel */
    static const double chain[][6] = {
        {0, 1, 16, 1, 2, 8},  {0, 4, 4, 13, 2, 16}, {0, 2, 19, 1, 1, 8},  {0, 3, 16, 16, 4, 8},
        {0, 1, 12, 9, 2, 8},  {0, 2, 6, 12, 2, 8},  {1, 2, 13, 4, 2, 16}, {1, 1, 7, 13, 1, 8},
        {1, 5, 9, 6, 2, 16},  {2, 1, 16, 1, 2, 8},  {2, 4, 13, 7, 4, 16}, {2, 8, 5, 3, 2, 8},
    };
    static const char *const sname[] = {"rv", "pp", "fp"};
    static const double prop[][9] = {
        {0, 1, 4, 1, 0.25, 0.5, 0.5, 0.5, 0.5},   {0, 1, 16, 1, 0.25, 0.5, 0.5, 0.5, 0.5},
        {0, 1, 16, 1, 0.75, 0.3, 0.7, 0.2, 0.8},  {0, 1, 16, 7, 0.6, 0.5, 0.5, 0.5, 0.5},
        {0, 2, 19, 1, 0.3, 0.5, 0.5, 0.5, 0.5},   {0, 3, 16, 16, 0.3, 0.5, 0.5, 0.5, 0.5},
        {0, 4, 4, 13, 0.45, 0.5, 0.5, 0.5, 0.5},  {0, 1, 12, 9, 0.25, 0.5, 0.5, 0.5, 0.5},
        {1, 2, 13, 4, 0.25, 0.5, 0.5, 0.5, 0.5},  {1, 1, 7, 13, 0.9, 0.5, 0.5, 0.5, 0.5},
        {2, 1, 16, 1, 0.25, 0.5, 0.5, 0.5, 0.5},  {2, 4, 13, 7, 0.4, 0.5, 0.5, 0.5, 0.5},
    };
    char label[128];
    size_t i;
    for (i = 0; i < sizeof chain / sizeof chain[0]; ++i) {
        snprintf(label, sizeof label, "%s, seed %g, pixel (%g, %g), stage %g, %g iterations", sname[(int)chain[i][0]],
                 chain[i][1], chain[i][2], chain[i][3], chain[i][4], chain[i][5]);
        emit(g, "mutate_reservoir", "Mutations 14;Mutations 16;Mutations 19;Mutations 20;Mutations 23", label,
             chain[i], 6);
    }
    for (i = 0; i < sizeof prop / sizeof prop[0]; ++i) {
        snprintf(label, sizeof label, "%s, seed %g, pixel (%g, %g), xi %g", sname[(int)prop[i][0]], prop[i][1],
                 prop[i][2], prop[i][3], prop[i][4]);
        emit(g, "mutate_propose", "Mutations 19;Mutations 20", label, prop[i], 9);
    }
}

/* ---- the stochastic pairwise step (Stochastic MIS Eqs. 14-19, §4.3) ------------------- */

/* seed, Ñ, Ñ_c, scaling, x, y, n, (x_i, y_i, c_i, s_i) x n, u[1 + n], up[Ñ], uc[Ñ_c] ->
 * the output reservoir (valid, d, k, p̂, W, c), from_neighbour, m̃_c, then per neighbour i:
 * K(i), K'(i), P(i) used, m̃_i, J_i, p̂_{<-i}(Y_c). Neighbour i's reservoir is its initial
 * reservoir with confidence c_i and W scaled by s_i; s_i < 0 empties it (a pixel without a
 * contributing sample). The canonical reservoir has confidence 1. */
int vectors_eval_stochastic_step(const double *in, int n_in, double *out)
{
    step_scene sc;
    restir_options o;
    restir_context c;
    stochastic_options so;
    stochastic_workspace w;
    spatial_stats st;
    path_vertex x1s[1 + STEP_MAX_NEIGHBORS];
    reservoir rs[1 + STEP_MAX_NEIGHBORS], res;
    const path_vertex *x1[1 + STEP_MAX_NEIGHBORS];
    const reservoir *rin[1 + STEP_MAX_NEIGHBORS];
    real u[1 + STEP_MAX_NEIGHBORS], up[16], uc[16];
    int np, nc, n, i, k = 0, m;
    uint32_t seed = (uint32_t)in[0];
    rerror e;
    if (n_in < 7 || load(&sc)) return -1;
    np = (int)in[1];
    nc = (int)in[2];
    n = (int)in[6];
    if (np < 1 || np > 16 || nc < 1 || nc > 16 || n < 1 || n > STEP_MAX_NEIGHBORS ||
        n_in != 7 + 4 * n + 1 + n + np + nc || !pixel_ok(&sc, in[4], in[5]))
        return -1;
    m = n + 1;
    restir_options_default(&o);
    restir_context_for(&c, sc.s, sc.lights, &o);
    stochastic_options_default(&so);
    so.n_picks = np;
    so.n_canonical_picks = nc;
    so.confidence_scaling = in[3] != 0;
    if (!initial_at(&sc, &c, &o, seed, (int)in[4], (int)in[5], &x1s[0], &rs[0])) return -1;
    for (i = 0; i < n; ++i) {
        const double *d = in + 7 + 4 * i;
        if (!pixel_ok(&sc, d[0], d[1]) || !initial_at(&sc, &c, &o, seed, (int)d[0], (int)d[1], &x1s[i + 1], &rs[i + 1]))
            return -1;
        rs[i + 1].confidence = (real)d[2];
        if (d[3] < 0) {
            path_sample_clear(&rs[i + 1].y);
            rs[i + 1].W = 0;
        } else
            rs[i + 1].W *= (real)d[3];
    }
    k = 7 + 4 * n;
    for (i = 0; i < m; ++i) u[i] = (real)in[k++];
    for (i = 0; i < np; ++i) up[i] = (real)in[k++];
    for (i = 0; i < nc; ++i) uc[i] = (real)in[k++];
    for (i = 0; i < m; ++i) {
        x1[i] = &x1s[i];
        rin[i] = &rs[i];
    }
    if (stochastic_workspace_alloc(&w, m, &e)) return -1;
    memset(&st, 0, sizeof st);
    stochastic_pairwise_resample(&c, &so, m, x1, rin, u, up, uc, &res, &w, &st);
    k = out_reservoir(out, &res);
    out[k++] = (double)st.selected_neighbor;
    out[k++] = (double)w.m_c_used;
    for (i = 0; i < n; ++i) {
        out[k++] = w.K[i];
        out[k++] = w.Kc[i];
        out[k++] = (double)w.P_used[i];
        out[k++] = (double)w.m_used[i];
        out[k++] = (double)w.jacobian[i];
        out[k++] = (double)w.q_back[i];
    }
    stochastic_workspace_free(&w);
    return k;
}

static void emit_stoch(vectors_emit_fn emit, void *g, const char *label, double seed, int np, int nc, int scaling,
                       int x, int y, int n, const double *nb, const double *picks)
{
    double v[128];
    int k = 0, i;
    v[k++] = seed;
    v[k++] = np;
    v[k++] = nc;
    v[k++] = scaling;
    v[k++] = x;
    v[k++] = y;
    v[k++] = n;
    for (i = 0; i < 4 * n; ++i) v[k++] = nb[i];
    for (i = 0; i < 1 + n + np + nc; ++i) v[k++] = picks[i];
    emit(g, "stochastic_pairwise_resample", "Stochastic MIS 14;Stochastic MIS 15;Stochastic MIS 16;"
                                            "Stochastic MIS 17;Stochastic MIS 18;Stochastic MIS 19",
         label, v, k);
}

void vectors_cases_stochastic_step(vectors_emit_fn emit, void *g)
{
    /* neighbours: x, y, c, W scale (-1: empty) */
    static const double four[] = {10, 9, 1, 1, 14, 9, 1, 1, 12, 7, 1, 1, 12, 11, 1, 1};
    static const double four_empty[] = {10, 9, 1, -1, 14, 9, 1, 1, 12, 7, 1, -1, 12, 11, 1, -1};
    static const double all_empty[] = {10, 9, 1, -1, 14, 9, 2, -1, 12, 7, 1, -1};
    static const double unequal[] = {5, 5, 4, 1, 7, 4, 1, 1, 3, 6, 0.5, 2, 6, 7, 3, 0.25, 4, 3, 1, 1};
    static const double one[] = {13, 9, 1, 1};
    static const double eight[] = {10, 9, 1, 1,  14, 9, 1, -1, 12, 7, 1, 1,  12, 11, 1, 1,
                                   11, 8, 1, -1, 13, 10, 1, 1, 9, 9, 1, -1, 15, 9, 1, 1};
    static const double p1[] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.3, 0.7};
    static const double p1b[] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.05, 0.95};
    static const double p1c[] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.9, 0.3};
    static const double p2[] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.1, 0.6, 0.2, 0.8};
    static const double pu[] = {0.5, 0.2, 0.4, 0.6, 0.8, 0.5, 0.25, 0.75, 0.5, 0.1, 0.9};
    static const double pone[] = {0.5, 0.5, 0.4, 0.6};
    static const double p8[] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.2, 0.7, 0.3, 0.1, 0.55};
    emit_stoch(emit, g, "4 neighbours, N~ = N~_c = 1, scaling", 1, 1, 1, 1, 12, 9, 4, four, p1);
    emit_stoch(emit, g, "4 neighbours, N~ = N~_c = 1, picks near the ends", 1, 1, 1, 1, 12, 9, 4, four, p1b);
    emit_stoch(emit, g, "4 neighbours, no scaling", 1, 1, 1, 0, 12, 9, 4, four, p1);
    emit_stoch(emit, g, "4 neighbours, N~ = N~_c = 2", 2, 2, 2, 1, 12, 9, 4, four, p2);
    emit_stoch(emit, g, "3 of 4 neighbours empty: canonical pick on an empty pixel", 1, 1, 1, 1, 12, 9, 4, four_empty,
               p1);
    emit_stoch(emit, g, "3 of 4 neighbours empty: canonical pick on the full pixel", 1, 1, 1, 1, 12, 9, 4, four_empty,
               p1c);
    emit_stoch(emit, g, "3 of 4 neighbours empty, N~ = N~_c = 2", 3, 2, 2, 1, 12, 9, 4, four_empty, p2);
    emit_stoch(emit, g, "every neighbour empty (P = 0 everywhere)", 1, 1, 1, 1, 12, 9, 3, all_empty, p1);
    emit_stoch(emit, g, "5 neighbours, unequal confidences and W, N~ = 3, N~_c = 2", 4, 3, 2, 1, 5, 5, 5, unequal, pu);
    emit_stoch(emit, g, "one neighbour (scaling 1: deterministic pairwise)", 5, 1, 1, 1, 12, 9, 1, one, pone);
    emit_stoch(emit, g, "8 neighbours, 3 empty, N~ = 2, N~_c = 3", 6, 2, 3, 1, 12, 9, 8, eight, p8);
}
