/* MCMC mutations of a reservoir's sample (Mutations §2.5, §3 Algorithm 3, §4; docs/mutations.md).
 *
 * After a resampling stage every pixel runs N Metropolis-Hastings iterations on its
 * reservoir's sample X with its own target p̂_i (Algorithm 3); the sample stays in the pixel
 * and its unbiased contribution weight follows Eq. 16 / App. A Eq. 23:
 *     W(x^k) = p̂(x^{k-1}) / p̂(x^k) * W(x^{k-1})    (the weight sum is unchanged, Eq. 17)
 *
 * Mutations act in the lobe-extended primary sample space (PSS, §4.1) of the pixel, where
 * our target p̂ = luminance(F) with F = f/p already IS the PSS contribution C(u) = p̂/q of
 * Eq. 19. The current sample's BSDF numbers are made explicit first (mutate_explicit): the
 * numbers the sample replays are its own, the implicit numbers at the reconnection (y_{k-1}
 * towards x_k, x_k towards x_{k+1}) are recovered by inverse sampling (bsdf_lobe_sample_inverse;
 * the lobe number is drawn uniformly in the lobe's interval, an exact Gibbs step because F
 * depends on it only through the lobe). Strategies (§4.3; enum mutate_strategy):
 *   rv  (default) perturb the numbers at y_{k-1} only: a new reconnection vertex z_k, connected
 *       to the kept x_{k+1}; the numbers at z_k and x_{k+1} follow by inverse sampling, and the
 *       kernel ratio is Eq. 20 (mutate_rv_ratio_terms; docs/mutations.md derives it again).
 *   pp  perturb the numbers of y_1..y_{k-1} (replay up to the reconnection vertex z_k), then
 *       connect to x_{k+1} as rv; the full path (fp) when the sample has no reconnection vertex.
 *   fp  perturb every BSDF number of the path (symmetric kernel, ratio 1). NEE numbers stay.
 * Direct lighting (d = 2, §4.2 "DI"): every strategy perturbs the numbers that sample y_2
 * (symmetric): the direction numbers at y_1, or for an NEE sample the two numbers of the point
 * on the light (kept in pss[] at vertex d-1, path_sample.h; the light itself stays). The same
 * NEE point numbers are the numbers of x_d for fp, and of the reconnection vertex for rv/pp
 * when it is an NEE light vertex (k = d).
 * A proposal that changes the path's structure (reconnection index, lobes at the determined
 * vertices), is occluded or black has T = 0: rejected, by reason.
 * Acceptance (Eq. 14 with Eq. 19):  a = min(1, p̂(z) T(z->x) / (p̂(x) T(x->z))).
 *
 * Random numbers: RNG_MUTATE (docs/rng.md), base key (seed, pixel, frame's tree-0 sample),
 * vertex = the stage (enum mutate_stage), slot = 64 * iteration + j: j < 45 perturbs PSS
 * number j, 45..46 the lobe numbers of the determined vertices k, k+1, 48..49 the lobe
 * numbers recovered at y_{k-1}, x_k, j = 63 is the acceptance test. */
#ifndef RESTIR_MUTATE_H
#define RESTIR_MUTATE_H

#include <stdint.h>
#include "restir/restir/reservoir.h"
#include "restir/restir/path_replay.h"
#include "restir/restir/restir_context.h"

#define MUTATE_MAX_ITERATIONS 1000 /* 64 slots per iteration in the 16-bit slot field */
#define MUTATE_SLOT_ACCEPT 63
#define MUTATE_S1 (1.0 / 1024.0) /* Kelemen et al. 2002 perturbation, s in (s1, s2] */
#define MUTATE_S2 (1.0 / 64.0)       /* (the paper gives no values: Kelemen's; docs/deviations.md) */

/* The perturbation of one PSS number (Mutations §4.1; docs/mutations.md "Kernels"):
 *   kelemen  (default) u +- s, s = s2 exp(-log(s2/s1) U): Kelemen et al. 2002's kernel. The
 *            paper says "Gaussian noise" with this s as the amount: a deviation (the
 *            oracle's default since before issue 28; docs/deviations.md).
 *   gaussian u + s n, n ~ N(0, 1), with s = --mutation-sigma, or (sigma 0, default) the
 *            paper's s = s2 exp(-log(s2/s1) U) as the standard deviation.
 * Both wrap to [0,1) (the unit circle): the kernel is a translation on the circle by a
 * step whose law is even, so T(x->y) = T(y->x) exactly (the ratio in Eq. 19 is 1). */
