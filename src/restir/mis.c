/* Resampling MIS weights of GRIS with confidence weights. Formulas, index conventions
 * and the partition-of-unity proofs: docs/mis-derivations.md. */
#include "restir/restir/mis.h"

#include <math.h>
#include <string.h>

static real max2(real a, real b) { return a > b ? a : b; }

real mis_product_ratio(real c_n, real p_n, real c_a, real p_a, real c_b, real p_b)
{
    real den = c_a * p_a + c_b * p_b, c_max, p_max;
    if (isfinite((double)den)) return den > 0 ? c_n * p_n / den : -1;
    /* Overflow: rescale (c_n, p_n are among the a, b terms or no larger in our uses). */
    c_max = max2(c_n, max2(c_a, c_b));
    p_max = max2(p_n, max2(p_a, p_b));
    den = (c_a / c_max) * (p_a / p_max) + (c_b / c_max) * (p_b / p_max);
    return den > 0 ? (c_n / c_max) * (p_n / p_max) / den : -1;
}

/* Reads p̂_{<-i}(y_j), counting it as a shift evaluation when it is one: a non-canonical
 * domain i evaluated at a sample that did not come from i (include/restir/restir/mis.h). */
static real read_ptarget(const mis_input *in, int i, int j, long *shifts)
{
    if (shifts && i >= in->n_canonical && i != j) (*shifts)++;
    return mis_ptarget(in, i, j);
}

static real canonical_confidence(const mis_input *in)
{
    real c = 0;
    int r;
    for (r = 0; r < in->n_canonical; ++r) c += in->confidence[r];
    return c;
}

static real other_confidence(const mis_input *in)
{
    real c = 0;
    int k;
    for (k = in->n_canonical; k < in->m; ++k) c += in->confidence[k];
    return c;
}

/* The all-zero convention: the weight goes to the canonical domains, split by confidence. */
static real canonical_share(const mis_input *in, int i)
{
    real c_R;
    if (i >= in->n_canonical) return 0;
    c_R = canonical_confidence(in);
    return c_R > 0 ? in->confidence[i] / c_R : (real)1 / (real)in->n_canonical;
}

/* GRIS §5.6 constant weights with confidences (GRIS §6.2): c_i / sum c. */
real mis_constant(const mis_input *in, int i, int j, long *shifts)
{
    real total = canonical_confidence(in) + other_confidence(in);
    (void)j;
    (void)shifts;
    return total > 0 ? in->confidence[i] / total : canonical_share(in, i);
}

/* mis_talbot when a term c_k p̂_{<-k} or their sum overflows (float build, huge
 * confidences or targets): every c_k divided by the largest c, every p̂ by the largest
 * p̂ of column j, which leaves the weight unchanged (mis_product_ratio). */
static real talbot_rescaled(const mis_input *in, int i, int j)
{
    real c_max = 0, p_max = 0, numerator = 0, denominator = 0;
    int k;
    for (k = 0; k < in->m; ++k) {
        c_max = max2(c_max, in->confidence[k]);
        p_max = max2(p_max, mis_ptarget(in, k, j));
    }
    for (k = 0; k < in->m; ++k) {
        real term = (in->confidence[k] / c_max) * (mis_ptarget(in, k, j) / p_max);
        denominator += term;
        if (k == i) numerator = term;
    }
    return denominator > 0 ? numerator / denominator : canonical_share(in, i);
}

/* GRIS Eq. 36; Stochastic MIS Eq. 9: the balance heuristic over the "p̂ from k" of Eq. 35
 * (GRIS Eq. 5 is the special case of identity shifts and known source pdfs). */
real mis_talbot(const mis_input *in, int i, int j, long *shifts)
{
    real numerator = 0, denominator = 0;
    int k;
    for (k = 0; k < in->m; ++k) {
        real term = in->confidence[k] * read_ptarget(in, k, j, shifts);
        denominator += term;
        if (k == i) numerator = term;
    }
    if (!isfinite((double)denominator)) return talbot_rescaled(in, i, j);
    return denominator > 0 ? numerator / denominator : canonical_share(in, i);
}

/* The two-domain balance heuristic a / (a + b) inside one pair; an empty pair (a = b = 0)
 * belongs to the canonical side, so this returns 0 for it. */
static real pair_balance(real c_a, real p_a, real c_b, real p_b)
{
    real r = mis_product_ratio(c_a, p_a, c_a, p_a, c_b, p_b);
    return r < 0 ? 0 : r;
}

/* The generalized pairwise family (docs/mis-derivations.md §3). Each non-canonical domain
 * k forms a pair with the canonical set and holds a share lambda_k of the unit weight;
 * the defensive variant reserves lambda_c = c_R / C for the canonical set up front:
 *     uniform (GRIS Eq. 37):    lambda_c = 0,        lambda_k = c_k / c_S
 *     defensive (GRIS Eq. 38):  lambda_c = c_R / C,  lambda_k = c_k / C
 * Within pair k the balance heuristic uses c_S q_k against c_R p̂ (c_S, not c_k: pair k
 * stands in for all non-canonical domains; docs §3.3). */
