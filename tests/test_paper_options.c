/* The papers' versions where the oracle deviates (issue 28; docs/deviations.md):
 *   - the Gaussian PSS perturbation of Mutations §4.1 (--mutation-kernel gaussian) is a
 *     symmetric kernel, exactly: on a grid of 64 cells and a regular grid of its numbers
 *     (each sign/angle number b paired with b + 1/2, a measure-preserving map), the count
 *     of moves from cell i to cell j equals the count from j to i, cell by cell, for the
 *     paper's log-uniform amount and for fixed sigma 0.02 and 0.3 (steps that wrap); each
 *     number moved by the mirrored numbers comes back; every value stays in [0,1); and the
 *     step law is the normal one (E[n^2] = 1 on the grid). Kelemen's kernel passes the same
 *     count test. Planted bug: gaussian-asymmetric-wrap (reflects below 0, wraps above 1).
 *   - paired per-channel N vs 0 mutations with the Gaussian kernel (unbiased);
 *   - the temporal M-cap in both modes, exactly: temporal_capped_confidence by hand, and the
 *     confidences a still-camera sequence with 2 path trees per frame reaches: relative
 *     (c_prev <= C c_cur) 2 + min(c_1, 2.5 x 2) = 7, absolute (Mutations Algorithm 2,
 *     c_prev <= C) 2 + 2.5 = 4.5. Planted bug: mcap-on-output (caught by both tests). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "restir/restir/mutate.h"
#include "restir/restir/reservoir_dump.h"
#include "restir/restir/temporal.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"
#include "restir_util.h"
#include "test.h"

#define GRID_CELLS 64

/* Kernel under test: 0 Kelemen (xi[0] only), 1 Gaussian with sigma (0: the paper's amount). */
static real perturb(int gaussian, double sigma, real u, const real xi[3])
{
    return gaussian ? mutate_perturb_gaussian(u, xi, sigma) : mutate_perturb(u, xi[0]);
}

/* Transition counts between GRID_CELLS cells: from the centre of cell i, every number
 * triple of a regular grid (na x nb x nU midpoints), into the cell of the result. A kernel
 * T(x->y) = f(y - x mod 1) with f even gives count[i][j] = count[j][i] (up to a result
 * landing exactly on a cell edge, which these grids do not produce). Returns the number of
 * asymmetric cell pairs; *outside counts results outside [0,1). */
static long asymmetric_cells(int gaussian, double sigma, int na, int nb, int nU, long *outside, long *worst_diff,
                             long *moved)
{
    static long count[GRID_CELLS][GRID_CELLS];
    int i, j, a, b, k;
    long bad = 0;
    memset(count, 0, sizeof count);
    *outside = 0;
    *worst_diff = 0;
    *moved = 0;
    for (i = 0; i < GRID_CELLS; ++i) {
        real u = (real)((i + 0.5) / GRID_CELLS);
        for (a = 0; a < na; ++a)
            for (b = 0; b < nb; ++b)
                for (k = 0; k < nU; ++k) {
                    real xi[3], v;
                    int cell;
                    xi[0] = (real)((a + 0.5) / na);
                    xi[1] = (real)((b + 0.5) / nb);
                    xi[2] = (real)((k + 0.5) / nU);
                    v = perturb(gaussian, sigma, u, xi);
                    if (!(v >= 0 && v < 1)) {
                        ++*outside;
                        continue;
                    }
                    cell = (int)(v * GRID_CELLS);
                    if (cell >= GRID_CELLS) cell = GRID_CELLS - 1;
                    count[i][cell]++;
                    *moved += cell != i;
                }
    }
    for (i = 0; i < GRID_CELLS; ++i)
        for (j = i + 1; j < GRID_CELLS; ++j)
            if (count[i][j] != count[j][i]) {
                long d = labs(count[i][j] - count[j][i]);
                bad++;
                if (d > *worst_diff) *worst_diff = d;
            }
    return bad;
}

/* Kelemen's kernel draws the sign and size from one number (xi[0]); the Gaussian's sign
 * and angle from xi[1], so for Kelemen the grid runs over xi[0] only. */
TEST(paper_mutation_kernels_symmetric_on_grid_exact)
{
    static const double sigmas[] = {0, 0.02, 0.3};
    long outside, worst, bad, moved, total;
    int i;
    for (i = 0; i < 3; ++i) {
        int nU = sigmas[i] > 0 ? 1 : 16;
        bad = asymmetric_cells(1, sigmas[i], 40, 64, nU, &outside, &worst, &moved);
        total = (long)GRID_CELLS * 40 * 64 * nU;
        CHECKF(bad == 0 && outside == 0,
               "gaussian sigma %g: %ld asymmetric cell pairs (worst count difference %ld), %ld values outside [0,1)",
               sigmas[i], bad, worst, outside);
        CHECKF(moved > total / 10, "gaussian sigma %g: only %ld of %ld moves leave their cell (test too weak)",
               sigmas[i], moved, total);
    }
    bad = asymmetric_cells(0, 0, 4096, 1, 1, &outside, &worst, &moved);
    CHECKF(bad == 0 && outside == 0, "kelemen: %ld asymmetric cell pairs (worst %ld), %ld values outside [0,1)", bad,
           worst, outside);
    CHECKF(moved > GRID_CELLS * 4096L / 10, "kelemen: only %ld moves leave their cell", moved);
}

