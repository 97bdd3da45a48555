/* Weighted reservoir streaming and the UCW (reservoir.c): selection probabilities,
 * invalid weights, the exact decision rule, GRIS Eqs. 19/22, confidence bookkeeping, and
 * initial resampling from N path trees with Russian roulette (pitfall 2, docs/restir-pt.md §11), with its
 * broken variants detected. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/reservoir.h"
#include "test.h"

static path_sample tagged_sample(uint32_t tag, real target)
{
    path_sample s;
    path_sample_begin(&s, 1, 2, tag);
    s.technique = PATH_TECH_BSDF;
    s.length = 3;
    s.lobe[1] = 0;
    s.lobe[2] = 1;
    path_sample_set_contribution(&s, rgb_gray(target));
    return s;
}

/* Chao 1982: each candidate ends up selected with probability w_j / sum w. Zero and invalid
 * (NaN, Inf, negative) weights are never selected; invalid ones are counted. */
TEST(reservoir_selection_probabilities)
{
    static const double weights[8] = {1, 0, 3, NAN, 2, 0.5, INFINITY, -1};
    enum { RUNS = 200000 };
    long counts[8] = {0};
    double chi2 = 0, wsum = 6.5;
    int run, j;
    for (run = 0; run < RUNS; ++run) {
        reservoir r;
        rng_key key = rng_key_make(test_seed(), (uint32_t)run, 17);
        reservoir_init(&r);
        for (j = 0; j < 8; ++j) {
            path_sample s = tagged_sample((uint32_t)j, 1);
            reservoir_stream(&r, &s, (real)weights[j], rng_u(key, RNG_RIS, 0, (uint32_t)j));
        }
        CHECK(path_sample_is_valid(&r.y));
        CHECK(r.n_invalid == 3);
        CHECK_NEAR(r.wsum, wsum, 1e-6);
        counts[r.y.sample]++;
    }
    CHECK(counts[1] == 0 && counts[3] == 0 && counts[6] == 0 && counts[7] == 0);
    for (j = 0; j < 8; ++j) {
        double expected = RUNS * (weights[j] > 0 && isfinite(weights[j]) ? weights[j] / wsum : 0);
        if (expected > 0) chi2 += (counts[j] - expected) * (counts[j] - expected) / expected;
    }
    /* 3 degrees of freedom: P(chi2 > 21.1) = 1e-4 */
    CHECKF(chi2 < 21.1, "chi2 = %g (counts %ld %ld %ld %ld)", chi2, counts[0], counts[2], counts[4], counts[5]);
}

/* The decision is exactly u < w / wsum (bit-reproducible rule, docs/formats.md): the first
 * positive weight is always taken, a tie u == w/wsum is not. */
TEST(reservoir_decision_rule)
{
    real wsum = 0;
    uint32_t invalid = 0;
    CHECK(wrs_update(&wsum, 2, (real)0.999999, &invalid) == 1);
    CHECK(wrs_update(&wsum, 2, (real)0.5, &invalid) == 0); /* 0.5 < 2/4 is false */
    CHECK(wrs_update(&wsum, 4, (real)0.49, &invalid) == 1); /* 0.49 < 4/8 */
    CHECK(wrs_update(&wsum, 0, 0, &invalid) == 0);
    CHECK(wsum == 8 && invalid == 0);
    CHECK(wrs_update(&wsum, (real)NAN, 0, &invalid) == 0 && invalid == 1 && wsum == 8);
    CHECK(wrs_update(&wsum, -1, 0, NULL) == 0 && wsum == 8);
}

/* GRIS Eq. 22: W = wsum / p̂(Y) with no 1/M; an empty reservoir, or an inconsistent
 * selection with p̂(Y) = 0, gives W = 0 (the null sample of GRIS §4.2). */
TEST(reservoir_finalize_ucw)
{
    reservoir r;
    path_sample a = tagged_sample(0, 2), b = tagged_sample(1, 0);
    reservoir_init(&r);
    reservoir_finalize(&r);
    CHECK(r.W == 0 && !path_sample_is_valid(&r.y));
    CHECK(rgb_is_black(reservoir_estimate(&r)));
    reservoir_stream(&r, &a, 3, 0);
    reservoir_stream(&r, &b, 0, 0); /* zero weight: skipped */
    reservoir_finalize(&r);
    CHECK_NEAR(r.W, 1.5, 1e-12);
    CHECK_NEAR(luminance(reservoir_estimate(&r)), 3, 1e-6); /* F(Y) W = 2 * 1.5 */
    reservoir_init(&r);
    reservoir_stream(&r, &b, 1, 0); /* a caller bug: positive weight, zero target */
    reservoir_finalize(&r);
    CHECK(r.W == 0 && r.n_invalid == 1);
}

TEST(reservoir_confidence_and_weights)
{
    reservoir r;
    reservoir_init(&r);
    reservoir_add_confidence(&r, 20);
    reservoir_cap_confidence(&r, 8);
    CHECK(r.confidence == 8);
    reservoir_add_confidence(&r, 1);
    reservoir_cap_confidence(&r, 20);
    CHECK(r.confidence == 9);
    /* GRIS Eq. 19 and its failed-shift bracket */
    CHECK_NEAR(gris_resampling_weight((real)0.5, 2, 3, (real)0.25), 0.75, 1e-12);
    CHECK(gris_resampling_weight((real)0.5, 0, (real)INFINITY, 1) == 0);
    CHECK(gris_resampling_weight((real)0.5, 2, 3, 0) == 0);
    CHECK(gris_resampling_weight(0, 2, 3, (real)INFINITY) == 0);
    CHECK_NEAR(ris_candidate_weight(2, 4, 8), 1, 1e-12);
}

