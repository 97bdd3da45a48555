/* Golden test vectors: the evaluators (one per library function, inputs and outputs as
 * flat number lists) and the generator of the cases (include/restir/oracle/vectors.h,
 * docs/oracle.md). The cases include the extremes a GPU port gets wrong first: grazing
 * angles, roughness 1e-4, nearly coincident points, zero targets, failed shifts
 * (Jacobian or target 0), NaN/negative weights. Non-finite numbers are the strings
 * "inf", "-inf", "nan". */
#include "restir/oracle/vectors.h"

#include "vectors_step.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/atomic_file.h"
#include "restir/core/json_text.h"
#include "restir/core/rng.h"
#include "restir/core/warp.h"
#include "restir/frame/options.h"
#include "restir/oracle/vectors_domain.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/restir/footprint.h"
#include "restir/restir/mis.h"
#include "restir/restir/mutate.h"
#include "restir/restir/pairing.h"
#include "restir/restir/reconnection.h"
#include "restir/restir/reservoir.h"
#include "restir/restir/stochastic_mis.h"
#include "restir/scene/bsdf.h"
#include "restir/scene/lights.h"
#include "restir/scene/microfacet.h"

/* ---- evaluators ---------------------------------------------------------------------- */

static vec3 in3(const double *in) { return v3((real)in[0], (real)in[1], (real)in[2]); }
static vec2 in2(const double *in) { return v2((real)in[0], (real)in[1]); }
static int out3(double *out, vec3 v)
{
    out[0] = (double)v.x;
    out[1] = (double)v.y;
    out[2] = (double)v.z;
    return 3;
}
static int outc(double *out, rgb c)
{
    out[0] = (double)c.r;
    out[1] = (double)c.g;
    out[2] = (double)c.b;
    return 3;
}
static int out2(double *out, vec2 v)
{
    out[0] = (double)v.x;
    out[1] = (double)v.y;
    return 2;
}

#define NEED(n)                      \
    do {                             \
        if (n_in != (n)) return -1;  \
    } while (0)

static int e_rng_u(const double *in, int n_in, double *out)
{
    rng_key k;
    NEED(6);
    k = rng_key_at(rng_key_make((uint32_t)in[0], (uint32_t)in[1], (uint32_t)in[2]), (uint32_t)in[3], (uint32_t)in[4],
                   (uint32_t)in[5]);
    out[0] = (double)rng_bits(k);
    out[1] = (double)rng_uniform(k);
    return 2;
}

static int e_rng_pcg4d(const double *in, int n_in, double *out)
{
    uint32_t v[4];
    int i;
    NEED(4);
    for (i = 0; i < 4; ++i) v[i] = (uint32_t)in[i];
    rng_pcg4d(v);
    for (i = 0; i < 4; ++i) out[i] = (double)v[i];
    return 4;
}

static int e_disk(const double *in, int n_in, double *out)
{
    NEED(2);
    out2(out, warp_disk_concentric(in2(in)));
    out[2] = (double)warp_disk_pdf();
    return 3;
}
static int e_disk_inv(const double *in, int n_in, double *out)
{
    NEED(2);
    return out2(out, warp_disk_concentric_inverse(in2(in)));
}
static int e_cosine(const double *in, int n_in, double *out)
{
    vec3 w;
    NEED(2);
    w = warp_cosine_hemisphere(in2(in));
    out3(out, w);
    out[3] = (double)warp_cosine_hemisphere_pdf(w.z);
    return 4;
}
static int e_cosine_inv(const double *in, int n_in, double *out)
{
    NEED(3);
    return out2(out, warp_cosine_hemisphere_inverse(in3(in)));
}
static int e_sphere(const double *in, int n_in, double *out)
{
    NEED(2);
    out3(out, warp_uniform_sphere(in2(in)));
    out[3] = (double)warp_uniform_sphere_pdf();
    return 4;
}
static int e_sphere_inv(const double *in, int n_in, double *out)
{
    NEED(3);
    return out2(out, warp_uniform_sphere_inverse(in3(in)));
}
static int e_hemi(const double *in, int n_in, double *out)
{
    NEED(2);
    out3(out, warp_uniform_hemisphere(in2(in)));
    out[3] = (double)warp_uniform_hemisphere_pdf();
    return 4;
}
static int e_hemi_inv(const double *in, int n_in, double *out)
{
    NEED(3);
    return out2(out, warp_uniform_hemisphere_inverse(in3(in)));
}
static int e_cone(const double *in, int n_in, double *out)
{
    NEED(3);
    out3(out, warp_uniform_cone(in2(in), (real)in[2]));
    out[3] = (double)warp_uniform_cone_pdf((real)in[2]);
    return 4;
}
static int e_cone_inv(const double *in, int n_in, double *out)
{
    NEED(4);
    return out2(out, warp_uniform_cone_inverse(in3(in), (real)in[3]));
}
static int e_tri(const double *in, int n_in, double *out)
{
    NEED(2);
    return out2(out, warp_uniform_triangle(in2(in)));
}
static int e_tri_inv(const double *in, int n_in, double *out)
{
    NEED(2);
    return out2(out, warp_uniform_triangle_inverse(in2(in)));
}

static int e_ggx_alpha(const double *in, int n_in, double *out)
{
    NEED(1);
    out[0] = (double)ggx_alpha_from_roughness((real)in[0]);
    return 1;
}
static int e_ggx_D(const double *in, int n_in, double *out)
{
    NEED(4);
    out[0] = (double)ggx_D(in3(in), (real)in[3]);
    return 1;
}
static int e_ggx_G1(const double *in, int n_in, double *out)
{
    NEED(7);
    out[0] = (double)ggx_G1(in3(in), in3(in + 3), (real)in[6]);
    out[1] = (double)ggx_lambda(in3(in), (real)in[6]);
    return 2;
}
static int e_vndf_pdf(const double *in, int n_in, double *out)
{
    NEED(7);
    out[0] = (double)ggx_vndf_pdf(in3(in), in3(in + 3), (real)in[6]);
    return 1;
}
static int e_vndf_sample(const double *in, int n_in, double *out)
{
    NEED(6);
    return out3(out, ggx_vndf_sample(in3(in), in2(in + 3), (real)in[5]));
}
static int e_vndf_inv(const double *in, int n_in, double *out)
{
    vec2 u = v2(0, 0);
    NEED(7);
    out[0] = (double)ggx_vndf_sample_inverse(in3(in), in3(in + 3), (real)in[6], &u);
    out2(out + 1, u);
    return 3;
}
static int e_fresnel(const double *in, int n_in, double *out)
{
    NEED(2);
    out[0] = (double)fresnel_dielectric((real)in[0], (real)in[1]);
    return 1;
}

/* material: type, Kd rgb, Ks rgb, roughness, ior (9 numbers) */
static bsdf in_bsdf(const double *in)
{
    material m;
    memset(&m, 0, sizeof m);
    m.type = (enum material_type)(int)in[0];
    m.diffuse = rgb_make((real)in[1], (real)in[2], (real)in[3]);
    m.specular = rgb_make((real)in[4], (real)in[5], (real)in[6]);
    m.roughness = (real)in[7];
    m.ior = (real)in[8];
    return bsdf_from_material(&m);
}

static int e_lobe_probs(const double *in, int n_in, double *out)
{
    bsdf b;
    real p[BSDF_MAX_LOBES];
    int i;
    NEED(12);
    b = in_bsdf(in);
    bsdf_lobe_probabilities(&b, in3(in + 9), p);
    for (i = 0; i < BSDF_MAX_LOBES; ++i) out[i] = i < bsdf_lobe_count(&b) ? (double)p[i] : 0.0;
    out[BSDF_MAX_LOBES] = bsdf_lobe_count(&b);
    return BSDF_MAX_LOBES + 1;
}
static int e_lobe_eval(const double *in, int n_in, double *out)
{
    bsdf b;
    int lobe = (int)in[9];
    NEED(16);
    b = in_bsdf(in);
    if (lobe < 0 || lobe >= bsdf_lobe_count(&b)) return -1;
    outc(out, bsdf_lobe_eval(&b, lobe, in3(in + 10), in3(in + 13)));
    out[3] = (double)bsdf_lobe_pdf(&b, lobe, in3(in + 10), in3(in + 13));
    return 4;
}
static int e_lobe_sample(const double *in, int n_in, double *out)
{
    bsdf b;
    bsdf_sample_record s;
    int lobe = (int)in[9];
    NEED(15);
    b = in_bsdf(in);
    if (lobe < 0 || lobe >= bsdf_lobe_count(&b)) return -1;
    memset(&s, 0, sizeof s);
    out[0] = (double)bsdf_lobe_sample(&b, lobe, in3(in + 10), in2(in + 13), &s);
    if (out[0] == 0) memset(&s, 0, sizeof s); /* a failed sample's record is unspecified */
    out3(out + 1, s.wi);
    outc(out + 4, s.f_cos);
    out[7] = (double)s.pdf;
    out[8] = (double)s.is_delta;
    return 9;
}
static int e_lobe_inv(const double *in, int n_in, double *out)
{
    bsdf b;
    vec2 u = v2(0, 0);
    int lobe = (int)in[9];
    NEED(16);
    b = in_bsdf(in);
    if (lobe < 0 || lobe >= bsdf_lobe_count(&b)) return -1;
    out[0] = (double)bsdf_lobe_sample_inverse(&b, lobe, in3(in + 10), in3(in + 13), &u);
    if (out[0] == 0) u = v2(0, 0);
    out2(out + 1, u);
    return 3;
}
static int e_bsdf_eval(const double *in, int n_in, double *out)
{
    bsdf b;
    NEED(15);
    b = in_bsdf(in);
    outc(out, bsdf_eval(&b, in3(in + 9), in3(in + 12)));
    out[3] = (double)bsdf_pdf(&b, in3(in + 9), in3(in + 12));
    return 4;
}
static int e_bsdf_sample(const double *in, int n_in, double *out)
{
    bsdf b;
    bsdf_sample_record s;
    NEED(15);
    b = in_bsdf(in);
    memset(&s, 0, sizeof s);
    out[0] = (double)bsdf_sample(&b, in3(in + 9), (real)in[12], in2(in + 13), &s);
    if (out[0] == 0) memset(&s, 0, sizeof s);
    out[1] = s.lobe;
    out3(out + 2, s.wi);
    outc(out + 5, s.weight);
    out[8] = (double)s.pdf;
    out[9] = (double)s.lobe_prob;
    return 10;
}

static int e_area_to_sa(const double *in, int n_in, double *out)
{
    NEED(10);
    out[0] = (double)pdf_area_to_solid_angle((real)in[0], in3(in + 1), in3(in + 4), in3(in + 7));
    return 1;
}
static int e_light_emitted(const double *in, int n_in, double *out)
{
    NEED(9);
    return outc(out, light_emitted(rgb_make((real)in[0], (real)in[1], (real)in[2]), in3(in + 3), in3(in + 6)));
}
static int e_light_inv(const double *in, int n_in, double *out)
{
    NEED(2);
    return out2(out, light_sample_point_inverse(in2(in)));
}

static int e_wrs_update(const double *in, int n_in, double *out)
{
    real wsum = (real)in[0];
    uint32_t bad = 0;
    NEED(3);
    out[0] = wrs_update(&wsum, (real)in[1], (real)in[2], &bad);
    out[1] = (double)wsum;
    out[2] = bad;
    return 3;
}
static int e_ris_weight(const double *in, int n_in, double *out)
{
    NEED(3);
    out[0] = (double)ris_candidate_weight((real)in[0], (real)in[1], (real)in[2]);
    return 1;
}
static int e_gris_weight(const double *in, int n_in, double *out)
{
    NEED(4);
    out[0] = (double)gris_resampling_weight((real)in[0], (real)in[1], (real)in[2], (real)in[3]);
    return 1;
}
/* n, then n x (w, u, target), then the confidence of every input: the WRS stream, then
 * the finalisation W = wsum / p̂(Y). */
