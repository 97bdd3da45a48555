/* Evidence for the MCMC mutations (issue 26), at the pipeline's own call sites:
 *   - the MH acceptance through mutate_reservoir (the function the pipeline calls), exactly:
 *     for every pixel and key the one-iteration chain accepts iff its acceptance number is
 *     below min(1, T p̂(z)/p̂(x)) of the proposal the same numbers make (Mutations Eqs. 14,
 *     19, 20), for each strategy rv / pp / fp; plus the acceptance frequency against the
 *     sum of those probabilities (mutant mh-no-target-ratio: colour bias with luminance
 *     exact, invisible to every luminance test);
 *   - paired N vs 0 mutations per channel (bench.h): pp on cornell-glossy (make test), every
 *     strategy on cornell-glossy, glass and a two-tone scene (long);
 *   - rc_retrace_suffix keeps a mutated sample's NEE light point (the sample's numbers in
 *     pss[], not its replay identity's): mutations on an animated scene. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "pt_util.h"
#include "restir/scene/lights.h"
#include "restir/restir/mutate.h"
#include "restir/restir/reconnection.h"
#include "restir/frame/offline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

/* ---- rc_retrace_suffix with mutated numbers -------------------------------------------------- */

/* scenes/shadow.scene (a moving box; the suffix re-trace runs for every temporal reuse),
 * reconnection shift, paths up to 3 segments: NEE paths have x_k = x_{d-1} and their light
 * point is placed by the NEE numbers. An fp mutation moves those numbers (pss[] at vertex
 * d-1); re-expressing the mutated sample in the very scene it lives in (no motion) must give
 * it back: the same light direction w_k, L_k and light pdf. Before the fix the re-trace
 * placed the light point with the replay identity's original numbers. */
TEST(evidence_retrace_keeps_mutated_nee_numbers)
{
    rt_frame f;
    int x, y, checked = 0, moved = 0;
    if (rt_frame_open(&f, "scenes/shadow.scene", 24, RESTIR_SHIFT_RECONNECTION, 3, test_seed())) return;
    for (y = 0; y < f.s.height && !test_has_failed(); ++y)
        for (x = 0; x < f.s.width && !test_has_failed(); ++x) {
            const path_sample *py = &f.res.reservoirs[y * f.s.width + x].y;
            path_vertex v;
            path_sample u, z, back;
            real xi[PATH_MAX_PSS], xl[2], ratio, un[PATH_MAX_PSS], zn[PATH_MAX_PSS];
            rng_key key = rng_key_make(test_seed(), (uint32_t)(y * f.s.width + x), 17);
            int i, k;
            double dw;
            if (!path_sample_is_valid(py) || py->technique != PATH_TECH_NEE || py->rc_k == PATH_RC_NONE ||
                py->rc_k != py->length - 1 || !rt_primary_vertex(&f.s, x, y, &v))
                continue;
            for (i = 0; i < PATH_MAX_PSS; ++i) xi[i] = rng_u(key, RNG_TEST, 0, (uint32_t)i);
            xl[0] = rng_u(key, RNG_TEST, 1, 0);
            xl[1] = rng_u(key, RNG_TEST, 1, 1);
            u.pss = un;
            z.pss = zn;
            if (mutate_explicit(&f.c, &v, py, xl, &u)) continue;
            if (mutate_propose(&f.c, &v, &u, MUTATE_FP, xi, xl, &z, &ratio) >= 0) continue;
            k = z.rc_k;
            if (z.technique != PATH_TECH_NEE || k != z.length - 1) continue;
            ++checked;
            CHECKF(rc_retrace_suffix(&f.c, &z, NULL, &back) == SHIFT_OK,
                   "pixel (%d,%d): the re-trace of a mutated NEE sample in its own scene fails", x, y);
            dw = v3_length(v3_sub(back.rc_wo, z.rc_wo));
            if (dw > 1e-3) ++moved;
            CHECKF(dw <= 1e-3 && fabs((double)(back.light_pdf - z.light_pdf)) <= 1e-3 * (double)z.light_pdf,
                   "pixel (%d,%d): re-tracing the mutated sample moved its light point: |dw_k| %.3g, light pdf %.6g -> "
                   "%.6g (the NEE numbers of pss[] were not used)",
                   x, y, dw, (double)z.light_pdf, (double)back.light_pdf);
        }
    rt_frame_close(&f);
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  %d mutated NEE samples re-traced, %d moved\n", checked, moved);
    CHECKF(checked >= 30, "only %d mutated NEE samples with k = d-1", checked);
}

