/* Evidence for the temporal step (issue 26), on the paired bench (bench.h):
 *   - temporal MIS, paired on the same seeds: Talbot and pairwise-defensive temporal MIS
 *     against no temporal reuse (all three unbiased for the same frame), on a panning
 *     camera over a glossy scene, frame 8, per channel. The history candidate's MIS term
 *     must be the stored p̂_{t-1}(X)/J (GRIS Eq. 35, App. B); the current frame's p̂_t(y)
 *     there (mutant temporal-mis-current-target) breaks the partition of unity of the
 *     weights of a path although Talbot's weights still sum to one for the matrix used;
 *   - the M-cap on the input (GRIS §6.2, §6.4): exactly c_out = c_0 + min(c_1, C c_0) in
 *     every pixel of a still-camera sequence (mutant mcap-on-output);
 *   - the temporal reverse shift's round trip (temporal_check_round_trip), the DEBUG
 *     invariant, on real steps and on planted violations. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/scene/lights.h"
#include "restir/restir/reservoir_dump.h"
#include "restir/restir/temporal_check.h"
#include "restir/frame/pipeline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/scene/scene_trace.h"
#include "restir/frame/options.h"

static void pan_options(restir_options *o, int temporal, int temporal_mis, int max_depth)
{
    restir_options_default(o);
    o->temporal.enabled = temporal;
    o->temporal.mis = temporal_mis;
    o->spatial.mis = MIS_TALBOT;
    o->spatial_passes = 0;
    o->candidates = 1;
    o->max_depth = max_depth;
    o->shift = RESTIR_SHIFT_HYBRID;
    o->temporal.mcap = 20;
    o->threads = 2;
}

/* Talbot and pairwise-defensive temporal MIS against no temporal reuse, same seeds: both
 * consistent with it (a test failure is recorded otherwise). */
static void temporal_paired(int res, int runs, int frame, double pan, int max_depth)
{
    bench_paired talbot, pairwise;
    scene s;
    bench_sequence_config none, t, pw;
    int k;
    uint32_t seed0 = test_seed() * 2246822519u + 77u;
    if (rt_load_glossy_pan(&s, res, pan)) return;
    none.s = t.s = pw.s = &s;
    none.frame = t.frame = pw.frame = frame;
    pan_options(&none.o, 0, MIS_TALBOT, max_depth);
    pan_options(&t.o, 1, MIS_TALBOT, max_depth);
    pan_options(&pw.o, 1, MIS_PAIRWISE_DEFENSIVE, max_depth);
    bench_paired_init(&talbot, "temporal Talbot vs none, glossy pan");
    bench_paired_init(&pairwise, "temporal pairwise-defensive vs none, glossy pan");
    for (k = 0; k < runs && !test_has_failed(); ++k) {
        double a[3], b[3], c[3];
        uint32_t seed = seed0 + 7919u * (uint32_t)k;
        if (bench_sequence_run(&none, seed, b) || bench_sequence_run(&t, seed, a) || bench_sequence_run(&pw, seed, c))
            break;
        bench_paired_add(&talbot, a, b);
        bench_paired_add(&pairwise, c, b);
    }
    scene_free(&s);
    if (test_has_failed()) return;
    bench_paired_finish(&talbot);
    bench_paired_finish(&pairwise);
    if (bench_paired_expect_consistent(&talbot, BENCH_Z_CONSISTENT)) return;
    bench_paired_expect_consistent(&pairwise, BENCH_Z_CONSISTENT);
}

/* Paths up to 3 segments at 32², K = 128. */
TEST_LONG(evidence_temporal_mis_paired_pan_long)
{
    temporal_paired(32, 128, 8, 200, 3);
}

/* ---- the reverse shift's round trip (temporal_check.h), exact ------------------------------ */

/* The primary vertex of pixel (x, y) seen by the camera of keyframe time `frame`. */
static int primary_at(const scene *s, int frame, int x, int y, path_vertex *v)
{
    camera cam;
    ray r;
    surface_hit h;
    camera_init(&cam, scene_camera_at(s, frame), s->width, s->height);
    r = primary_ray(&cam, x, y, 0, 0, 0);
    if (!scene_intersect(s, &r, &h)) return 0;
    path_vertex_make(v, s, &h, v3_from_f(r.dir));
    return 1;
}

/* Real temporal steps (the library's temporal_resample with two contexts, as the pipeline
 * calls it): domain 0 = pixel p's initial reservoir of frame t, domain 1 = p's initial
 * reservoir of frame t-1 seen by frame t-1's camera (a camera panning 12.5 units a frame).
 * After every step the round trip must hold; planting a wrong diagonal entry (x 1.02) or a
 * wrong stored target (x 1.02) must fire it in every checked step. */
