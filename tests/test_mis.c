/* Resampling MIS weights (include/restir/restir/mis.h, docs/mis-derivations.md): partition of
 * unity on random inputs with failed shifts, zero targets and random confidences; the
 * paper's literal formulas for unit confidences; closed forms for M = 2; the weight bound
 * behind GRIS Eq. 39; shift counts. The unbiasedness evidence is tests/test_mis_toy.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "restir/restir/mis.h"
#include "restir/core/rng.h"
#include "test.h"

#define MAX_M 8
#define TOL (sizeof(real) == 4 ? 2e-5 : 1e-12)

/* Test randomness: consecutive addresses of the RNG_TEST stream. */
typedef struct {
    rng_key key;
    uint32_t n;
} test_rng;

static test_rng test_rng_make(uint32_t test_id, uint32_t trial)
{
    test_rng r;
    r.key = rng_key_at(rng_key_make(test_seed(), test_id, trial), RNG_TEST, 0, 0);
    r.n = 0;
    return r;
}

static real urand(test_rng *r)
{
    rng_key k = r->key;
    k.vertex = (r->n >> 16) & 0xffu;
    k.slot = r->n & 0xffffu;
    r->n++;
    return rng_uniform(k);
}

/* A random GRIS configuration. */
typedef struct {
    int m, n_canonical;
    real c[MAX_M];
    real p[MAX_M * MAX_M];
    mis_input in;
} mis_case;

static void case_wire(mis_case *t)
{
    t->in.m = t->m;
    t->in.n_canonical = t->n_canonical;
    t->in.confidence = t->c;
    t->in.ptarget = t->p;
}

/* A case by hand: m domains, the first n_canonical canonical, confidences c, every "p̂
 * from i" 0 (the caller sets the ones it needs). */
static void hand_case(mis_case *t, int m, int n_canonical, const real *c)
{
    int i;
    memset(t, 0, sizeof *t);
    t->m = m;
    t->n_canonical = n_canonical;
    for (i = 0; i < m; ++i) t->c[i] = c[i];
    case_wire(t);
}

/* Random case: about 30% failed shifts (zero "p̂ from i"), 15% zero canonical targets,
 * 10% zero confidences, targets spread over four orders of magnitude. Canonical rows are
 * one shared p̂(y_j) (identity shift, same target). */
static void random_case(test_rng *r, mis_case *t, int allow_zero_confidence)
{
    int i, j;
    t->m = 1 + (int)(urand(r) * MAX_M);
    t->n_canonical = 1 + (int)(urand(r) * t->m);
    for (i = 0; i < t->m; ++i) {
        t->c[i] = (allow_zero_confidence && urand(r) < 0.1) ? 0 : (real)0.05 + 5 * urand(r);
    }
    for (j = 0; j < t->m; ++j) {
        real canonical = urand(r) < 0.15 ? 0 : (real)pow(10.0, 4.0 * urand(r) - 2.0);
        for (i = 0; i < t->m; ++i) {
            real v = urand(r) < 0.3 ? 0 : (real)pow(10.0, 4.0 * urand(r) - 2.0);
            t->p[i * t->m + j] = i < t->n_canonical ? canonical : v;
        }
    }
    case_wire(t);
}

/* One property over random cases: trial 0..trials-1 of test `id` (its own RNG addresses),
 * each case drawn by random_case and given to check (with the RNG, for more numbers), until
 * a check fails. */
typedef void (*case_check)(test_rng *r, mis_case *t, int trial);

static void each_random_case(uint32_t id, int trials, int allow_zero_confidence, case_check check)
{
    int trial;
    for (trial = 0; trial < trials && !test_has_failed(); ++trial) {
        test_rng r = test_rng_make(id, (uint32_t)trial);
        mis_case t;
        random_case(&r, &t, allow_zero_confidence);
        check(&r, &t, trial);
    }
}

static const mis_family proper_families[3] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};