static int e_stream(const double *in, int n_in, double *out)
{
    reservoir r;
    int n = n_in > 0 ? (int)in[0] : -1, i;
    if (n < 0 || n_in != 1 + 4 * n) return -1;
    reservoir_init(&r);
    for (i = 0; i < n; ++i) {
        path_sample y;
        path_sample_begin(&y, 1, 0, (uint32_t)i);
        y.length = 2;
        y.technique = PATH_TECH_NEE;
        y.target = (real)in[1 + 4 * i + 2];
        reservoir_stream(&r, &y, (real)in[1 + 4 * i], (real)in[1 + 4 * i + 1]);
        reservoir_add_confidence(&r, (real)in[1 + 4 * i + 3]);
    }
    reservoir_finalize(&r);
    out[0] = path_sample_is_valid(&r.y) ? (double)r.y.sample : -1.0;
    out[1] = (double)r.wsum;
    out[2] = (double)r.W;
    out[3] = (double)r.confidence;
    out[4] = r.n_invalid;
    return 5;
}
static int e_estimate(const double *in, int n_in, double *out)
{
    reservoir r;
    NEED(4);
    reservoir_init(&r);
    path_sample_begin(&r.y, 1, 0, 0);
    r.y.length = 2;
    r.y.technique = PATH_TECH_NEE;
    path_sample_set_contribution(&r.y, rgb_make((real)in[0], (real)in[1], (real)in[2]));
    r.W = (real)in[3];
    outc(out, reservoir_estimate(&r));
    out[3] = (double)r.y.target; /* p̂ = luminance(F) */
    return 4;
}
static int e_cap(const double *in, int n_in, double *out)
{
    reservoir r;
    NEED(2);
    reservoir_init(&r);
    r.confidence = (real)in[0];
    reservoir_cap_confidence(&r, (real)in[1]);
    out[0] = (double)r.confidence;
    return 1;
}

/* family, M, R, c[M], ptarget[M*M] (row i = domain i), j -> m_0(y_j) .. m_{M-1}(y_j);
 * family_override >= 0 replaces in[0] (the Falcor form has no family number) */
static int e_mis_family(int family_override, const double *in, int n_in, double *out)
{
    real c[8], p[64], m[8];
    mis_input mi;
    int f, M, R, j, i;
    long shifts = 0;
    if (n_in < 3) return -1;
    f = (int)in[0];
    M = (int)in[1];
    R = (int)in[2];
    if (f < 0 || f > 3 || M < 1 || M > 8 || R < 1 || R > M || n_in != 3 + M + M * M + 1) return -1;
    for (i = 0; i < M; ++i) c[i] = (real)in[3 + i];
    for (i = 0; i < M * M; ++i) p[i] = (real)in[3 + M + i];
    j = (int)in[3 + M + M * M];
    if (j < 0 || j >= M) return -1;
    mi.m = M;
    mi.n_canonical = R;
    mi.confidence = c;
    mi.ptarget = p;
    mis_weights_at(family_override >= 0 ? (mis_family)family_override : (mis_family)f, &mi, j, m, &shifts);
    for (i = 0; i < M; ++i) out[i] = (double)m[i];
    return M;
}

static int e_mis(const double *in, int n_in, double *out) { return e_mis_family(-1, in, n_in, out); }
/* M, R, c[M], ptarget[M*M], j -> m_0(y_j) .. m_{M-1}(y_j) in the Falcor confidence form */
static int e_mis_falcor(const double *in, int n_in, double *out)
{
    double with_family[VECTORS_MAX_IN + 1];
    if (n_in < 2 || n_in >= VECTORS_MAX_IN) return -1;
    with_family[0] = 3; /* e_mis's family slot; replaced below */
    memcpy(with_family + 1, in, (size_t)n_in * sizeof *in);
    return e_mis_family(MIS_PAIRWISE_DEFENSIVE_FALCOR, with_family, n_in + 1, out);
}

static int e_pair_canonical(const double *in, int n_in, double *out)
{
    NEED(4);
    out[0] = (double)mis_pair_canonical((real)in[0], (real)in[1], (real)in[2], (real)in[3]);
    return 1;
}
static int e_pair_neighbor(const double *in, int n_in, double *out)
{
    NEED(4);
    out[0] = (double)mis_pair_neighbor((real)in[0], (real)in[1], (real)in[2], (real)in[3]);
    return 1;
}

static int e_rc_jacobian(const double *in, int n_in, double *out)
{
    rc_terms t;
    path_sample x;
    NEED(6);
    memset(&t, 0, sizeof t);
    path_sample_clear(&x);
    t.pdf_prev = (real)in[0];
    t.geom = (real)in[1];
    t.pdf_k = (real)in[2];
    x.rc_pdf_prev = (real)in[3];
    x.rc_geom = (real)in[4];
    x.rc_pdf = (real)in[5];
    out[0] = (double)rc_jacobian(&t, &x);
    return 1;
}

/* ---- stochastic pairwise MIS (Stochastic MIS §3-§4; docs/stochastic-mis.md) ------------ */

/* m, Ñ, P[m], u[Ñ] -> K[m], distinct */
static int e_stoch_pick(const double *in, int n_in, double *out)
{
    real P[16], u[16];
    int K[16], m, n, i;
    if (n_in < 2) return -1;
    m = (int)in[0];
    n = (int)in[1];
    if (m < 1 || m > 16 || n < 1 || n > 16 || n_in != 2 + m + n) return -1;
    for (i = 0; i < m; ++i) P[i] = (real)in[2 + i];
    for (i = 0; i < n; ++i) u[i] = (real)in[2 + m + i];
    out[m] = stochastic_pick(P, m, n, u, K);
    for (i = 0; i < m; ++i) out[i] = K[i];
    return m + 1;
}
static int e_stoch_weight(const double *in, int n_in, double *out)
{
    NEED(4);
    out[0] = (double)stochastic_mis_weight((int)in[0], (int)in[1], (real)in[2], (real)in[3]);
    return 1;
}
/* m, a[m] -> P[m], sum */
static int e_stoch_p(const double *in, int n_in, double *out)
{
    real a[16], P[16];
    int m = n_in > 0 ? (int)in[0] : 0, i;
    if (m < 1 || m > 16 || n_in != 1 + m) return -1;
    for (i = 0; i < m; ++i) a[i] = (real)in[1 + i];
    out[m] = (double)stochastic_selection_p(a, m, P);
    for (i = 0; i < m; ++i) out[i] = (double)P[i];
    return m + 1;
}
static int e_stoch_m(const double *in, int n_in, double *out)
{
    NEED(5);
    out[0] = (double)stochastic_pairwise_m((real)in[0], (real)in[1], (real)in[2], (real)in[3], (real)in[4]);
    return 1;
}
static int e_stoch_b(const double *in, int n_in, double *out)
{
    NEED(5);
    out[0] = (double)stochastic_pairwise_b((real)in[0], (real)in[1], (real)in[2], (real)in[3], (real)in[4]);
    return 1;
}
static int e_stoch_scale(const double *in, int n_in, double *out)
{
    NEED(2);
    out[0] = (double)stochastic_confidence_scale((int)in[0], (int)in[1]);
    return 1;
}

/* The weights of one stochastic pairwise GRIS step with the shifts' results given as
 * numbers: the fixed composition stochastic_pairwise_resample (stochastic_spatial.c) makes
 * of stochastic_confidence_scale (§4.3), stochastic_canonical_picks and
 * stochastic_canonical_term (Eqs. 18-19), stochastic_selection_p (Eq. 17), stochastic_pick,
 * stochastic_pairwise_m and stochastic_mis_weight (Eqs. 15-16) and gris_resampling_weight
 * (Eq. 14). Inputs: n (non-canonical domains), Ñ, Ñ_c, scaling (0/1), c_c, p̂(Y_c), W_c,
 * then per domain i = 1..n: c_i, p̂_i(X_i), W_i, J_i = |dT_i/dX_i| (0: the shift in
 * fails), p̂(Y_i), q_i = p̂_{<-i}(Y_c) (the canonical sample shifted out, times J); then
 * up[Ñ] (Eq. 17 picks), uc[Ñ_c] (canonical picks). Outputs: m̃_c, w̃_c, then per i: K(i),
 * m̃_i, w̃_i. */
#define STOCH_MAX_N 8
static int e_stoch_step(const double *in, int n_in, double *out)
{
    real a[STOCH_MAX_N], P[STOCH_MAX_N], up[16], uc[16], scale, c_c, c_S = 0, C, p_c, m_c = 1;
    int K[STOCH_MAX_N], Kc[STOCH_MAX_N], n, np, nc, i, o = 2;
    const double *d;
    if (n_in < 7) return -1;
    n = (int)in[0];
    np = (int)in[1];
    nc = (int)in[2];
    if (n < 1 || n > STOCH_MAX_N || np < 1 || np > 16 || nc < 1 || nc > 16 || n_in != 7 + 6 * n + np + nc) return -1;
    d = in + 7;
    for (i = 0; i < np; ++i) up[i] = (real)in[7 + 6 * n + i];
    for (i = 0; i < nc; ++i) uc[i] = (real)in[7 + 6 * n + np + i];
    scale = in[3] != 0 ? stochastic_confidence_scale(np, n) : 1;
    c_c = (real)in[4];
    p_c = (real)in[5];
    for (i = 0; i < n; ++i) c_S += scale * (real)d[6 * i]; /* Eq. 12 over the scaled c_i */
    C = c_c + c_S;
    if (C > 0) {
        m_c = c_c / C;
        stochastic_canonical_picks(n, nc, uc, Kc);
        for (i = 0; i < n; ++i)
            if (Kc[i])
                m_c += stochastic_canonical_term(Kc[i], nc, n, c_c, c_S, scale * (real)d[6 * i], (real)d[6 * i + 5], p_c);
    }
    out[0] = (double)m_c;
    out[1] = (double)gris_resampling_weight(m_c, p_c, (real)in[6], 1);
    for (i = 0; i < n; ++i) {
        real c_i = (real)d[6 * i], t = (real)d[6 * i + 1], W = (real)d[6 * i + 2];
        a[i] = t > 0 && W > 0 ? c_i * t * W : 0; /* c_i p̂(X_i) W_i of a usable input */
    }
    stochastic_selection_p(a, n, P);
    stochastic_pick(P, n, np, up, K);
    for (i = 0; i < n; ++i) {
        real jac = (real)d[6 * i + 3], ty = (real)d[6 * i + 4], mi = 0, wi = 0;
        if (K[i] && jac > 0) {
            real q = (real)d[6 * i + 1] / jac; /* p̂_{<-i}(Y_i) = p̂_i(X_i) / J_i (Eq. 10) */
            mi = stochastic_mis_weight(K[i], np, P[i], stochastic_pairwise_m(c_c, c_S, scale * (real)d[6 * i], q, ty));
            wi = gris_resampling_weight(mi, ty, (real)d[6 * i + 2], jac); /* Eq. 14 */
        }
        out[o++] = K[i];
        out[o++] = (double)mi;
        out[o++] = (double)wi;
    }
    return o;
}

/* ---- paired reuse textures (Enhanced §3, Eq. 3; docs/enhanced.md §2) -------------------- */