/* ---- the MH acceptance at the pipeline's call site (mutate_reservoir), exact ---------------- */

/* One iteration of mutate_reservoir (the pipeline's call) from reservoir r0 with key/stage:
 * returns 1 if it accepted, 0 if not, -1 if the chain did not start (skipped); *a receives
 * the probability the same numbers must accept with, min(1, T p̂(z)/p̂(x)) computed here from
 * the proposal (mutate_explicit + mutate_propose on those numbers; -1 if the proposal is
 * impossible, T = 0). */
static int one_iteration(const restir_context *c, const path_vertex *v, const reservoir *r0, rng_key key, int strategy,
                         double *a, real *u_accept)
{
    const int stage = MUTATE_AFTER_TEMPORAL;
    reservoir r = *r0;
    real home[PATH_MAX_PSS], un[PATH_MAX_PSS], zn[PATH_MAX_PSS], xi[PATH_MAX_PSS], xc[2], xl[2], ratio;
    path_sample u, z;
    mutate_stats st;
    int j, nv = path_sample_is_valid(&r0->y) ? r0->y.length - 1 : 0;
    memset(&st, 0, sizeof st);
    mutate_reservoir(c, v, key, stage, strategy, 1, &r, home, &st);
    if (st.skipped) return -1;
    for (j = 0; j < 2; ++j) {
        xc[j] = rng_u(key, RNG_MUTATE, (uint32_t)stage, MUTATE_SLOT_LOBE_CURRENT + (uint32_t)j);
        xl[j] = rng_u(key, RNG_MUTATE, (uint32_t)stage, MUTATE_SLOT_LOBE_PROPOSAL + (uint32_t)j);
    }
    for (j = 0; j < PATH_PSS_PER_VERTEX * nv; ++j) xi[j] = rng_u(key, RNG_MUTATE, (uint32_t)stage, (uint32_t)j);
    *u_accept = rng_u(key, RNG_MUTATE, (uint32_t)stage, MUTATE_SLOT_ACCEPT);
    u.pss = un;
    z.pss = zn;
    *a = -1;
    if (mutate_explicit(c, v, &r0->y, xc, &u) == 0 && mutate_propose(c, v, &u, strategy, xi, xl, &z, &ratio) < 0) {
        double q = (double)(z.target * ratio / r0->y.target); /* Mutations Eqs. 14, 19 (20 in the ratio) */
        *a = q < 1 ? q : 1;
    }
    return st.accepted == 1;
}

/* For every pixel of cornell-glossy, glass and the spot scene (hybrid shift), 12 keys per
 * pixel and every strategy: the chain's decision equals u < min(1, T p̂(z)/p̂(x)) for the
 * proposal of the same numbers, and the acceptance count matches the sum of those
 * probabilities. */
static void acceptance_case(const char *path, int strategy, long *decisions, long *mismatches, double *sum_a,
                            double *sum_var, long *accepted)
{
    rt_frame f;
    int x, y, key_i;
    if (rt_frame_open(&f, path, 16, RESTIR_SHIFT_HYBRID, 4, test_seed())) return;
    for (y = 0; y < f.s.height; ++y)
        for (x = 0; x < f.s.width; ++x) {
            const reservoir *r0 = &f.res.reservoirs[y * f.s.width + x];
            path_vertex v;
            if (!path_sample_is_valid(&r0->y) || !(r0->W > 0) || !rt_primary_vertex(&f.s, x, y, &v)) continue;
            for (key_i = 0; key_i < 12; ++key_i) {
                rng_key key = rng_key_make(test_seed() + 3u, (uint32_t)(y * f.s.width + x), 1000u + (uint32_t)key_i);
                double a;
                real ua;
                int acc = one_iteration(&f.c, &v, r0, key, strategy, &a, &ua);
                if (acc < 0) break; /* the chain cannot start from this sample */
                if (a < 0) {        /* T = 0: must be rejected */
                    *mismatches += acc;
                    continue;
                }
                ++*decisions;
                *mismatches += acc != ((double)ua < a);
                *accepted += acc;
                *sum_a += a;
                *sum_var += a * (1 - a);
            }
        }
    rt_frame_close(&f);
}