/* GRIS Eq. 20 / Stochastic MIS Eq. 8: for every proper family and every sample point y_j,
 * the weights are >= 0 and sum to 1; where p̂(y_j) > 0 the weight of a domain that cannot
 * produce y_j (failed shift: "p̂ from i" = 0) or has zero confidence is exactly 0, so the
 * sum over the domains that CAN produce y_j is 1 too (the sum Eq. 20 really asks for);
 * this needs some canonical confidence (c_R > 0), otherwise the canonical fallback holds.
 * Points with all-zero targets get the documented canonical convention. */
static void partition_of_unity_random(test_rng *r, mis_case *t, int trial)
{
    int f, i, j;
    (void)r;
    for (f = 0; f < 3; ++f) {
        for (j = 0; j < t->m; ++j) {
            real m[MAX_M], sum = 0, sum_generating = 0, p_hat = t->p[j], c_R = 0;
            for (i = 0; i < t->n_canonical; ++i) c_R += t->c[i];
            mis_weights_at(proper_families[f], &t->in, j, m, NULL);
            for (i = 0; i < t->m; ++i) {
                real q = t->p[i * t->m + j];
                CHECKF(m[i] >= 0 && m[i] <= 1 + TOL, "%s trial %d: m_%d(y_%d) = %g",
                       mis_family_name(proper_families[f]), trial, i, j, (double)m[i]);
                sum += m[i];
                if (q > 0) sum_generating += m[i];
                if (p_hat > 0 && c_R > 0 && (q == 0 || t->c[i] == 0))
                    CHECKF(m[i] == 0, "%s trial %d: domain %d cannot produce y_%d but m = %g",
                           mis_family_name(proper_families[f]), trial, i, j, (double)m[i]);
            }
            CHECKF(fabs(sum - 1) <= TOL, "%s trial %d (M=%d R=%d) at y_%d: sum m = %.17g",
                   mis_family_name(proper_families[f]), trial, t->m, t->n_canonical, j, (double)sum);
            if (p_hat > 0)
                CHECKF(fabs(sum_generating - 1) <= TOL, "%s trial %d: sum over producing domains %.17g",
                       mis_family_name(proper_families[f]), trial, (double)sum_generating);
        }
    }
}

TEST(mis_partition_of_unity_random)
{
    each_random_case(1, 3000, 1, partition_of_unity_random);
}

/* The all-zero convention: a point no domain's target reaches (outside supp p̂) gets its
 * whole weight on the canonical domains, split by confidence, for every family. */
TEST(mis_all_zero_targets_convention)
{
    static const real c[4] = {1, 3, 2, 5};
    mis_case t;
    int f, i;
    hand_case(&t, 4, 2, c);
    for (f = 0; f < 3; ++f) {
        real m[4];
        mis_weights_at(proper_families[f], &t.in, 2, m, NULL);
        CHECK_NEAR(m[0], 0.25, TOL);
        CHECK_NEAR(m[1], 0.75, TOL);
        CHECK(m[2] == 0 && m[3] == 0);
    }
    /* all confidences zero as well: equal split over the canonical domains */
    for (i = 0; i < 4; ++i) t.c[i] = 0;
    for (f = 0; f < MIS_FAMILY_COUNT; ++f) {
        real m[4];
        mis_weights_at((mis_family)f, &t.in, 0, m, NULL);
        CHECK_NEAR(m[0], 0.5, TOL);
        CHECK_NEAR(m[1], 0.5, TOL);
        CHECK(m[2] == 0 && m[3] == 0);
    }
}

/* GRIS §5.6: constant weights c_i / sum c sum to 1 over ALL domains, but Eq. 20 sums only
 * over the domains that can produce y. Where a shift fails (supports differ) that sum is
 * (sum of the producing confidences) / (sum of all) < 1: y is under-counted (bias, darker).
 * Where every domain covers y it is a partition of unity (the all-canonical exception). */