static int e_shuffle_count(const double *in, int n_in, double *out)
{
    NEED(1);
    out[0] = pairing_shuffle_count(in[0]);
    return 1;
}
/* w, sigma, seed, id, then either 5 numbers of a placement (flip, mirror, transpose, ox, oy)
 * and a pixel x, y -> dx, dy, n_sigma; the partner of the partner is checked by the caller */
static int e_partner(const double *in, int n_in, double *out)
{
    reuse_texture t;
    reuse_transform f;
    rerror e;
    int dx, dy;
    NEED(11);
    if (reuse_texture_build(&t, (int)in[0], in[1], (uint32_t)in[2], (uint32_t)in[3], &e)) return -1;
    f.flip = (int)in[4];
    f.mirror = (int)in[5];
    f.transpose = (int)in[6];
    f.ox = (int)in[7];
    f.oy = (int)in[8];
    reuse_partner_offset(&t, &f, (int)in[9], (int)in[10], &dx, &dy);
    out[0] = dx;
    out[1] = dy;
    out[2] = t.shuffles;
    reuse_texture_free(&t);
    return 3;
}
/* w, sigma, seed, id, sample -> flip, mirror, transpose, ox, oy */
static int e_placement(const double *in, int n_in, double *out)
{
    reuse_texture t;
    reuse_transform f;
    rerror e;
    NEED(5);
    if (reuse_texture_build(&t, (int)in[0], in[1], (uint32_t)in[2], (uint32_t)in[3], &e)) return -1;
    f = reuse_transform_draw(&t, (uint32_t)in[2], (uint32_t)in[4], (uint32_t)in[3]);
    out[0] = f.flip;
    out[1] = f.mirror;
    out[2] = f.transpose;
    out[3] = f.ox;
    out[4] = f.oy;
    reuse_texture_free(&t);
    return 5;
}

/* ---- the footprint reconnection criterion (Enhanced §4, Eq. 5; docs/enhanced.md §1) ---- */

/* A vertex with material in[0..8] at position in[9..11], normal (geometric = shading)
 * in[12..14], direction towards its predecessor in[15..17]. */
static void in_vertex(const double *in, path_vertex *v)
{
    memset(v, 0, sizeof *v);
    v->position = in3(in + 9);
    v->ng = v->ns = v3_normalize(in3(in + 12));
    v->wo = v3_normalize(in3(in + 15));
    v->frame = shading_frame_make(v->ns);
    v->wo_local = shading_frame_to_local(&v->frame, v->wo);
    v->b = in_bsdf(in);
    bsdf_lobe_probabilities(&v->b, v->wo_local, v->lobe_p);
}
static unsigned in_lobe(double l) { return l == -1 ? PATH_LOBE_NEE : l == -2 ? PATH_LOBE_NONE : (unsigned)l; }

/* x_{k-1}: vertex (18), lobe; x_k: light (0/1), vertex (18), lobe, w_k (3); roughness
 * threshold, c, primary footprint -> forward, inverse, result (enum shift_failure) */
static int e_footprint(const double *in, int n_in, double *out)
{
    path_vertex a, b;
    rc_vertex pa, pb;
    rc_criterion crit;
    real fwd, inv;
    NEED(45);
    in_vertex(in, &a);
    in_vertex(in + 20, &b);
    memset(&crit, 0, sizeof crit);
    crit.mode = RC_MODE_FOOTPRINT;
    crit.roughness_threshold = (real)in[42];
    crit.footprint_c = (real)in[43];
    pa.position = a.position;
    pa.at_infinity = pb.at_infinity = 0;
    pa.ng = a.ng;
    pa.surface = &a;
    pa.lobe = in_lobe(in[18]);
    pa.wi = v3_normalize(v3_sub(b.position, a.position));
    pa.rough = rc_vertex_is_rough(&a.b, pa.lobe, crit.roughness_threshold);
    pb.position = b.position;
    pb.ng = b.ng;
    pb.surface = in[19] != 0 ? NULL : &b;
    pb.lobe = in[19] != 0 ? PATH_LOBE_NONE : in_lobe(in[38]);
    pb.wi = v3_normalize(in3(in + 39));
    pb.rough = rc_vertex_is_rough(pb.surface ? &b.b : NULL, pb.lobe, crit.roughness_threshold);
    rc_footprints(&pa, &pb, &fwd, &inv);
    out[0] = (double)fwd;
    out[1] = (double)inv;
    out[2] = (double)rc_footprint_test(&crit, &pa, &pb, (real)in[44]);
    return 3;
}
/* t = ||x_0 - x_1||, n_g, w_o (towards the camera) -> ||x_0 - x_1||^2 / (|<n_g, w_o>| / 4 pi) */
static int e_primary_footprint(const double *in, int n_in, double *out)
{
    path_vertex v;
    NEED(7);
    memset(&v, 0, sizeof v);
    v.hit.t = (float)in[0];
    v.ng = v3_normalize(in3(in + 1));
    v.wo = v3_normalize(in3(in + 4));
    out[0] = (double)rc_primary_footprint(&v);
    return 1;
}

/* ---- scene-level shifts: scenes/cornell.scene at 24 x 18, frame 0, pixel centres ------- */

#define SHIFT_SCENE "scenes/cornell.scene"
#define SHIFT_W 24
#define SHIFT_H 18

static struct {
    int state; /* 0 not loaded, 1 loaded, -1 failed */
    scene s;
    light_set lights;
    gbuffer g;
} shift_scene;

/* The scene, its lights and G-buffer, loaded once (relative to the working directory: the
 * repository root). Not thread-safe: vectors are generated and checked on one thread. */
static int shift_scene_load(void)
{
    rerror e;
    camera cam;
    if (shift_scene.state) return shift_scene.state > 0 ? 0 : -1;
    shift_scene.state = -1;
    if (scene_load(&shift_scene.s, vectors_shift_scene_path(), &e)) return -1;
    shift_scene.s.width = SHIFT_W;
    shift_scene.s.height = SHIFT_H;
    if (scene_prepare(&shift_scene.s, &e) || lights_build(&shift_scene.lights, &shift_scene.s, &e)) return -1;
    camera_init(&cam, scene_camera_at(&shift_scene.s, 0), SHIFT_W, SHIFT_H);
    if (gbuffer_build(&shift_scene.g, &shift_scene.s, &cam, 1, 0, 0, 1, &e)) return -1;
    shift_scene.state = 1;
    return 0;
}

int vectors_scene(const scene **s, const light_set **lights, const gbuffer **g, int *width, int *height)
{
    if (shift_scene_load()) return -1;
    *s = &shift_scene.s;
    *lights = &shift_scene.lights;
    *g = &shift_scene.g;
    *width = SHIFT_W;
    *height = SHIFT_H;
    return 0;
}

/* shift (0 reconnection, 1 random replay, 2 hybrid), seed, base x, y, destination x, y ->
 * base: valid, d, k, p̂; shift: failure reason (enum shift_failure, 0 = ok), J, offset d, k,
 * F rgb, p̂ (Stochastic MIS Eq. 5: Y = T(X); Jacobian GRIS Eq. 54 / Enhanced Eq. 2; the
 * target p̂_{<-i} of GRIS Eq. 35 is p̂(Y) / J of the reverse direction). */
static int e_shift(const double *in, int n_in, double *out)
{
    restir_options o;
    restir_context ctx;
    initial_options io;
    initial_stats st;
    reservoir base;
    path_sample y;
    path_vertex x1, y1;
    shift_info info;
    real jac = 0;
    int kind = (int)in[0], bx = (int)in[2], by = (int)in[3], dx = (int)in[4], dy = (int)in[5], fail;
    NEED(6);
    if (kind < 0 || kind > 2 || bx < 0 || by < 0 || dx < 0 || dy < 0 || bx >= SHIFT_W || dx >= SHIFT_W ||
        by >= SHIFT_H || dy >= SHIFT_H || shift_scene_load())
        return -1;
    restir_options_default(&o);
    o.shift = kind;
    o.seed = (uint32_t)in[1];
    restir_context_for(&ctx, &shift_scene.s, &shift_scene.lights, &o);
    restir_initial_options_for(&io, &o);
    memset(&st, 0, sizeof st);
    reservoir_init(&base);
    if (gbuffer_primary_vertex(&shift_scene.s, &shift_scene.g, (long)by * SHIFT_W + bx, &x1))
        initial_sample_pixel(&ctx, &io, &x1, o.seed, (uint32_t)(by * SHIFT_W + bx), 0, &base, &st);
    out[0] = path_sample_is_valid(&base.y);
    out[1] = base.y.length;
    out[2] = base.y.rc_k;
    out[3] = (double)base.y.target;
    path_sample_clear(&y);
    memset(&info, 0, sizeof info);
    if (!path_sample_is_valid(&base.y)) fail = SHIFT_FAIL_EMPTY;
    else if (!gbuffer_primary_vertex(&shift_scene.s, &shift_scene.g, (long)dy * SHIFT_W + dx, &y1))
        fail = SHIFT_FAIL_NO_PRIMARY;
    else
        fail = (int)shift_path(&ctx, &y1, &base.y, &y, &jac, &info);
    if (fail != SHIFT_OK) {
        path_sample_clear(&y);
        jac = 0;
    }
    out[4] = fail;
    out[5] = (double)jac;
    out[6] = y.length;
    out[7] = y.rc_k;
    outc(out + 8, y.F);
    out[11] = (double)y.target;
    return 12;
}

/* ---- MCMC mutations (mutate.h) ---- */
static int e_mutate_perturb(const double *in, int n_in, double *out)
{
    NEED(2);
    out[0] = (double)mutate_perturb((real)in[0], (real)in[1]);
    return 1;
}
static int e_mutate_perturb_gaussian(const double *in, int n_in, double *out)
{
    real xi[3];
    NEED(5);
    xi[0] = (real)in[1];
    xi[1] = (real)in[2];
    xi[2] = (real)in[3];
    out[0] = (double)mutate_perturb_gaussian((real)in[0], xi, in[4]);
    return 1;
}
static int e_mutate_acceptance(const double *in, int n_in, double *out)
{
    NEED(3);
    out[0] = (double)mutate_acceptance((real)in[0], (real)in[1], (real)in[2]);
    return 1;
}
static int e_mutate_weight(const double *in, int n_in, double *out)
{
    NEED(3);
    out[0] = (double)mutate_weight((real)in[0], (real)in[1], (real)in[2]);
    return 1;
}
static int e_mutate_eq20(const double *in, int n_in, double *out)
{
    real z[3], y[3];
    int i;
    NEED(6);
    for (i = 0; i < 3; ++i) {
        z[i] = (real)in[i];
        y[i] = (real)in[3 + i];
    }
    out[0] = (double)mutate_eq20_ratio(z, y);
    return 1;
}