TEST(evidence_mutate_acceptance_at_call_site_exact)
{
    static const char *const scenes[] = {"scenes/cornell-glossy.scene", "scenes/glass.scene", NULL};
    int strategy, i;
    for (strategy = 0; strategy < MUTATE_STRATEGY_COUNT && !test_has_failed(); ++strategy) {
        long decisions = 0, mismatches = 0, accepted = 0;
        double sum_a = 0, sum_var = 0, z;
        for (i = 0; i < 3 && !test_has_failed(); ++i)
            acceptance_case(scenes[i], strategy, &decisions, &mismatches, &sum_a, &sum_var, &accepted);
        if (test_has_failed()) return;
        z = sum_var > 0 ? (accepted - sum_a) / sqrt(sum_var) : 0;
        if (getenv("RESTIR_TEST_VERBOSE"))
            fprintf(stderr, "  %s: %ld decisions, %ld accepted, expected %.1f (z %+.2f), %ld mismatches\n",
                    mutate_strategy_names[strategy], decisions, accepted, sum_a, z, mismatches);
        CHECKF(decisions >= 500, "%s: only %ld MH decisions", mutate_strategy_names[strategy], decisions);
        CHECKF(sum_a < decisions - 20, "%s: too few proposals with acceptance < 1 (sum a %.1f of %ld)",
               mutate_strategy_names[strategy], sum_a, decisions);
        CHECKF(mismatches == 0,
               "%s: the pipeline's MH step decided %ld of %ld proposals otherwise than u < min(1, T p̂(z)/p̂(x)) "
               "(accepted %ld, expected %.1f: z %+.2f)",
               mutate_strategy_names[strategy], mismatches, decisions, accepted, sum_a, z);
    }
}

/* ---- paired N vs 0 mutations, per channel ------------------------------------------------------ */

/* Frame 4 of a sequence with N = 20 mutations of `strategy` after the temporal step against
 * the same sequence without (same seeds: the frames share their initial and temporal samples
 * until the first mutation). path: a scene file, or NULL for the two-tone scene (indirect
 * light only, roughness threshold 0.5: prefix mutations move y_2). */
static void mutate_paired(const char *path, int res, int runs, int strategy, bench_paired *p, char *name, size_t n)
{
    scene s;
    restir_options o;
    snprintf(name, n, "mutations %s x20 vs none, %s", mutate_strategy_names[strategy], path ? path : "two-tone");
    bench_paired_init(p, name);
    if (path ? rt_load_scene(path, res, &s) : rt_make_two_tone(&s, res)) return;
    rt_mutation_options(&o);
    if (!path) {
        o.roughness_threshold = 0.5;
        o.paths = RESTIR_PATHS_INDIRECT;
    }
    o.mutation.strategy = strategy;
    rt_mutation_paired(&s, &o, runs, test_seed() * 40503u + 7u + 1000u * (uint32_t)strategy, p);
    scene_free(&s);
}

/* Every strategy on cornell-glossy, glass and the two-tone scene. */
TEST_LONG(evidence_mutate_paired_per_channel_long)
{
    static const char *const scenes[] = {"scenes/cornell-glossy.scene", "scenes/glass.scene", NULL};
    int strategy, i;
    for (i = 0; i < 3 && !test_has_failed(); ++i)
        for (strategy = 0; strategy < MUTATE_STRATEGY_COUNT && !test_has_failed(); ++strategy) {
            bench_paired p;
            char name[160];
            mutate_paired(scenes[i], 16, 32, strategy, &p, name, sizeof name);
            if (!test_has_failed()) bench_paired_expect_consistent(&p, BENCH_Z_CONSISTENT);
        }
}