/* The step of the Gaussian kernel is a translation on the circle undone by the mirrored
 * numbers (b -> b +- 1/2 negates it), including steps across 0 and 1. */
TEST(paper_gaussian_perturb_mirror_returns)
{
    rng_key key = rng_key_make(test_seed(), 29, 5);
    const double tol = sizeof(real) == sizeof(float) ? 2e-6 : 1e-12;
    double worst = 0;
    int i, bad = 0;
    for (i = 0; i < 20000; ++i) {
        real xi[3], m[3], u = rng_u(key, RNG_TEST, 0, (uint32_t)i), v, w;
        double back, sigma = i % 3 == 0 ? 0 : (i % 3 == 1 ? 0.01 : 0.2);
        int j;
        if (i % 5 == 0) u = (real)(i % 2 ? 0.9995 : 0.0005); /* near the wrap */
        for (j = 0; j < 3; ++j) xi[j] = rng_u(key, RNG_TEST, 1 + (uint32_t)j, (uint32_t)i);
        m[0] = xi[0];
        m[1] = xi[1] < (real)0.5 ? xi[1] + (real)0.5 : xi[1] - (real)0.5;
        m[2] = xi[2];
        v = mutate_perturb_gaussian(u, xi, sigma);
        w = mutate_perturb_gaussian(v, m, sigma);
        back = fabs((double)w - (double)u);
        if (back > 0.5) back = 1 - back;
        if (!(v >= 0 && v < 1) || !(w >= 0 && w < 1)) bad++;
        if (back > worst) worst = back;
    }
    CHECKF(bad == 0, "%d Gaussian perturbations outside [0,1)", bad);
    CHECKF(worst <= tol, "the mirrored numbers do not undo a step: off by %g", worst);
}

/* The step law: sigma 0.001 (no wrap), a stratified 1000 x 1000 grid of (a, b): E[d^2] =
 * sigma^2 and E[d^4] = 3 sigma^4 within 1% (a normal's moments; Kelemen's +-s would give
 * a kurtosis of 1). */
TEST(paper_gaussian_perturb_is_normal)
{
    const double sigma = 0.001;
    double m2 = 0, m4 = 0;
    int a, b, n = 1000;
    for (a = 0; a < n; ++a)
        for (b = 0; b < n; ++b) {
            real xi[3];
            double d;
            xi[0] = (real)((a + 0.5) / n);
            xi[1] = (real)((b + 0.5) / n);
            xi[2] = (real)0.5;
            d = ((double)mutate_perturb_gaussian((real)0.5, xi, sigma) - 0.5) / sigma;
            m2 += d * d;
            m4 += d * d * d * d;
        }
    m2 /= (double)n * n;
    m4 /= (double)n * n;
    CHECKF(fabs(m2 - 1) < 0.01 && fabs(m4 / 3 - 1) < 0.03, "E[n^2] = %.4f (1), E[n^4] = %.4f (3)", m2, m4);
}

/* Frame 4 with N = 20 pp mutations after the temporal step, Gaussian kernel with the
 * paper's amount, against the same sequence without mutations (same seeds), per channel,
 * cornell-glossy 16^2, K = 32 pairs (as evidence_mutate_paired_per_channel for Kelemen). */
TEST(paper_gaussian_mutations_paired_per_channel)
{
    scene s;
    restir_options o;
    bench_paired p;
    bench_paired_init(&p, "gaussian pp mutations x20 vs none, cornell-glossy");
    if (rt_load_scene("scenes/cornell-glossy.scene", 16, &s)) return;
    rt_mutation_options(&o);
    o.mutation.strategy = MUTATE_PP;
    o.mutation.kernel = MUTATE_KERNEL_GAUSSIAN;
    rt_mutation_paired(&s, &o, 32, test_seed() * 40503u + 7u + 5000u, &p);
    scene_free(&s);
    if (!test_has_failed()) bench_paired_expect_consistent(&p, BENCH_Z_CONSISTENT);
}