/* ---- initial resampling from N path trees (GRIS §8.3, Enhanced §2.3, pitfall 2, docs/restir-pt.md §11) ----
 * Each tree emits one candidate per "length" d = 2, 3, 4 (three integrands of the
 * path-space sum, GRIS Eq. 50), each with its own RGB contribution F_d(x), x uniform in
 * PSS; Russian roulette kills the tree after d = 2 with probability 0.3 and after d = 3
 * with 0.4 (cumulative survival 0.7 and 0.42 is the PSS source pdf, RR not in F). The
 * reservoir estimate F(Y) W_Y must be unbiased for sum_d int F_d. */
#define TREE_RUNS 40000
#define TREE_N 4

typedef enum { TREES_CORRECT, TREES_W_OVER_CANDIDATES, TREES_NO_ONE_OVER_N } trees_variant;

static rgb tree_contribution(int d, real x)
{
    switch (d) {
    case 2: return rgb_make(1 + x, (real)0.5, 2 * x);
    case 3: return x < (real)0.9 ? rgb_make(x * x, 1 - x, (real)0.3) : rgb_gray(0);
    default: return rgb_make((real)0.2, 3 * x * x * x, x);
    }
}

static rgb tree_integral(void) { return rgb_make(1.5 + 0.243 + 0.2, 0.5 + 0.495 + 0.75, 1.0 + 0.27 + 0.5); }

static rgb trees_run(uint32_t run, trees_variant variant, real *confidence)
{
    static const real survival[5] = {0, 0, 1, (real)0.7, (real)0.42};
    rng_key key = rng_key_make(test_seed() ^ 0xbb67ae85u, run, 0);
    reservoir r;
    int tree, d, streamed = 0;
    real n = variant == TREES_NO_ONE_OVER_N ? 1 : TREE_N;
    reservoir_init(&r);
    for (tree = 0; tree < TREE_N; ++tree) {
        for (d = 2; d <= 4; ++d) {
            real x = rng_u(key, RNG_BSDF, (uint32_t)d, (uint32_t)tree);
            path_sample s;
            if (d >= 3 && rng_u(key, RNG_RR, (uint32_t)d, (uint32_t)tree) >= survival[d] / survival[d - 1]) break;
            path_sample_begin(&s, 0, run, (uint32_t)tree);
            s.technique = PATH_TECH_BSDF;
            s.length = (uint8_t)d;
            path_sample_set_contribution(&s, tree_contribution(d, x));
            reservoir_stream(&r, &s, ris_candidate_weight(s.target, 1 / survival[d], n),
                             rng_u(key, RNG_RIS, (uint32_t)d, (uint32_t)tree));
            streamed++;
        }
    }
    reservoir_add_confidence(&r, TREE_N); /* c = number of trees */
    reservoir_finalize(&r);
    if (variant == TREES_W_OVER_CANDIDATES && streamed) r.W /= (real)streamed; /* pitfall 2 */
    *confidence = r.confidence;
    return reservoir_estimate(&r);
}

/* Returns the largest |z| over the three channels. */
static double trees_max_z(trees_variant variant)
{
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0}, zmax = 0;
    rgb truth = tree_integral();
    double t[3];
    uint32_t run;
    int c;
    t[0] = truth.r;
    t[1] = truth.g;
    t[2] = truth.b;
    for (run = 0; run < TREE_RUNS; ++run) {
        real conf;
        rgb v = trees_run(run, variant, &conf);
        double vc[3];
        vc[0] = v.r;
        vc[1] = v.g;
        vc[2] = v.b;
        for (c = 0; c < 3; ++c) {
            sum[c] += vc[c];
            sum2[c] += vc[c] * vc[c];
        }
        if (conf != TREE_N) return 1e9;
    }
    for (c = 0; c < 3; ++c) {
        double mean = sum[c] / TREE_RUNS, se = sqrt((sum2[c] / TREE_RUNS - mean * mean) / (TREE_RUNS - 1));
        double z = fabs(mean - t[c]) / se;
        if (z > zmax) zmax = z;
    }
    return zmax;
}

TEST(reservoir_initial_path_trees_unbiased)
{
    double z = trees_max_z(TREES_CORRECT);
    if (getenv("RESTIR_TEST_VERBOSE"))
        printf("    trees: correct %.2f, W/#candidates %.2f, no 1/N %.2f\n", z, trees_max_z(TREES_W_OVER_CANDIDATES),
               trees_max_z(TREES_NO_ONE_OVER_N));
    CHECKF(z < 4.0, "initial RIS over %d trees biased: max |z| = %.2f", TREE_N, z);
    /* broken: W divided by the number of streamed candidates (pitfall 2) */
    z = trees_max_z(TREES_W_OVER_CANDIDATES);
    CHECKF(z > 4.0, "W / #candidates not detected: max |z| = %.2f", z);
    /* broken: the constant MIS weight 1/N of the N trees left out */
    z = trees_max_z(TREES_NO_ONE_OVER_N);
    CHECKF(z > 4.0, "missing 1/N not detected: max |z| = %.2f", z);
}
