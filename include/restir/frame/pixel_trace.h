/* One pixel's reuse steps as the real-time pipeline computed them (`restir inspect
 * --from-dump`, docs/oracle.md §6): the frame's stage listener (stage_hook.h) may name one
 * pixel; the temporal step (temporal.h), each spatial pass's GRIS step (spatial.h, also the
 * Enhanced pair step) and the stochastic pairwise step (stochastic_spatial.h) of that pixel
 * then hand it a pixel_trace filled from the step's own workspace right after the step, so
 * that every printed number is the renderer's, not a re-implementation's. */
#ifndef RESTIR_FRAME_PIXEL_TRACE_H
#define RESTIR_FRAME_PIXEL_TRACE_H

#include <stdint.h>
#include "restir/core/rng.h"
#include "restir/restir/mutate.h"
#include "restir/restir/reservoir.h"
#include "restir/restir/spatial.h"
#include "restir/restir/stochastic_spatial.h"

#define PIXEL_TRACE_MAX_DOMAINS 64 /* domains recorded per step (more are counted, not kept) */

enum pixel_trace_step {
    PIXEL_TRACE_TEMPORAL,   /* GRIS §6.3 step 2: domain 0 = this frame, 1 = the previous frame's pixel */
    PIXEL_TRACE_SPATIAL,    /* GRIS §6.3 step 3 with a MIS family (spatial_resample) */
    PIXEL_TRACE_PAIR,       /* Enhanced §3: the same step with the pre-pass's pair shifts */
    PIXEL_TRACE_STOCHASTIC, /* Stochastic MIS §4: stochastic pairwise MIS */
    PIXEL_TRACE_MUTATION    /* Mutations Alg. 3: the MCMC chain after the stage's step (same
                               stage name; only `mutation`, `key`, `out` are set) */
};

/* One domain i of a step. */
typedef struct {
    long pixel;           /* the domain's pixel (temporal i = 1: in the previous frame) */
    real u;               /* its selection number: RNG_RIS, the step's vertex, slot i */
    int valid;            /* a sample and a successful shift into the pixel (stochastic: also picked) */
    reservoir in;         /* the input reservoir (scalars only: W, wsum, confidence, sample id) */
    real confidence;      /* c_i as the step's MIS used it (after an M-cap; stochastic: scaled) */
    real jacobian;        /* |dT_i/dX_i| (1 for i = 0) */
    real target;          /* p̂(y_i) = p̂_{<-0}(y_i), y_i = T_i(X_i) (GRIS Eq. 35) */
    real target_own;      /* p̂_{<-i}(y_i) = p̂_i(X_i) / J_i */
    real target_back;     /* p̂_{<-i}(y_0): the canonical sample seen from domain i (0: not needed) */
    real m;               /* m_i(y_i) (GRIS Eqs. 36-38; stochastic: m̃_i, Eq. 16) */
    real w;               /* w_i = m_i p̂(y_i) W_i J_i (GRIS Eq. 19) */
    int picks;            /* stochastic: K(i), the times domain i was picked (Eq. 16) */
    real P;               /* stochastic: the pick probability P(i) (Eq. 17) */
    int candidate;        /* spatial i >= 1: the neighbour candidate k that proposed it (its
                             numbers: RNG_NEIGHBOR, vertex k; neighbors.h); -1: none (i = 0,
                             temporal, reuse cells) */
} pixel_trace_domain;

typedef struct {
    char stage[32];       /* "temporal", "spatial1", ... */
    int step;             /* enum pixel_trace_step */
    uint32_t frame;
    long pixel;
    int pass;             /* spatial pass (0-based), -1 temporal */
    rng_key key;          /* the pixel's RNG key (initial_pixel_key): seed, pixel, sample */
    uint32_t vertex;      /* RNG_RIS vertex of the selection numbers (slot = domain) */
    uint32_t neighbor_sample; /* spatial: the RNG_NEIGHBOR sample of the neighbour choice */
    int mis;              /* mis_family of the step (-1: stochastic pairwise) */
    real mcap;            /* temporal: the M-cap applied to domain 1 */
    int m;                /* domains (M) */
    int kept;             /* domains recorded: min(m, PIXEL_TRACE_MAX_DOMAINS) */
    pixel_trace_domain d[PIXEL_TRACE_MAX_DOMAINS];
    int n_picks, n_canonical;  /* stochastic: Ñ, Ñ_c and their numbers (RNG_RIS vertices */
    real up[STOCHASTIC_MAX_PICKS], uc[STOCHASTIC_MAX_PICKS]; /* STOCHASTIC_PICK / _CANONICAL) */
    real m_c;             /* stochastic: m̃_c of the canonical sample (Eq. 18) */
    int selected;         /* the domain whose candidate became the output (-1: none) */
    reservoir out;        /* the step's output (scalars) */
    mutate_trace mutation; /* PIXEL_TRACE_MUTATION: the chain (RNG_MUTATE, vertex = mutate_stage) */
    int mutate_stage;      /* enum mutate_stage */
} pixel_trace;

/* The trace of a GRIS step (temporal, spatial or pair): domains 0..m-1 with pixels[i],
 * inputs in[i], numbers u[i] and the workspace ws the step just filled (NULL: no reuse,
 * m = 1, the output is in[0]: temporal reuse without history). */
void pixel_trace_gris(pixel_trace *t, int step, const char *stage, uint32_t frame, long pixel, int pass, rng_key key,
                      uint32_t vertex, int mis, int m, const long *pixels, const reservoir *const *in, const real *u,
                      const spatial_workspace *ws, const reservoir *out);

/* The trace of a stochastic pairwise step (its workspace sw, pick numbers up, uc). */
void pixel_trace_stochastic(pixel_trace *t, const char *stage, uint32_t frame, long pixel, int pass, rng_key key,
                            const stochastic_options *so, int m, const long *pixels, const reservoir *const *in,
                            const real *u, const real *up, const real *uc, const stochastic_workspace *sw,
                            const reservoir *out);

#endif
