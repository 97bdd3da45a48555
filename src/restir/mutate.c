/* MCMC mutations after resampling (Mutations §3 Algorithm 3, §4.1-4.3, App. C; include/restir/restir/mutate.h,
 * docs/mutations.md). */
#include "restir/restir/mutate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/reconnection.h"
#include "restir/scene/scene_trace.h"

const char *const mutate_strategy_names[] = {"rv", "pp", "fp", NULL};
const char *const mutate_after_names[] = {"none", "initial", "temporal", "initial,temporal", "spatial",
                                          "initial,spatial", "temporal,spatial", "initial,temporal,spatial", NULL};
const char *const mutate_kernel_names[] = {"kelemen", "gaussian", NULL};
const char *const mutate_skip_names[] = {"empty", "no_reconnection", "inverse", "irreproducible", NULL};
const char *const mutate_reject_names[] = {"replay", "inverse", "occluded", "structure", "zero", NULL};

void mutate_stats_add(mutate_stats *acc, const mutate_stats *add)
{
    int i;
    acc->pixels += add->pixels;
    acc->skipped += add->skipped;
    for (i = 0; i < MUTATE_REASON_SKIP_COUNT; ++i) acc->skip[i] += add->skip[i];
    acc->proposals += add->proposals;
    acc->accepted += add->accepted;
    acc->rejected_mh += add->rejected_mh;
    acc->pss_numbers += add->pss_numbers;
    acc->duplicates += add->duplicates;
    acc->final_valid += add->final_valid;
    for (i = 0; i < MUTATE_REJECT_COUNT; ++i) acc->rejected[i] += add->rejected[i];
}

/* Mutations §4.1, the proposal of the PSS chain of Mutations Eq. 19 (Kelemen et al.
 * 2002): s = s2 exp(-log(s2/s1) U), s in (s1, s2], added or subtracted with probability 1/2 each, wrapped to [0,1): a symmetric kernel on the circle. */
real mutate_perturb(real u, real xi)
{
    int up = xi < (real)0.5;
    real U = up ? 2 * xi : 2 * xi - 1;
    real s = (real)MUTATE_S2 * (real)exp(-log(MUTATE_S2 / MUTATE_S1) * (double)U);
    real v = up ? u + s : u - s;
    if (v >= 1) v -= 1;
    if (v < 0) v += 1;
    if (!(v >= 0 && v < 1)) v = 0; /* u - s + 1 rounded up to 1 */
    return v;
}

/* Mutations §4.1 as the paper states it ("perturbing each element of u with Gaussian noise",
 * amount s = s2 exp(-log(s2/s1) U)): the symmetric proposal of Mutations Eq. 19, whose kernel
 * ratio is then 1; docs/mutations.md "Kernels" derives the symmetry:
 * the step d = s n has an even law (the sign is a separate fair number), and wrapping
 * makes the kernel a translation on the circle, so T(x->y) = sum_k f(y - x + k) =
 * T(y->x). The sum is in double; a result that rounds to 1 is 0 (as mutate_perturb). */
real mutate_perturb_gaussian(real u, const real xi[3], double sigma)
{
    const double two_pi = 6.283185307179586;
    double b = (double)xi[1], sign = b < 0.5 ? 1.0 : -1.0;
    double angle = b < 0.5 ? 2 * b : 2 * b - 1;
    double radius = sqrt(-2.0 * log(1.0 - (double)xi[0]));
    double s = sigma > 0 ? sigma : MUTATE_S2 * exp(-log(MUTATE_S2 / MUTATE_S1) * (double)xi[2]);
    double v = (double)u + sign * s * radius * cos(two_pi * angle);
    real r;
    v -= floor(v); /* wrap: the circle */
    r = (real)v;
    return r >= 0 && r < 1 ? r : 0;
}

/* Mutations Eq. 14 in PSS (Mutations Eq. 19): the acceptance probability before min(1, .). */
real mutate_acceptance(real target_x, real target_z, real ratio)
{
    return target_z * ratio / target_x;
}

/* Mutations Eq. 23: W(x^k) = p̂(x^{k-1}) / p̂(x^k) W(x^{k-1}); over the chain Mutations Eq. 16. */
real mutate_weight(real W, real target_x, real target_z)
{
    return W * (target_x / target_z);
}

