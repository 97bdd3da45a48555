/* ReSTIR PT under the sky (docs/environment.md): scenes/courtyard.scene has no emissive
 * triangle, so every path ends at infinity (environment map or sun), by NEE or by an
 * escaped BSDF ray. Every shift x {Talbot, pairwise-defensive} with spatial reuse against
 * the path tracer (unpaired, Welch per block and channel R, G, B), K spatial passes against
 * 0 passes on the same numbers (paired), temporal reuse against the path tracer, and light
 * RIS with tiles (the sky as one more light). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/restir/mutate.h"
#include "restir/frame/pipeline.h"
#include "restir/frame/options.h"

#define ALPHA 1e-3
#define RES 16
#define RUNS 16
#define BLOCK 4

static int verbose(void) { return getenv("RESTIR_TEST_VERBOSE") != NULL; }

/* The stochastic pairwise step (an algorithm, not a MIS family: spatial_options.h). */
#define STOCHASTIC_STEP (-1)

static void sky_options(restir_options *o, int shift, int mis, int passes, uint32_t salt)
{
    restir_options_default(o);
    o->seed = test_seed() * 4099u + 977u * salt + 13u;
    o->shift = shift;
    if (mis == STOCHASTIC_STEP) o->spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE;
    else o->spatial.mis = (mis_family)mis;
    o->spatial_passes = passes;
    o->spatial.neighbors = 3;
    o->spatial.radius = 4.0;
    o->frames = 2;
    o->candidates = 2;
    o->max_depth = 4;
    o->threads = 2;
}

static void report(const char *what, const check_result *c, int biased)
{
    if (verbose())
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                rt_mean_z(c), c->lum_a.mean, c->lum_b.mean, c->rejected, c->tests, c->worst.z);
    test_margin(fabs(rt_mean_z(c)) > fabs(c->worst.z) ? rt_mean_z(c) : c->worst.z);
    if (biased)
        CHECKF(c->different, "%s: the biased estimator was not detected (mean z %.2f, worst block z %.2f)", what,
               rt_mean_z(c), c->worst.z);
    else
        CHECKF(!c->different, "%s: differs: mean z %.2f (p %.3g), %ld of %ld blocks rejected, worst z %.2f", what,
               rt_mean_z(c), c->global.p, c->rejected, c->tests, c->worst.z);
}

static int pt_reference(const scene *s, check_side *pt, int light_ris)
{
    pt_options ref;
    pt_options_default(&ref);
    ref.seed = test_seed() * 7919u + 3;
    ref.spp = 64;
    ref.max_depth = 4;
    ref.light_ris.candidates = light_ris;
    ref.threads = 2;
    return rt_pt_side_options(s, &ref, RUNS, BLOCK, pt);
}

/* The three shifts every comparison below runs. */
static const int sky_shifts[] = {RESTIR_SHIFT_RECONNECTION, RESTIR_SHIFT_REPLAY, RESTIR_SHIFT_HYBRID};

/* The courtyard (RES x RES) and its path-traced reference (plain NEE). 0 on success (a test
 * failure is recorded and nothing is left allocated otherwise). */
static int open_courtyard(scene *s, check_side *pt)
{
    if (rt_load_scene("scenes/courtyard.scene", RES, s)) return -1;
    if (pt_reference(s, pt, 0) == 0) return 0;
    scene_free(s);
    return -1;
}

/* Side a (freed here) against b, check_compare (paired 0) or check_compare_paired, reported
 * as `what`. */
static void compare_report(check_side *a, const check_side *b, int paired, const char *what, int biased)
{
    check_result c;
    int status = rt_compare_sides(a, b, ALPHA, BLOCK, paired, &c);
    check_side_free(a);
    if (status) return;
    report(what, &c, biased);
    check_result_free(&c);
}

static void unpaired(const scene *s, const check_side *pt, const restir_options *o, const char *what, int biased)
{
    check_side a;
    if (rt_restir_side(s, o, RUNS, BLOCK, &a) == 0) compare_report(&a, pt, 0, what, biased);
}

/* Every shift x {Talbot, pairwise-defensive}, 2 spatial passes, against the path tracer; and
 * stochastic pairwise MIS (Stochastic MIS, one pick) with the hybrid shift. */
