/* The footprint reconnection criterion (--rc-criterion footprint; Enhanced §4, Eq. 5;
 * src/restir/footprint.c, docs/enhanced.md §1):
 *   - Eq. 5 by hand on constructed vertex pairs (both footprints, footnote 6 skips, the
 *     Dirac x_k, alpha_min at x_{k-1}, the primary footprint);
 *   - offline ReSTIR PT with the criterion agrees with the reference path tracer under
 *     the K-run statistics of `restir check` (a subset here, the matrix in TEST_LONG);
 *   - the exact invertibility tests and the base-only ablation: tests/test_shift.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/footprint.h"
#include "restir/frame/options.h"
#include "restir_util.h"
#include "test.h"

#define ALPHA 1e-3

#ifdef RESTIR_REAL_FLOAT
#define REL_TOL 1e-5 /* float estimator precision */
#else
#define REL_TOL 1e-9
#endif

/* ---- Eq. 5 by hand ------------------------------------------------------------------- */

/* A path vertex on the plane z = 0 (normal +z) at p with material m, seen from `from`. */
static void plane_vertex(path_vertex *v, const material *m, vec3 p, vec3 from)
{
    memset(v, 0, sizeof *v);
    v->position = p;
    v->ng = v->ns = v3(0, 0, 1);
    v->wo = v3_normalize(v3_sub(from, p));
    v->frame = shading_frame_make(v->ns);
    v->wo_local = shading_frame_to_local(&v->frame, v->wo);
    v->b = bsdf_from_material(m);
}

static rc_vertex rcv(const path_vertex *v, unsigned lobe, vec3 wi)
{
    rc_vertex r;
    r.position = v->position;
    r.at_infinity = 0;
    r.ng = v->ng;
    r.surface = v;
    r.lobe = lobe;
    r.wi = wi;
    r.rough = rc_vertex_is_rough(&v->b, lobe, (real)0.2);
    return r;
}

static material make_material(enum material_type type, real roughness)
{
    material m;
    memset(&m, 0, sizeof m);
    m.type = type;
    m.diffuse = rgb_gray((real)0.5);
    m.specular = rgb_gray((real)0.9);
    m.roughness = roughness;
    m.ior = (real)1.5;
    return m;
}