int mutate_bsdf_vertices(const path_sample *y)
{
    if (!path_sample_is_valid(y)) return 0;
    return y->length - 1 - (y->technique == PATH_TECH_NEE);
}

static real unit_open(real u)
{
    if (!(u >= 0)) return 0;
    return u < 1 ? u : (real)(1.0 - 1.0 / 16777216.0); /* the largest float below 1 */
}

/* Inverse sampling (§4, [Bitterli et al. 2017]): the numbers with which vertex v samples the
 * world direction w through `lobe`: the direction numbers by the lobe's sample_inverse, the
 * lobe number uniform in the lobe's interval [lo, hi) of bsdf_select_lobe (xi). 1 on success. */
int mutate_invert_bounce(const path_vertex *v, int lobe, vec3 w, real xi, real u[3])
{
    real lo, hi;
    vec2 d;
    vec3 wi = shading_frame_to_local(&v->frame, w);
    if (lobe < 0 || lobe >= bsdf_lobe_count(&v->b) || bsdf_lobe_is_delta(&v->b, lobe)) return 0;
    bsdf_lobe_interval(&v->b, v->wo_local, lobe, &lo, &hi);
    if (!(hi > lo)) return 0;
    if (!bsdf_lobe_sample_inverse(&v->b, lobe, v->wo_local, wi, &d)) return 0;
    u[0] = lo + xi * (hi - lo);
    if (!(u[0] < hi)) u[0] = lo;
    u[0] = unit_open(u[0]);
    u[1] = unit_open(d.x);
    u[2] = unit_open(d.y);
    return 1;
}

/* The direction in which vertex v must sample to hit the point `target`: from the ray's
 * spawn origin (scene_spawn_ray offsets it off the surface by a few hundred ulps), so that
 * the replayed ray lands on the target to float precision. */
vec3 mutate_direction_to(const path_vertex *v, vec3 target)
{
    vec3 d0 = v3_normalize(v3_sub(target, v->position));
    ray r = scene_spawn_ray(v->hit.position, v->hit.ng, v3f_from(d0), v3f_from(v->wo));
    return v3_normalize(v3_sub(target, v3_from_f(r.origin)));
}

static void set_numbers(path_sample *s, int vertex, const real u[3])
{
    int j;
    for (j = 0; j < PATH_PSS_PER_VERTEX; ++j) s->pss[(vertex - 1) * PATH_PSS_PER_VERTEX + j] = u[j];
}

/* Numbered vertices of a sample: x_1..x_{d-1}; the last one's numbers are the NEE point
 * numbers (path_sample.h) when x_d is NEE-sampled. */
static int numbered_vertices(const path_sample *y) { return path_sample_is_valid(y) ? y->length - 1 : 0; }

/* The sample with every number explicit (mutate.h). */
int mutate_explicit(const restir_context *c, const path_vertex *y1, const path_sample *y, const real xi_lobe[2],
                    path_sample *u)
{
    path_trunk t;
    int nb = mutate_bsdf_vertices(y), k = y->rc_k, v;
    real n[4], *store = u->pss; /* the caller's storage (mutate.h) */
    *u = *y;
    path_sample_copy_pss(y, store);
    u->pss = store;
    for (v = 1; v <= nb; ++v) { /* the numbers the sample replays (identity or explicit) */
        path_bsdf_numbers(y, v, n);
        set_numbers(u, v, n);
    }
    if (y->technique == PATH_TECH_NEE) { /* the point on the light (the light itself stays) */
        path_nee_numbers(y, n);
        n[0] = 0; /* unused slot */
        n[1] = n[2];
        n[2] = n[3];
        set_numbers(u, y->length - 1, n);
    }
    u->n_pss = (uint8_t)(PATH_PSS_PER_VERTEX * numbered_vertices(y));
    if (k == PATH_RC_NONE || k - 1 > nb) return 0; /* no implicit numbers */
    /* y_{k-1} samples x_k, x_k samples w_k: implicit, recovered by inverse sampling. */
    if (trunk_replay(&t, c, y1, y, k - 1) != SHIFT_OK) return MUTATE_SKIP_IRREPRODUCIBLE + 1;
    /* x_k at infinity: the direction itself (docs/environment.md) */
    if (!mutate_invert_bounce(&t.v[k - 1], y->lobe[k - 1],
                              (y->rc_flags & PATH_RC_FLAG_DISTANT) ? light_distant_direction(y->rc_position)
                                                                   : mutate_direction_to(&t.v[k - 1], v3_from_f(y->rc_position)),
                              xi_lobe[0], n))
        return MUTATE_SKIP_INVERSE + 1;
    set_numbers(u, k - 1, n);
    if (k > nb) return 0;
    if (trunk_sample(&t, n) != SHIFT_OK || trunk_trace(&t, c->path.scene) != SHIFT_OK)
        return MUTATE_SKIP_IRREPRODUCIBLE + 1;
    if (!mutate_invert_bounce(&t.v[k], y->lobe[k], y->rc_wo, xi_lobe[1], n)) return MUTATE_SKIP_INVERSE + 1;
    set_numbers(u, k, n);
    return 0;
}