#define MAT "type,Kd.r,Kd.g,Kd.b,Ks.r,Ks.g,Ks.b,roughness,ior"
static const vector_fn table[] = {
    {"rng", "rng_u", "seed,pixel,sample,stream,vertex,slot -> bits,u", e_rng_u},
    {"rng", "rng_pcg4d", "v0,v1,v2,v3 -> v0,v1,v2,v3", e_rng_pcg4d},
    {"warp", "warp_disk_concentric", "u.x,u.y -> p.x,p.y,pdf", e_disk},
    {"warp", "warp_disk_concentric_inverse", "p.x,p.y -> u.x,u.y", e_disk_inv},
    {"warp", "warp_cosine_hemisphere", "u.x,u.y -> w.x,w.y,w.z,pdf", e_cosine},
    {"warp", "warp_cosine_hemisphere_inverse", "w.x,w.y,w.z -> u.x,u.y", e_cosine_inv},
    {"warp", "warp_uniform_sphere", "u.x,u.y -> w.x,w.y,w.z,pdf", e_sphere},
    {"warp", "warp_uniform_sphere_inverse", "w.x,w.y,w.z -> u.x,u.y", e_sphere_inv},
    {"warp", "warp_uniform_hemisphere", "u.x,u.y -> w.x,w.y,w.z,pdf", e_hemi},
    {"warp", "warp_uniform_hemisphere_inverse", "w.x,w.y,w.z -> u.x,u.y", e_hemi_inv},
    {"warp", "warp_uniform_cone", "u.x,u.y,cos_max -> w.x,w.y,w.z,pdf", e_cone},
    {"warp", "warp_uniform_cone_inverse", "w.x,w.y,w.z,cos_max -> u.x,u.y", e_cone_inv},
    {"warp", "warp_uniform_triangle", "u.x,u.y -> b1,b2", e_tri},
    {"warp", "warp_uniform_triangle_inverse", "b1,b2 -> u.x,u.y", e_tri_inv},
    {"microfacet", "ggx_alpha_from_roughness", "roughness -> alpha", e_ggx_alpha},
    {"microfacet", "ggx_D", "m.x,m.y,m.z,alpha -> D", e_ggx_D},
    {"microfacet", "ggx_G1", "w.x,w.y,w.z,m.x,m.y,m.z,alpha -> G1,lambda", e_ggx_G1},
    {"microfacet", "ggx_vndf_pdf", "wo.x,wo.y,wo.z,m.x,m.y,m.z,alpha -> pdf_m", e_vndf_pdf},
    {"microfacet", "ggx_vndf_sample", "wo.x,wo.y,wo.z,u.x,u.y,alpha -> m.x,m.y,m.z", e_vndf_sample},
    {"microfacet", "ggx_vndf_sample_inverse", "wo.x,wo.y,wo.z,m.x,m.y,m.z,alpha -> ok,u.x,u.y", e_vndf_inv},
    {"microfacet", "fresnel_dielectric", "cos_i,eta -> F", e_fresnel},
    {"bsdf", "bsdf_lobe_probabilities", MAT ",wo.x,wo.y,wo.z -> P(lobe0|wo),P(lobe1|wo),lobe_count",
     e_lobe_probs},
    {"bsdf", "bsdf_lobe_eval_pdf", MAT ",lobe,wo.x,wo.y,wo.z,wi.x,wi.y,wi.z -> f.r,f.g,f.b,pdf", e_lobe_eval},
    {"bsdf", "bsdf_lobe_sample",
     MAT ",lobe,wo.x,wo.y,wo.z,u.x,u.y -> ok,wi.x,wi.y,wi.z,f_cos.r,f_cos.g,f_cos.b,pdf,is_delta", e_lobe_sample},
    {"bsdf", "bsdf_lobe_sample_inverse", MAT ",lobe,wo.x,wo.y,wo.z,wi.x,wi.y,wi.z -> ok,u.x,u.y", e_lobe_inv},
    {"bsdf", "bsdf_eval_pdf", MAT ",wo.x,wo.y,wo.z,wi.x,wi.y,wi.z -> f.r,f.g,f.b,pdf", e_bsdf_eval},
    {"bsdf", "bsdf_sample",
     MAT ",wo.x,wo.y,wo.z,u_lobe,u.x,u.y -> ok,lobe,wi.x,wi.y,wi.z,weight.r,weight.g,weight.b,pdf,lobe_prob",
     e_bsdf_sample},
    {"light", "pdf_area_to_solid_angle", "pdf_area,x.x,x.y,x.z,y.x,y.y,y.z,ny.x,ny.y,ny.z -> pdf_solid_angle",
     e_area_to_sa},
    {"light", "light_emitted", "Le.r,Le.g,Le.b,n.x,n.y,n.z,to.x,to.y,to.z -> L.r,L.g,L.b", e_light_emitted},
    {"light", "light_sample_point_inverse", "b1,b2 -> u.x,u.y", e_light_inv},
    {"wrs", "wrs_update", "wsum,w,u -> selected,wsum,n_invalid", e_wrs_update},
    {"wrs", "ris_candidate_weight", "target,ucw,n_trees -> w", e_ris_weight},
    {"wrs", "gris_resampling_weight", "mis,target,ucw,jacobian -> w", e_gris_weight},
    {"wrs", "reservoir_stream_finalize", "n,(w,u,target,confidence) x n -> selected,wsum,W,confidence,n_invalid",
     e_stream},
    {"wrs", "reservoir_estimate", "F.r,F.g,F.b,W -> FW.r,FW.g,FW.b,target", e_estimate},
    {"wrs", "reservoir_cap_confidence", "c,cap -> c", e_cap},
    {"mis", "mis_weights", "family(0 constant,1 talbot,2 pairwise,3 defensive),M,R,c[M],ptarget[M*M],j -> m[M]",
     e_mis},
    {"mis", "mis_pairwise_defensive_falcor", "M,R,c[M],ptarget[M*M],j -> m[M]", e_mis_falcor},
    {"mis", "mis_pair_canonical", "c_c,p_c,c_n,p_n_from_c -> m_c", e_pair_canonical},
    {"mis", "mis_pair_neighbor", "c_n,p_n_from_n,c_c,p_c_at_n -> m_n", e_pair_neighbor},
    {"shift", "shift_path",
     "shift(0 reconnection,1 replay,2 hybrid),seed,base.x,base.y,dest.x,dest.y -> base_valid,base_d,base_k,"
     "base_target,failure,J,d,k,F.r,F.g,F.b,target",
     e_shift},
    {"reconnection", "rc_jacobian", "pdf_prev_y,geom_y,pdf_k_y,pdf_prev_x,geom_x,pdf_k_x -> J", e_rc_jacobian},
    {"stochastic", "stochastic_pick", "m,N~,P[m],u[N~] -> K[m],distinct", e_stoch_pick},
    {"stochastic", "stochastic_mis_weight", "K,N~,P,m -> m~", e_stoch_weight},
    {"stochastic", "stochastic_selection_p", "m,a[m] (a_i = c_i p^_i(X_i) W_i) -> P[m],sum", e_stoch_p},
    {"stochastic", "stochastic_pairwise_m", "c_c,c_S,c_i,q_i,p -> m_i", e_stoch_m},
    {"stochastic", "stochastic_pairwise_b", "c_c,c_S,c_i,q_i,p -> b_i", e_stoch_b},
    {"stochastic", "stochastic_confidence_scale", "N~,M -> scale", e_stoch_scale},
    {"stochastic", "stochastic_pairwise_weights",
     "n,N~,N~_c,scaling,c_c,p^(Y_c),W_c,(c_i,p^_i(X_i),W_i,J_i,p^(Y_i),q_i=p^_{<-i}(Y_c)) x n,up[N~],uc[N~_c] -> "
     "m~_c,w~_c,(K_i,m~_i,w~_i) x n",
     e_stoch_step},
    {"stochastic", "stochastic_pairwise_resample",
     "seed,N~,N~_c,scaling,x,y,n,(x_i,y_i,c_i,W scale (-1 empty)) x n,u[1+n],up[N~],uc[N~_c] -> valid,d,k,target,W,c,"
     "from_neighbour,m~_c,(K_i,K'_i,P_i,m~_i,J_i,q_i=p^_{<-i}(Y_c)) x n",
     vectors_eval_stochastic_step},
    {"temporal", "temporal_resample",
     "mis(0 constant,1 talbot,2 pairwise,3 defensive),mcap,seed_t,seed_t-1,x,y,qx,qy (-1: no history),c_t,c_t-1,u0,u1 "
     "-> valid,d,k,target,W,c,from_history,capped,ptarget[2*2],m_0(y_0),m_1(y_1),J_1",
     vectors_eval_temporal_step},
    {"pairing", "pairing_shuffle_count", "sigma -> n_sigma", e_shuffle_count},
    {"pairing", "reuse_partner_offset",
     "w,sigma,seed,id,flip,mirror,transpose,ox,oy,x,y -> dx,dy,n_sigma (texture from reuse_texture_build)", e_partner},
    {"pairing", "reuse_transform_draw", "w,sigma,seed,id,sample -> flip,mirror,transpose,ox,oy", e_placement},
    {"footprint", "rc_footprint_test",
     MAT ",x,y,z,n.x,n.y,n.z,wo.x,wo.y,wo.z,lobe (x_{k-1}; lobe -1 = NEE),light (1: x_k is the light vertex x_d),"
     MAT ",x,y,z,n.x,n.y,n.z,wo.x,wo.y,wo.z,lobe,w_k.x,w_k.y,w_k.z (x_k),roughness_threshold,c,primary_footprint -> "
     "forward,inverse,result (enum shift_failure)",
     e_footprint},
    {"footprint", "rc_primary_footprint", "t,ng.x,ng.y,ng.z,wo.x,wo.y,wo.z -> footprint", e_primary_footprint},
    {"mutation", "mutate_perturb", "u,xi -> v", e_mutate_perturb},
    {"mutation", "mutate_perturb_gaussian", "u,a,b,U,sigma -> v (sigma 0: the paper's amount from U)",
     e_mutate_perturb_gaussian},
    {"mutation", "mutate_acceptance", "target_x,target_z,kernel_ratio -> a (before min(1, .))", e_mutate_acceptance},
    {"mutation", "mutate_weight", "W,target_x,target_z -> W", e_mutate_weight},
    {"mutation", "mutate_eq20_ratio", "p_k_z,G_z,p_k1_z,p_k_y,G_y,p_k1_y -> T(z->y)/T(y->z)", e_mutate_eq20},
    {"mutation", "mutate_reservoir",
     "strategy(0 rv,1 pp,2 fp),seed,x,y,stage(1,2,4),iterations -> valid,d,k,target,W,c (before),valid,d,k,target,W,c,"
     "F.r,F.g,F.b,n_pss (after),proposals,accepted,rejected_mh,skipped",
     vectors_eval_mutate_chain},
    {"mutation", "mutate_propose",
     "strategy,seed,x,y,xi,xi_lobe[2],xi_lobe_current[2] -> explicit,A_y terms[3],result (-1 ok),ratio,target_z,d_z,k_z",
     vectors_eval_mutate_propose},
    {NULL, NULL, NULL, NULL}};

static const vector_fn *find_fn(const char *fn)
{
    int i;
    for (i = 0; table[i].fn; ++i)
        if (!strcmp(table[i].fn, fn)) return &table[i];
    return NULL;
}

/* ---- the generator ------------------------------------------------------------------- */

typedef struct {
    FILE *fp;            /* NULL: only look for want_eq */
    const char *family;  /* the family being written */
    const char *want_eq;
    int found;
} gen;

/* 1 if the ';'-separated list has the tag. */
static int eq_list_has(const char *list, const char *eq)
{
    size_t n = strlen(eq);
    const char *p = list;
    while (p && *p) {
        const char *end = strchr(p, ';');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (len == n && !strncmp(p, eq, n)) return 1;
        p = end ? end + 1 : NULL;
    }
    return 0;
}

/* A finite number with 17 significant digits; "inf", "-inf", "nan" as strings (JSON has
 * no non-finite numbers, and several cases need them as inputs). */
static void put_value(FILE *fp, double v)
{
    if (isnan(v)) fputs("\"nan\"", fp);
    else if (isinf(v)) fputs(v > 0 ? "\"inf\"" : "\"-inf\"", fp);
    else json_put_number(fp, v);
}

