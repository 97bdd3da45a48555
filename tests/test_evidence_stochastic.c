/* Evidence for stochastic pairwise MIS (issue 26) where it is exercised least: domains
 * whose reservoir holds no contributing sample (empty, or W = 0). On an open scene with
 * indirect light only, most rays leave the scene and most reservoirs are empty:
 *   - paired per channel (bench.h) against the deterministic all-M comparator (defensive
 *     pairwise MIS over the same domains, which the stochastic weights estimate), same seeds:
 *     run k of both reuses exactly the same initial samples and neighbours;
 *   - the pick distributions by chi-squared: the Ñ picks against P(i) of Eq. 17 and the Ñ_c
 *     canonical picks against P_c = 1/M, over every domain, empty ones included. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "chi2.h"
#include "restir/scene/lights.h"
#include "restir/restir/stochastic_mis.h"
#include "restir/restir/stochastic_picks_check.h"
#include "restir/frame/offline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

/* The stochastic pairwise step (an algorithm, not a MIS family: spatial_options.h). */
#define STOCHASTIC_STEP (-1)

static void sto_options(restir_options *o, int mis, int n, int nc, int scaling_off, int cells, int max_depth)
{
    restir_options_default(o);
    o->shift = RESTIR_SHIFT_HYBRID;
    if (mis == STOCHASTIC_STEP) o->spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE;
    else o->spatial.mis = (mis_family)mis;
    o->stochastic.n_picks = n;
    o->stochastic.n_canonical_picks = nc;
    o->stochastic.confidence_scaling = !scaling_off;
    o->spatial_passes = 1;
    o->spatial.pattern = NEIGHBOR_BOX;
    o->spatial.radius = 2;
    o->spatial.cells = cells;
    o->candidates = 1;
    o->max_depth = max_depth;
    o->paths = max_depth > 2 ? RESTIR_PATHS_INDIRECT : RESTIR_PATHS_ALL;
    o->threads = 2;
}

/* scenes/shadow.scene (a floor, two walls, a small light, a box: open geometry), 1 path tree,
 * max_depth 2: direct light only (the shadowed pixels are empty); max_depth 3: indirect light
 * only (most reservoirs are empty: most bounce rays leave the scene). Stochastic (Ñ, Ñ_c)
 * against all-M defensive pairwise over the same 5 x 5 box. */
static void sto_paired(int res, int runs, int max_depth, int n, int nc, int cells, bench_paired *p, const char *name)
{
    scene s;
    bench_sequence_config a, b;
    if (rt_load_scene("scenes/shadow.scene", res, &s)) return;
    a.s = b.s = &s;
    a.frame = b.frame = BENCH_OFFLINE;
    sto_options(&a.o, STOCHASTIC_STEP, n, nc, 0, cells, max_depth);
    sto_options(&b.o, MIS_PAIRWISE_DEFENSIVE, n, nc, 0, cells, max_depth);
    bench_paired_init(p, name);
    bench_paired_run(p, runs, test_seed() * 2654435761u + 977u + (uint32_t)(n * 10 + nc), bench_sequence_run, &a, bench_sequence_run, &b);
    scene_free(&s);
}

TEST(evidence_stochastic_paired_empty_reservoirs)
{
    bench_paired p[2];
    sto_paired(24, 24, 2, 4, 2, 0, &p[0], "stochastic N~4 N~c2 vs all-M defensive, shadow direct only");
    if (!test_has_failed())
        sto_paired(24, 24, 3, 1, 1, 0, &p[1], "stochastic N~1 N~c1 vs all-M defensive, shadow indirect only");
    if (test_has_failed()) return;
    if (bench_paired_expect_consistent(&p[0], BENCH_Z_CONSISTENT)) return;
    bench_paired_expect_consistent(&p[1], BENCH_Z_CONSISTENT);
}

/* ---- the pick distributions, chi-squared, and the pick-count invariant ------------------------ */

/* Pearson's statistic of counts against expectations, cells with expectation < 5 pooled;
 * returns the upper-tail p (chi2_survival) and the dof in *dof. */
static double pearson(const double *obs, const double *expect, int n, int *dof)
{
    double x = 0, po = 0, pe = 0;
    int i, cells = 0;
    for (i = 0; i < n; ++i) {
        if (expect[i] < 5) {
            po += obs[i];
            pe += expect[i];
            continue;
        }
        x += (obs[i] - expect[i]) * (obs[i] - expect[i]) / expect[i];
        ++cells;
    }
    if (pe > 0) {
        x += (po - pe) * (po - pe) / pe;
        ++cells;
    } else if (po > 0)
        return 0; /* picks where none may land */
    *dof = cells - 1;
    return *dof > 0 ? chi2_survival(x, *dof) : 1;
}

/* On shadow.scene with indirect light only (most reservoirs empty), for pixels with many
 * empty neighbours: the library's step called R times with fresh pick numbers; the Ñ picks
 * against Ñ P(i) (Eq. 17 recomputed here) and the Ñ_c canonical picks against Ñ_c / M over
 * ALL M domains (P_c), and the pick-count invariant after every call; two planted
 * violations per pixel (a canonical pick left without its shift, a pick too many) fire it. */