TEST(footprint_eq5_by_hand)
{
    material lambert = make_material(MAT_LAMBERT, 1), metal = make_material(MAT_CONDUCTOR, (real)0.4);
    material mirror = make_material(MAT_DIELECTRIC, 0);
    path_vertex a, b, cam;
    rc_vertex pa, pb;
    rc_criterion crit;
    real fwd, inv, expect_fwd, d = 2, primary;
    vec3 up_b, w;
    memset(&crit, 0, sizeof crit);
    crit.mode = RC_MODE_FOOTPRINT;
    crit.roughness_threshold = (real)0.2;
    crit.footprint_c = (real)0.02;
    /* x_{k-1} = a at the origin (Lambert, seen from straight above), x_k = b on a wall
     * facing -x at distance d along +x... here both on z = 0 planes for simplicity: b
     * is the point (0, 0, d) of a ceiling facing down. */
    plane_vertex(&a, &lambert, v3(0, 0, 0), v3(1, 0, 1));
    plane_vertex(&b, &lambert, v3(0, 0, d), v3(0, 0, 0));
    b.ng = b.ns = v3(0, 0, -1);
    b.frame = shading_frame_make(b.ns);
    up_b = v3_normalize(v3(1, 0, -1));
    pa = rcv(&a, 0, v3(0, 0, 1));
    pb = rcv(&b, 0, up_b);
    /* forward: p = cos/pi = 1/pi straight up, G = 1/d^2: footprint pi d^2; inverse skipped (Lambert x_k) */
    rc_footprints(&pa, &pb, &fwd, &inv);
    expect_fwd = PI_R * d * d;
    CHECKF(fabs(fwd - expect_fwd) < REL_TOL * expect_fwd, "forward footprint %g, expected %g", (double)fwd,
           (double)expect_fwd);
    CHECK(isinf(inv));
    /* a glossy x_k: the inverse footprint is (P(l|wo') pdf_l(w_k) G(x_k -> x_{k-1}))^-1. */
    plane_vertex(&b, &metal, v3(0, 0, d), v3(0, 0, 0));
    b.ng = b.ns = v3(0, 0, -1);
    b.frame = shading_frame_make(b.ns);
    /* the vertex's own wo is NOT what the inverse term reads: it uses the direction to the
     * pair's x_{k-1} (an offset's y_{k-1} differs from the base's x_{k-1}) */
    b.wo = v3_normalize(v3(-1, 0, -1));
    b.wo_local = shading_frame_to_local(&b.frame, b.wo);
    pb = rcv(&b, 0, up_b);
    rc_footprints(&pa, &pb, &fwd, &inv);
    {
        real pl[BSDF_MAX_LOBES];
        vec3 wo = shading_frame_to_local(&b.frame, v3(0, 0, -1)), wi = shading_frame_to_local(&b.frame, up_b);
        real density;
        bsdf_lobe_probabilities(&b.b, wo, pl);
        density = pl[0] * bsdf_lobe_pdf(&b.b, 0, wo, wi) * 1 / (d * d);
        CHECKF(fabs(inv - 1 / density) < REL_TOL / density, "inverse footprint %g, expected %g", (double)inv,
               (double)(1 / density));
    }
    /* an NEE direction at x_k or an emissive x_k: skipped (footnote 6); a mirror x_k: zero. */
    pb.lobe = PATH_LOBE_NEE;
    rc_footprints(&pa, &pb, &fwd, &inv);
    CHECK(isinf(inv));
    pb.surface = NULL;
    pb.lobe = PATH_LOBE_NONE;
    rc_footprints(&pa, &pb, &fwd, &inv);
    CHECK(isinf(inv));
    plane_vertex(&b, &mirror, v3(0, 0, d), v3(0, 0, 0));
    b.ng = b.ns = v3(0, 0, -1);
    b.frame = shading_frame_make(b.ns);
    pb = rcv(&b, 0, up_b);
    rc_footprints(&pa, &pb, &fwd, &inv);
    CHECK(inv == 0);
    CHECK(rc_footprint_test(&crit, &pa, &pb, 1) == SHIFT_FAIL_RC_FOOTPRINT);
    /* an NEE-sampled x_k (x_{k-1}'s lobe NEE): the forward footprint is skipped. */
    pa.lobe = PATH_LOBE_NEE;
    pb.surface = NULL;
    pb.lobe = PATH_LOBE_NONE;
    rc_footprints(&pa, &pb, &fwd, &inv);
    CHECK(isinf(fwd) && isinf(inv));
    /* the threshold: c/100 times the primary footprint ||x0-x1||^2 / (cos / 4 pi). */
    plane_vertex(&cam, &lambert, v3(0, 0, 0), v3(0, 3, 4)); /* x1 at distance 5, cos 0.8 */
    cam.hit.t = 5;
    primary = rc_primary_footprint(&cam);
    CHECKF(fabs(primary - 25 / (0.8 / (4 * PI_R))) < REL_TOL * primary, "primary footprint %g", (double)primary);
    pa = rcv(&a, 0, v3(0, 0, 1));
    plane_vertex(&b, &lambert, v3(0, 0, d), v3(0, 0, 0));
    b.ng = b.ns = v3(0, 0, -1);
    pb = rcv(&b, 0, up_b);
    /* pi d^2 >= c/100 * F  <=>  F <= 100 pi d^2 / c */
    CHECK(rc_footprint_test(&crit, &pa, &pb, expect_fwd * 100 / crit.footprint_c * (real)0.999) == SHIFT_OK);
    CHECK(rc_footprint_test(&crit, &pa, &pb, expect_fwd * 100 / crit.footprint_c * (real)1.001) ==
          SHIFT_FAIL_RC_FOOTPRINT);
    /* alpha_min at x_{k-1}: a glossy x_{k-1} below the roughness threshold is not connectable. */
    pa.rough = 0;
    CHECK(rc_footprint_test(&crit, &pa, &pb, 0) == SHIFT_FAIL_RC_ROUGHNESS);
    w = v3(0, 0, 0);
    (void)w;
}

/* ---- unbiasedness against the path tracer ------------------------------------------- */

typedef struct {
    int shift, mis, passes, ablation, frames;
    int force_nee; /* Enhanced §6.2.3 */
} fp_case;