static void emit(gen *g, const char *fn, const char *eqs, const char *label, const double *in, int n_in)
{
    const vector_fn *f = find_fn(fn);
    double out[VECTORS_MAX_OUT];
    int n_out, i;
    const char *p;
    if (!f || strcmp(f->family, g->family)) return; /* not this family's pass */
    if (!g->fp) {
        if (g->want_eq && eq_list_has(eqs, g->want_eq)) g->found = 1;
        return;
    }
    n_out = f->eval(in, n_in, out);
    if (n_out < 0) return; /* a generator bug; the coverage test would notice missing lines */
    fprintf(g->fp, "{\"family\": \"%s\", \"fn\": \"%s\", \"eq\": [", f->family, f->fn);
    for (p = eqs, i = 0; *p; ++i) {
        const char *end = strchr(p, ';');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        fprintf(g->fp, "%s\"%.*s\"", i ? ", " : "", (int)len, p);
        p += len;
        if (*p == ';') ++p;
    }
    fprintf(g->fp, "], \"case\": ");
    json_put_string(g->fp, label);
    fprintf(g->fp, ", \"sig\": ");
    json_put_string(g->fp, f->sig);
    fprintf(g->fp, ", \"in\": [");
    for (i = 0; i < n_in; ++i) {
        if (i) fputs(", ", g->fp);
        put_value(g->fp, in[i]);
    }
    fprintf(g->fp, "], \"out\": [");
    for (i = 0; i < n_out; ++i) {
        if (i) fputs(", ", g->fp);
        put_value(g->fp, out[i]);
    }
    fprintf(g->fp, "]}\n");
}

static void emit_cb(void *g, const char *fn, const char *eqs, const char *label, const double *in, int n_in)
{
    emit((gen *)g, fn, eqs, label, in, n_in);
}

#define EMIT(fn, eqs, label, ...)                                       \
    do {                                                                \
        const double in_[] = {__VA_ARGS__};                             \
        emit(g, fn, eqs, label, in_, (int)(sizeof in_ / sizeof in_[0])); \
    } while (0)

static void gen_rng(gen *g)
{
    static const uint32_t addr[][6] = {{1, 0, 0, 1, 1, 0},          {1, 0, 0, 1, 1, 1},
                                       {1, 12345, 7, 4, 48, 0},      {2, 12345, 7, 4, 48, 0},
                                       {0xffffffffu, 0xffffffffu, 0xffffffffu, 255, 255, 65535},
                                       {7, 640 * 360 - 1, 32, 2, 3, 2}, {1, 5, 0, 4, 32, 3}};
    size_t i;
    for (i = 0; i < sizeof addr / sizeof addr[0]; ++i)
        EMIT("rng_u", "", "address", addr[i][0], addr[i][1], addr[i][2], addr[i][3], addr[i][4], addr[i][5]);
    EMIT("rng_pcg4d", "", "zero", 0, 0, 0, 0);
    EMIT("rng_pcg4d", "", "words", 1, 2, 3, 4);
    EMIT("rng_pcg4d", "", "max", 4294967295.0, 4294967295.0, 4294967295.0, 4294967295.0);
}

static void gen_warp(gen *g)
{
    static const double us[][2] = {{0.5, 0.5}, {0.25, 0.75}, {0, 0}, {0.999999999, 0.123}, {1e-9, 0.5}, {0.5, 1e-9}};
    size_t i;
    for (i = 0; i < sizeof us / sizeof us[0]; ++i) {
        const char *label = us[i][0] < 1e-6 || us[i][1] < 1e-6 || us[i][0] > 0.99999 ? "edge" : "interior";
        vec2 d = warp_disk_concentric(v2((real)us[i][0], (real)us[i][1]));
        vec3 w = warp_cosine_hemisphere(v2((real)us[i][0], (real)us[i][1]));
        EMIT("warp_disk_concentric", "", label, us[i][0], us[i][1]);
        EMIT("warp_disk_concentric_inverse", "", label, (double)d.x, (double)d.y);
        EMIT("warp_cosine_hemisphere", "", label, us[i][0], us[i][1]);
        EMIT("warp_cosine_hemisphere_inverse", "", label, (double)w.x, (double)w.y, (double)w.z);
        w = warp_uniform_sphere(v2((real)us[i][0], (real)us[i][1]));
        EMIT("warp_uniform_sphere", "", label, us[i][0], us[i][1]);
        EMIT("warp_uniform_sphere_inverse", "", label, (double)w.x, (double)w.y, (double)w.z);
        w = warp_uniform_hemisphere(v2((real)us[i][0], (real)us[i][1]));
        EMIT("warp_uniform_hemisphere", "", label, us[i][0], us[i][1]);
        EMIT("warp_uniform_hemisphere_inverse", "", label, (double)w.x, (double)w.y, (double)w.z);
        EMIT("warp_uniform_cone", "", label, us[i][0], us[i][1], 0.9);
        EMIT("warp_uniform_cone", "", "narrow cone", us[i][0], us[i][1], 0.999999);
        w = warp_uniform_cone(v2((real)us[i][0], (real)us[i][1]), (real)0.9);
        EMIT("warp_uniform_cone_inverse", "", label, (double)w.x, (double)w.y, (double)w.z, 0.9);
        d = warp_uniform_triangle(v2((real)us[i][0], (real)us[i][1]));
        EMIT("warp_uniform_triangle", "", label, us[i][0], us[i][1]);
        EMIT("warp_uniform_triangle_inverse", "", label, (double)d.x, (double)d.y);
    }
}

/* Unit directions by polar cosine (1e-4 is grazing) and azimuth. */
static vec3 dir(double cos_t, double phi)
{
    double s = sqrt(fmax(0, 1 - cos_t * cos_t));
    return v3((real)(s * cos(phi)), (real)(s * sin(phi)), (real)cos_t);
}

static void gen_microfacet(gen *g)
{
    static const double rough[] = {1e-4, 0.05, 0.3, 0.7, 1.0};
    static const double cosines[] = {1.0, 0.7, 0.2, 1e-4};
    size_t i, k;
    for (i = 0; i < sizeof rough / sizeof rough[0]; ++i) {
        double a = (double)ggx_alpha_from_roughness((real)rough[i]);
        const char *label = rough[i] < 1e-3 ? "roughness 1e-4" : "rough";
        EMIT("ggx_alpha_from_roughness", "", label, rough[i]);
        for (k = 0; k < sizeof cosines / sizeof cosines[0]; ++k) {
            vec3 wo = dir(cosines[k], 0.3), m = dir(fmax(cosines[k], 0.5), 1.1), s;
            const char *lk = cosines[k] < 1e-3 ? "grazing" : label;
            EMIT("ggx_D", "", lk, (double)m.x, (double)m.y, (double)m.z, a);
            EMIT("ggx_G1", "", lk, (double)wo.x, (double)wo.y, (double)wo.z, (double)m.x, (double)m.y, (double)m.z, a);
            EMIT("ggx_vndf_pdf", "", lk, (double)wo.x, (double)wo.y, (double)wo.z, (double)m.x, (double)m.y,
                 (double)m.z, a);
            EMIT("ggx_vndf_sample", "", lk, (double)wo.x, (double)wo.y, (double)wo.z, 0.37, 0.81, a);
            s = ggx_vndf_sample(wo, v2((real)0.37, (real)0.81), (real)a);
            EMIT("ggx_vndf_sample_inverse", "", lk, (double)wo.x, (double)wo.y, (double)wo.z, (double)s.x, (double)s.y,
                 (double)s.z, a);
        }
    }
    EMIT("fresnel_dielectric", "", "normal", 1.0, 1.5);
    EMIT("fresnel_dielectric", "", "grazing", 1e-4, 1.5);
    EMIT("fresnel_dielectric", "", "inside", -0.5, 1.5);
    EMIT("fresnel_dielectric", "", "total internal reflection", -0.2, 1.5);
}

static void gen_bsdf(gen *g)
{
    /* type, Kd, Ks, roughness, ior */
    static const double mats[][9] = {
        {MAT_LAMBERT, 0.8, 0.5, 0.2, 0, 0, 0, 1, 1.5},      {MAT_CONDUCTOR, 0, 0, 0, 0.9, 0.6, 0.3, 1e-4, 1.5},
        {MAT_CONDUCTOR, 0, 0, 0, 0.9, 0.6, 0.3, 0.3, 1.5},  {MAT_CONDUCTOR, 0, 0, 0, 0.9, 0.6, 0.3, 1.0, 1.5},
        {MAT_PLASTIC, 0.5, 0.2, 0.1, 1, 1, 1, 0.5, 1.5},    {MAT_PLASTIC, 0.5, 0.2, 0.1, 1, 1, 1, 1e-4, 1.5},
        {MAT_DIELECTRIC, 0, 0, 0, 1, 1, 1, 0, 1.5},         {MAT_ROUGH_DIELECTRIC, 0, 0, 0, 1, 1, 1, 0.3, 1.5}};
    static const char *const mat_names[] = {"lambert", "conductor r=1e-4", "conductor r=0.3", "conductor r=1",
                                            "plastic r=0.5", "plastic r=1e-4", "smooth glass", "rough glass r=0.3"};
    static const double cosines[] = {1.0, 0.6, 1e-4, -0.5};
    size_t i, k;
    for (i = 0; i < sizeof mats / sizeof mats[0]; ++i) {
        const double *m = mats[i];
        bsdf b = in_bsdf(m);
        int lobes = bsdf_lobe_count(&b), l;
        for (k = 0; k < sizeof cosines / sizeof cosines[0]; ++k) {
            vec3 wo = dir(cosines[k], 0.4), wi = dir(0.5, 2.0), wr = v3(-wo.x, -wo.y, wo.z), wt = dir(-0.6, 3.5);
            char label[96];
            snprintf(label, sizeof label, "%s, %s", mat_names[i],
                     cosines[k] < 0 ? "wo below" : cosines[k] < 1e-3 ? "grazing wo" : "wo above");
            EMIT("bsdf_lobe_probabilities", "GRIS 50", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8],
                 (double)wo.x, (double)wo.y, (double)wo.z);
            EMIT("bsdf_eval_pdf", "GRIS 49", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8],
                 (double)wo.x, (double)wo.y, (double)wo.z, (double)wi.x, (double)wi.y, (double)wi.z);
            EMIT("bsdf_eval_pdf", "GRIS 49", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8],
                 (double)wo.x, (double)wo.y, (double)wo.z, (double)wr.x, (double)wr.y, (double)wr.z);
            EMIT("bsdf_sample", "GRIS 50", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], (double)wo.x,
                 (double)wo.y, (double)wo.z, 0.3, 0.42, 0.77);
            EMIT("bsdf_sample", "GRIS 50", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], (double)wo.x,
                 (double)wo.y, (double)wo.z, 0.95, 1e-7, 0.999999);
            for (l = 0; l < lobes; ++l) {
                bsdf_sample_record s;
                EMIT("bsdf_lobe_eval_pdf", "GRIS 50", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], l,
                     (double)wo.x, (double)wo.y, (double)wo.z, (double)wi.x, (double)wi.y, (double)wi.z);
                EMIT("bsdf_lobe_eval_pdf", "GRIS 50", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], l,
                     (double)wo.x, (double)wo.y, (double)wo.z, (double)wt.x, (double)wt.y, (double)wt.z);
                EMIT("bsdf_lobe_sample", "GRIS 50", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], l,
                     (double)wo.x, (double)wo.y, (double)wo.z, 0.42, 0.77);
                memset(&s, 0, sizeof s);
                if (bsdf_lobe_sample(&b, l, wo, v2((real)0.42, (real)0.77), &s))
                    EMIT("bsdf_lobe_sample_inverse", "GRIS 50", label, m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7],
                         m[8], l, (double)wo.x, (double)wo.y, (double)wo.z, (double)s.wi.x, (double)s.wi.y,
                         (double)s.wi.z);
            }
        }
    }
}