enum mutate_kernel { MUTATE_KERNEL_KELEMEN = 0, MUTATE_KERNEL_GAUSSIAN = 1 };
extern const char *const mutate_kernel_names[]; /* "kelemen", "gaussian" */
/* Gaussian kernel numbers: number j of the proposal reads xi[j] (as Kelemen: the radius),
 * xi[MUTATE_XI_STRIDE + j] (sign and angle) and xi[2 MUTATE_XI_STRIDE + j] (the amount U);
 * RNG_MUTATE vertex stage, stage + MUTATE_GAUSSIAN_VERTEX, stage + 2 MUTATE_GAUSSIAN_VERTEX,
 * the same slot (docs/rng.md). */
#define MUTATE_XI_STRIDE 64
#define MUTATE_GAUSSIAN_VERTEX 8u

enum mutate_strategy { MUTATE_RV = 0, MUTATE_PP = 1, MUTATE_FP = 2 };
#define MUTATE_STRATEGY_COUNT 3
extern const char *const mutate_strategy_names[]; /* "rv", "pp", "fp" */
#define MUTATE_SLOT_LOBE_PROPOSAL 45 /* + 0: vertex k, + 1: vertex k+1 */
#define MUTATE_SLOT_LOBE_CURRENT 48  /* + 0: vertex k-1, + 1: vertex k */

/* Why a pixel's chain did not run, or a proposal was impossible (T = 0). */
enum mutate_reason {
    MUTATE_SKIP_EMPTY = 0,      /* empty reservoir, W = 0 or p̂ = 0 */
    MUTATE_SKIP_NO_RC,          /* rv: the sample has no reconnection vertex */
    MUTATE_SKIP_INVERSE,        /* the implicit numbers could not be recovered (Dirac or unreachable lobe) */
    MUTATE_SKIP_IRREPRODUCIBLE, /* the explicit vector does not replay to the sample (rounding at an edge) */
    MUTATE_REASON_SKIP_COUNT
};
enum mutate_reject {
    MUTATE_REJECT_REPLAY = 0,   /* the perturbed path fails (miss, no direction, black) */
    MUTATE_REJECT_INVERSE,      /* z_k or x_{k+1} cannot sample the kept direction with the kept lobe */
    MUTATE_REJECT_OCCLUDED,     /* z_k does not see x_{k+1} (the ray hits another point) */
    MUTATE_REJECT_STRUCTURE,    /* the proposal's reconnection index or lobes differ (connectability) */
    MUTATE_REJECT_ZERO,         /* p̂(z) = 0 */
    MUTATE_REJECT_COUNT
};
extern const char *const mutate_skip_names[];
extern const char *const mutate_reject_names[];

/* Where in the frame (bits of mutation_options.stages; also the RNG_MUTATE vertex). */
enum mutate_stage { MUTATE_AFTER_INITIAL = 1, MUTATE_AFTER_TEMPORAL = 2, MUTATE_AFTER_SPATIAL = 4 };
/* index = the bit set: "none", "initial", "temporal", "initial,temporal", "spatial", ... */
extern const char *const mutate_after_names[];

/* The mutation technique's options (Mutations Algorithm 3; the real-time pipeline). */
typedef struct {
    int count;                     /* N Metropolis-Hastings iterations per pixel and stage (default 0: off) */
    enum mutate_strategy strategy; /* default rv (Mutations §4.3) */
    int stages;                    /* enum mutate_stage bits (default MUTATE_AFTER_TEMPORAL, Mutations §3) */
    enum mutate_kernel kernel;     /* default kelemen (the deviation, kept: outputs unchanged) */
    double sigma;                  /* gaussian: the standard deviation in PSS units; 0 (default):
                                      the paper's log-uniform amount s in (s1, s2] */
} mutation_options;

void mutation_options_default(mutation_options *o);
/* 0, or -1 with "mutation: what is wrong". */
int mutation_options_validate(const mutation_options *o, rerror *e);