/* G(a -> b) = |n_g(b) . w| / ||b - a||^2 (GRIS Eq. 52). */
static real geometry_term(const path_vertex *a, const path_vertex *b)
{
    vec3 d = v3_sub(b->position, a->position);
    real r2 = v3_dot(d, d);
    return r2 > 0 ? (real)fabs(v3_dot(b->ng, d)) / (r2 * v3_length(d)) : 0;
}

/* Mutations Eq. 20 / App. C Eq. 33, one side (mutate.h): terms[0..2] = p(w_{k-1}, w_k),
 * G(x_k -> x_{k+1}), p(w_k, w_{k+1}), each 1 where it does not apply. t holds x_1..x_{k+1}
 * and the bounces b[k] (and b[k+1] when x_{k+1} is a BSDF-sampling scattering vertex). */
void mutate_rv_terms(const path_trunk *t, int k, int nb, real terms[3])
{
    terms[0] = terms[1] = terms[2] = 1;
    if (k > nb) return; /* x_{k+1} does not exist, or is NEE-sampled: its numbers do not move */
    terms[0] = t->b[k].pdf_lobe;
    /* 1 for x_{k+1} at infinity, whose measure is solid angle (docs/environment.md §5.2) */
    terms[1] = path_vertex_is_distant(&t->v[k + 1]) ? 1 : geometry_term(&t->v[k], &t->v[k + 1]);
    if (k + 1 <= nb) terms[2] = t->b[k + 1].pdf_lobe;
}

real mutate_rv_ratio_terms(const path_trunk *t, int k, int nb)
{
    real a[3];
    mutate_rv_terms(t, k, nb, a);
    return a[0] * a[1] * a[2];
}

/* Mutations Eq. 20: T(v->u)/T(u->v) = |cos phi| |y_{i+1} - y_i|^2 p(v_{i-1}, v_i) p(v_i, w_{i+1})
 *                                     / (|cos theta| |y_{i+1} - z_i|^2 p(w_{i-1}, w_i) p(w_i, w_{i+1}))
 * with G = |cos| / dist^2 at the kept vertex y_{i+1}: A(z) / A(y), 0 if A(y) = 0. */
real mutate_eq20_ratio(const real z[3], const real y[3])
{
    real num = z[0] * z[1] * z[2], den = y[0] * y[1] * y[2];
    return den > 0 ? num / den : 0;
}

/* 1 if the two points coincide up to float geometry (the reconnection ray z_k -> x_{k+1}
 * reached the kept vertex and not an occluder). */
static int same_point(vec3 a, vec3 b)
{
    vec3 d = v3_sub(a, b);
    real scale = (real)fabs(a.x) + (real)fabs(a.y) + (real)fabs(a.z) + 1;
    return v3_length(d) <= (real)1e-4 * scale;
}

/* The kernel of a proposal (mutation_options.kernel, .sigma). */
typedef struct {
    enum mutate_kernel kind;
    double sigma;
} kernel_choice;