TEST(restir_sky_unpaired_every_shift)
{
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_DEFENSIVE};
    scene s;
    check_side pt;
    int i, j;
    if (open_courtyard(&s, &pt)) return;
    for (i = 0; i < 3 && !test_has_failed(); ++i)
        for (j = 0; j < 2 && !test_has_failed(); ++j) {
            restir_options o;
            char what[128];
            sky_options(&o, sky_shifts[i], families[j], 2, (uint32_t)(3 * i + j));
            snprintf(what, sizeof what, "courtyard shift %s mis %s", restir_shift_names[sky_shifts[i]],
                     restir_mis_names[families[j]]);
            unpaired(&s, &pt, &o, what, 0);
        }
    if (!test_has_failed()) {
        restir_options o;
        sky_options(&o, RESTIR_SHIFT_HYBRID, STOCHASTIC_STEP, 2, 17);
        unpaired(&s, &pt, &o, "courtyard shift hybrid mis stochastic-pairwise", 0);
    }
    check_side_free(&pt);
    scene_free(&s);
}

/* Light RIS with tiles (the environment and the sun are entries of the light table, so
 * candidates and tile entries) through the hybrid shift, against the plain path tracer. */
TEST(restir_sky_light_ris_tiles)
{
    scene s;
    check_side pt;
    restir_options o;
    if (open_courtyard(&s, &pt)) return;
    sky_options(&o, RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 1, 41);
    o.light_ris.candidates = 8;
    o.light_ris.tiles = 1;
    unpaired(&s, &pt, &o, "courtyard hybrid light-ris 8 tiles", 0);
    sky_options(&o, RESTIR_SHIFT_RECONNECTION, MIS_TALBOT, 1, 43);
    o.light_ris.candidates = 8;
    unpaired(&s, &pt, &o, "courtyard reconnection light-ris 8", 0);
    check_side_free(&pt);
    scene_free(&s);
}

/* K = 2 spatial passes against 0 passes with the same numbers (check_compare_paired): the
 * initial samples cancel, so the spatial reuse alone is tested, per block and channel. */
TEST(restir_sky_paired_every_shift)
{
    static const int families[] = {MIS_PAIRWISE_UNIFORM, MIS_TALBOT};
    scene s;
    int i;
    if (rt_load_scene("scenes/courtyard.scene", RES, &s)) return;
    for (i = 0; i < 3 && !test_has_failed(); ++i) {
        restir_options oa, ob;
        check_side a, base;
        char what[128];
        sky_options(&oa, sky_shifts[i], families[i % 2], 2, 60u + (uint32_t)i);
        ob = oa;
        ob.spatial_passes = 0;
        if (rt_restir_side(&s, &oa, RUNS, BLOCK, &a)) break;
        if (rt_restir_side(&s, &ob, RUNS, BLOCK, &base)) {
            check_side_free(&a);
            break;
        }
        snprintf(what, sizeof what, "courtyard paired 2 vs 0 passes shift %s mis %s", restir_shift_names[sky_shifts[i]],
                 restir_mis_names[families[i % 2]]);
        compare_report(&a, &base, 1, what, 0);
        check_side_free(&base);
    }
    scene_free(&s);
}

/* ---- temporal reuse (still camera): frame 3 of K sequences against the path tracer ---- */

TEST(restir_sky_temporal)
{
    scene s;
    check_side pt;
    int i;
    if (open_courtyard(&s, &pt)) return;
    for (i = 0; i < 5 && !test_has_failed(); ++i) {
        restir_options o;
        rt_frame_sides q;
        char what[128];
        sky_options(&o, i < 3 ? sky_shifts[i] : i == 3 ? RESTIR_SHIFT_RECONNECTION : RESTIR_SHIFT_HYBRID,
                    MIS_PAIRWISE_DEFENSIVE, 1, 80u + (uint32_t)i);
        o.temporal.mis = i == 1 ? MIS_PAIRWISE_DEFENSIVE : MIS_TALBOT;
        if (i >= 3) { /* MCMC mutations after temporal reuse (Mutations Algorithm 3): rv, pp */
            o.mutation.count = 2;
            o.mutation.strategy = i == 3 ? MUTATE_RV : MUTATE_PP;
        }
        q.times[0] = 3; /* frame 3 of K sequences 0..3 */
        q.nt = 1;
        if (rt_frame_sides_run(&s, &o, RUNS, BLOCK, &q)) break;
        snprintf(what, sizeof what, "courtyard temporal frame 3 shift %s temporal %s mutations %d %s",
                 restir_shift_names[o.shift], restir_mis_names[o.temporal.mis], o.mutation.count,
                 mutate_strategy_names[o.mutation.strategy]);
        compare_report(&q.side[0], &pt, 0, what, 0); /* frees the side */
    }
    check_side_free(&pt);
    scene_free(&s);
}