typedef struct {
    uint64_t pixels;      /* reservoirs offered to the chain */
    uint64_t skipped;     /* ... whose chain did not run (sum of skip[]) */
    uint64_t skip[MUTATE_REASON_SKIP_COUNT];
    uint64_t proposals;
    uint64_t accepted;
    uint64_t rejected_mh; /* proposal valid, lost the acceptance test */
    uint64_t rejected[MUTATE_REJECT_COUNT]; /* proposal impossible (T = 0), by reason */
    uint64_t pss_numbers; /* sum over pixels of the explicit numbers (n_pss) the final sample keeps */
    uint64_t duplicates;  /* final reservoirs of each frame whose sample another pixel also holds (Fig. 8) */
    uint64_t final_valid; /* final reservoirs of each frame with a sample */
} mutate_stats;

void mutate_stats_add(mutate_stats *acc, const mutate_stats *add);

/* Kelemen's symmetric perturbation of u in [0,1) on the unit circle: one number xi decides
 * the sign (xi < 1/2) and the size s = s2 exp(-log(s2/s1) U), U = 2 xi mod 1. */
real mutate_perturb(real u, real xi);
/* Mutations §4.1 with Gaussian noise: v = u + s n wrapped to [0,1), n = +-sqrt(-2 log(1 - a))
 * cos(2 pi b') (Box-Muller; the sign is xi[1] < 1/2, b' = 2 xi[1] mod 1), a = xi[0], s = sigma
 * if sigma > 0 else s2 exp(-log(s2/s1) xi[2]). Mirroring xi[1] by 1/2 negates the step exactly. */
real mutate_perturb_gaussian(real u, const real xi[3], double sigma);

/* The MH acceptance ratio p̂(z) T(z->x) / (p̂(x) T(x->z)) (Mutations Eqs. 14, 19; accept iff
 * u < it), and the UCW after an accepted step (Mutations Eq. 23). The 1-D toy test uses them. */
real mutate_acceptance(real target_x, real target_z, real ratio);
real mutate_weight(real W, real target_x, real target_z);

/* The explicit vector of sample y of the pixel with primary hit y1 (mutate_explicit):
 * *u = y with pss[] holding the numbers of x_1..x_{d-1} (n_pss = 3 (d-1); NEE point numbers
 * at x_{d-1} of an NEE path), the
 * implicit ones recovered by inverse sampling with lobe numbers xi_lobe[0..1] (y_{k-1}, x_k).
 * u->pss must point to the caller's storage of PATH_MAX_PSS numbers (the vector is written
 * there; path_sample.h: numbers out of line). 0 on success, else an enum mutate_reason + 1. */
int mutate_explicit(const restir_context *c, const path_vertex *y1, const path_sample *y, const real xi_lobe[2],
                    path_sample *u);
/* Inverse sampling (§4): the numbers u[0..2] with which vertex v samples world direction w
 * through `lobe` (direction numbers by the lobe's sample_inverse; the lobe number uniform in
 * the lobe's interval by xi). 1 on success, 0 for a Dirac or unreachable lobe. */
int mutate_invert_bounce(const path_vertex *v, int lobe, vec3 w, real xi, real u[3]);
/* The direction in which v must sample so that its spawned ray (scene_spawn_ray) hits target. */
vec3 mutate_direction_to(const path_vertex *v, vec3 target);
/* BSDF-sampled vertices of a sample: d - 1, or d - 2 if x_d is NEE-sampled. */
int mutate_bsdf_vertices(const path_sample *y);

/* One proposal of strategy `strategy` from the explicit current sample u (mutate_explicit of
 * y): xi[j] perturbs pss number j (j < 3 (d-1)), xi_lobe[0..1] draw the lobe numbers of the
 * determined vertices. On success (return -1) *z is the recorded proposal and *ratio =
 * T(z->y)/T(y->z) (Mutations Eq. 20 for rv/pp with a reconnection vertex, else 1); otherwise
 * the enum mutate_reject (T = 0). z->pss must point to the caller's storage of PATH_MAX_PSS
 * numbers, not u's (the perturbed vector is written there). */
int mutate_propose(const restir_context *c, const path_vertex *y1, const path_sample *u, int strategy, const real *xi,
                   const real xi_lobe[2], path_sample *z, real *ratio);