TEST(evidence_stochastic_picks_chi2_and_counts)
{
    scene s;
    restir_options o;
    restir_result res;
    light_set lights;
    restir_context c;
    stochastic_workspace sw;
    rerror e;
    const int R = 4000, n_picks = 2, nc = 2;
    int px, tested = 0, worst_dof = 0, violations = 0, with_empty = 0, planted = 0, planted_fired = 0;
    double worst_p = 1;
    char why[512] = "";
    if (rt_load_scene("scenes/shadow.scene", 24, &s)) return;
    sto_options(&o, STOCHASTIC_STEP, n_picks, nc, 0, 0, 3);
    o.spatial_passes = 0;
    o.keep_reservoirs = 1;
    o.seed = test_seed();
    if (restir_render(&s, &o, &res, &e) || lights_build(&lights, &s, &e) || stochastic_workspace_alloc(&sw, 25, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&s);
        return;
    }
    restir_context_for(&c, &s, &lights, &o);
    for (px = 0; px < 20 * 20 && tested < 12 && !test_has_failed(); px += 7) {
        int x = 2 + px % 20, y = 2 + px / 20, dx, dy, m = 0, i, r, empty = 0, dof;
        path_vertex verts[25];
        const path_vertex *x1[25];
        const reservoir *in[25];
        double a[24], sum_a = 0, ok_k[24], ok_kc[24], ek[24], ekc[24], p;
        stochastic_options so;
        if (!rt_primary_vertex(&s, x, y, &verts[0]) || !path_sample_is_valid(&res.reservoirs[y * 24 + x].y)) continue;
        x1[0] = &verts[0];
        in[0] = &res.reservoirs[y * 24 + x];
        m = 1;
        for (dy = -2; dy <= 2; ++dy)
            for (dx = -2; dx <= 2; ++dx) {
                if ((!dx && !dy) || !rt_primary_vertex(&s, x + dx, y + dy, &verts[m])) continue;
                x1[m] = &verts[m];
                in[m] = &res.reservoirs[(y + dy) * 24 + x + dx];
                empty += !(path_sample_is_valid(&in[m]->y) && in[m]->W > 0);
                ++m;
            }
        if (m < 10 || empty == 0) continue;
        with_empty += empty * 2 > m - 1;
        so.n_picks = n_picks;
        so.n_canonical_picks = nc;
        so.confidence_scaling = 1;
        so.naive_p = 0;
        sw.vertex = NULL;
        for (i = 0; i < m - 1; ++i) {
            const reservoir *q = in[i + 1];
            a[i] = path_sample_is_valid(&q->y) && q->W > 0 ? (double)q->confidence * (double)q->y.target * (double)q->W : 0;
            sum_a += a[i];
            ok_k[i] = ok_kc[i] = 0;
        }
        for (r = 0; r < R; ++r) {
            rng_key key = rng_key_make(test_seed() + 11u, (uint32_t)(y * 24 + x), (uint32_t)r);
            real u[25], up[2], uc[2];
            reservoir out;
            spatial_stats st, before;
            memset(&st, 0, sizeof st);
            for (i = 0; i < m; ++i) u[i] = rng_u(key, RNG_TEST, 0, (uint32_t)i);
            for (i = 0; i < 2; ++i) {
                up[i] = rng_u(key, RNG_TEST, 1, (uint32_t)i);
                uc[i] = rng_u(key, RNG_TEST, 2, (uint32_t)i);
            }
            before = st;
            stochastic_pairwise_resample(&c, &so, m, x1, in, u, up, uc, &out, &sw, &st);
            if (stochastic_check_pick_counts(&so, m, in, &sw, &before, &st, why, sizeof why)) ++violations;
            if (r == 0) { /* planted: one canonical pick skipped, one pick too many */
                spatial_stats skipped = st;
                char w2[512];
                int last = m - 2;
                skipped.mis_shifts -= st.mis_shifts > before.mis_shifts;
                skipped.shifts -= st.mis_shifts > before.mis_shifts;
                planted_fired += st.mis_shifts > before.mis_shifts &&
                                 stochastic_check_pick_counts(&so, m, in, &sw, &before, &skipped, w2, sizeof w2);
                sw.K[last]++;
                planted_fired += stochastic_check_pick_counts(&so, m, in, &sw, &before, &st, w2, sizeof w2);
                sw.K[last]--;
                planted += 1 + (st.mis_shifts > before.mis_shifts);
            }
            for (i = 0; i < m - 1; ++i) {
                ok_k[i] += sw.K[i];
                ok_kc[i] += sw.Kc[i];
            }
        }
        for (i = 0; i < m - 1; ++i) {
            ek[i] = sum_a > 0 ? (double)R * n_picks * a[i] / sum_a : 0;
            ekc[i] = (double)R * nc / (m - 1);
        }
        p = pearson(ok_k, ek, m - 1, &dof);
        if (p < worst_p) worst_p = p, worst_dof = dof;
        p = pearson(ok_kc, ekc, m - 1, &dof);
        if (p < worst_p) worst_p = p, worst_dof = dof;
        ++tested;
    }
    stochastic_workspace_free(&sw);
    lights_free(&lights);
    restir_result_free(&res);
    scene_free(&s);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %d pixels (%d with most neighbours empty), worst chi2 p %.3g (dof %d), %d pick-count violations\n",
                tested, with_empty, worst_p, worst_dof, violations);
    CHECKF(tested >= 6 && with_empty >= 3, "only %d pixels tested, %d with most neighbours empty", tested, with_empty);
    CHECKF(violations == 0, "%d of %d steps broke the pick counts: %s", violations, tested * R, why);
    CHECKF(planted_fired == planted && planted >= tested, "the pick-count check fired on %d of %d planted violations",
           planted_fired, planted);
    CHECKF(worst_p > chi2_sidak(1e-4, 2 * tested), "pick distribution off: chi2 p %.3g (dof %d)", worst_p, worst_dof);
}
