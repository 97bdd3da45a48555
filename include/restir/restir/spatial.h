/* One spatial GRIS step at one pixel (GRIS §6.3 step 3, Eq. 19, 22, 35-38; Stochastic MIS
 * §2, Eqs. 9-12; docs/restir-pt.md "Spatial reuse").
 *
 * Domains i = 0..M-1: domain 0 is the pixel's own reservoir (CANONICAL, identity shift),
 * domains 1..M-1 are the accepted neighbours (neighbors.h). Candidate j's sample X_j is
 * shifted into the pixel, y_j = T_j(X_j) with J_j = |dT_j/dX_j| (shift.h), and
 *     w_j = m_j(y_j) p̂(y_j) W_j J_j                 (GRIS Eq. 19)
 *     W_Y = sum_j w_j / p̂(Y),  c = sum_j c_j       (GRIS Eq. 22, §6.2)
 * with m_j from mis.h. The M x M matrix of "p̂ from i" (GRIS Eq. 35) is filled only where
 * the chosen family reads it:
 *     row 0 (canonical):     p̂(y_j), the forward shift's target;
 *     diagonal j >= 1:       p̂_j(X_j) / J_j;
 *     i >= 1, i != j:        y_j shifted back OUT into neighbour i: p̂_i(T_i^{-1}(y_j)) |dT_i^{-1}/dy_j|
 *                            (one shift each: Talbot every column, O(M^2); pairwise only
 *                            the canonical column j = 0, O(M); constant none).
 * A failed shift is p̂ = 0 (GRIS Eq. 35). Every domain enters the MIS denominators and the
 * confidence, also an empty reservoir or one whose forward shift failed. */
#ifndef RESTIR_SPATIAL_H
#define RESTIR_SPATIAL_H

#include <stddef.h>
#include "restir/restir/mis.h"
#include "restir/restir/reservoir.h"
#include "restir/restir/shift.h"

typedef struct {
    uint64_t pixels;   /* GRIS steps (pixels with a primary hit) */
    uint64_t domains;  /* sum of M over the steps */
    uint64_t shifts;   /* shift evaluations: forward (neighbours in) + MIS (out / across) */
    uint64_t mis_shifts; /* the MIS part of `shifts` */
    uint64_t outcome[SHIFT_FAILURE_COUNT]; /* every shift by result; outcome[SHIFT_OK] = successes */
    uint64_t selected_neighbor; /* steps whose output sample came from a neighbour */
    uint64_t invalid_weights;   /* guards that changed the estimate (docs/precision.md): the
                                   outputs' n_invalid (resampling weights skipped as NaN, Inf
                                   or < 0; W = 0 for p̂(Y) = 0), NaN/Inf selection weights of
                                   stochastic MIS, NaN/Inf vector-shading weights */
} spatial_stats;

/* Scratch space for steps with up to max_domains domains (one per worker). */
typedef struct {
    int max_domains;
    real *ptarget, *confidence, *jacobian;
    real *mis;      /* m_j(y_j) the step used for candidate j (0 if it was not valid) */
    real *check_confidence; /* scratch of spatial_check_step */
    path_sample *shifted;          /* storage of the shifts made by the step */
    const path_sample **cand;      /* y_j: &shifted[j], the canonical reservoir's own sample
                                      (j = 0), or a pair-step record (read in place) */
    unsigned char *valid;
} spatial_workspace;

int spatial_workspace_alloc(spatial_workspace *w, int max_domains, rerror *e);
void spatial_workspace_free(spatial_workspace *w);

/* The GRIS step: x1[i] is domain i's primary vertex, in[i] its reservoir (i = 0 is the
 * pixel's own), u[i] the selection number of candidate i (RNG_RIS). 1 <= m <= w->max_domains. */
void spatial_resample(const restir_context *c, mis_family mis, int m, const path_vertex *const *x1,
                      const reservoir *const *in, const real *u, reservoir *out, spatial_workspace *w,
                      spatial_stats *st);

/* Optional step before a shift between domains of different frames (temporal reuse in
 * animated scenes, temporal.h): re-expresses sample x of domain `from` in the scene of
 * domain `to` (rc_retrace_suffix); a failure makes that shift fail. */