/* K runs of offline ReSTIR PT with the footprint criterion against the reference pt. */
static void expect(const scene *s, const check_side *pt, const char *name, const fp_case *m, int runs, int biased)
{
    restir_options o;
    check_side a;
    char what[256];
    rt_spatial_options(&o, test_seed() * 2389u + 31u * (uint32_t)m->shift + 7u * (uint32_t)m->mis + (uint32_t)m->passes,
                       m->shift, m->mis, m->passes, 4, 4.0 * s->width / 16);
    o.ablation = m->ablation;
    o.frames = m->frames;
    o.candidates = 2;
    o.max_depth = 4;
    o.rc_criterion = RC_MODE_FOOTPRINT;
    o.force_nee_reconnection = m->force_nee;
    if (rt_restir_side(s, &o, runs, 4, &a)) return;
    snprintf(what, sizeof what, "%s footprint%s shift %s mis %s passes %d ablate %s", name,
             m->force_nee ? " forced-nee" : "", restir_shift_names[m->shift], restir_mis_names[m->mis], m->passes,
             restir_ablation_names[m->ablation]);
    rt_expect_verdict(&a, pt, ALPHA, 4, what, biased, NULL);
}

/* path NULL: the spot scene (glossy floor, small light: the footprint test fires there);
 * "spot-0.1": its floor at roughness 0.1, below the threshold, so that NEE from the floor
 * has no connectable pair unless forced (Enhanced §6.2.3). */
static int open_scene(const char *path, int res, scene *s)
{
    rerror e;
    int glossy = path && !strcmp(path, "spot-0.1");
    if (path && !glossy) return rt_load_scene(path, res, s);
    if (rt_make_spot(s, res)) return -1;
    if (glossy) {
        size_t i;
        for (i = 0; i < s->material_count; ++i)
            if (s->materials[i].type == MAT_CONDUCTOR) s->materials[i].roughness = (real)0.1;
    }
    if (scene_prepare(s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(s);
        return -1;
    }
    return 0;
}

static void cases_on(const char *path, const char *name, const fp_case *cases, int n, int runs, uint32_t spp,
                     int biased)
{
    scene s;
    check_side pt;
    int i;
    if (open_scene(path, 16, &s)) return;
    if (rt_pt_side(&s, test_seed() * 7919u + 5, runs, spp, 4, 0, 4, &pt)) {
        scene_free(&s);
        return;
    }
    for (i = 0; i < n && !test_has_failed(); ++i) expect(&s, &pt, name, &cases[i], runs, biased);
    check_side_free(&pt);
    scene_free(&s);
}

TEST(restir_footprint_unbiased_subset)
{
    static const fp_case glossy[] = {
        {RESTIR_SHIFT_HYBRID, MIS_TALBOT, 3, RESTIR_ABLATE_NONE, 4, 0},
        {RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 1, RESTIR_ABLATE_NONE, 4, 1}, /* + forced NEE */
    };
    static const fp_case spot[] = {{RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_UNIFORM, 3, RESTIR_ABLATE_NONE, 8, 1}};
    cases_on("scenes/cornell-glossy.scene", "cornell-glossy", glossy, 2, 16, 64, 0);
    if (!test_has_failed()) cases_on("spot-0.1", "spot-0.1", spot, 1, 16, 256, 0);
}

TEST_LONG(restir_footprint_unbiased_matrix_long)
{
    static const char *const scenes[] = {"scenes/cornell.scene", "scenes/cornell-glossy.scene", "scenes/glass.scene",
                                         NULL};
    fp_case m[6];
    int f, p, i = 0, sc;
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_UNIFORM, MIS_PAIRWISE_DEFENSIVE};
    for (f = 0; f < 3; ++f)
        for (p = 0; p < 2; ++p) {
            m[i].shift = RESTIR_SHIFT_HYBRID;
            m[i].mis = families[f];
            m[i].passes = p ? 3 : 1;
            m[i].ablation = RESTIR_ABLATE_NONE;
            m[i].frames = 4;
            m[i].force_nee = f == 1; /* pairwise with Enhanced §6.2.3 */
            ++i;
        }
    for (sc = 0; scenes[sc] && !test_has_failed(); ++sc) {
        int glass = strstr(scenes[sc], "glass") != NULL;
        for (i = 0; i < 6; ++i) m[i].frames = glass ? 16 : 4;
        cases_on(scenes[sc], scenes[sc], m, 6, 24, glass ? 256 : 64, 0);
    }
    if (!test_has_failed()) cases_on(NULL, "spot", m, 6, 24, 256, 0);
}

/* ---- paired tests on shared seeds (docs/statistics.md "Paired check") ------------------ */

typedef struct {
    int passes, criterion, ablation; /* spatial passes, rc_mode, ablation */
    int force_nee;                   /* Enhanced §6.2.3 */
} fp_side;

/* K runs of side a against side b on the same seeds, both hybrid / pairwise-defensive
 * with c = 0.02: run k of a and run k of b draw the same initial samples and the same
 * neighbours, so their per-run differences cancel the shared noise. E[a - b] = 0 if both
 * are unbiased, so with a validated b a rejection is a's bias. */
