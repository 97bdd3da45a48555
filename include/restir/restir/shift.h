/* Shift mappings T from a base path x of one pixel to an offset path y of another
 * (GRIS §4.3, §7; Enhanced §2.3), in the lobe-extended primary sample space (PSS) of
 * GRIS §7.6 / §8.1 where the target is p̂ = luminance(F), F = f/p (docs/design.md, Conventions).
 *
 * A shift starts at the destination pixel's primary hit y_1 (path_vertex, built by the
 * path sampler from the camera ray) and returns the offset path as a complete
 * path_sample in the destination domain (F(y), p̂(y), lobes, reconnection data with the
 * destination's source terms, so y can itself be shifted back: T^{-1}(y) = x), together
 * with the PSS Jacobian |dT/du|, or a named failure (restir_context.h) and nothing else:
 *
 *   reconnection  y_2 = x_2 (k = 2 always; GRIS §7.4):  J = Enhanced Eq. 2 at k = 2;
 *   replay        every number of x replayed from y_1 (GRIS §7.2): J = 1 (GRIS §8.1, PSS);
 *   hybrid        numbers replayed up to y_{k-1}, then reconnection to x_k (GRIS §7.4-7.6):
 *                 J = 1 x Enhanced Eq. 2 (= GRIS Eq. 52 converted by Eq. 54); fails unless
 *                 the offset path selects the same k under the same criterion (invertibility).
 *
 * The replay identity of the offset stays the base's (seed, pixel, sample): the replayed
 * numbers ARE the base's numbers, which is what makes replay the identity in PSS. */
#ifndef RESTIR_SHIFT_H
#define RESTIR_SHIFT_H

#include "restir/restir/reconnection.h"

/* Optional details of one shift (restir inspect, tests). */
typedef struct {
    int replayed;   /* vertices y_1..y_n built by replay (n) */
    rc_terms terms; /* reconnection terms (valid when reconnected) */
    int reconnected;
} shift_info;

/* T_{x's pixel -> y1's pixel}(x) with the context's shift. On SHIFT_OK, *y is the offset
 * path and *jacobian = |dT/du| > 0; on failure *y is empty and *jacobian = 0.
 * info may be NULL. */
enum shift_failure shift_path(const restir_context *c, const path_vertex *y1, const path_sample *x, path_sample *y,
                              real *jacobian, shift_info *info);

/* The three mappings, whatever the context's shift (the sample must carry the
 * reconnection index its own mapping expects: k = 2, none, or rc_select's). */
enum shift_failure shift_reconnection(const restir_context *c, const path_vertex *y1, const path_sample *x,
                                      path_sample *y, real *jacobian, shift_info *info);
enum shift_failure shift_random_replay(const restir_context *c, const path_vertex *y1, const path_sample *x,
                                       path_sample *y, real *jacobian, shift_info *info);
enum shift_failure shift_hybrid(const restir_context *c, const path_vertex *y1, const path_sample *x, path_sample *y,
                                real *jacobian, shift_info *info);

/* The hybrid shift's invertibility test (GRIS §7.4, pitfall 3, docs/restir-pt.md §11) on the replayed
 * offset prefix y_1..y_{k-1} (t->n = k - 1) followed by x's x_k: SHIFT_OK if the offset
 * path's first connectable pair is (y_{k-1}, x_k); SHIFT_FAIL_RC_EARLIER if a pair
 * (y_{j-1}, y_j) with j < k-1 is connectable, SHIFT_FAIL_RC_PREV if (y_{k-2}, y_{k-1})
 * is, SHIFT_FAIL_RC_ROUGHNESS / _DISTANCE if (y_{k-1}, x_k) is not. */
enum shift_failure hybrid_same_reconnection(const restir_context *c, const path_trunk *t, const path_sample *x);

#endif