/* Perturbs pss numbers of vertices first..last of z (§4.1: Kelemen, or Gaussian). */
static void perturb_vertices(path_sample *z, int first, int last, const real *xi, const kernel_choice *k)
{
    int i;
    for (i = (first - 1) * PATH_PSS_PER_VERTEX; i < last * PATH_PSS_PER_VERTEX; ++i) {
        if (k->kind == MUTATE_KERNEL_GAUSSIAN) {
            real g[3];
            g[0] = xi[i];
            g[1] = xi[MUTATE_XI_STRIDE + i];
            g[2] = xi[2 * MUTATE_XI_STRIDE + i];
            z->pss[i] = mutate_perturb_gaussian(z->pss[i], g, k->sigma);
        } else
            z->pss[i] = mutate_perturb(z->pss[i], xi[i]);
    }
}

/* One proposal z of the chain (Mutations §4.1-4.3): the perturbed numbers replayed into a
 * path of the pixel, with the kernel ratio the acceptance of Mutations Eq. 19 needs (1 for
 * the symmetric kernels, Mutations Eq. 20 for RV and PP). */
int mutate_propose(const restir_context *c, const path_vertex *y1, const path_sample *u, int strategy, const real *xi,
                   const real xi_lobe[2], path_sample *z, real *ratio)
{
    return mutate_propose_kernel(c, y1, u, strategy, MUTATE_KERNEL_KELEMEN, 0, xi, xi_lobe, z, ratio);
}

int mutate_propose_kernel(const restir_context *c, const path_vertex *y1, const path_sample *u, int strategy,
                          enum mutate_kernel kernel, double sigma, const real *xi, const real xi_lobe[2],
                          path_sample *z, real *ratio)
{
    kernel_choice kc;
    path_trunk ty, tz;
    path_end end;
    real n[3], a_y[3], a_z[3], *store = z->pss; /* the caller's storage, not u's (mutate.h) */
    int nb = mutate_bsdf_vertices(u), k = u->rc_k, j;
    kc.kind = kernel;
    kc.sigma = sigma;
    *z = *u;
    path_sample_copy_pss(u, store);
    z->pss = store;
    *ratio = 1;
    if (strategy == MUTATE_FP || k == PATH_RC_NONE) {
        /* fp (pp without reconnection vertex: "the full path is mutated"): symmetric. */
        perturb_vertices(z, 1, numbered_vertices(u), xi, &kc);
        if (path_record(c, y1, z) != SHIFT_OK) return MUTATE_REJECT_REPLAY;
        return path_sample_is_valid(z) && z->target > 0 ? -1 : MUTATE_REJECT_ZERO;
    }
    /* rv / pp: perturb the numbers that sample the reconnection vertex (rv) or all up to it
     * (pp; for k = d with NEE these are the light point numbers: the DI mutation of §4.2). */
    perturb_vertices(z, strategy == MUTATE_RV ? k - 1 : 1, k - 1, xi, &kc);
    if (k <= nb) { /* z_k connects to the kept x_{k+1}: numbers by inverse sampling (App. C) */
        /* the current path's x_{k+1} and w_{k+1} (and the denominator of Eq. 20) */
        if (path_replay(&ty, c, y1, u, &end) != SHIFT_OK) return MUTATE_REJECT_REPLAY;
        mutate_rv_terms(&ty, k, nb, a_y);
        if (trunk_replay(&tz, c, y1, z, k) != SHIFT_OK) return MUTATE_REJECT_REPLAY; /* z_2..z_k */
        int distant = path_vertex_is_distant(&ty.v[k + 1]); /* x_{k+1} = x_d at infinity: keep its direction */
        if (!mutate_invert_bounce(&tz.v[k], u->lobe[k],
                                  distant ? ty.v[k + 1].position : mutate_direction_to(&tz.v[k], ty.v[k + 1].position),
                                  xi_lobe[0], n))
            return MUTATE_REJECT_INVERSE;
        set_numbers(z, k, n);
        if (trunk_sample(&tz, n) != SHIFT_OK) return MUTATE_REJECT_INVERSE;
        if ((distant ? trunk_trace_escape(&tz, c) : trunk_trace(&tz, c->path.scene)) != SHIFT_OK ||
            tz.v[k + 1].hit.triangle != ty.v[k + 1].hit.triangle ||
            !same_point(tz.v[k + 1].position, ty.v[k + 1].position))
            return MUTATE_REJECT_OCCLUDED;
        if (k + 1 <= nb) { /* x_{k+1} keeps w_{k+1} under the new incoming direction */
            if (!mutate_invert_bounce(&tz.v[k + 1], u->lobe[k + 1], ty.b[k + 1].wi, xi_lobe[1], n))
                return MUTATE_REJECT_INVERSE;
            set_numbers(z, k + 1, n);
            if (trunk_sample(&tz, n) != SHIFT_OK) return MUTATE_REJECT_INVERSE;
        }
        mutate_rv_terms(&tz, k, nb, a_z);
        *ratio = mutate_eq20_ratio(a_z, a_y); /* Mutations Eq. 20 */
        if (!(*ratio > 0) || !isfinite((double)*ratio)) return MUTATE_REJECT_ZERO;
    } /* else x_k is the last vertex, or x_{k+1} is its NEE sample (the NEE numbers stay, area
       * sampling does not depend on x_k): nothing is determined, the kernel is symmetric */
    if (path_record(c, y1, z) != SHIFT_OK) return MUTATE_REJECT_REPLAY;
    if (z->rc_k != u->rc_k) return MUTATE_REJECT_STRUCTURE; /* connectability changed: T = 0 (§4.3) */
    for (j = k; j <= nb && j <= k + 1; ++j)
        if (z->lobe[j] != u->lobe[j]) return MUTATE_REJECT_STRUCTURE;
    if (!(z->target > 0)) return MUTATE_REJECT_ZERO;
    return -1;
}

