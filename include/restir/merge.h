/* Two-domain resampling: a pixel's canonical reservoir merged with ONE shifted
 * neighbour reservoir (GRIS §4, Eq. 36 with confidence weights for M = 2 domains;
 * Mutations App. B Eqs. 31-32; docs/restir-pt.md "Two-domain merge").
 *
 *   canonical x_c (pixel c, W_c, c_c):
 *     m_c = c_c p̂_c(x_c) / (c_c p̂_c(x_c) + c_n p̂_n(T_{c->n}(x_c)) |dT_{c->n}/dx_c|)      (Eq. 31)
 *     w_c = m_c p̂_c(x_c) W_c                                                              (GRIS Eq. 19)
 *   neighbour x_n (pixel n, W_n, c_n), y_n = T_{n->c}(x_n), J = |dT_{n->c}/dx_n|:
 *     m_n = c_n p̂_n(x_n)/J / (c_n p̂_n(x_n)/J + c_c p̂_c(y_n))                              (Eq. 32)
 *     w_n = m_n p̂_c(y_n) W_n J                                                            (GRIS Eq. 19)
 *   Y selected with probability w/(w_c + w_n); W_Y = (w_c + w_n) / p̂_c(Y) (GRIS Eq. 22);
 *   c = c_c + c_n (GRIS §6.2).
 * A domain's weight does not depend on what that domain happened to sample: an empty
 * neighbour reservoir still enters m_c with its confidence (and likewise the canonical
 * domain enters m_n). A failed shift contributes p̂ = 0 (GRIS Eq. 35). */
#ifndef RESTIR_MERGE_H
#define RESTIR_MERGE_H

#include "restir/reservoir.h"
#include "restir/shift.h"

typedef struct {
    uint64_t merges;      /* pixels merged with a neighbour */
    uint64_t no_neighbor; /* the drawn neighbour was the pixel itself, off-screen or had no primary hit */
    uint64_t shifts;      /* shifts attempted (canonical out, neighbour in) */
    uint64_t outcome[SHIFT_FAILURE_COUNT]; /* by result; outcome[SHIFT_OK] = successes */
    uint64_t selected_neighbor; /* merged reservoirs that kept the neighbour's (shifted) sample */
} merge_stats;

/* Merges canonical reservoir rc (primary hit xc1) with neighbour reservoir rn (primary hit
 * xn1) into out, with the RIS numbers u_c (canonical streamed first) and u_n. */
void merge_two_domains(const restir_context *c, const path_vertex *xc1, const reservoir *rc, const path_vertex *xn1,
                       const reservoir *rn, real u_c, real u_n, reservoir *out, merge_stats *st);

void merge_stats_add(merge_stats *acc, const merge_stats *add);

#endif
