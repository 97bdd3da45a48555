/* Two-domain resampling (include/restir/merge.h). */
#include "restir/merge.h"

#include "restir/mis.h"

static real ablated_jacobian(const restir_context *c, real jacobian)
{
    /* The jacobian ablation drops |dT/dx| wherever it enters (weights and MIS). */
    return c->ablation == RESTIR_ABLATE_JACOBIAN && jacobian > 0 ? 1 : jacobian;
}

static enum shift_failure counted_shift(const restir_context *c, const path_vertex *to, const path_sample *x,
                                        path_sample *y, real *jacobian, merge_stats *st)
{
    enum shift_failure why = shift_path(c, to, x, y, jacobian, NULL);
    st->shifts++;
    st->outcome[why]++;
    *jacobian = ablated_jacobian(c, *jacobian);
    return why;
}

void merge_two_domains(const restir_context *c, const path_vertex *xc1, const reservoir *rc, const path_vertex *xn1,
                       const reservoir *rn, real u_c, real u_n, reservoir *out, merge_stats *st)
{
    path_sample shifted;
    real jacobian;
    reservoir_init(out);
    st->merges++;
    if (path_sample_is_valid(&rc->y) && rc->W > 0) {
        /* p̂ from n at x_c (GRIS Eq. 35): the canonical sample shifted into domain n. */
        real p_c = rc->y.target, p_n_from_c = 0, m_c;
        if (counted_shift(c, xn1, &rc->y, &shifted, &jacobian, st) == SHIFT_OK) p_n_from_c = shifted.target * jacobian;
        m_c = mis_pair_canonical(rc->confidence, p_c, rn->confidence, p_n_from_c); /* Mutations Eq. 31 */
        reservoir_stream(out, &rc->y, gris_resampling_weight(m_c, p_c, rc->W, 1), u_c);
    }
    if (path_sample_is_valid(&rn->y) && rn->W > 0 &&
        counted_shift(c, xc1, &rn->y, &shifted, &jacobian, st) == SHIFT_OK) {
        real p_n_from_n = rn->y.target / jacobian, p_c_at_n = shifted.target;
        real m_n = mis_pair_neighbor(rn->confidence, p_n_from_n, rc->confidence, p_c_at_n); /* Mutations Eq. 32 */
        if (reservoir_stream(out, &shifted, gris_resampling_weight(m_n, p_c_at_n, rn->W, jacobian), u_n))
            st->selected_neighbor++;
    }
    reservoir_add_confidence(out, rc->confidence);
    reservoir_add_confidence(out, rn->confidence);
    reservoir_finalize(out);
}

void merge_stats_add(merge_stats *acc, const merge_stats *add)
{
    int i;
    acc->merges += add->merges;
    acc->no_neighbor += add->no_neighbor;
    acc->shifts += add->shifts;
    acc->selected_neighbor += add->selected_neighbor;
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i) acc->outcome[i] += add->outcome[i];
}