typedef struct {
    enum shift_failure (*fn)(const void *user, int from, int to, const path_sample *x, path_sample *out);
    const void *user;
} domain_refresh;

/* The same step where the domains i >= 1 live in another frame (temporal reuse,
 * temporal.h): forward shifts T_j(X_j) into the pixel use c (the current frame's scene),
 * the MIS shifts back out into domain i >= 1 use `away` (that domain's own scene, GRIS
 * App. B); x1[i] must be domain i's primary vertex in its own frame; rf (may be NULL)
 * runs before every shift from one domain into another. spatial_resample is
 * gris_resample(c, c, NULL, ...). */
void gris_resample(const restir_context *c, const restir_context *away, const domain_refresh *rf, mis_family mis,
                   int m, const path_vertex *const *x1, const reservoir *const *in, const real *u, reservoir *out,
                   spatial_workspace *w, spatial_stats *st);

/* Enhanced §3 pair step: the shift of one pixel's sample to its partner, computed once by
 * the pre-pass (pair_step.h) and read by both pixels of the pair. */
typedef struct {
    path_sample y;   /* T(X) in the partner's pixel (valid iff ok) */
    real jacobian;   /* |dT/dX| */
    unsigned char ok; /* the sample was valid (W > 0) and the shift succeeded */
} pair_shift;

/* Per neighbour domain d >= 1 of a GRIS step whose pairs were shifted by the pre-pass:
 * forward[d] = T_{d->0}(X_d), the partner's shift into this pixel (the candidate y_d);
 * reverse[d] = T_{0->d}(X_0), this pixel's shift into partner d, whose p̂ J is the
 * pairwise MIS entry p̂_{<-d}(X_0) (GRIS Eq. 35, canonical column). drop_reverse is the
 * ablation "pair-mis": that entry is taken as 0 (one side of the pair's MIS dropped). */
typedef struct {
    const pair_shift *const *forward;
    const pair_shift *const *reverse;
    int drop_reverse;
} pair_shifts;

/* spatial_resample with the forward shifts and the canonical MIS column taken from pre
 * instead of being shifted here (the same values: the result is bit-identical). Entries
 * the family reads beyond those (Talbot: p̂_{<-i}(y_j), i, j >= 1) are shifted as usual. */
void spatial_resample_preshifted(const restir_context *c, mis_family mis, int m, const path_vertex *const *x1,
                                 const reservoir *const *in, const pair_shifts *pre, const real *u, reservoir *out,
                                 spatial_workspace *w, spatial_stats *st);

/* One shift of x to the pixel of `to` (shift.h), counted in st by outcome; the jacobian
 * ablation takes |dT/dx| as 1 wherever it enters (weights and MIS). Shared by every GRIS step
 * (spatial, temporal, stochastic pairwise). */
enum shift_failure spatial_counted_shift(const restir_context *c, const path_vertex *to, const path_sample *x,
                                         path_sample *y, real *jacobian, spatial_stats *st);

void spatial_stats_add(spatial_stats *acc, const spatial_stats *add);

/* The invariants of the GRIS step gris_resample just computed into out, with its
 * workspace w still holding the step (the debug build runs this after every step and
 * aborts on failure; docs/statistics.md "Debug invariants"):
 *   - every input confidence c_j >= 0, out's c = sum_j c_j exactly (failed shifts too),
 *     out's W >= 0 and finite;
 *   - for every candidate j that entered the resampling, the MIS weights recomputed over
 *     the TRUE input confidences sum to one over all domains, failed shifts included
 *     (sum_i m_i(y_j) = 1, GRIS Eq. 17), and the m_j(y_j) the step used equals them;
 *   - every successful reconnection (candidate j >= 1 with a reconnection vertex) is
 *     visible: y_1..y_{k-1} replayed from x1[0] and the segment y_{k-1} -> x_k re-traced.
 * Returns 0, or nonzero with what failed in why[0..why_size). */
int spatial_check_step(const restir_context *c, mis_family mis, int m, const path_vertex *const *x1,
                       const reservoir *const *in, const reservoir *out, spatial_workspace *w, char *why,
                       size_t why_size);

#endif
