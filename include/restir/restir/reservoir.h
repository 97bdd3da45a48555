/* Reservoirs and weighted reservoir streaming: the resampling step of (G)RIS.
 *
 * A reservoir (GRIS §6.2; Enhanced §2.2; Stochastic MIS §2.6) is the tuple
 * (Y, W_Y, c): the selected sample, its unbiased contribution weight (UCW) and its
 * confidence weight. While candidates stream in it holds the running weight sum
 * instead of W. The cached target p̂(Y) is the sample's own `y.target` (the target of
 * the pixel that owns the reservoir: a shifted candidate carries its shifted F).
 *
 * One GRIS step (GRIS Eqs. 19 and 22; Stochastic MIS Eqs. 6-7):
 *     reservoir_init(&r);
 *     for each candidate j:   (y_j = T_j(X_j), the shifted sample, with its target p̂(y_j))
 *         w_j = gris_resampling_weight(m_j(y_j), p̂(y_j), W_j, |dT_j/dX_j|);   (mis.h for m_j)
 *         reservoir_stream(&r, &y_j, w_j, u_j);     u_j from the RNG_RIS stream
 *         reservoir_add_confidence(&r, c_j);        every input, also failed shifts (GRIS §6.2)
 *     reservoir_finalize(&r);                       W = sum w / p̂(Y), no 1/M (GRIS Eq. 22)
 *     (temporal inputs: reservoir_cap_confidence on the input before, GRIS §6.4)
 *
 * Initial sampling from N path trees per pixel (GRIS §8.3, Enhanced §2.3): every tree
 * emits at most one candidate per (length d, technique) integrand of the path-space sum
 * (GRIS Eq. 50), so each integrand has N identically distributed canonical candidates and
 * its resampling MIS weight is the constant 1/N, exact here because all N are canonical
 * (GRIS §5.6, "Constant resampling weights"). Hence:
 *     w = ris_candidate_weight(p̂(x), W_x, N)  = p̂(x) W_x / N     (GRIS Eq. 1, M -> N)
 *     W = wsum / p̂(Y)                         = sum_trees sum_cands p̂ W_x / (N p̂(Y))
 *     c = N                                    (reservoir_add_confidence(&r, N))
 * with W_x = 1 / (Russian-roulette survival probability) in PSS (the authors' Falcor code
 * does the same). The number of candidates is NOT M: dividing the weight sum of a tree's
 * sum over path lengths by its candidate count again is a bias. */
#ifndef RESTIR_RESERVOIR_H
#define RESTIR_RESERVOIR_H

#include <stdint.h>
#include <stddef.h>
#include "restir/core/error.h"
#include "restir/restir/path_sample.h"

typedef struct {
    path_sample y;      /* selected sample Y; empty (PATH_TECH_NONE) if nothing was selected */
    real wsum;          /* sum of the streamed resampling weights w_j */
    real W;             /* UCW of Y, set by reservoir_finalize (0 before and when empty) */
    real confidence;    /* c: confidence weight (GRIS §6.2 "M_r") */
    uint32_t n_invalid; /* weights skipped because NaN, infinite or negative */
} reservoir;

/* An empty reservoir: no sample, wsum = W = c = 0. */
void reservoir_init(reservoir *r);

/* Weighted reservoir sampling, one step (Chao 1982; Mutations Alg. 1; GRIS §2.1): adds w
 * to *wsum and returns 1 ("select this candidate") with probability w / *wsum, decided as
 * u < w / *wsum with u in [0,1). Weights that are 0 are skipped (return 0, not counted);
 * NaN, infinite or negative weights are skipped and counted in *n_invalid. */
int wrs_update(real *wsum, real w, real u, uint32_t *n_invalid);

/* Streams candidate y with resampling weight w (GRIS Eq. 19): wrs_update on r->wsum, and
 * y is copied into r->y if selected. u must come from the caller's addressed RNG_RIS
 * stream. Returns 1 if y was selected. */
int reservoir_stream(reservoir *r, const path_sample *y, real w, real u);

/* The UCW of the selection, W = wsum / p̂(Y) (GRIS Eq. 22; Eq. 2 for plain RIS; Stochastic
 * MIS Eq. 7). The 1/M of older RIS formulas lives in the MIS weights m_j (GRIS footnote 6),
 * never here. Empty reservoirs (and a selected Y with p̂(Y) <= 0 or a non-finite quotient,
 * which the weights should have excluded; counted in n_invalid) get W = 0: the GRIS §4.2
 * "null sample" that contributes nothing. */
void reservoir_finalize(reservoir *r);

/* c += c_j for an input of the resampling (GRIS §6.2: c of the output = sum of the inputs). */
void reservoir_add_confidence(reservoir *r, real c);
/* c = min(c, cap) (GRIS §6.2 M_c and §6.4; Enhanced §2.2 c_Cap). */
void reservoir_cap_confidence(reservoir *r, real cap);

/* Resampling weight of one candidate, GRIS Eq. 19 (Enhanced Eq. 1, Stochastic MIS Eq. 6):
 *     w = m(y) * p̂(y) * W_x * |dT/dx|
 * A failed shift passes target 0 or jacobian 0 and gets exactly 0 (the Iverson bracket of
 * Stochastic MIS Eq. 6), also when another factor is infinite. */
real gris_resampling_weight(real mis, real target, real ucw, real jacobian);

/* Resampling weight of an initial candidate when N path trees are resampled together:
 * GRIS Eq. 1 with the constant MIS weight 1/N (see the header comment). */
real ris_candidate_weight(real target, real ucw, real n_trees);

/* The pixel estimate F(Y) * W_Y (GRIS Eq. 3; averaged over frames it is GRIS Eq. 47). */
rgb reservoir_estimate(const reservoir *r);

/* ---- reservoir buffers (one reservoir per pixel) and their primary-sample rows
 * The explicit numbers of mutated samples live out of line (path_sample.h). A buffer that
 * can hold mutated samples is allocated with rows: after its n reservoirs come n rows of
 * PATH_MAX_PSS numbers, row p belonging to reservoir p, in the same block (free() frees
 * both, and swapping two buffer pointers swaps their rows too). Runs without mutations
 * allocate no rows (issue 17: 224 instead of 576 B per reservoir). */
reservoir *reservoir_buffer_alloc(size_t n, int pss_rows, rerror *e);
/* Row p of a buffer of n reservoirs allocated with rows. */
real *reservoir_buffer_pss_row(reservoir *rs, size_t n, size_t p);
/* Every sample of the buffer (allocated with rows) takes its numbers into its own row
 * (path_sample_keep_pss). A stage that writes a buffer leaves samples pointing into the
 * rows of the buffers it read (a shift or a copy by value shares the numbers); this is
 * called when the stage is done, before anything writes those buffers again. On `threads`
 * workers (threads.h). */
void reservoir_buffer_keep_pss(reservoir *rs, size_t n, int threads);

#endif
