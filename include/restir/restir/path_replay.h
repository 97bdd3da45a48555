/* Building a path vertex by vertex from its random numbers: the one code path that
 * ReSTIR's initial path trees, the recording of a selected path, and random replay share
 * (GRIS §7.2 "random replay"; docs/design.md, Conventions). It calls the reference path tracer's per-vertex
 * steps (vertex_sampling.h) with the same arguments in the same order, so the same numbers
 * from the same primary hit give bit-identical vertices, lobes and throughputs. (The
 * initial trees, initial.c, run these steps on a rolling pair of vertices instead of a
 * path_trunk: path_trace_bounce, and the tree's RNG_BSDF numbers through the path tracer's
 * vertex_sample_bsdf, the numbers path_bsdf_numbers gives a sample without pss[].)
 *
 * Numbers: the BSDF step at x_j uses the sample's RNG_BSDF numbers at vertex j (slot 0
 * picks the lobe, slots 1-2 the direction), replaced by the explicit primary-sample
 * vector pss[] where the sample has one; NEE at x_j uses RNG_NEE numbers at vertex j.
 * Russian roulette is never part of a replay (Enhanced §6.2.4). */
#ifndef RESTIR_PATH_REPLAY_H
#define RESTIR_PATH_REPLAY_H

#include "restir/restir/connectability.h"
#include "restir/restir/path_sample.h"
#include "restir/restir/restir_context.h"

/* The vertices x_1..x_n of a path prefix. */
typedef struct {
    int n;                          /* vertices x_1..x_n are present (n >= 1) */
    path_vertex v[PATH_MAX_LENGTH + 1];  /* v[j] = x_j, 1 <= j <= n (v[0] unused) */
    bsdf_bounce b[PATH_MAX_LENGTH + 1];  /* b[j]: the BSDF sample at x_j towards x_{j+1} */
    rgb beta[PATH_MAX_LENGTH + 2];       /* beta[j] = prod_{i<j} b[i].weight: the PSS
                                          * throughput arriving at x_j (beta[1] = 1; no
                                          * Russian roulette) */
} path_trunk;

/* A trunk holding the primary hit x1 only. */
void trunk_begin(path_trunk *t, const path_vertex *x1);

/* The three BSDF numbers (lobe, direction, direction) of vertex j of sample s. */
void path_bsdf_numbers(const path_sample *s, int vertex, real u[3]);

/* The four NEE numbers of an NEE path's last vertex (light selection, point on the light):
 * RNG_NEE at vertex d-1, the point numbers replaced by pss[] where it covers vertex d-1
 * (path_sample.h; MCMC mutations of the light point, Mutations §4.2). */
void path_nee_numbers(const path_sample *s, real u[4]);
/* Samples the BSDF at the last vertex x_n with numbers u: fills b[n] and beta[n+1].
 * SHIFT_OK, SHIFT_FAIL_REPLAY_SAMPLE (no direction) or SHIFT_FAIL_REPLAY_ZERO (the
 * throughput beta[n+1] is black). */
enum shift_failure trunk_sample(path_trunk *t, const real u[3]);
/* The ray of bounce b sampled at v, traced: its hit is built in *next (SHIFT_OK), or it
 * missed (SHIFT_FAIL_REPLAY_MISS). With `sky` non-NULL and holding distant lights, a ray
 * leaving the scene reaches the vertex at infinity along it instead
 * (path_vertex_make_distant; docs/environment.md). The one step of trunk_trace and
 * trunk_trace_escape, also for a loop that keeps only x_i and x_{i+1} (initial.c). */
enum shift_failure path_trace_bounce(const scene *s, const light_set *sky, const path_vertex *v, const bsdf_bounce *b,
                                     path_vertex *next);

/* Traces the ray sampled at x_n and appends the hit x_{n+1}: SHIFT_OK or SHIFT_FAIL_REPLAY_MISS. */
enum shift_failure trunk_trace(path_trunk *t, const scene *s);

/* trunk_trace, except that a ray leaving the scene of a context with distant lights
 * appends the vertex at infinity along it (path_vertex_make_distant; docs/environment.md):
 * for the LAST bounce of a path, which may end at the sky. */
enum shift_failure trunk_trace_escape(path_trunk *t, const restir_context *c);

/* Replays the prefix x_1..x_n (n - 1 bounces) of sample s from the primary hit x1. */
enum shift_failure trunk_replay(path_trunk *t, const restir_context *c, const path_vertex *x1, const path_sample *s,
                                int n);

/* ---- the last vertex (GRIS Eq. 49: balance heuristic between NEE and BSDF sampling) ---- */

/* The contribution of an NEE path ending at x_i: beta_i * f|cos| Le / p_light * w_nee
 * (the reference path tracer's increment without Russian roulette). */
rgb nee_path_contribution(const path_context *c, rgb beta, const nee_sample *n);
/* The contribution of a BSDF path whose bounce b at `from` hit the emitter `hit`:
 * beta_hit * Le * w_bsdf (0 if hit does not emit towards from). *light_pdf receives the
 * NEE pdf of that emitter point seen from `from` = x_{from_index} of the path with base key
 * `path` (0 after a Dirac bounce: NEE cannot produce the path; with light RIS the estimate
 * p̃ of path_light_pdf_hit, from the path's own numbers). */
rgb emitter_path_contribution(const path_context *c, rgb beta_hit, const path_vertex *from, const path_vertex *hit,
                              const bsdf_bounce *b, rng_key path, int from_index, real *light_pdf);
/* The same given le = path_vertex_emitted(c, hit), not black: for a caller that tests it
 * first (initial.c computes b's all-lobe pdf only for such hits). */
rgb emitted_path_contribution(const path_context *c, rgb le, rgb beta_hit, const path_vertex *from,
                              const path_vertex *hit, const bsdf_bounce *b, rng_key path, int from_index,
                              real *light_pdf);

/* How a full path ends. */
typedef struct {
    rgb F;          /* the path contribution (PSS, no roulette) */
    real light_pdf; /* NEE solid-angle pdf of x_d seen from x_{d-1} (0 if NEE cannot produce it) */
    nee_sample nee; /* technique NEE: the light sample at x_{d-1} */
} path_end;

/* Completes the trunk x_1..x_{d-1} (t->n = d - 1) into the length-d path of sample s
 * with its technique: NEE from x_{d-1} with the sample's NEE numbers, or the BSDF bounce
 * at x_{d-1} appended as x_d (t->n = d). Fails with SHIFT_FAIL_NEE, SHIFT_FAIL_REPLAY_*
 * or SHIFT_FAIL_REPLAY_NO_LIGHT (x_d emits nothing towards x_{d-1}). */
enum shift_failure trunk_finish(path_trunk *t, const restir_context *c, const path_sample *s, path_end *end);

/* Replays the whole path of sample s (length, technique, numbers) from x1. */
enum shift_failure path_replay(path_trunk *t, const restir_context *c, const path_vertex *x1, const path_sample *s,
                               path_end *end);

/* The lobe-extended description of a replayed path (GRIS §7.6): lobe[j] for j = 1..d-1
 * (PATH_LOBE_NEE at x_{d-1} of an NEE path) and the connectability of each vertex
 * (v[1..d]) for rc_select. */
void trunk_lobes(const path_trunk *t, int d, int technique, uint8_t lobe[PATH_MAX_LENGTH]);
void trunk_rc_vertices(const path_trunk *t, const restir_context *c, const uint8_t lobe[PATH_MAX_LENGTH], int d,
                       const path_end *end, int technique, rc_vertex v[PATH_MAX_LENGTH + 1]);

#endif