static void gen_light(gen *g)
{
    EMIT("pdf_area_to_solid_angle", "", "facing", 0.25, 0, 0, 0, 0, 0, 2, 0, 0, -1);
    EMIT("pdf_area_to_solid_angle", "", "oblique", 0.25, 0, 0, 0, 1, 0.5, 2, 0, 0.6, -0.8);
    EMIT("pdf_area_to_solid_angle", "", "grazing", 0.25, 0, 0, 0, 1, 0, 0, 0, 1e-6, -1);
    EMIT("pdf_area_to_solid_angle", "", "nearly coincident", 0.25, 0, 0, 0, 1e-7, 0, 1e-7, 0, 0, -1);
    EMIT("pdf_area_to_solid_angle", "", "coincident", 0.25, 1, 1, 1, 1, 1, 1, 0, 0, -1);
    EMIT("light_emitted", "", "front", 5, 4, 3, 0, 0, 1, 0.3, 0, 0.9);
    EMIT("light_emitted", "", "back", 5, 4, 3, 0, 0, 1, 0.3, 0, -0.9);
    EMIT("light_emitted", "", "grazing", 5, 4, 3, 0, 0, 1, 1, 0, 1e-9);
    EMIT("light_sample_point_inverse", "", "interior", 0.2, 0.3);
    EMIT("light_sample_point_inverse", "", "vertex", 0, 0);
}

static void gen_wrs(gen *g)
{
    static const char ris[] = "GRIS 1;Mutations 5;Mutations 7;Mutations 11;Stochastic MIS 2";
    static const char gris[] = "GRIS 6;GRIS 7;GRIS 19;Enhanced 1;Mutations 12;Mutations 13;Stochastic MIS 6";
    static const char fin[] = "GRIS 2;GRIS 22;Mutations 8;Stochastic MIS 7";
    EMIT("wrs_update", "Mutations 6", "first candidate", 0, 0.5, 0.99);
    EMIT("wrs_update", "Mutations 6", "accepted", 1.0, 0.5, 0.3);
    EMIT("wrs_update", "Mutations 6", "rejected", 1.0, 0.5, 0.34);
    EMIT("wrs_update", "Mutations 6", "boundary u = w/wsum", 1.5, 0.5, 0.25);
    EMIT("wrs_update", "Mutations 6", "zero weight", 1.0, 0, 0.0);
    EMIT("wrs_update", "Mutations 6", "negative weight", 1.0, -0.5, 0.0);
    EMIT("wrs_update", "Mutations 6", "NaN weight", 1.0, NAN, 0.0);
    EMIT("wrs_update", "Mutations 6", "infinite weight", 1.0, INFINITY, 0.0);
    EMIT("ris_candidate_weight", ris, "one tree", 0.7, 1.0, 1);
    EMIT("ris_candidate_weight", ris, "32 trees, roulette", 0.7, 4.0, 32);
    EMIT("ris_candidate_weight", ris, "zero target", 0.0, 3.0, 4);
    EMIT("gris_resampling_weight", gris, "canonical", 0.5, 0.8, 2.0, 1.0);
    EMIT("gris_resampling_weight", gris, "shifted", 0.25, 0.8, 2.0, 1.7);
    EMIT("gris_resampling_weight", gris, "failed shift (J = 0, infinite UCW)", 0.25, 0.8, INFINITY, 0.0);
    EMIT("gris_resampling_weight", gris, "zero target", 0.25, 0.0, 2.0, INFINITY);
    EMIT("gris_resampling_weight", gris, "tiny jacobian", 1.0, 1e-300, 1e300, 1e-10);
    EMIT("reservoir_stream_finalize", fin, "empty", 0);
    EMIT("reservoir_stream_finalize", fin, "three candidates", 3, 0.5, 0.9, 1.2, 1, 0.25, 0.1, 0.4, 1, 1.0, 0.5, 2.0, 1);
    EMIT("reservoir_stream_finalize", fin, "zero weights only", 2, 0, 0.1, 1.0, 1, 0, 0.9, 1.0, 1);
    EMIT("reservoir_stream_finalize", fin, "selected target 0 (null sample)", 1, 0.5, 0.2, 0.0, 1);
    EMIT("reservoir_stream_finalize", fin, "NaN and negative skipped", 3, NAN, 0.1, 1, 1, -1, 0.1, 1, 1, 0.3, 0.5, 0.6,
         1);
    EMIT("reservoir_estimate", "Mutations 9", "gray", 0.5, 0.5, 0.5, 2.0);
    EMIT("reservoir_estimate", "Mutations 9", "colour", 1.0, 0.2, 0.05, 0.75);
    EMIT("reservoir_estimate", "Mutations 9", "null sample", 1.0, 0.2, 0.05, 0.0);
    EMIT("reservoir_cap_confidence", "", "capped", 45, 20);
    EMIT("reservoir_cap_confidence", "", "below cap", 5, 20);
    EMIT("reservoir_cap_confidence", "", "infinite cap", 5, INFINITY);
}

static void emit_mis(gen *g, int family, int M, int R, const double *c, const double *p, int j, const char *label)
{
    static const char *const eqs[] = {"", "GRIS 5;GRIS 36;Stochastic MIS 9",
                                      "GRIS 37", "GRIS 38;Stochastic MIS 11a;Stochastic MIS 11b;Stochastic MIS 12"};
    double in[VECTORS_MAX_IN];
    int n = 0, i;
    in[n++] = family;
    in[n++] = M;
    in[n++] = R;
    for (i = 0; i < M; ++i) in[n++] = c[i];
    for (i = 0; i < M * M; ++i) in[n++] = p[i];
    in[n++] = j;
    emit(g, "mis_weights", eqs[family], label, in, n);
}

/* The Falcor confidence form of GRIS Eq. 38 (mis_pairwise_defensive_falcor): the same
 * inputs as the stochastic form's rows above, plus two cases that tell the forms apart or
 * together: equal confidences (both forms agree) and one neighbour with a temporal-like
 * confidence 20 against 1 (they differ most). */
static void emit_mis_falcor_rows(gen *g, const double *c3, const double *p3, const double *zero3, const double *c4,
                                 const double *p4)
{
    static const double c_equal[] = {1, 1, 1}, c2[] = {1, 20}, p2[] = {0.8, 0.6, 0.5, 0.9};
    double in[VECTORS_MAX_IN];
    struct {
        int M, R;
        const double *c, *p;
        const char *label;
    } cases[5];
    int k, i, j, n;
    cases[0].M = 3, cases[0].R = 1, cases[0].c = c3, cases[0].p = p3, cases[0].label = "3 domains, R = 1";
    cases[1].M = 3, cases[1].R = 1, cases[1].c = c3, cases[1].p = zero3, cases[1].label = "zero targets everywhere";
    cases[2].M = 4, cases[2].R = 2, cases[2].c = c4, cases[2].p = p4,
    cases[2].label = "4 domains, R = 2, temporal-like confidence 20";
    cases[3].M = 3, cases[3].R = 1, cases[3].c = c_equal, cases[3].p = p3,
    cases[3].label = "equal confidences: equals the stochastic form";
    cases[4].M = 2, cases[4].R = 1, cases[4].c = c2, cases[4].p = p2,
    cases[4].label = "one neighbour, confidence 20 against 1: the forms differ most";
    for (k = 0; k < 5; ++k)
        for (j = 0; j < cases[k].M; ++j) {
            n = 0;
            in[n++] = cases[k].M;
            in[n++] = cases[k].R;
            for (i = 0; i < cases[k].M; ++i) in[n++] = cases[k].c[i];
            for (i = 0; i < cases[k].M * cases[k].M; ++i) in[n++] = cases[k].p[i];
            in[n++] = j;
            emit(g, "mis_pairwise_defensive_falcor", "GRIS 38", cases[k].label, in, n);
        }
    /* the stochastic form on the two new cases, for a side-by-side comparison */
    for (j = 0; j < 3; ++j) emit_mis(g, 3, 3, 1, c_equal, p3, j, "equal confidences: equals the Falcor form");
    for (j = 0; j < 2; ++j) emit_mis(g, 3, 2, 1, c2, p2, j, "one neighbour, confidence 20 against 1: the forms differ most");
}

static void gen_mis(gen *g)
{
    /* 3 domains, canonical 0; p[i*3 + j] = p̂_{<-i}(y_j) */
    static const double c3[] = {1, 2, 0.5}, p3[] = {0.8, 0.6, 0.1, 0.5, 0.9, 0.2, 0.0, 0.3, 0.7};
    static const double zero3[] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    static const double c4[] = {1, 1, 20, 3},
                        p4[] = {1, 0.5, 0.25, 2, 0.7, 1, 0.1, 0.2, 0.3, 0.4, 1.5, 0, 1e-12, 5, 0.6, 0.9};
    int f, j;
    for (f = 0; f <= 3; ++f)
        for (j = 0; j < 3; ++j) {
            emit_mis(g, f, 3, 1, c3, p3, j, "3 domains, R = 1");
            emit_mis(g, f, 3, 1, c3, zero3, j, "zero targets everywhere");
        }
    for (f = 0; f <= 3; ++f)
        for (j = 0; j < 4; ++j) emit_mis(g, f, 4, 2, c4, p4, j, "4 domains, R = 2, temporal-like confidence 20");
    emit_mis_falcor_rows(g, c3, p3, zero3, c4, p4);
    EMIT("mis_pair_canonical", "Mutations 31", "two frames", 1, 0.8, 20, 0.6);
    EMIT("mis_pair_canonical", "Mutations 31", "failed reverse shift", 1, 0.8, 20, 0);
    EMIT("mis_pair_canonical", "Mutations 31", "zero denominator", 1, 0, 20, 0);
    EMIT("mis_pair_neighbor", "Mutations 32", "two frames", 20, 0.6, 1, 0.8);
    EMIT("mis_pair_neighbor", "Mutations 32", "zero target at the current pixel", 20, 0.6, 1, 0);
    EMIT("mis_pair_neighbor", "Mutations 32", "zero denominator", 20, 0, 1, 0);
}

static void gen_reconnection(gen *g)
{
    static const char eqs[] = "GRIS 52;GRIS 54;Enhanced 2";
    EMIT("rc_jacobian", eqs, "identity (own pixel)", 0.3, 0.05, 0.8, 0.3, 0.05, 0.8);
    EMIT("rc_jacobian", eqs, "k = d (pdf_k = 1)", 0.4, 0.02, 1, 0.3, 0.05, 1);
    EMIT("rc_jacobian", eqs, "nearly coincident vertices (huge G)", 0.3, 1e12, 0.8, 0.3, 1e10, 0.8);
    EMIT("rc_jacobian", eqs, "grazing at x_k (tiny G)", 0.3, 1e-9, 0.8, 0.3, 0.05, 0.8);
    EMIT("rc_jacobian", eqs, "failed shift (offset pdf 0)", 0, 0.05, 0.8, 0.3, 0.05, 0.8);
    EMIT("rc_jacobian", eqs, "degenerate base (denominator 0)", 0.3, 0.05, 0.8, 0, 0.05, 0.8);
}