/* Whether strategy can move sample y at all (else the pixel is skipped, by reason). */
static int skip_reason(int strategy, const path_sample *y)
{
    if (!path_sample_is_valid(y)) return MUTATE_SKIP_EMPTY;
    if (strategy == MUTATE_RV && y->rc_k == PATH_RC_NONE) return MUTATE_SKIP_NO_RC;
    return -1;
}

/* Mutations Algorithm 3 (one pixel): N Metropolis-Hastings iterations with the pixel's p̂,
 * acceptance Eq. 14 / Eq. 19, the UCW update of Eq. 16 applied per accepted step (App. A
 * Eq. 23; the product telescopes to Eq. 16). */
void mutate_reservoir(const restir_context *c, const path_vertex *y1, rng_key key, int stage, int strategy,
                      int iterations, reservoir *r, real *pss_home, mutate_stats *st)
{
    mutation_options mo;
    mutation_options_default(&mo);
    mo.strategy = (enum mutate_strategy)strategy;
    mo.count = iterations;
    mutate_reservoir_opts(c, y1, key, stage, &mo, r, pss_home, st);
}

void mutate_reservoir_opts(const restir_context *c, const path_vertex *y1, rng_key key, int stage,
                           const mutation_options *mo, reservoir *r, real *pss_home, mutate_stats *st)
{
    mutate_reservoir_traced(c, y1, key, stage, mo, r, pss_home, st, NULL);
}

/* Iteration it's record in tr (NULL: none kept). */
static void trace_it(mutate_trace *tr, int it, int outcome, real tx, real tz, real ratio, real a, real u, real W)
{
    if (!tr || it >= MUTATE_TRACE_MAX) return;
    tr->it[it].outcome = outcome;
    tr->it[it].target_x = tx;
    tr->it[it].target_z = tz;
    tr->it[it].ratio = ratio;
    tr->it[it].a = a;
    tr->it[it].u = u;
    tr->it[it].W = W;
    tr->n = it + 1;
}

