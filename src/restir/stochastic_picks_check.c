/* Pick counts of a stochastic pairwise MIS step (include/restir/stochastic_picks_check.h). */
#include "restir/restir/stochastic_picks_check.h"

#include <math.h>
#include <stdio.h>

static int usable(const reservoir *r) { return path_sample_is_valid(&r->y) && r->W > 0; }

int stochastic_check_pick_counts(const stochastic_options *so, int m, const reservoir *const *in,
                                 const stochastic_workspace *w, const spatial_stats *before, const spatial_stats *after,
                                 char *why, size_t why_size)
{
    int n = m - 1, i, sum_k = 0, sum_kc = 0, distinct_k = 0, distinct_kc = 0, any_p = 0, canonical_ran;
    uint64_t mis_shifts = after->mis_shifts - before->mis_shifts, shifts = after->shifts - before->shifts;
    double scale = 1, C = in[0]->confidence;
    if (so->confidence_scaling && n > 0 && so->n_picks < n) scale = (double)so->n_picks / n;
    for (i = 1; i < m; ++i) C += scale * (double)in[i]->confidence;
    canonical_ran = usable(in[0]) && n > 0 && C > 0;
    for (i = 0; i < n; ++i) {
        const reservoir *r = in[i + 1];
        double a = usable(r) ? (double)r->confidence * (double)r->y.target * (double)r->W : 0; /* Eq. 17 */
        int p_pos = so->naive_p ? a > 0 : a > 0 && isfinite(a);
        any_p |= p_pos;
        if (w->K[i] < 0 || (w->K[i] > 0 && !p_pos)) {
            snprintf(why, why_size, "stochastic picks: K(%d) = %d for a domain with P = 0", i + 1, w->K[i]);
            return 1;
        }
        sum_k += w->K[i];
        distinct_k += w->K[i] > 0;
        if (canonical_ran) {
            if (w->Kc[i] < 0) {
                snprintf(why, why_size, "stochastic picks: K'(%d) = %d < 0", i + 1, w->Kc[i]);
                return 1;
            }
            sum_kc += w->Kc[i];
            distinct_kc += w->Kc[i] > 0;
        }
    }
    if (n > 0 && sum_k != (any_p ? so->n_picks : 0)) {
        snprintf(why, why_size, "stochastic picks: %d picks made, Ñ = %d (%s)", sum_k, so->n_picks,
                 any_p ? "some P(i) > 0" : "every P(i) = 0");
        return 1;
    }
    if (canonical_ran && sum_kc != so->n_canonical_picks) {
        snprintf(why, why_size, "stochastic picks: %d canonical picks over the M = %d domains, Ñ_c = %d", sum_kc, n,
                 so->n_canonical_picks);
        return 1;
    }
    if (mis_shifts != (uint64_t)distinct_kc) {
        snprintf(why, why_size,
                 "stochastic picks: %llu MIS shifts of the canonical sample for %d distinct canonical picks (every "
                 "pick, empty domains included, enters m̃_c: Stochastic MIS Eqs. 18-19)",
                 (unsigned long long)mis_shifts, distinct_kc);
        return 1;
    }
    if (shifts != mis_shifts + (uint64_t)distinct_k) {
        snprintf(why, why_size, "stochastic picks: %llu shifts for %d distinct picks and %llu canonical shifts",
                 (unsigned long long)shifts, distinct_k, (unsigned long long)mis_shifts);
        return 1;
    }
    return 0;
}