TEST(mis_constant_is_not_a_partition_where_supports_differ)
{
    int trial, i, j, seen_deficit = 0;
    mis_case t;
    static const real c[3] = {1, 2, 3};
    /* a hand example first: domain 2 cannot produce y_0 */
    hand_case(&t, 3, 1, c);
    t.p[0 * 3 + 0] = 0.7;
    t.p[1 * 3 + 0] = 0.4;
    t.p[2 * 3 + 0] = 0; /* failed shift of y_0 into domain 2 */
    {
        real m0 = mis_constant(&t.in, 0, 0, NULL), m1 = mis_constant(&t.in, 1, 0, NULL);
        CHECK_NEAR(m0 + m1, 0.5, TOL); /* (1 + 2) / 6: half of y_0's weight is lost */
        CHECK_NEAR(mis_talbot(&t.in, 0, 0, NULL) + mis_talbot(&t.in, 1, 0, NULL), 1, TOL);
    }
    for (trial = 0; trial < 2000; ++trial) {
        test_rng r = test_rng_make(2, (uint32_t)trial);
        random_case(&r, &t, 0);
        for (j = 0; j < t.m; ++j) {
            real sum_all = 0, sum_generating = 0, c_generating = 0, c_all = 0;
            int all_cover = 1;
            if (t.p[j] == 0) continue; /* outside supp p̂: Eq. 20 does not apply */
            for (i = 0; i < t.m; ++i) {
                real m = mis_constant(&t.in, i, j, NULL), q = t.p[i * t.m + j];
                sum_all += m;
                c_all += t.c[i];
                if (q > 0) {
                    sum_generating += m;
                    c_generating += t.c[i];
                } else {
                    all_cover = 0;
                }
            }
            CHECK_NEAR(sum_all, 1, TOL);
            CHECK_NEAR(sum_generating, c_generating / c_all, TOL);
            if (all_cover) {
                CHECK_NEAR(sum_generating, 1, TOL);
            } else {
                CHECKF(sum_generating < 1 - 1e-3, "trial %d: constant MIS sums to %g over producing domains", trial,
                       (double)sum_generating);
                seen_deficit++;
            }
        }
    }
    CHECK(seen_deficit > 1000);
}

/* GRIS Eq. 36 with equal "p̂ from i" reduces to the confidence shares c_i / sum c
 * (the reservoir-merge weights of GRIS §6.2); with unit confidences to 1/M. */
TEST(mis_talbot_equal_targets_gives_confidence_shares)
{
    int trial, i, j;
    for (trial = 0; trial < 500; ++trial) {
        test_rng r = test_rng_make(3, (uint32_t)trial);
        mis_case t;
        real c_sum = 0, q = (real)0.01 + urand(&r);
        random_case(&r, &t, 1);
        for (i = 0; i < t.m * t.m; ++i) t.p[i] = q;
        for (i = 0; i < t.m; ++i) c_sum += t.c[i];
        if (c_sum == 0) continue;
        for (j = 0; j < t.m; ++j)
            for (i = 0; i < t.m; ++i) CHECK_NEAR(mis_talbot(&t.in, i, j, NULL), t.c[i] / c_sum, TOL);
    }
}

/* Pairwise MIS approximates the Talbot denominator sum_k c_k q_k by c_S q_i (pair i stands
 * in for all non-canonical domains, docs §3.3). So when every non-canonical "p̂ from k"
 * equals the same q, the uniform variant IS the Talbot weight, for any p̂ and confidences. */
static void pairwise_uniform_equals_talbot_when_neighbors_agree(test_rng *r, mis_case *t, int trial)
{
    int i, j, k;
    for (j = 0; j < t->m; ++j) {
        real q = urand(r) < 0.2 ? 0 : (real)0.01 + urand(r);
        for (k = t->n_canonical; k < t->m; ++k) t->p[k * t->m + j] = q;
    }
    for (j = 0; j < t->m; ++j)
        for (i = 0; i < t->m; ++i)
            CHECKF(fabs(mis_pairwise_uniform(&t->in, i, j, NULL) - mis_talbot(&t->in, i, j, NULL)) <= TOL,
                   "trial %d i %d j %d", trial, i, j);
}

TEST(mis_pairwise_uniform_equals_talbot_when_neighbors_agree)
{
    each_random_case(4, 1000, 0, pairwise_uniform_equals_talbot_when_neighbors_agree);
}

/* ---- the papers' formulas, transcribed literally for unit confidences ---- */

