/* Private to src/oracle. Golden vectors of whole steps through the real code path
 * (src/oracle/vectors_step.c; docs/oracle.md §2 "Whole steps"): the temporal step
 * (temporal_resample), a whole mutation chain (mutate_reservoir), one rv/pp/fp proposal with
 * its kernel terms (mutate_propose, mutate_rv_terms) and the stochastic pairwise step
 * (stochastic_pairwise_resample), each on the shift vectors' scene (vectors.c) with
 * reservoirs built by initial_sample_pixel. A vector that re-implements a step's arithmetic
 * cannot see a bug in the step; these call it. */
#ifndef RESTIR_SRC_ORACLE_VECTORS_STEP_H
#define RESTIR_SRC_ORACLE_VECTORS_STEP_H

#include "restir/render/gbuffer.h"
#include "restir/scene/lights.h"
#include "restir/scene/scene.h"

/* The shift vectors' scene (vectors.c): 0 and the loaded scene, or -1. */
int vectors_scene(const scene **s, const light_set **lights, const gbuffer **g, int *width, int *height);

/* Evaluators (vector_fn.eval): the number of outputs, -1 for inputs that do not fit. */
int vectors_eval_temporal_step(const double *in, int n_in, double *out);
int vectors_eval_mutate_chain(const double *in, int n_in, double *out);
int vectors_eval_mutate_propose(const double *in, int n_in, double *out);
int vectors_eval_stochastic_step(const double *in, int n_in, double *out);

/* The cases: emit(g, fn, eqs, label, in, n_in) once per vector. */
typedef void (*vectors_emit_fn)(void *g, const char *fn, const char *eqs, const char *label, const double *in,
                                int n_in);
void vectors_cases_temporal(vectors_emit_fn emit, void *g);
void vectors_cases_mutate_step(vectors_emit_fn emit, void *g);
void vectors_cases_stochastic_step(vectors_emit_fn emit, void *g);

#endif