void mutate_reservoir_traced(const restir_context *c, const path_vertex *y1, rng_key key, int stage,
                             const mutation_options *mo, reservoir *r, real *pss_home, mutate_stats *st,
                             mutate_trace *tr)
{
    real xi[3 * MUTATE_XI_STRIDE], u_numbers[PATH_MAX_PSS], z_numbers[PATH_MAX_PSS];
    int strategy = (int)mo->strategy, iterations = mo->count, gaussian = mo->kernel == MUTATE_KERNEL_GAUSSIAN;
    int it, j, why;
    if (tr) {
        tr->skip = -1;
        tr->n = 0;
    }
    st->pixels++;
    why = !(r->W > 0) || !(r->y.target > 0) ? MUTATE_SKIP_EMPTY : skip_reason(strategy, &r->y);
    if (why >= 0 && tr) tr->skip = why;
    if (why >= 0) {
        st->skipped++;
        st->skip[why]++;
        st->pss_numbers += r->y.n_pss;
        return;
    }
    for (it = 0; it < iterations; ++it) {
        path_sample u, z;
        real ratio, a, ua, tx, xl[2], xc[2];
        uint32_t slot = 64u * (uint32_t)it;
        int nv = numbered_vertices(&r->y);
        u.pss = u_numbers;
        z.pss = z_numbers;
        for (j = 0; j < 2; ++j) {
            xc[j] = rng_u(key, RNG_MUTATE, (uint32_t)stage, slot + MUTATE_SLOT_LOBE_CURRENT + (uint32_t)j);
            xl[j] = rng_u(key, RNG_MUTATE, (uint32_t)stage, slot + MUTATE_SLOT_LOBE_PROPOSAL + (uint32_t)j);
        }
        why = mutate_explicit(c, y1, &r->y, xc, &u);
        if (!why && it == 0) { /* the explicit vector must replay to the sample (float geometry) */
            path_sample check = u;
            if (path_record(c, y1, &check) != SHIFT_OK || check.rc_k != r->y.rc_k ||
                !((real)fabs((double)(check.target - r->y.target)) <= (real)1e-3 * r->y.target))
                why = MUTATE_SKIP_IRREPRODUCIBLE + 1;
        }
        if (why) {
            if (it == 0) { /* the chain cannot start from this sample */
                if (tr) tr->skip = why - 1;
                st->skipped++;
                st->skip[why - 1]++;
                st->pss_numbers += r->y.n_pss;
                return;
            }
            why = MUTATE_REJECT_INVERSE; /* cannot happen after an accepted proposal; counted */
            st->proposals++;
            st->rejected[why]++;
            trace_it(tr, it, why, r->y.target, 0, 0, 0, 0, r->W);
            continue;
        }
        for (j = 0; j < PATH_PSS_PER_VERTEX * nv; ++j) {
            xi[j] = rng_u(key, RNG_MUTATE, (uint32_t)stage, slot + (uint32_t)j);
            if (gaussian) { /* the sign/angle and amount numbers (mutate.h; docs/rng.md) */
                xi[MUTATE_XI_STRIDE + j] = rng_u(key, RNG_MUTATE, (uint32_t)stage + MUTATE_GAUSSIAN_VERTEX, slot + (uint32_t)j);
                xi[2 * MUTATE_XI_STRIDE + j] =
                    rng_u(key, RNG_MUTATE, (uint32_t)stage + 2 * MUTATE_GAUSSIAN_VERTEX, slot + (uint32_t)j);
            }
        }
        st->proposals++;
        why = mutate_propose_kernel(c, y1, &u, strategy, mo->kernel, mo->sigma, xi, xl, &z, &ratio);
        if (why >= 0) {
            st->rejected[why]++;
            trace_it(tr, it, why, r->y.target, 0, 0, 0, 0, r->W);
            continue;
        }
        if (c->ablation == RESTIR_ABLATE_RV_KERNEL) ratio = 1; /* ablation: symmetric kernel */
        a = mutate_acceptance(r->y.target, z.target, ratio);
        ua = rng_u(key, RNG_MUTATE, (uint32_t)stage, slot + MUTATE_SLOT_ACCEPT);
        if (!(ua < a)) {
            st->rejected_mh++;
            trace_it(tr, it, MUTATE_TRACE_REJECTED_MH, r->y.target, z.target, ratio, a, ua, r->W);
            continue;
        }
        st->accepted++;
        tx = r->y.target;
        if (c->ablation != RESTIR_ABLATE_MUTATION_W) r->W = mutate_weight(r->W, r->y.target, z.target);
        trace_it(tr, it, MUTATE_TRACE_ACCEPTED, tx, z.target, ratio, a, ua, r->W);
        r->y = z;
        path_sample_keep_pss(&r->y, pss_home); /* z_numbers is the next proposal's storage */
    }
    st->pss_numbers += r->y.n_pss;
}

/* ---- duplicates (Mutations Fig. 8) ------------------------------------------------------ */

