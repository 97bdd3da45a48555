/* Private to src/frame. The Enhanced §3 pair step of paired spatial reuse (pair_step.c):
 * each reciprocal pair shifts its two samples once each, in a pre-pass, instead of four
 * times in two GRIS steps. */
#ifndef RESTIR_SRC_FRAME_PAIR_STEP_H
#define RESTIR_SRC_FRAME_PAIR_STEP_H

#include "stages.h"

/* Enhanced §3 pair step (pair_step.c). The pre-pass of spatial pass j->pass: every pixel's
 * sample j->src[p] shifted once to each accepted partner into j->pair. */
void frame_pair_prepass(frame_job *j);
/* Pixel p's domains for the pass from the pre-pass: its neighbours into w->nbr, w->slot,
 * the cached x1 of every domain into w->x1; returns n (pair_n[p] >= 0). */
int frame_pair_domains(frame_job *j, worker_state *w, long p);
int frame_pair_alloc(frame_job *j, rerror *e);
void frame_pair_free(frame_job *j);
/* The pass's GRIS step at pixel p (n accepted neighbours in w->nbr, textures in w->slot,
 * domains set up in w) from the pre-pass shifts: no shift between the pair is made here. */
void frame_pair_resample(frame_job *j, worker_state *w, long p, int n, reservoir *out);

#endif