static void round_trip_case(int shift, int mis, long *checked, long *fired_diag, long *fired_target)
{
    scene s;
    light_set lights;
    restir_context cur, prev;
    restir_options o;
    initial_options io;
    spatial_workspace ws;
    rerror e;
    const int t = 5;
    int x, y;
    if (rt_load_glossy_pan(&s, 16, 200)) return;
    if (lights_build(&lights, &s, &e) || spatial_workspace_alloc(&ws, 2, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&s);
        return;
    }
    restir_options_default(&o);
    o.shift = shift;
    o.max_depth = 4;
    restir_context_for(&cur, &s, &lights, &o);
    prev = cur; /* a distinct context of frame t-1 (the scene is static: the camera moves) */
    restir_initial_options_for(&io, &o);
    for (y = 0; y < s.height && !test_has_failed(); ++y)
        for (x = 0; x < s.width && !test_has_failed(); ++x) {
            path_vertex xc, xp;
            reservoir rc, rp, out, bad;
            initial_stats ist;
            temporal_stats tst;
            real u[2];
            char why[512];
            long before;
            uint32_t p = (uint32_t)(y * s.width + x);
            rng_key key = rng_key_make(test_seed(), p, 991);
            if (!primary_at(&s, t, x, y, &xc) || !primary_at(&s, t - 1, x, y, &xp)) continue;
            memset(&ist, 0, sizeof ist);
            memset(&tst, 0, sizeof tst);
            initial_sample_pixel(&cur, &io, &xc, test_seed(), p, (uint32_t)t, &rc, &ist);
            initial_sample_pixel(&prev, &io, &xp, test_seed(), p, (uint32_t)t - 1, &rp, &ist);
            u[0] = rng_u(key, RNG_TEST, 0, 0);
            u[1] = rng_u(key, RNG_TEST, 0, 1);
            temporal_resample(&cur, &prev, NULL, (mis_family)mis, &xc, &xp, &rc, &rp, 20, u, &out, &ws, &tst);
            before = *checked;
            CHECKF(temporal_check_round_trip(&prev, NULL, &xp, &rp.y, &ws, why, sizeof why, checked) == 0,
                   "shift %s, MIS %s, pixel (%d,%d): %s", restir_shift_names[shift], mis_family_name((mis_family)mis),
                   x, y, why);
            if (*checked == before) continue;
            bad = rp;
            bad.y.target *= (real)(sizeof(real) == 4 ? 1.10 : 1.02); /* beyond the check's tolerance */
            *fired_target += temporal_check_round_trip(&prev, NULL, &xp, &bad.y, &ws, why, sizeof why, NULL);
            ws.ptarget[3] *= (real)(sizeof(real) == 4 ? 1.10 : 1.02);
            *fired_diag += temporal_check_round_trip(&prev, NULL, &xp, &rp.y, &ws, why, sizeof why, NULL);
        }
    spatial_workspace_free(&ws);
    lights_free(&lights);
    scene_free(&s);
}

TEST(evidence_temporal_round_trip_exact)
{
    int shift;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift) {
        long checked = 0, fired_diag = 0, fired_target = 0;
        round_trip_case(shift, shift == 1 ? MIS_PAIRWISE_DEFENSIVE : MIS_TALBOT, &checked, &fired_diag, &fired_target);
        if (test_has_failed()) return;
        if (getenv("RESTIR_TEST_VERBOSE"))
            fprintf(stderr, "  %s: %ld round trips, planted diagonal fired %ld, planted target fired %ld\n",
                    restir_shift_names[shift], checked, fired_diag, fired_target);
        CHECKF(checked >= 40, "%s: only %ld temporal round trips checked", restir_shift_names[shift], checked);
        CHECKF(fired_diag == checked && fired_target == checked,
               "%s: the planted violations fired %ld and %ld times in %ld checked steps", restir_shift_names[shift],
               fired_diag, fired_target, checked);
    }
}

/* ---- the M-cap on the input, exact ------------------------------------------------------------ */

/* GRIS §6.2, §6.4: the history's confidence is capped BEFORE the step, so the output of a
 * pixel with history is c_0 + min(c_1, C c_0). A still camera, no spatial pass, 1 path tree
 * (c_0 = 1), C = 2.5: c = 1, 2, 3, 3.5, 3.5 ... in frames 0, 1, 2, 3, 4 exactly. Capping
 * the output instead (min(c_0 + c_1, C c_0)) stays unbiased but gives 2.5 (mutant
 * mcap-on-output). Read from the sequence checkpoint (the final reservoirs of frame 4). */
TEST(evidence_temporal_mcap_on_input_exact)
{
    rt_mcap_sequence_exact(1, TEMPORAL_MCAP_RELATIVE, 3.5, "c_0 + min(c_1, C c_0) = 3.5");
}