static uint64_t mix64(uint64_t h, uint64_t v)
{
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    return h ^ (h >> 29);
}

/* The identity of a sample: replay identity, structure, x_k, and the explicit numbers. */
static uint64_t sample_hash(const path_sample *y)
{
    uint64_t h = mix64(0, ((uint64_t)y->seed << 32) | y->pixel);
    uint32_t bits[3];
    int i;
    h = mix64(h, ((uint64_t)y->sample << 32) | ((uint64_t)y->length << 16) | ((uint64_t)y->rc_k << 8) | y->n_pss);
    memcpy(bits, &y->rc_position, sizeof bits);
    h = mix64(h, ((uint64_t)bits[0] << 32) | bits[1]);
    h = mix64(h, bits[2]);
    for (i = 0; i < y->n_pss; ++i) h = mix64(h, (uint64_t)(y->pss[i] * 9007199254740992.0));
    return h;
}

/* LSD radix sort of n keys, 8 bits per pass, through tmp[n] (issue 17: qsort of a 512 x 512
 * frame's hashes was 2% of a real-time frame, all of it serial; this is a few ms). */
static void radix_sort_u64(uint64_t *a, uint64_t *tmp, size_t n)
{
    int shift;
    for (shift = 0; shift < 64; shift += 8) {
        size_t count[257] = {0}, i;
        uint64_t *t;
        for (i = 0; i < n; ++i) count[((a[i] >> shift) & 0xFF) + 1]++;
        for (i = 1; i < 257; ++i) count[i] += count[i - 1];
        for (i = 0; i < n; ++i) tmp[count[(a[i] >> shift) & 0xFF]++] = a[i];
        t = a; /* the sorted pass becomes the input of the next (8 passes: ends in a) */
        a = tmp;
        tmp = t;
    }
}

uint64_t mutate_count_duplicates(const reservoir *r, size_t n, uint64_t *valid)
{
    uint64_t *h = malloc(2 * (n ? n : 1) * sizeof *h), dup = 0;
    size_t i, m = 0, run;
    *valid = 0;
    if (!h) return 0;
    for (i = 0; i < n; ++i)
        if (path_sample_is_valid(&r[i].y) && r[i].W > 0) h[m++] = sample_hash(&r[i].y);
    radix_sort_u64(h, h + m, m);
    for (i = 0; i < m; i += run) {
        for (run = 1; i + run < m && h[i + run] == h[i]; ++run) {}
        if (run > 1) dup += run;
    }
    *valid = m;
    free(h);
    return dup;
}

void mutation_options_default(mutation_options *o)
{
    o->count = 0;
    o->strategy = MUTATE_RV;
    o->stages = MUTATE_AFTER_TEMPORAL;
    o->kernel = MUTATE_KERNEL_KELEMEN;
    o->sigma = 0;
}

int mutation_options_validate(const mutation_options *o, rerror *e)
{
    if (o->count < 0 || o->count > MUTATE_MAX_ITERATIONS)
        return rerror_set(e, "mutation: count %d (must be 0..%d)", o->count, MUTATE_MAX_ITERATIONS);
    if ((int)o->strategy < 0 || (int)o->strategy >= MUTATE_STRATEGY_COUNT)
        return rerror_set(e, "mutation: unknown strategy %d", (int)o->strategy);
    if (o->stages & ~(MUTATE_AFTER_INITIAL | MUTATE_AFTER_TEMPORAL | MUTATE_AFTER_SPATIAL))
        return rerror_set(e, "mutation: unknown stage bits %#x", (unsigned)o->stages);
    if (o->kernel != MUTATE_KERNEL_KELEMEN && o->kernel != MUTATE_KERNEL_GAUSSIAN)
        return rerror_set(e, "mutation: unknown kernel %d", (int)o->kernel);
    if (!(o->sigma >= 0 && o->sigma <= 0.5))
        return rerror_set(e, "mutation: sigma %g (must be in [0, 0.5]; 0: the paper's amount in (1/1024, 1/64])",
                          o->sigma);
    if (o->sigma > 0 && o->kernel != MUTATE_KERNEL_GAUSSIAN)
        return rerror_set(e, "mutation: sigma %g needs the gaussian kernel", o->sigma);
    return 0;
}
