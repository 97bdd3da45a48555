/* Private to src/oracle. `restir inspect`'s two-domain GRIS steps (inspect_step.c; the
 * text in inspect.c, the JSON in inspect_json.c). */
#ifndef RESTIR_INSPECT_STEP_H
#define RESTIR_INSPECT_STEP_H

#include <stdio.h>
#include "restir/restir/initial.h"
#include "restir/frame/options.h"
#include "restir/restir/spatial.h"

/* One GRIS step with two domains, with everything the tour's hand computation needs: the
 * workspace's ptarget (GRIS Eq. 35), J, c (after any M-cap), m_j (Eqs. 36-38), the w_j
 * (Eq. 19), and out->wsum, out->W (Eq. 22). */
typedef struct {
    int temporal;         /* 0: the spatial step, 1: the temporal step (domain 1 = frame f - 1) */
    int shown;            /* 0: --mis stochastic-pairwise (no 2-domain dispatch to show) */
    real u[2], w[2];      /* selection numbers, resampling weights w_j (GRIS Eq. 19) */
    int selected;         /* j of the selected candidate, -1 if none */
    reservoir in[2], out; /* the inputs and the step's output */
    spatial_workspace ws;
} inspect_step;

/* One spatial GRIS step at pixel p (GRIS §6.3, Alg. 2 for M = 2): domain 0 = p's initial
 * reservoir ra (canonical), domain 1 = the neighbour's rb (primary vertex xb), with the
 * selection numbers of spatial pass 1 (offline.c spatial_pixel) and o->spatial.mis. */
int inspect_spatial_step(const restir_context *c, const restir_options *o, const initial_options *io,
                         const path_vertex *xa, const path_vertex *xb, const reservoir *ra, const reservoir *rb,
                         uint32_t p, inspect_step *g, rerror *e);
/* The temporal GRIS step of pixel p in a static scene (see inspect_step.c). */
int inspect_temporal_step(const restir_context *c, const restir_options *o, const initial_options *io,
                          const path_vertex *xa, const path_vertex *xprev, const reservoir *ra, const reservoir *rprev,
                          uint32_t p, inspect_step *g, rerror *e);

#endif