/* GRIS Eq. 36 (Talbot 2005 generalized): p̂_<-i / sum_j p̂_<-j. */
static real paper_eq36(const mis_case *t, int i, int y)
{
    real s = 0;
    int k;
    for (k = 0; k < t->m; ++k) s += t->p[k * t->m + y];
    return t->p[i * t->m + y] / s;
}

/* GRIS Eq. 37 (uniform) and Eq. 38 (defensive), canonical set R = {0..|R|-1}. */
static real paper_eq37_38(const mis_case *t, int i, int y, int defensive)
{
    int M = t->m, R = t->n_canonical, k;
    real p_hat = t->p[y], s = 0;
    if (i >= R) {
        real q = t->p[i * M + y];
        real m = q / (R * p_hat + (M - R) * q);
        return defensive ? (real)(M - R) / M * m : m;
    }
    for (k = R; k < M; ++k) s += p_hat / (R * p_hat + (M - R) * t->p[k * M + y]);
    return defensive ? (real)1 / M + s / M : s / (M - R);
}

/* With c_i = 1 the confidence-weighted families are exactly GRIS Eqs. 36, 37 and 38 (any
 * |R|), checked where the paper's formulas are defined (positive targets). */
static void unit_confidences_match_gris_eqs_36_37_38(test_rng *r, mis_case *t, int trial)
{
    int i, j, k;
    (void)trial;
    if (t->m == t->n_canonical) return; /* Eq. 37 needs a non-canonical domain */
    for (i = 0; i < t->m; ++i) t->c[i] = 1;
    for (k = 0; k < t->m * t->m; ++k) t->p[k] = (real)0.01 + urand(r); /* positive */
    for (j = 0; j < t->m; ++j) {
        real pj = t->p[j];
        for (i = 0; i < t->n_canonical; ++i) t->p[i * t->m + j] = pj;
    }
    for (j = 0; j < t->m; ++j) {
        for (i = 0; i < t->m; ++i) {
            CHECK_NEAR(mis_talbot(&t->in, i, j, NULL), paper_eq36(t, i, j), TOL);
            CHECK_NEAR(mis_pairwise_uniform(&t->in, i, j, NULL), paper_eq37_38(t, i, j, 0), TOL);
            CHECK_NEAR(mis_pairwise_defensive(&t->in, i, j, NULL), paper_eq37_38(t, i, j, 1), TOL);
        }
    }
}

TEST(mis_unit_confidences_match_gris_eqs_36_37_38)
{
    each_random_case(5, 1500, 0, unit_confidences_match_gris_eqs_36_37_38);
}

/* Stochastic MIS Eqs. 11a/11b/12 (one canonical domain c = 0, confidences c_i),
 * transcribed literally, equal mis_pairwise_defensive. */
static void defensive_matches_stochastic_mis_eq_11(test_rng *r, mis_case *t, int trial)
{
    int i, j, k;
    (void)trial;
    t->n_canonical = 1;
    case_wire(t);
    for (k = 0; k < t->m * t->m; ++k) t->p[k] = (real)0.01 + urand(r);
    for (j = 0; j < t->m; ++j) {
        real cS = 0, cc = t->c[0], p_hat = t->p[j];
        for (k = 1; k < t->m; ++k) cS += t->c[k]; /* Eq. 12 */
        for (i = 0; i < t->m; ++i) {
            real expected;
            if (i > 0) { /* Eq. 11a */
                real q = t->p[i * t->m + j];
                expected = cS / (cS + cc) * t->c[i] * q / (cS * q + cc * p_hat);
            } else { /* Eq. 11b */
                expected = cc / (cS + cc);
                for (k = 1; k < t->m; ++k)
                    expected += t->c[k] / (cS + cc) * cc * p_hat / (cS * t->p[k * t->m + j] + cc * p_hat);
            }
            CHECK_NEAR(mis_pairwise_defensive(&t->in, i, j, NULL), expected, TOL);
        }
    }
}

TEST(mis_defensive_matches_stochastic_mis_eq_11)
{
    each_random_case(6, 1000, 0, defensive_matches_stochastic_mis_eq_11);
}