static real mis_pairwise(const mis_input *in, int i, int j, int defensive, long *shifts)
{
    int R = in->n_canonical, k;
    real c_R = canonical_confidence(in), c_S = other_confidence(in), C = c_R + c_S;
    real p = mis_ptarget(in, 0, j); /* p̂(y_j): canonical row, identity shift, free */
    real share_norm = defensive ? C : c_S;
    real canonical_total;
    if (share_norm <= 0) return canonical_share(in, i); /* no non-canonical confidence */
    if (i >= R) {
        real q = read_ptarget(in, i, j, shifts);
        return in->confidence[i] / share_norm * pair_balance(c_S, q, c_R, p);
    }
    canonical_total = defensive ? c_R / C : 0;
    for (k = R; k < in->m; ++k) {
        real q = read_ptarget(in, k, j, shifts);
        canonical_total += in->confidence[k] / share_norm * (1 - pair_balance(c_S, q, c_R, p));
    }
    return canonical_share(in, i) * canonical_total;
}

/* GRIS Eq. 37 (uniform generalized pairwise MIS), with confidences. */
real mis_pairwise_uniform(const mis_input *in, int i, int j, long *shifts)
{
    return mis_pairwise(in, i, j, 0, shifts);
}

/* GRIS Eq. 38 (defensive generalized pairwise MIS); Stochastic MIS Eqs. 11-12. */
real mis_pairwise_defensive(const mis_input *in, int i, int j, long *shifts)
{
    return mis_pairwise(in, i, j, 1, shifts);
}

/* The confidence form of defensive pairwise MIS in the authors' Falcor ReSTIR PT code
 * (SpatialReuse.cs.slang as summarised in /work/shared/notes/public-restir-implementations.md
 * §1.7 and §4; issue 31 reports vork's WebGPU port does the same): the canonical sample
 * starts at 1, each neighbour adds its pair's canonical share, all divided by n + 1, and
 * the pair's canonical term is M_c p̂ / k. GRIS Eq. 38 with per-pair confidences; the
 * partition of unity is docs/mis-derivations.md §3.5. */
real mis_pairwise_defensive_falcor(const mis_input *in, int i, int j, long *shifts)
{
    int R = in->n_canonical, k;
    real c_R = canonical_confidence(in), n = (real)(in->m - R), share, canonical_total = 1;
    real p = mis_ptarget(in, 0, j); /* p̂(y_j): canonical row, identity shift, free */
    if (in->m == R) return canonical_share(in, i); /* no neighbour: the canonical set alone */
    share = 1 / (n + 1);
    if (i >= R) return share * pair_balance(in->confidence[i], read_ptarget(in, i, j, shifts), c_R / n, p);
    for (k = R; k < in->m; ++k)
        canonical_total += 1 - pair_balance(in->confidence[k], read_ptarget(in, k, j, shifts), c_R / n, p);
    return canonical_share(in, i) * share * canonical_total;
}

real mis_weight(mis_family f, const mis_input *in, int i, int j, long *shifts)
{
    switch (f) {
    case MIS_PAIRWISE_DEFENSIVE_FALCOR: return mis_pairwise_defensive_falcor(in, i, j, shifts);
    case MIS_CONSTANT: return mis_constant(in, i, j, shifts);
    case MIS_TALBOT: return mis_talbot(in, i, j, shifts);
    case MIS_PAIRWISE_UNIFORM: return mis_pairwise_uniform(in, i, j, shifts);
    case MIS_PAIRWISE_DEFENSIVE: return mis_pairwise_defensive(in, i, j, shifts);
    }
    return 0;
}

void mis_weights_at(mis_family f, const mis_input *in, int j, real *out, long *shifts)
{
    int i;
    for (i = 0; i < in->m; ++i) out[i] = mis_weight(f, in, i, j, shifts);
}

long mis_shift_count(mis_family f, int m, int n_canonical)
{
    long M = m, R = n_canonical;
    switch (f) {
    case MIS_CONSTANT: return 0;
    case MIS_TALBOT: return (M - R) * (M - 1); /* every non-canonical row at every other column */
    case MIS_PAIRWISE_UNIFORM:
    case MIS_PAIRWISE_DEFENSIVE:
    case MIS_PAIRWISE_DEFENSIVE_FALCOR: return R * (M - R); /* canonical samples into every other domain */
    }
    return 0;
}

/* Mutations App. B Eq. 31 (canonical sample of a two-domain merge). */
real mis_pair_canonical(real c_c, real p_c, real c_n, real p_n_from_c)
{
    real r = mis_product_ratio(c_c, p_c, c_c, p_c, c_n, p_n_from_c);
    return r < 0 ? 1 : r;
}

/* Mutations App. B Eq. 32 (shifted neighbour sample of a two-domain merge). */
real mis_pair_neighbor(real c_n, real p_n_from_n, real c_c, real p_c_at_n)
{
    return pair_balance(c_n, p_n_from_n, c_c, p_c_at_n);
}

/* The one name table of the MIS families (mis.h); the CLI's --mis reads it too. */
const char *const restir_mis_names[] = {"constant", "talbot", "pairwise", "pairwise-defensive", NULL};

const char *mis_family_name(mis_family f)
{
    if (f == MIS_PAIRWISE_DEFENSIVE_FALCOR) return "pairwise-defensive (falcor confidences)";
    return (int)f >= 0 && (int)f < MIS_FAMILY_COUNT ? restir_mis_names[f] : "unknown";
}

int mis_family_parse(const char *name, mis_family *f)
{
    int i;
    for (i = 0; i < MIS_FAMILY_COUNT; ++i) {
        if (strcmp(name, restir_mis_names[i]) == 0) {
            *f = (mis_family)i;
            return 0;
        }
    }
    return -1;
}