/* Every shift from a few base pixels to their neighbours (and to themselves: J = 1), for
 * three seeds: successes with each mapping and the failure reasons the scene produces. */
static void gen_shift(gen *g)
{
    static const char eqs[] = "Stochastic MIS 5;GRIS 35;Stochastic MIS 10;GRIS 54";
    static const int pix[][4] = {{12, 9, 12, 9}, {12, 9, 13, 9}, {5, 12, 6, 13}, {20, 4, 18, 4},
                                 {3, 3, 4, 3},   {12, 15, 11, 15}, {8, 9, 16, 9}};
    static const char *const names[] = {"reconnection", "random replay", "hybrid"};
    size_t i;
    int kind, seed;
    char label[96];
    for (kind = 0; kind < 3; ++kind)
        for (seed = 1; seed <= 3; ++seed)
            for (i = 0; i < sizeof pix / sizeof pix[0]; ++i) {
                snprintf(label, sizeof label, "%s, %s", names[kind],
                         pix[i][0] == pix[i][2] && pix[i][1] == pix[i][3] ? "own pixel" : "neighbour");
                EMIT("shift_path", eqs, label, kind, seed, pix[i][0], pix[i][1], pix[i][2], pix[i][3]);
            }
}

static void gen_stochastic(gen *g)
{
    static const char e15[] = "Stochastic MIS 15", e17[] = "Stochastic MIS 17", e19[] = "Stochastic MIS 19";
    static const char e16[] = "Stochastic MIS 11a;Stochastic MIS 16";
    static const char step[] = "Stochastic MIS 14;Stochastic MIS 15;Stochastic MIS 16;Stochastic MIS 17;"
                               "Stochastic MIS 18;Stochastic MIS 19";
    EMIT("stochastic_pick", e15, "3 domains, 4 picks", 3, 4, 0.5, 0.3, 0.2, 0.1, 0.45, 0.7, 0.95);
    EMIT("stochastic_pick", e15, "u on a CDF boundary (0.5, 0.8)", 3, 2, 0.5, 0.3, 0.2, 0.5, 0.8);
    EMIT("stochastic_pick", e15, "u = 0 and u just below 1", 3, 2, 0.5, 0.3, 0.2, 0, 0.99999999999999989);
    EMIT("stochastic_pick", e15, "a zero-probability domain is never picked", 3, 3, 0.6, 0, 0.4, 0.6, 0.59999999999999998,
         0.6000000000000001);
    EMIT("stochastic_pick", e15, "all P = 0: no pick", 2, 2, 0, 0, 0.3, 0.7);
    EMIT("stochastic_mis_weight", e15, "K = 2 of 4 picks, P = 0.25", 2, 4, 0.25, 0.3);
    EMIT("stochastic_mis_weight", e15, "not picked", 0, 4, 0.25, 0.3);
    EMIT("stochastic_mis_weight", e15, "P = 0", 0, 4, 0, 0.3);
    EMIT("stochastic_mis_weight", e15, "one pick, P = 1: m~ = m", 1, 1, 1, 0.3);
    EMIT("stochastic_mis_weight", e15, "tiny P (large m~)", 1, 1, 1e-12, 0.5);
    EMIT("stochastic_selection_p", e17, "3 domains", 3, 1, 2, 3);
    EMIT("stochastic_selection_p", e17, "negative and NaN count as 0", 4, 1, -1, NAN, 2);
    EMIT("stochastic_selection_p", e17, "infinite weight counts as 0", 3, 1, INFINITY, 1);
    EMIT("stochastic_selection_p", e17, "all zero", 2, 0, 0);
    EMIT("stochastic_selection_p", e17, "extreme range", 3, 1e-30, 1, 1e30);
    EMIT("stochastic_pairwise_m", e16, "c_c 1, c_S 3", 1, 3, 1, 0.4, 0.7);
    EMIT("stochastic_pairwise_m", e16, "zero target at the pixel", 1, 3, 1, 0.4, 0);
    EMIT("stochastic_pairwise_m", e16, "empty pair (q = p = 0)", 1, 3, 1, 0, 0);
    EMIT("stochastic_pairwise_m", e16, "C = 0", 0, 0, 0, 0.4, 0.7);
    EMIT("stochastic_pairwise_m", e16, "temporal-like confidence 20", 1, 20, 20, 0.4, 0.7);
    EMIT("stochastic_pairwise_b", e19, "c_c 1, c_S 3", 1, 3, 1, 0.4, 0.7);
    EMIT("stochastic_pairwise_b", e19, "failed reverse shift (q = 0)", 1, 3, 1, 0, 0.7);
    EMIT("stochastic_pairwise_b", e19, "empty pair (q = p = 0)", 1, 3, 1, 0, 0);
    EMIT("stochastic_pairwise_b", e19, "C = 0", 0, 0, 0, 0.4, 0.7);
    EMIT("stochastic_confidence_scale", "", "N~ = 1 of M = 4", 1, 4);
    EMIT("stochastic_confidence_scale", "", "N~ = M: deterministic pairwise", 4, 4);
    EMIT("stochastic_confidence_scale", "", "N~ > M", 8, 4);
    EMIT("stochastic_confidence_scale", "", "no neighbour", 1, 0);
    /* whole steps: n, N~, N~_c, scaling, c_c, p(Y_c), W_c, (c, p(X), W, J, p(Y), q) x n, up, uc */
    EMIT("stochastic_pairwise_weights", step, "3 neighbours, N~ = N~_c = 1, scaled confidences", 3, 1, 1, 1, 1, 0.5,
         2.0, 1, 0.3, 3.0, 0.9, 0.35, 0.45, 1, 0.8, 1.5, 1.1, 0.6, 0.2, 1, 0.1, 4.0, 1.0, 0.12, 0.3, 0.55, 0.4);
    EMIT("stochastic_pairwise_weights", step, "3 neighbours, N~ = N~_c = 2, no scaling", 3, 2, 2, 0, 1, 0.5, 2.0, 1,
         0.3, 3.0, 0.9, 0.35, 0.45, 1, 0.8, 1.5, 1.1, 0.6, 0.2, 1, 0.1, 4.0, 1.0, 0.12, 0.3, 0.1, 0.9, 0.2, 0.7);
    EMIT("stochastic_pairwise_weights", step, "the picked neighbour's shift fails (J = 0)", 2, 1, 1, 1, 1, 0.5, 2.0, 1,
         0.3, 3.0, 0, 0, 0.45, 1, 0.8, 1.5, 1.1, 0.6, 0.2, 0.2, 0.7);
    EMIT("stochastic_pairwise_weights", step, "zero confidence everywhere", 2, 1, 1, 1, 0, 0.5, 2.0, 0, 0.3, 3.0, 0.9,
         0.35, 0.45, 0, 0.8, 1.5, 1.1, 0.6, 0.2, 0.5, 0.5);
    EMIT("stochastic_pairwise_weights", step, "one neighbour, temporal-like confidence 20", 1, 1, 1, 1, 1, 0.5, 2.0, 20,
         0.3, 3.0, 0.9, 0.35, 0.45, 0.5, 0.5);
    EMIT("stochastic_pairwise_weights", step, "empty neighbour (W = 0) is never picked", 2, 1, 1, 1, 1, 0.5, 2.0, 1,
         0.3, 0, 0.9, 0.35, 0.45, 1, 0.8, 1.5, 1.1, 0.6, 0.2, 0.01, 0.5);
    /* the same step through stochastic_pairwise_resample itself, real shifts in the scene
     * (the lines above re-compose its arithmetic and cannot see a bug inside it) */
    vectors_cases_stochastic_step(emit_cb, g);
}

static void gen_pairing(gen *g)
{
    static const char eq[] = "Enhanced 3";
    static const double sig[] = {0.8, 1, 1.5, 2, 5.32, 10.64, 22};
    size_t i;
    char label[64];
    for (i = 0; i < sizeof sig / sizeof sig[0]; ++i) {
        snprintf(label, sizeof label, "sigma %g%s", sig[i], i == 0 ? " (the smallest: one pass)" : "");
        EMIT("pairing_shuffle_count", eq, label, sig[i]);
    }
    EMIT("reuse_partner_offset", eq, "w 32, sigma 5.32 (radius 10), identity placement", 32, 5.32, 1, 0, 0, 0, 0, 0, 0,
         5, 7);
    EMIT("reuse_partner_offset", eq, "the same texel wrapped (x + w)", 32, 5.32, 1, 0, 0, 0, 0, 0, 0, 37, 7);
    EMIT("reuse_partner_offset", eq, "flip, mirror, transpose and offset", 32, 5.32, 1, 0, 1, 1, 1, 9, 30, 5, 7);
    EMIT("reuse_partner_offset", eq, "texture id 3, smallest sigma", 16, 0.8, 2, 3, 0, 1, 0, 3, 0, 15, 15);
    EMIT("reuse_partner_offset", eq, "largest sigma", 64, 22, 1, 1, 1, 0, 1, 63, 0, 100, 200);
    for (i = 0; i < 3; ++i) EMIT("reuse_transform_draw", eq, "per-frame placement", 32, 5.32, 1, 0, (double)i);
    EMIT("reuse_transform_draw", eq, "texture id 7", 32, 5.32, 1, 7, 0);
}

/* x_{k-1} = a material on z = 0 at the origin seen from (1, 0, 1); x_k mostly on a ceiling
 * at height 2 facing down. */
#define FP_LAMBERT 0, 0.5, 0.5, 0.5, 0, 0, 0, 1, 1
#define FP_METAL(r) 1, 0, 0, 0, 0.9, 0.9, 0.9, r, 1
#define FP_MIRROR 3, 0, 0, 0, 0, 0, 0, 0, 1.5
#define FP_PREV(mat, lobe) mat, 0, 0, 0, 0, 0, 1, 1, 0, 1, lobe
#define FP_CEIL(mat, z, lobe) mat, 0, 0, z, 0, 0, -1, 0, 0, -1, lobe, 1, 0, -1
static void gen_footprint(gen *g)
{
    static const char eq[] = "Enhanced 5";
    EMIT("rc_footprint_test", eq, "Lambert -> Lambert: forward pi d^2, inverse skipped", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_LAMBERT, 2, 0), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "glossy x_k (roughness 0.4): both footprints", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_METAL(0.4), 2, 0), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "roughness 1e-4 at x_k: tiny inverse footprint", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_METAL(1e-4), 2, 0), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "mirror x_k: zero footprint, never connectable", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_MIRROR, 2, 0), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "x_k sampled by NEE at x_{k-1}, light vertex: both skipped",
         FP_PREV(FP_LAMBERT, -1), 1, FP_CEIL(FP_LAMBERT, 2, -2), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "NEE direction at x_k: inverse skipped", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_METAL(0.4), 2, -1), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "x_{k-1} not rough (roughness 1e-4)", FP_PREV(FP_METAL(1e-4), 0), 0,
         FP_CEIL(FP_LAMBERT, 2, 0), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "nearly coincident vertices", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_LAMBERT, 1e-6, 0), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "coincident vertices: zero footprint", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_LAMBERT, 0, 0), 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "grazing x_k (far along the floor)", FP_PREV(FP_LAMBERT, 0), 0, FP_LAMBERT, 50, 0,
         1e-3, 0, 0, -1, 0, 0, -1, 0, 1, 0, -1, 0.2, 0.02, 1000);
    EMIT("rc_footprint_test", eq, "large primary footprint: threshold not met", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_LAMBERT, 2, 0), 0.2, 0.02, 1e6);
    EMIT("rc_footprint_test", eq, "c = 2 (postponed reconnection)", FP_PREV(FP_LAMBERT, 0), 0,
         FP_CEIL(FP_LAMBERT, 2, 0), 0.2, 2, 1000);
    EMIT("rc_primary_footprint", eq, "distance 5, cos 0.8", 5, 0, 0, 1, 0, 0.6, 0.8);
    EMIT("rc_primary_footprint", eq, "head-on", 1, 0, 0, 1, 0, 0, 1);
    EMIT("rc_primary_footprint", eq, "grazing: infinite", 3, 0, 0, 1, 1, 0, 0);
}