/* M = 2 (one canonical, one neighbour): Talbot, uniform pairwise and the two-domain merge
 * weights of Mutations App. B Eqs. 31-32 are one and the same formula; the defensive
 * variant is its closed form (c_n/C) c_n q / (c_n q + c_c p̂) for the neighbour. A failed
 * shift of the canonical sample into the neighbour domain gives m_c = 1 (Mutations App. B).
 * (A failed forward shift of the neighbour has no y at all: its w is 0, m is not used.) */
TEST(mis_two_domains_closed_forms)
{
    int trial;
    for (trial = 0; trial < 2000; ++trial) {
        test_rng r = test_rng_make(7, (uint32_t)trial);
        mis_case t;
        real c_c = (real)0.1 + 4 * urand(&r), c_n = (real)0.1 + 4 * urand(&r);
        /* columns: 0 = canonical sample x_c, 1 = shifted neighbour sample x_n' */
        real p_c = urand(&r) < 0.1 ? 0 : urand(&r);          /* p̂_c(x_c) */
        real p_n_from_c = urand(&r) < 0.3 ? 0 : urand(&r);   /* p̂_n(x_c')|dx_c'/dx_c|, 0 = failed */
        real p_n_from_n = (real)0.01 + urand(&r);            /* p̂_n(x_n)/|dT/dx_n| */
        real p_c_at_n = urand(&r) < 0.3 ? 0 : urand(&r);     /* p̂_c(x_n') */
        real C = c_c + c_n;
        memset(&t, 0, sizeof t);
        t.m = 2;
        t.n_canonical = 1;
        t.c[0] = c_c;
        t.c[1] = c_n;
        t.p[0] = p_c;
        t.p[1] = p_c_at_n;
        t.p[2] = p_n_from_c;
        t.p[3] = p_n_from_n;
        case_wire(&t);
        /* Mutations Eq. 31 and 32 */
        CHECK_NEAR(mis_talbot(&t.in, 0, 0, NULL), mis_pair_canonical(c_c, p_c, c_n, p_n_from_c), TOL);
        CHECK_NEAR(mis_talbot(&t.in, 1, 1, NULL), mis_pair_neighbor(c_n, p_n_from_n, c_c, p_c_at_n), TOL);
        CHECK_NEAR(mis_pairwise_uniform(&t.in, 0, 0, NULL), mis_pair_canonical(c_c, p_c, c_n, p_n_from_c), TOL);
        CHECK_NEAR(mis_pairwise_uniform(&t.in, 1, 1, NULL), mis_pair_neighbor(c_n, p_n_from_n, c_c, p_c_at_n), TOL);
        /* defensive closed forms */
        CHECK_NEAR(mis_pairwise_defensive(&t.in, 1, 1, NULL), c_n / C * (c_n * p_n_from_n) /
                   (c_n * p_n_from_n + c_c * p_c_at_n), TOL);
        if (p_c > 0 || p_n_from_c > 0)
            CHECK_NEAR(mis_pairwise_defensive(&t.in, 0, 0, NULL),
                       c_c / C + c_n / C * (c_c * p_c) / (c_n * p_n_from_c + c_c * p_c), TOL);
        /* Mutations App. B: m_c(x_c) = 1 when x_c has no valid shift */
        if (p_n_from_c == 0 && p_c > 0) CHECK(mis_pair_canonical(c_c, p_c, c_n, 0) == 1);
    }
    /* unit confidences, equal targets: uniform halves, defensive 3/4 vs 1/4 */
    CHECK_NEAR(mis_pair_canonical(1, 0.5, 1, 0.5), 0.5, TOL);
    {
        real c[2] = {1, 1}, p[4] = {0.5, 0.5, 0.5, 0.5};
        mis_input in;
        in.m = 2;
        in.n_canonical = 1;
        in.confidence = c;
        in.ptarget = p;
        CHECK_NEAR(mis_pairwise_defensive(&in, 0, 0, NULL), 0.75, TOL);
        CHECK_NEAR(mis_pairwise_defensive(&in, 1, 0, NULL), 0.25, TOL);
    }
}