/* The options: validation of the kernel, its sigma and the M-cap mode. */
TEST(paper_options_validate)
{
    mutation_options m;
    temporal_options t;
    rerror e;
    mutation_options_default(&m);
    CHECK(m.kernel == MUTATE_KERNEL_KELEMEN && m.sigma == 0);
    m.sigma = 0.01;
    CHECK(mutation_options_validate(&m, &e) != 0); /* sigma without the gaussian kernel */
    m.kernel = MUTATE_KERNEL_GAUSSIAN;
    CHECKF(mutation_options_validate(&m, &e) == 0, "%s", e.msg);
    m.sigma = -1;
    CHECK(mutation_options_validate(&m, &e) != 0);
    temporal_options_default(&t);
    CHECK(t.mcap_mode == TEMPORAL_MCAP_RELATIVE);
    t.mcap_mode = (enum temporal_mcap_mode)7;
    CHECK(temporal_options_validate(&t, &e) != 0);
}

/* temporal_capped_confidence by hand: relative min(c_1, C c_0), absolute min(c_1, C). */
TEST(paper_mcap_modes_by_hand_exact)
{
    static const struct {
        double c1, c0, cap, relative, absolute;
    } rows[] = {
        {1600, 32, 50, 1600, 50}, /* issue 28: 32 candidates, cap 50 */
        {40, 2, 2.5, 5, 2.5},     {3, 2, 2.5, 3, 2.5},   {2, 2, 2.5, 2, 2},
        {7, 1, 20, 7, 7},         {100, 1, 20, 20, 20}, /* one candidate: the modes agree */
        {1e9, 4, INFINITY, 1e9, 1e9},
    };
    int i;
    for (i = 0; i < (int)(sizeof rows / sizeof rows[0]); ++i) {
        real r = temporal_capped_confidence((real)rows[i].c1, (real)rows[i].c0, (real)rows[i].cap, TEMPORAL_MCAP_RELATIVE);
        real a = temporal_capped_confidence((real)rows[i].c1, (real)rows[i].c0, (real)rows[i].cap, TEMPORAL_MCAP_ABSOLUTE);
        CHECKF((double)r == (double)(real)rows[i].relative && (double)a == (double)(real)rows[i].absolute,
               "c1 %g c0 %g C %g: relative %g (by hand %g), absolute %g (by hand %g)", rows[i].c1, rows[i].c0,
               rows[i].cap, (double)r, rows[i].relative, (double)a, rows[i].absolute);
    }
}

/* The final confidences of frame 4 of a still-camera sequence (cornell-glossy 16^2, no
 * spatial pass, 2 path trees: c_0 = 2, C = 2.5), every pixel with a history: relative
 * 2, 4, 6, 7, 7; absolute 2, 4, 4.5, 4.5, 4.5. Read from the sequence checkpoint. */
TEST(paper_mcap_modes_sequence_exact)
{
    rt_mcap_sequence_exact(2, TEMPORAL_MCAP_RELATIVE, 7, "relative cap");
    rt_mcap_sequence_exact(2, TEMPORAL_MCAP_ABSOLUTE, 4.5, "absolute cap");
}

/* The flags on the command line: each reaches --stats (only when it differs from the default;
 * --eq3-reading whenever the pairing is paired), and an inconsistent or unknown value is one
 * line naming the flag, exit 2. */
TEST(paper_options_cli)
{
    static const struct {
        const char *args, *expect;
    } bad[] = {
        {"--mutation-sigma 0.05", "--mutation-sigma"}, /* needs the gaussian kernel */
        {"--mutation-kernel normal", "--mutation-kernel"},
        {"--mcap-mode half", "--mcap-mode"},
        {"--eq3-reading exact", "--eq3-reading"},
    };
    char out[4096], stats[1024];
    char *text;
    size_t i;
    snprintf(stats, sizeof stats, "%s", test_tmp_path("paper-cli.json"));
    CHECKF(test_cli(out, sizeof out,
                    "render scenes/cornell-glossy.scene --method restir --preset gris-realtime --size 8x8 --sequence 0..1 "
                    "--mutations 1 --mutation-kernel gaussian --mutation-sigma 0.01 --mcap-mode absolute --pairing paired "
                    "--eq3-reading signed-ceil --quiet --no-png -o %s --stats %s",
                    test_tmp_path("paper-cli.pfm"), stats) == 0,
           "%s", out);
    text = test_read_text(stats);
    CHECKF(text && strstr(text, "\"mcap_mode\": \"absolute\"") && strstr(text, "\"eq3_reading\": \"signed-ceil\"") &&
               strstr(text, "\"mutation_kernel\": \"gaussian\", \"mutation_sigma\": 0.01"),
           "the options are not in --stats: %.300s", text ? text : "(no file)");
    free(text);
    for (i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        int status = test_cli(out, sizeof out,
                              "render scenes/cornell-glossy.scene --method restir --size 8x8 --sequence 0..1 %s --quiet "
                              "--no-png -o %s",
                              bad[i].args, test_tmp_path("paper-cli-bad.pfm"));
        CHECKF(status == 2 && strstr(out, bad[i].expect), "%s: exit %d, %s", bad[i].args, status, out);
    }
}