/* The terms of Mutations Eq. 20 for a path whose reconnection vertex x_k connects to x_{k+1}:
 * A = p(w_{k-1}, w_k) G(x_k -> x_{k+1}) p(w_k, w_{k+1}), with p = P(lobe|wo) pdf_lobe (the lobe
 * number is a PSS coordinate), p(w_k, w_{k+1}) = 1 when x_{k+1} is the last vertex or NEE-
 * samples it, A = 1 when x_{k+1} is NEE-sampled from x_k. T(z->y)/T(y->z) = A(z) / A(y). */
real mutate_rv_ratio_terms(const path_trunk *t, int k, int nb);
/* The three factors of A (p(w_{k-1}, w_k), G(x_k -> x_{k+1}), p(w_k, w_{k+1})), 1 where absent. */
void mutate_rv_terms(const path_trunk *t, int k, int nb, real terms[3]);
/* Mutations Eq. 20 from the factors of the proposal z and the current path y: A(z) / A(y)
 * (0 if A(y) = 0). */
real mutate_eq20_ratio(const real z[3], const real y[3]);

/* N iterations of Algorithm 3 with `strategy` (enum mutate_strategy) on reservoir r of the
 * pixel with primary hit y1, numbers from RNG_MUTATE at (key, vertex = stage). ablation:
 * RESTIR_ABLATE_MUTATION_W keeps W (no Eq. 16), RESTIR_ABLATE_RV_KERNEL accepts with the
 * kernel ratio taken as 1. An accepted sample's numbers go to pss_home (PATH_MAX_PSS
 * numbers: the row of r in its buffer, reservoir_buffer_pss_row; path_sample.h). */
void mutate_reservoir(const restir_context *c, const path_vertex *y1, rng_key key, int stage, int strategy,
                      int iterations, reservoir *r, real *pss_home, mutate_stats *st);
/* The same with the options' strategy, count and kernel (the pipeline's call). */
void mutate_reservoir_opts(const restir_context *c, const path_vertex *y1, rng_key key, int stage,
                           const mutation_options *mo, reservoir *r, real *pss_home, mutate_stats *st);
/* mutate_propose with kernel `kernel` (sigma as mutation_options.sigma); for the Gaussian
 * kernel xi holds 3 MUTATE_XI_STRIDE numbers (layout above). */
int mutate_propose_kernel(const restir_context *c, const path_vertex *y1, const path_sample *u, int strategy,
                          enum mutate_kernel kernel, double sigma, const real *xi, const real xi_lobe[2],
                          path_sample *z, real *ratio);

/* One pixel's chain as mutate_reservoir_traced ran it (`restir inspect --from-dump`). */
#define MUTATE_TRACE_MAX 16 /* iterations recorded (more run, uncounted here) */
enum { MUTATE_TRACE_ACCEPTED = -2, MUTATE_TRACE_REJECTED_MH = -1 }; /* else enum mutate_reject */
typedef struct {
    int skip; /* -1: the chain ran; else the enum mutate_skip that stopped it before iteration 0 */
    int n;    /* iterations recorded */
    struct {
        int outcome;      /* MUTATE_TRACE_ACCEPTED, MUTATE_TRACE_REJECTED_MH, or enum mutate_reject */
        real target_x;    /* p̂(x) of the current sample */
        real target_z;    /* p̂(z) of the proposal (0 if it failed) */
        real ratio;       /* T(z->x)/T(x->z) (Mutations Eq. 20) */
        real a;           /* the acceptance probability (Eqs. 14, 19) */
        real u;           /* the acceptance number: RNG_MUTATE, vertex = stage, slot 64 it + MUTATE_SLOT_ACCEPT */
        real W;           /* W after the iteration (Eq. 23 on acceptance) */
    } it[MUTATE_TRACE_MAX];
} mutate_trace;

/* mutate_reservoir, recording the chain into *tr (tr may be NULL: mutate_reservoir). */
void mutate_reservoir_traced(const restir_context *c, const path_vertex *y1, rng_key key, int stage,
                             const mutation_options *mo, reservoir *r, real *pss_home, mutate_stats *st,
                             mutate_trace *tr);

/* Mutations Fig. 8: of the n reservoirs, how many hold a sample (identity, x_k and explicit
 * numbers) that another reservoir holds too; *valid receives the number of non-empty ones. */
uint64_t mutate_count_duplicates(const reservoir *r, size_t n, uint64_t *valid);

#endif