/* The families in file order with their generators: a new family is one row here (its
 * evaluators are rows of `table` above). */
typedef struct {
    const char *name;
    void (*generate)(gen *g);
} vector_family;

/* MCMC mutations: the Kelemen kernel (symmetric, wrapped, s in (s1, s2]), the acceptance of
 * Eqs. 14/19, the UCW update of Eqs. 16/23, the rv kernel ratio of Eq. 20. */
static void gen_mutation(gen *g)
{
    static const double pert[][2] = {{0.5, 0.0}, {0.5, 0.25}, {0.5, 0.4999}, {0.5, 0.5}, {0.5, 0.75}, {0.5, 0.9999},
                                     {0.001, 0.75}, {0.999, 0.25}, {0.0, 0.6}};
    static const char *const plabel[] = {"add s2",          "add sqrt(s1 s2)", "add ~s1",      "subtract s2",
                                         "subtract sqrt(s1 s2)", "subtract ~s1", "wrap below 0", "wrap above 1",
                                         "u = 0 subtract"};
    size_t i;
    for (i = 0; i < sizeof pert / sizeof pert[0]; ++i)
        EMIT("mutate_perturb", "Mutations 19", plabel[i], pert[i][0], pert[i][1]);
    /* the paper's Gaussian kernel (--mutation-kernel gaussian; b and b + 1/2 mirror a step) */
    EMIT("mutate_perturb_gaussian", "Mutations 19", "paper's amount, U = 0 (s2)", 0.5, 0.6, 0.1, 0.0, 0.0);
    EMIT("mutate_perturb_gaussian", "Mutations 19", "the mirrored step (b + 1/2)", 0.5, 0.6, 0.6, 0.0, 0.0);
    EMIT("mutate_perturb_gaussian", "Mutations 19", "paper's amount, U = 1/2", 0.5, 0.9, 0.3, 0.5, 0.0);
    EMIT("mutate_perturb_gaussian", "Mutations 19", "fixed sigma 0.02", 0.25, 0.5, 0.05, 0.7, 0.02);
    EMIT("mutate_perturb_gaussian", "Mutations 19", "wrap above 1", 0.995, 0.95, 0.0, 0.0, 0.05);
    EMIT("mutate_perturb_gaussian", "Mutations 19", "wrap below 0", 0.005, 0.95, 0.5, 0.0, 0.05);
    EMIT("mutate_perturb_gaussian", "Mutations 19", "a = 0 (no step)", 0.3, 0.0, 0.2, 0.4, 0.0);
    EMIT("mutate_acceptance", "Mutations 14;Mutations 19", "symmetric, uphill", 0.2, 0.5, 1.0);
    EMIT("mutate_acceptance", "Mutations 14;Mutations 19", "symmetric, downhill", 0.5, 0.2, 1.0);
    EMIT("mutate_acceptance", "Mutations 14;Mutations 19", "asymmetric kernel", 0.5, 0.2, 3.0);
    EMIT("mutate_acceptance", "Mutations 14;Mutations 19", "impossible reverse (ratio 0)", 0.5, 0.7, 0.0);
    EMIT("mutate_weight", "Mutations 16;Mutations 23", "to a brighter sample", 2.0, 0.2, 0.5);
    EMIT("mutate_weight", "Mutations 16;Mutations 23", "to a darker sample", 2.0, 0.5, 0.2);
    EMIT("mutate_weight", "Mutations 16;Mutations 23", "same target", 3.0, 0.4, 0.4);
    EMIT("mutate_eq20_ratio", "Mutations 20", "identity", 0.3, 0.05, 0.8, 0.3, 0.05, 0.8);
    EMIT("mutate_eq20_ratio", "Mutations 20", "closer to x_{k+1} (larger G)", 0.3, 0.2, 0.8, 0.3, 0.05, 0.8);
    EMIT("mutate_eq20_ratio", "Mutations 20", "x_{k+1} last or NEE (p(w_k, w_{k+1}) = 1)", 0.4, 0.02, 1, 0.3, 0.05, 1);
    EMIT("mutate_eq20_ratio", "Mutations 20", "x_{k+1} NEE-sampled from x_k (all 1)", 1, 1, 1, 1, 1, 1);
    EMIT("mutate_eq20_ratio", "Mutations 20", "degenerate current path (A(y) = 0)", 0.3, 0.05, 0.8, 0, 0.05, 0.8);
    vectors_cases_mutate_step(emit_cb, g); /* whole chains and proposals through mutate.c */
}

/* The whole temporal step through temporal_resample (vectors_step.c). */
static void gen_temporal(gen *g) { vectors_cases_temporal(emit_cb, g); }

static const vector_family families[] = {
    {"rng", gen_rng},
    {"warp", gen_warp},
    {"microfacet", gen_microfacet},
    {"bsdf", gen_bsdf},
    {"light", gen_light},
    {"wrs", gen_wrs},
    {"mis", gen_mis},
    {"reconnection", gen_reconnection},
    {"shift", gen_shift},
    {"stochastic", gen_stochastic},
    {"pairing", gen_pairing},
    {"footprint", gen_footprint},
    {"mutation", gen_mutation},
    {"temporal", gen_temporal},
};
#define FAMILY_COUNT ((int)(sizeof families / sizeof families[0]))

const char *const *vectors_families(void)
{
    static const char *names[FAMILY_COUNT + 1];
    int i;
    for (i = 0; i < FAMILY_COUNT; ++i) names[i] = families[i].name;
    names[FAMILY_COUNT] = NULL;
    return names;
}

static void generate(gen *g, const vector_family *f)
{
    g->family = f->name;
    f->generate(g);
}

int vectors_cover(const char *eq)
{
    gen g;
    int i;
    memset(&g, 0, sizeof g);
    g.want_eq = eq;
    for (i = 0; i < FAMILY_COUNT; ++i) generate(&g, &families[i]);
    return g.found;
}

int vectors_write(const char *dir, rerror *e)
{
    char path[4200];
    struct stat st;
    int i;
    /* The scene first: a failure leaves no empty directory behind. */
    if (shift_scene_load())
        return rerror_set(e, "%s: cannot load it for the shift vectors (looked in the working directory and next to "
                             "the restir binary's build directory)",
                          SHIFT_SCENE);
    if (stat(dir, &st) != 0 && mkdir(dir, 0777) != 0 && errno != EEXIST)
        return rerror_set(e, "%s: cannot create directory: %s", dir, strerror(errno));
    for (i = 0; i < FAMILY_COUNT; ++i) {
        atomic_file f;
        gen g;
        memset(&g, 0, sizeof g);
        snprintf(path, sizeof path, "%s/%s.jsonl", dir, families[i].name);
        if (atomic_file_open(&f, path, e)) return -1;
        g.fp = f.fp;
        generate(&g, &families[i]);
        if (atomic_file_commit(&f, e)) return -1;
    }
    return 0;
}

/* ---- the check ----------------------------------------------------------------------- */

/* A number, or "inf", "-inf", "nan" (put_value). */
static int read_num(json_reader *r, double *v)
{
    char s[8];
    if (json_peek(r) != '"') return json_read_number(r, v);
    if (json_read_string(r, s, sizeof s)) return -1;
    if (!strcmp(s, "inf")) *v = INFINITY;
    else if (!strcmp(s, "-inf")) *v = -INFINITY;
    else if (!strcmp(s, "nan")) *v = NAN;
    else return rerror_at(r->e, r->path, r->line, "\"%s\" is not a number (\"inf\", \"-inf\" or \"nan\")", s);
    return 0;
}

static int read_array(json_reader *r, double *v, int max, int *n)
{
    *n = 0;
    if (json_expect(r, '[')) return -1;
    if (json_peek(r) == ']') return json_expect(r, ']');
    for (;;) {
        if (*n >= max) return rerror_at(r->e, r->path, r->line, "more than %d numbers", max);
        if (read_num(r, &v[(*n)++])) return -1;
        if (json_peek(r) != ',') break;
        r->pos++;
    }
    return json_expect(r, ']');
}

/* Same value: bit-identical doubles (NaN matches NaN). */
static int same_value(double want, double got)
{
    if (isnan(want) || isnan(got)) return isnan(want) && isnan(got);
    return want == got && signbit(want) == signbit(got);
}

int vectors_check_file(const char *path, long *lines, long *bad, rerror *e)
{
    json_reader r;
    int status = 0;
    *lines = *bad = 0;
    if (json_reader_open(&r, path, e)) return -1;
    while (json_peek(&r) == '{') {
        char fn[96] = "", key[32], label[128] = "", why[160];
        double in[VECTORS_MAX_IN], want[VECTORS_MAX_OUT], got[VECTORS_MAX_OUT];
        int n_in = -1, n_want = -1, n_got, i;
        long line;
        const vector_fn *f;
        json_expect(&r, '{');
        line = r.line;
        for (;;) {
            int st;
            if (json_read_string(&r, key, sizeof key) || json_expect(&r, ':')) goto malformed;
            if (!strcmp(key, "fn")) st = json_read_string(&r, fn, sizeof fn);
            else if (!strcmp(key, "case")) st = json_read_string(&r, label, sizeof label);
            else if (!strcmp(key, "in")) st = read_array(&r, in, VECTORS_MAX_IN, &n_in);
            else if (!strcmp(key, "out")) st = read_array(&r, want, VECTORS_MAX_OUT, &n_want);
            else st = json_skip_value(&r);
            if (st) goto malformed;
            if (json_peek(&r) != ',') break;
            r.pos++;
        }
        if (json_expect(&r, '}')) goto malformed;
        ++*lines;
        if (!(f = find_fn(fn)) || n_in < 0 || n_want < 0) {
            rerror_at(e, path, line, "unknown \"fn\" '%s' or missing \"in\"/\"out\"", fn);
            goto malformed;
        }
        /* A bad input or input count is a bad vector (exit 2), not a differing output. */
        if (vectors_input_problem(fn, in, n_in, why, sizeof why)) {
            rerror_at(e, path, line, "%s (%s): %s", fn, label, why);
            goto malformed;
        }
        n_got = f->eval(in, n_in, got);
        if (n_got < 0) {
            rerror_at(e, path, line, "%s (%s): %d inputs do not fit \"%s\"", fn, label, n_in, f->sig);
            goto malformed;
        }
        if (n_got != n_want) {
            if (!*bad) rerror_at(e, path, line, "%s (%s): %d outputs, the vector has %d", fn, label, n_got, n_want);
            ++*bad;
            continue;
        }
        for (i = 0; i < n_got; ++i)
            if (!same_value(want[i], got[i])) {
                if (!*bad)
                    rerror_at(e, path, line, "%s (%s): output %d is %.17g, the vector says %.17g", fn, label, i, got[i],
                              want[i]);
                ++*bad;
                break;
            }
    }
    if (json_expect_end(&r)) goto malformed;
    json_reader_close(&r);
    if (*lines == 0) return rerror_at(e, path, 0, "no vectors (an empty file checks nothing)");
    return *bad ? 1 : status;
malformed:
    json_reader_close(&r);
    return -1;
}