static void paired_expect(const char *path, const char *name, const fp_side *sa, const fp_side *sb, int runs,
                          int biased)
{
    scene s;
    restir_options oa, ob;
    check_side a, b;
    check_result r;
    if (open_scene(path, 16, &s)) return;
    restir_options_default(&oa);
    oa.seed = test_seed() * 2654435761u + 29u;
    oa.shift = RESTIR_SHIFT_HYBRID;
    oa.spatial.mis = MIS_PAIRWISE_DEFENSIVE;
    oa.spatial.neighbors = 4;
    oa.spatial.radius = 4.0 * s.width / 16;
    oa.frames = 4;
    oa.candidates = 2;
    oa.max_depth = 4;
    oa.threads = 2;
    ob = oa;
    oa.spatial_passes = sa->passes;
    oa.rc_criterion = sa->criterion;
    oa.ablation = sa->ablation;
    oa.force_nee_reconnection = sa->force_nee;
    ob.force_nee_reconnection = sb->force_nee;
    ob.spatial_passes = sb->passes;
    ob.rc_criterion = sb->criterion;
    ob.ablation = sb->ablation;
    if (rt_restir_side(&s, &oa, runs, 4, &a) == 0) {
        if (rt_restir_side(&s, &ob, runs, 4, &b) == 0) {
            if (rt_compare_paired(&a, &b, ALPHA, 4, &r) == 0) {
                double z = stats_t_to_z(r.global.t, r.global.dof);
                char what[256];
                snprintf(what, sizeof what, "%s: %s%s %d passes%s%s vs %s %d passes", name, rc_mode_names[sa->criterion],
                         sa->force_nee ? " forced-nee" : "", sa->passes, sa->ablation ? " ablate " : "",
                         sa->ablation ? restir_ablation_names[sa->ablation] : "", rc_mode_names[sb->criterion],
                         sb->passes);
                if (getenv("RESTIR_TEST_VERBOSE"))
                    fprintf(stderr, "  paired %s: mean z %.2f (relative diff %+.4f%%), %ld/%ld blocks rejected, worst "
                                    "block z %.2f\n", what, z, 100 * r.bias, r.rejected, r.tests, r.worst.z);
                if (biased)
                    CHECKF(r.different, "%s: not detected by the paired test (mean z %.2f, worst block z %.2f)", what, z,
                           r.worst.z);
                else
                    CHECKF(!r.different, "%s: differ on the same seeds: mean z %.2f, %ld blocks rejected, worst z %.2f",
                           what, z, r.rejected, r.worst.z);
                check_result_free(&r);
            }
            check_side_free(&b);
        }
        check_side_free(&a);
    }
    scene_free(&s);
}

TEST(restir_footprint_paired_and_base_only_detected)
{
    static const fp_side initial = {0, RC_MODE_FOOTPRINT, RESTIR_ABLATE_NONE, 0};
    static const fp_side footprint = {3, RC_MODE_FOOTPRINT, RESTIR_ABLATE_NONE, 0};
    static const fp_side gris = {3, RC_MODE_GRIS, RESTIR_ABLATE_NONE, 0};
    static const fp_side base_only = {3, RC_MODE_FOOTPRINT, RESTIR_ABLATE_FOOTPRINT_BASE, 0};
    static const fp_side forced = {3, RC_MODE_GRIS, RESTIR_ABLATE_NONE, 1};
    static const fp_side gris_initial = {0, RC_MODE_GRIS, RESTIR_ABLATE_NONE, 0};
    const char *glossy = "scenes/cornell-glossy.scene";
    /* footprint against the 0-pass baseline (validated in test_restir_initial.c) */
    paired_expect(glossy, "cornell-glossy", &footprint, &initial, 16, 0);
    /* two unbiased estimators that differ wherever the criteria pick another k: not
     * different (the control for the next line's power) */
    if (!test_has_failed()) paired_expect(glossy, "cornell-glossy", &gris, &footprint, 48, 0);
    /* the criterion on the base path only: E[a - b] is its bias */
    if (!test_has_failed()) paired_expect(glossy, "cornell-glossy", &base_only, &footprint, 48, 1);
    /* Enhanced §6.2.3 forced NEE reconnection against the 0-pass baseline, where it acts */
    if (!test_has_failed()) paired_expect("spot-0.1", "spot-0.1", &forced, &gris_initial, 16, 0);
}