/* The bound behind GRIS Eq. 39 (Theorem A.4), with confidences: for every proper family
 *     m_i(y) p̂(y) <= (c_i / c_R) p̂_{<-i}(y),
 * so a candidate's resampling weight w_i = m_i p̂ W_i J_i <= (c_i/c_R) p̂_i(X_i) W_i stays
 * bounded whatever its Jacobian. The defensive variant also keeps the canonical weight
 * >= c_r / C and a neighbour's <= c_i / C ("always higher for canonical samples"). */
static void weight_bound_gris_eq_39(test_rng *r, mis_case *t, int trial)
{
    int f, i, j;
    real c_R = 0, C = 0;
    (void)r;
    for (i = 0; i < t->m; ++i) {
        C += t->c[i];
        if (i < t->n_canonical) c_R += t->c[i];
    }
    for (j = 0; j < t->m; ++j) {
        real p_hat = t->p[j];
        if (p_hat == 0) continue;
        for (f = 0; f < 3; ++f) {
            for (i = 0; i < t->m; ++i) {
                real m = mis_weight(proper_families[f], &t->in, i, j, NULL), q = t->p[i * t->m + j];
                CHECKF(m * p_hat <= t->c[i] / c_R * q * (1 + TOL) + TOL * q, "%s trial %d i %d j %d",
                       mis_family_name(proper_families[f]), trial, i, j);
                if (proper_families[f] == MIS_PAIRWISE_DEFENSIVE) {
                    if (i < t->n_canonical) CHECK(m >= t->c[i] / C - TOL);
                    else CHECK(m <= t->c[i] / C + TOL);
                }
            }
        }
    }
}

TEST(mis_weight_bound_gris_eq_39)
{
    each_random_case(8, 2000, 0, weight_bound_gris_eq_39);
}

/* Shift evaluations per GRIS step: counted reads of entries that need a shift, summed over
 * the resampling weights m_j(y_j), equal mis_shift_count: Talbot (M-R)(M-1) = O(M^2),
 * pairwise R(M-R) = O(M). Pairwise also never touches the entries it does not need: they
 * are poisoned with NaN here and the weights stay finite and unchanged. */
TEST(mis_shift_counts)
{
    int M, R, f, i, j;
    for (M = 1; M <= MAX_M; ++M) {
        for (R = 1; R <= M; ++R) {
            test_rng r = test_rng_make(9, (uint32_t)(M * 16 + R));
            mis_case t, poisoned;
            memset(&t, 0, sizeof t);
            t.m = M;
            t.n_canonical = R;
            for (i = 0; i < M; ++i) t.c[i] = (real)0.5 + urand(&r);
            for (i = 0; i < M * M; ++i) t.p[i] = (real)0.01 + urand(&r);
            for (j = 0; j < M; ++j)
                for (i = 1; i < R; ++i) t.p[i * M + j] = t.p[j];
            case_wire(&t);
            poisoned = t;
            for (i = R; i < M; ++i)
                for (j = R; j < M; ++j)
                    if (i != j) poisoned.p[i * M + j] = (real)NAN;
            case_wire(&poisoned);
            for (f = 0; f < MIS_FAMILY_COUNT; ++f) {
                long shifts = 0;
                for (j = 0; j < M; ++j) {
                    real m = mis_weight((mis_family)f, &t.in, j, j, &shifts);
                    if (f != MIS_TALBOT) CHECK(mis_weight((mis_family)f, &poisoned.in, j, j, NULL) == m);
                }
                CHECKF(shifts == mis_shift_count((mis_family)f, M, R), "%s M=%d R=%d: counted %ld, formula %ld",
                       mis_family_name((mis_family)f), M, R, shifts, mis_shift_count((mis_family)f, M, R));
            }
        }
    }
    CHECK(mis_shift_count(MIS_TALBOT, 7, 1) == 36);
    CHECK(mis_shift_count(MIS_PAIRWISE_DEFENSIVE, 7, 1) == 6);
}

TEST(mis_family_names)
{
    int f;
    mis_family parsed;
    for (f = 0; f < MIS_FAMILY_COUNT; ++f) {
        CHECK(mis_family_parse(mis_family_name((mis_family)f), &parsed) == 0);
        CHECK((int)parsed == f);
    }
    CHECK(mis_family_parse("balance", &parsed) != 0);
}
