/* Weighted reservoir streaming and the unbiased contribution weight of (G)RIS. */
#include "restir/restir/reservoir.h"

#include <math.h>
#include "restir/core/threads.h"

void reservoir_init(reservoir *r)
{
    path_sample_clear(&r->y);
    r->wsum = 0;
    r->W = 0;
    r->confidence = 0;
    r->n_invalid = 0;
}

/* Chao 1982 (Mutations Alg. 1): after the step, each streamed candidate is the selection
 * with probability w_j / sum w (Mutations Eq. 6), because a later candidate replaces it
 * with probability w / wsum. */
int wrs_update(real *wsum, real w, real u, uint32_t *n_invalid)
{
    if (w == 0) return 0;
    if (!(w > 0) || !isfinite(w)) { /* NaN, negative or infinite: skip and count */
        if (n_invalid) (*n_invalid)++;
        return 0;
    }
    *wsum += w;
    return u < w / *wsum;
}

int reservoir_stream(reservoir *r, const path_sample *y, real w, real u)
{
    if (!wrs_update(&r->wsum, w, u, &r->n_invalid)) return 0;
    r->y = *y;
    return 1;
}

/* GRIS Eq. 22: W_Y = (1 / p̂(Y)) sum_j w_j (GRIS Eq. 2 for plain RIS; Mutations Eq. 8;
 * Stochastic MIS Eq. 7). */
void reservoir_finalize(reservoir *r)
{
    r->W = 0;
    if (!path_sample_is_valid(&r->y)) return;
    if (r->y.target > 0 && isfinite(r->wsum / r->y.target))
        r->W = r->wsum / r->y.target;
    else
        r->n_invalid++; /* a positive weight was given to a sample with p̂ = 0 */
}

void reservoir_add_confidence(reservoir *r, real c) { r->confidence += c; }

void reservoir_cap_confidence(reservoir *r, real cap)
{
    if (r->confidence > cap) r->confidence = cap;
}

/* GRIS Eq. 19 (with the Iverson bracket of Stochastic MIS Eq. 6 for a failed shift).
 * GRIS Eq. 7 is its overview form, Enhanced Eq. 1 and Mutations Eq. 13 restate it, and
 * GRIS Eq. 6 / Mutations Eq. 12 are the identity-shift case (J = 1). */
real gris_resampling_weight(real mis, real target, real ucw, real jacobian)
{
    if (mis == 0 || target == 0 || ucw == 0 || jacobian == 0) return 0;
    return mis * target * ucw * jacobian;
}

/* GRIS Eq. 1 with M -> N path trees (the constant 1/N is exact: all trees are canonical).
 * Mutations Eq. 7 restates it; Mutations Eqs. 5 and 11 are the resulting estimator of the
 * normalisation. */
real ris_candidate_weight(real target, real ucw, real n_trees)
{
    return gris_resampling_weight((real)1 / n_trees, target, ucw, 1);
}

/* GRIS Eq. 3: the estimate f(Y) W_Y, here with the RGB contribution F (Mutations Eq. 9). */
rgb reservoir_estimate(const reservoir *r)
{
    if (!path_sample_is_valid(&r->y) || r->W == 0) return rgb_gray(0);
    return rgb_scale(r->y.F, r->W);
}

reservoir *reservoir_buffer_alloc(size_t n, int pss_rows, rerror *e)
{
    /* sizeof(reservoir) is a multiple of the alignment of real, so the rows are aligned */
    return rmalloc(n ? n : 1, sizeof(reservoir) + (pss_rows ? PATH_MAX_PSS * sizeof(real) : 0), e);
}

real *reservoir_buffer_pss_row(reservoir *rs, size_t n, size_t p) { return (real *)(void *)(rs + n) + p * PATH_MAX_PSS; }

typedef struct {
    reservoir *rs;
    size_t n;
} keep_job;

static void keep_item(void *ctx, long p, int worker)
{
    keep_job *k = ctx;
    (void)worker;
    path_sample_keep_pss(&k->rs[p].y, reservoir_buffer_pss_row(k->rs, k->n, (size_t)p));
}

void reservoir_buffer_keep_pss(reservoir *rs, size_t n, int threads)
{
    keep_job k;
    k.rs = rs;
    k.n = n;
    parallel_items((long)n, threads, keep_item, &k); /* each item writes its own row only */
}
