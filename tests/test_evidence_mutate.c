/* Evidence for the MCMC mutations (issue 26), at the pipeline's own call sites:
 *   - the MH acceptance through mutate_reservoir (the function the pipeline calls), exactly:
 *     for every pixel and key the one-iteration chain accepts iff its acceptance number is
 *     below min(1, T p̂(z)/p̂(x)) of the proposal the same numbers make (Mutations Eqs. 14,
 *     19, 20), for each strategy rv / pp / fp; plus the acceptance frequency against the
 *     sum of those probabilities (mutant mh-no-target-ratio: colour bias with luminance
 *     exact, invisible to every luminance test);
 *   - paired N vs 0 mutations per channel (bench.h) on a two-tone scene;
 *   - rc_retrace_suffix keeps a mutated sample's NEE light point (the sample's numbers in
 *     pss[], not its replay identity's): mutations on an animated scene. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "restir/lights.h"
#include "restir/mutate.h"
#include "restir/reconnection.h"
#include "restir_util.h"
#include "test.h"

/* A frame's reservoirs and the context to mutate them (shift, max depth). */
typedef struct {
    scene s;
    restir_result res;
    light_set lights;
    restir_context c;
} mfix;

static int mfix_open(mfix *f, const char *path, int res, int shift, int max_depth, uint32_t seed)
{
    restir_options o;
    rerror e;
    memset(f, 0, sizeof *f);
    if (rt_load_scene(path, res, &f->s)) return -1;
    restir_options_default(&o);
    o.shift = shift;
    o.max_depth = max_depth;
    o.keep_reservoirs = 1;
    o.seed = seed;
    o.threads = 2;
    if (restir_render(&f->s, &o, &f->res, &e) || lights_build(&f->lights, &f->s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&f->s);
        return -1;
    }
    restir_context_for(&f->c, &f->s, &f->lights, &o);
    return 0;
}

static void mfix_close(mfix *f)
{
    lights_free(&f->lights);
    restir_result_free(&f->res);
    scene_free(&f->s);
}

/* ---- rc_retrace_suffix with mutated numbers -------------------------------------------------- */

/* scenes/shadow.scene (a moving box; the suffix re-trace runs for every temporal reuse),
 * reconnection shift, paths up to 3 segments: NEE paths have x_k = x_{d-1} and their light
 * point is placed by the NEE numbers. An fp mutation moves those numbers (pss[] at vertex
 * d-1); re-expressing the mutated sample in the very scene it lives in (no motion) must give
 * it back: the same light direction w_k, L_k and light pdf. Before the fix the re-trace
 * placed the light point with the replay identity's original numbers. */
TEST(evidence_retrace_keeps_mutated_nee_numbers)
{
    mfix f;
    int x, y, checked = 0, moved = 0;
    if (mfix_open(&f, "scenes/shadow.scene", 24, RESTIR_SHIFT_RECONNECTION, 3, test_seed())) return;
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
    mfix_close(&f);
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  %d mutated NEE samples re-traced, %d moved\n", checked, moved);
    CHECKF(checked >= 30, "only %d mutated NEE samples with k = d-1", checked);
}
