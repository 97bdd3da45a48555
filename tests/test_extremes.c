/* The extremes suite (issue 16, docs/precision.md): the estimators at the edges of their
 * inputs, in whichever precision the test binary was built (`make test-extremes` runs it
 * in the double and the float build). Each case counts non-finite pixels and samples
 * (they must be 0: nothing is dropped silently) and measures the bias against an exact
 * reference where one exists:
 *   - a tiny bright light (area 1e-8 x s^2, radiance 1e8) over a Lambertian floor, direct
 *     light only: per pixel L = rho Le A h^2 / (pi r^4) (a point light; the light's size
 *     changes it by O(A / r^2) = 1e-8), at scene scales s = 1e-4 .. 1e5, with the light
 *     at grazing height (cos theta ~ 1e-4 on the floor), the camera at grazing height
 *     (cos theta_o ~ 1e-4), and images of 1 x 1 and 8192 x 1;
 *   - the emitting Lambertian furnace sphere (pt_util.h): L_D = Le (1 - rho^D) / (1 - rho)
 *     at the largest max depth of each method (PT 255, ReSTIR 16), at scales 1e-4 and 1e5,
 *     with 255 neighbours, and through the real-time pipeline with M-caps 1 .. 1e6 and inf;
 *   - MIS weights with confidences up to 1e30, targets 1e-30 .. 1e30 and M = 2048 domains,
 *     against the same weights computed from rescaled inputs (the weights are invariant
 *     under c -> c / a, p̂ -> p̂ / b); these overflowed to NaN in the float build before
 *     mis_product_ratio (docs/precision.md);
 *   - resource limits: hostile OBJ, PFM and --size inputs fail with file:line before
 *     allocating (docs/formats.md "Limits").
 * Set RESTIR_EXTREMES_TABLE=FILE to append one row per measured case
 * (scripts/extremes.sh builds the table of docs/precision.md from it). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include "pt_util.h"
#include "restir_util.h"
#include "restir/restir/mis.h"
#include "restir/metrics/stats.h"
#include "restir/restir/stochastic_mis.h"
#include "restir/scene/text.h"
#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"

static char out[65536];

/* ---- measuring a case --------------------------------------------------------------- */

typedef struct {
    double mean, se;    /* mean over runs of the image-mean luminance, its standard error */
    int runs;           /* runs behind se (the t-test has runs - 1 degrees of freedom) */
    double ref;         /* the exact image mean */
    long nonfinite;     /* non-finite pixels over all runs, plus non-finite PT samples */
} extreme_result;

/* Image-mean luminance; non-finite pixels are counted (and left out of the mean). */
static double image_mean(const image *im, long *nonfinite)
{
    double sum = 0;
    size_t i, n = (size_t)im->width * im->height;
    for (i = 0; i < n; ++i) {
        const float *p = im->px + 3 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            (*nonfinite)++;
            continue;
        }
        sum += (double)luminance(rgb_make(p[0], p[1], p[2]));
    }
    return sum / (double)n;
}

static void runs_summary(const double *x, int n, extreme_result *r)
{
    double m = 0, v = 0;
    int k;
    for (k = 0; k < n; ++k) m += x[k];
    m /= n;
    for (k = 0; k < n; ++k) v += (x[k] - m) * (x[k] - m);
    r->mean = m;
    r->se = n > 1 ? sqrt(v / (n - 1) / n) : 0;
    r->runs = n;
}

enum { MAX_RUNS = 32 };

static int pt_runs(const scene *s, int max_depth, int runs, uint32_t spp, unsigned ablations, extreme_result *r)
{
    double x[MAX_RUNS];
    int k;
    r->nonfinite = 0;
    for (k = 0; k < runs; ++k) {
        pt_options o;
        pt_result res;
        rerror e;
        test_pt_options(&o, test_seed() * 7919u + 11u, spp, max_depth);
        o.sample_offset = (uint32_t)k * spp;
        o.quiet = 1;
        o.ablations = ablations;
        if (pt_render(s, &o, &res, &e)) {
            test_fail(__FILE__, __LINE__, "pt_render: %s", e.msg);
            return -1;
        }
        r->nonfinite += (long)res.state.nonfinite;
        x[k] = image_mean(&res.mean, &r->nonfinite);
        pt_result_free(&res);
    }
    runs_summary(x, runs, r);
    return 0;
}

static void restir_base(restir_options *o, int max_depth)
{
    restir_options_default(o);
    o->max_depth = max_depth;
    o->spatial_passes = 1;
    o->spatial.neighbors = 6;
    o->spatial.radius = 4;
    o->frames = 1;
    o->threads = 2;
    o->seed = test_seed() * 104729u + 3u;
}

static int restir_runs(const scene *s, const restir_options *base, int runs, extreme_result *r)
{
    double x[MAX_RUNS];
    int k;
    r->nonfinite = 0;
    for (k = 0; k < runs; ++k) {
        restir_result res;
        if (rt_restir_run(s, base, k, &res)) return -1;
        x[k] = image_mean(&res.mean, &r->nonfinite);
        restir_result_free(&res);
    }
    runs_summary(x, runs, r);
    return 0;
}

static void table_row(const char *name, const char *method, const extreme_result *r)
{
    const char *path = getenv("RESTIR_EXTREMES_TABLE");
    FILE *f;
    if (!path || !(f = fopen(path, "a"))) return;
    fprintf(f, "%s\t%s\t%s\t%u\t%.9g\t%.3g\t%.9g\t%ld\t%d\n", name, method, sizeof(real) == 4 ? "float" : "double",
            test_seed(), r->mean, r->se, r->ref, r->nonfinite, r->runs);
    fclose(f);
}

/* No non-finite pixel or sample, and the mean within rel_tol of the reference plus a
 * t-test at |z| < 4.5 (normal-equivalent of the t statistic with runs - 1 degrees of
 * freedom: few runs estimate se poorly). rel_tol covers what is not noise: the point-light
 * approximation, float rounding (docs/precision.md lists the measured errors). */
static void expect_unbiased(const char *name, const char *method, extreme_result *r, double rel_tol)
{
    double err = r->mean - r->ref, excess = fabs(err) - rel_tol * fabs(r->ref);
    double z = excess <= 0 ? 0 : (r->se > 0 ? stats_t_to_z(excess / r->se, r->runs - 1) : 1e3);
    table_row(name, method, r);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %-28s %-7s mean %.9g ref %.9g rel %.2e se/ref %.2e nonfinite %ld\n", name, method, r->mean,
                r->ref, err / r->ref, r->se / r->ref, r->nonfinite);
    CHECKF(r->nonfinite == 0, "%s, %s: %ld non-finite pixels or samples", name, method, r->nonfinite);
    if (!(z < 4.5)) test_margin(z);
    CHECKF(z < 4.5, "%s, %s: mean %.9g, reference %.9g (relative %.3g; se %.3g, %d runs, z %.2f)", name, method,
           r->mean, r->ref, err / r->ref, r->se, r->runs, z);
}

/* ---- the tiny bright light ------------------------------------------------------------- */

typedef struct {
    double scale;      /* every length times this */
    double height;     /* light height above the floor (before scaling) */
    double side;       /* light edge (area side^2, before scaling) */
    double radiance;   /* Le */
    int grazing_eye;   /* camera at height 1e-4 looking along the floor */
    int width, height_px;
} tiny_light;

static const double tiny_rho = 0.5;
static const double tiny_cx = 0.3, tiny_cz = 0.2; /* light centre (x, z) before scaling */

/* A 4 x 4 Lambertian floor (y = 0, facing up) and a square light facing down. */
static int tiny_light_scene(const tiny_light *t, scene *s)
{
    uint32_t floor_m, light_m;
    float h = (float)t->height, a = (float)t->side;
    if (test_scene_begin(s, 4, 2)) return -1;
    floor_m = test_scene_material(s, MAT_LAMBERT, rgb_gray((real)tiny_rho), rgb_gray(0));
    light_m = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_gray((real)t->radiance));
    test_scene_quad(s, v3f(-2, 0, -2), v3f(0, 0, 4), v3f(4, 0, 0), floor_m);
    test_scene_quad(s, v3f((float)tiny_cx - a / 2, h, (float)tiny_cz - a / 2), v3f(a, 0, 0), v3f(0, 0, a), light_m);
    if (t->grazing_eye)
        test_scene_camera(s, v3(0, (real)1e-4, (real)1.9), v3(0, 0, (real)0.9), v3(0, 1, 0), 40, 8);
    else
        test_scene_camera(s, v3(0, (real)2.5, (real)2.5), v3(0, 0, 0), v3(0, 1, 0), 50, 8);
    s->width = t->width;
    s->height = t->height_px;
    test_scene_scale(s, (float)t->scale);
    return test_scene_prepare(s);
}

/* The light as the renderer sees it: area and centroid of its two float triangles (the
 * float corners round a 1e-4 edge at 0.3 by ~1e-7 relative each, so the area A differs
 * from side^2 by up to ~1e-3 relative; the reference must use the A that is rendered). */
static void light_area_centroid(const scene *s, long double *area, long double c[3])
{
    size_t t;
    int k;
    *area = 0;
    c[0] = c[1] = c[2] = 0;
    for (t = 0; t < s->triangle_count; ++t) {
        const triangle *tr = &s->triangles[t];
        vec3f p0 = s->positions[tr->v[0]], p1 = s->positions[tr->v[1]], p2 = s->positions[tr->v[2]];
        long double e1[3], e2[3], n[3], a;
        if (!(s->materials[tr->material].emission.r > 0)) continue;
        e1[0] = (long double)p1.x - p0.x, e1[1] = (long double)p1.y - p0.y, e1[2] = (long double)p1.z - p0.z;
        e2[0] = (long double)p2.x - p0.x, e2[1] = (long double)p2.y - p0.y, e2[2] = (long double)p2.z - p0.z;
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        a = sqrtl(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2;
        *area += a;
        for (k = 0; k < 3; ++k)
            c[k] += a * ((long double)(k == 0 ? p0.x : k == 1 ? p0.y : p0.z) + (k == 0 ? p1.x : k == 1 ? p1.y : p1.z) +
                         (k == 0 ? p2.x : k == 1 ? p2.y : p2.z)) / 3;
    }
    for (k = 0; k < 3; ++k) c[k] /= *area;
}

/* The exact image mean: rho / pi Le A cos cos' / r^2 at every pixel's floor point, in
 * long double from the float positions the renderer sees (a point light at the
 * centroid: the light's extent changes L by O(A / r^2) <= 1e-7 here). */
static double tiny_light_reference(const tiny_light *t, const scene *s)
{
    long double sum = 0, A, c[3];
    int x, y;
    light_area_centroid(s, &A, c);
    for (y = 0; y < s->height; ++y)
        for (x = 0; x < s->width; ++x) {
            path_vertex v;
            long double dx, dz, r2;
            if (!rt_primary_vertex(s, x, y, &v) || v.position.y != 0) continue;
            dx = (long double)v.position.x - c[0];
            dz = (long double)v.position.z - c[2];
            r2 = dx * dx + dz * dz + c[1] * c[1];
            sum += tiny_rho / 3.14159265358979323846L * t->radiance * A * c[1] * c[1] / (r2 * r2);
        }
    return (double)(sum / ((long double)s->width * s->height));
}

static void tiny_light_case(const char *name, const tiny_light *t, int runs, double rel_tol)
{
    scene s;
    extreme_result r;
    restir_options o;
    if (tiny_light_scene(t, &s)) return;
    r.ref = tiny_light_reference(t, &s);
    CHECKF(r.ref > 0, "%s: no pixel sees the lit floor", name);
    if (pt_runs(&s, 2, runs, 2, 0, &r) == 0) expect_unbiased(name, "pt", &r, rel_tol);
    restir_base(&o, 2);
    if (!test_has_failed() && restir_runs(&s, &o, runs, &r) == 0) expect_unbiased(name, "restir", &r, rel_tol);
    scene_free(&s);
}

static tiny_light tiny_default(void)
{
    tiny_light t;
    t.scale = 1;
    t.height = 0.5;
    t.side = 1e-4;
    t.radiance = 1e8;
    t.grazing_eye = 0;
    t.width = t.height_px = 8;
    return t;
}

/* The point-light tolerance: the light's finite size changes L by ~A/r^2 (1e-8) and the
 * float build evaluates geometry terms in float (~1e-6 per factor). */
static double tiny_tol(void) { return sizeof(real) == 4 ? 2e-4 : 1e-6; }

TEST(extremes_tiny_bright_light)
{
    tiny_light t = tiny_default();
    tiny_light_case("light area 1e-8, Le 1e8", &t, 4, tiny_tol());
}

/* The same measurement rejects a deliberately broken estimator (docs/statistics.md): the
 * path tracer's light pdf 5% too large misses the exact image by thousands of standard
 * errors. (ReSTIR's jacobian and light-pdf ablations stay within the noise here: with a
 * 1e-8 light every pixel's own NEE candidate is almost exact and reuse changes little;
 * docs/precision.md gives the numbers. The furnace and spot tests of the ReSTIR suites
 * catch them.) */
TEST(extremes_tiny_light_rejects_ablation)
{
    tiny_light t = tiny_default();
    scene s;
    extreme_result r;
    double z;
    if (tiny_light_scene(&t, &s)) return;
    r.ref = tiny_light_reference(&t, &s);
    if (pt_runs(&s, 2, 4, 2, PT_ABLATE_LIGHT_PDF, &r)) {
        scene_free(&s);
        return;
    }
    scene_free(&s);
    z = fabs(r.mean - r.ref) / (4.5 * r.se + tiny_tol() * fabs(r.ref));
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  pt light-pdf ablation: rel %.3g, |bias| / (4.5 se + tol) = %.1f\n", (r.mean - r.ref) / r.ref,
                z);
    CHECKF(z > 10, "pt light-pdf ablation not rejected: |bias| / (4.5 se + tol) = %.1f", z);
}

TEST(extremes_tiny_light_scales)
{
    static const double scales[] = {1e-4, 1e5};
    size_t i;
    for (i = 0; i < sizeof scales / sizeof scales[0] && !test_has_failed(); ++i) {
        tiny_light t = tiny_default();
        char name[64];
        t.scale = scales[i];
        snprintf(name, sizeof name, "tiny light, scale %g", scales[i]);
        tiny_light_case(name, &t, 4, tiny_tol());
    }
}

/* The light at height 1e-4 over a floor 1..3 away: cos theta and cos theta' ~ 1e-4 (and
 * the floor right under the light at cos ~ 1). */
TEST(extremes_grazing_light)
{
    tiny_light t = tiny_default();
    t.height = 1e-4;
    t.side = 1e-5; /* below the height, so the floor under it is not inside the light */
    tiny_light_case("grazing light, cos 1e-4", &t, 16, tiny_tol());
}

/* The camera 1e-4 above the floor looking along it: the centre row hits the floor 1 away
 * at cos theta_o = 1e-4 (the rows above miss, the rows below hit at up to cos 0.3). */
TEST(extremes_grazing_camera)
{
    tiny_light t = tiny_default();
    t.grazing_eye = 1;
    t.width = t.height_px = 9;
    tiny_light_case("grazing camera, cos_o 1e-4", &t, 4, tiny_tol());
}

TEST(extremes_image_1x1_and_8192x1)
{
    tiny_light t = tiny_default();
    t.width = t.height_px = 1;
    t.grazing_eye = 1; /* the centre pixel of the grazing view sees the floor */
    tiny_light_case("image 1x1", &t, 4, tiny_tol());
    if (test_has_failed()) return;
    t = tiny_default();
    t.width = 8192;
    t.height_px = 1;
    tiny_light_case("image 8192x1", &t, 4, tiny_tol());
}

/* ---- the furnace ---------------------------------------------------------------------- */

static int furnace(scene *s, int res, double scale)
{
    if (test_scene_furnace_sphere(s, rgb_gray(1), rgb_gray((real)0.5), res)) return -1;
    if (scale != 1) test_scene_scale(s, (float)scale);
    return test_scene_prepare(s);
}

static double furnace_reference(int depth) { return (1 - pow(0.5, depth)) / 0.5; }

static void furnace_case(const char *label, double scale, int res, int runs, int neighbors)
{
    scene s;
    extreme_result r;
    restir_options o;
    char name[96];
    snprintf(name, sizeof name, "%s, %dx%d, %d runs", label, res, res, runs);
    if (furnace(&s, res, scale)) return;
    r.ref = furnace_reference(PT_MAX_DEPTH_LIMIT);
    if (pt_runs(&s, PT_MAX_DEPTH_LIMIT, runs, 2, 0, &r) == 0) expect_unbiased(name, "pt d255", &r, 1e-5);
    restir_base(&o, PATH_MAX_LENGTH);
    o.spatial.neighbors = neighbors;
    o.spatial.radius = neighbors > 6 ? 64 : 4;
    r.ref = furnace_reference(PATH_MAX_LENGTH);
    if (!test_has_failed() && restir_runs(&s, &o, runs, &r) == 0) expect_unbiased(name, "restir d16", &r, 1e-5);
    scene_free(&s);
}

/* The longest paths each method allows (PT 255 segments: the throughput 0.5^254
 * underflows in float, which must give 0, not NaN; ReSTIR 16). */
TEST(extremes_furnace_longest_paths) { furnace_case("furnace, longest paths", 1, 6, 4, 6); }

TEST(extremes_furnace_scales)
{
    furnace_case("furnace, scale 1e-4", 1e-4, 6, 4, 6);
    if (!test_has_failed()) furnace_case("furnace, scale 1e5", 1e5, 6, 4, 6);
}

/* NEIGHBOR_MAX_COUNT = 255 neighbours per pixel (the most the RNG key addresses). */
TEST_LONG(extremes_furnace_255_neighbours) { furnace_case("furnace, 255 neighbours", 1, 24, 4, NEIGHBOR_MAX_COUNT); }

TEST_LONG(extremes_furnace_long)
{
    furnace_case("furnace, longest paths", 1, 12, 12, 6);
    if (!test_has_failed()) furnace_case("furnace, scale 1e-4", 1e-4, 12, 12, 6);
    if (!test_has_failed()) furnace_case("furnace, scale 1e5", 1e5, 12, 12, 6);
}

/* ---- M-caps through the real-time pipeline --------------------------------------------- */

enum { MAX_FRAMES = 32 };

/* A still furnace over `frames` frames: the confidence of the temporal input grows to
 * min(mcap, frames) x the current one; the last frame must still average L_D. */
static void mcap_case(double mcap, int frames, int runs)
{
    scene s;
    extreme_result r;
    restir_options o;
    image img[MAX_FRAMES];
    double x[MAX_RUNS];
    char name[64];
    int k, f;
    CHECK(frames <= MAX_FRAMES);
    if (furnace(&s, 8, 1)) return;
    restir_base(&o, 4);
    o.temporal.mcap = mcap;
    o.temporal.enabled = 1;
    r.nonfinite = 0;
    for (k = 0; k < runs; ++k) {
        o.seed = test_seed() * 15485863u + (uint32_t)k;
        if (rt_sequence_images(&s, &o, 0, frames - 1, img)) {
            scene_free(&s);
            return;
        }
        x[k] = image_mean(&img[frames - 1], &r.nonfinite); /* the last frame */
        for (f = 0; f < frames; ++f) image_free(&img[f]);
    }
    runs_summary(x, runs, &r);
    r.ref = furnace_reference(4);
    snprintf(name, sizeof name, "furnace, M-cap %g, %d frames", mcap, frames);
    expect_unbiased(name, "realtime", &r, 1e-5);
    scene_free(&s);
}

TEST(extremes_mcaps)
{
    mcap_case(1, 6, 4);
    if (!test_has_failed()) mcap_case(1e6, 6, 4);
    if (!test_has_failed()) mcap_case(INFINITY, 6, 4);
}

TEST_LONG(extremes_mcaps_long)
{
    static const double caps[] = {1, 20, 1e3, 1e6, INFINITY};
    size_t i;
    for (i = 0; i < sizeof caps / sizeof caps[0] && !test_has_failed(); ++i) mcap_case(caps[i], 24, 12);
}

/* ---- roughness extremes and reconnections at distance -> 0: ReSTIR against PT ---------- */

/* ReSTIR's image mean against the path tracer's (independent runs of both; no exact
 * reference): the "spot" scene (restir_util.h: a GGX floor, a white back wall meeting it
 * in a corner, a small light 8 cm above the floor) with the floor's roughness r. With
 * corner = 1 the camera looks into the floor-wall corner and every vertex may reconnect
 * (roughness and distance thresholds 0), so reconnection segments shrink towards 0 and
 * G = cos cos / r^2 grows without bound there. */
static void spot_case(const char *label, double roughness, int corner, int res, int runs, uint32_t pt_spp)
{
    scene s;
    extreme_result pt, rs;
    restir_options o;
    char name[96];
    snprintf(name, sizeof name, "%s, %dx%d, %d runs", label, res, res, runs);
    if (rt_make_spot(&s, res)) return;
    s.materials[0].roughness = (real)roughness;
    if (corner)
        test_scene_camera(&s, v3(0, (real)0.3, (real)0.2), v3(0, (real)0.02, (real)0.6), v3(0, 1, 0), 40, res);
    if (test_scene_prepare(&s)) return;
    if (pt_runs(&s, 4, runs, pt_spp, 0, &pt)) {
        scene_free(&s);
        return;
    }
    restir_base(&o, 4);
    o.spatial_passes = 2;
    if (corner) {
        o.roughness_threshold = 0;
        o.distance_threshold = 0;
    }
    if (restir_runs(&s, &o, runs, &rs) == 0) {
        rs.ref = pt.mean;
        rs.nonfinite += pt.nonfinite;
        rs.se = sqrt(rs.se * rs.se + pt.se * pt.se);
        rs.runs = rs.runs < pt.runs ? rs.runs : pt.runs; /* conservative Welch dof */
        expect_unbiased(name, "restir vs pt", &rs, 0);
    }
    scene_free(&s);
}

TEST(extremes_roughness_and_corner)
{
    spot_case("GGX floor, roughness 1e-4", 1e-4, 0, 16, 8, 8);
    if (!test_has_failed()) spot_case("GGX floor, roughness 1", 1, 0, 16, 8, 8);
    if (!test_has_failed()) spot_case("corner, reconnect at any distance", 0.3, 1, 16, 8, 8);
}

TEST_LONG(extremes_roughness_and_corner_long)
{
    spot_case("GGX floor, roughness 1e-4", 1e-4, 0, 32, 12, 16);
    if (!test_has_failed()) spot_case("GGX floor, roughness 1", 1, 0, 32, 12, 16);
    if (!test_has_failed()) spot_case("corner, reconnect at any distance", 0.3, 1, 32, 12, 16);
}

/* ---- guards are counted -------------------------------------------------------------- */

/* The NaN/Inf policy of ReSTIR (docs/precision.md): half the furnace sphere gets the absurd
 * albedo 0.83 REAL_MAX, so candidate weights overflow. Every skipped weight is counted
 * (initial + spatial invalid_weights), and every non-finite pixel estimate is counted in
 * nonfinite_pixels and kept in the image (the image and the counter agree). */
TEST(extremes_restir_guards_counted)
{
    scene s;
    restir_options o;
    restir_result r;
    rerror e;
    uint32_t hot;
    size_t t;
    long image_nonfinite = 0;
    if (test_scene_furnace_sphere(&s, rgb_gray(1), rgb_gray((real)0.5), 8)) return;
    hot = test_scene_material(&s, MAT_LAMBERT, rgb_gray(REAL_MAX * (real)0.83), rgb_gray(1));
    for (t = 0; t < s.triangle_count; t += 2) s.triangles[t].material = hot;
    if (test_scene_prepare(&s)) return;
    restir_base(&o, 3);
    if (restir_render(&s, &o, &r, &e)) {
        scene_free(&s);
        CHECKF(0, "restir_render: %s", e.msg);
    }
    image_mean(&r.mean, &image_nonfinite);
    CHECKF(restir_stats_invalid_weights(&r.stats) > 0, "no invalid weight counted");
    CHECKF((uint64_t)image_nonfinite == r.stats.nonfinite_pixels, "%ld non-finite pixels in the image, %llu counted",
           image_nonfinite, (unsigned long long)r.stats.nonfinite_pixels);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  guards: invalid weights %llu (initial %llu), non-finite pixels %llu of %d\n",
                (unsigned long long)restir_stats_invalid_weights(&r.stats),
                (unsigned long long)r.stats.initial.invalid_weights, (unsigned long long)r.stats.nonfinite_pixels,
                s.width * s.height);
    restir_result_free(&r);
    scene_free(&s);
}

/* ---- MIS weights at huge confidences and targets -------------------------------------- */

/* Every family's weights at (c, p̂) against the same weights at (c / c_max, p̂ / p̂_max),
 * where no product can overflow: equal within the precision, finite, >= 0, summing to 1. */
static void mis_scaled_case(int fam, int m, const real *c, const real *pt)
{
    real cs[8], ps[64], w[8], ws[8], c_max = 0, p_max = 0, sum;
    mis_input in, ins;
    int i, j;
    double tol = sizeof(real) == 4 ? 2e-5 : 1e-12;
    for (i = 0; i < m; ++i) c_max = c[i] > c_max ? c[i] : c_max;
    for (i = 0; i < m * m; ++i) p_max = pt[i] > p_max ? pt[i] : p_max;
    for (i = 0; i < m; ++i) cs[i] = c[i] / c_max;
    for (i = 0; i < m * m; ++i) ps[i] = pt[i] / p_max;
    in.m = ins.m = m;
    in.n_canonical = ins.n_canonical = 1;
    in.confidence = c;
    in.ptarget = pt;
    ins.confidence = cs;
    ins.ptarget = ps;
    for (j = 0; j < m; ++j) {
        mis_weights_at((mis_family)fam, &in, j, w, NULL);
        mis_weights_at((mis_family)fam, &ins, j, ws, NULL);
        sum = 0;
        for (i = 0; i < m; ++i) {
            CHECKF(isfinite((double)w[i]) && w[i] >= 0, "%s: c = (%g, %g), p = %g: m_%d(y_%d) = %g",
                   mis_family_name((mis_family)fam), (double)c[0], (double)c[1], (double)pt[0], i, j, (double)w[i]);
            CHECKF(fabs((double)w[i] - (double)ws[i]) <= tol, "%s: c = (%g, %g), p = %g: m_%d(y_%d) = %.9g, rescaled %.9g",
                   mis_family_name((mis_family)fam), (double)c[0], (double)c[1], (double)pt[0], i, j, (double)w[i],
                   (double)ws[i]);
            sum += w[i];
        }
        CHECK_NEAR(sum, 1, 1e-5);
    }
}

TEST(extremes_mis_huge_confidences_and_targets)
{
    /* the last entry, REAL_MAX / 10, overflows the products in either build */
    const double cs[] = {1, 1e6, 1e20, 1e30, (double)REAL_MAX / 10};
    const double ps[] = {1e-30, 1e-10, 1, 1e10, 1e30, (double)REAL_MAX / 10};
    size_t a, b, k;
    int fam, i;
    for (fam = 0; fam < MIS_FAMILY_COUNT; ++fam)
        for (a = 0; a < 5; ++a)
            for (b = 0; b < 5; ++b)
                for (k = 0; k < 6; ++k) {
                    real c[3], pt[9];
                    c[0] = (real)cs[a];
                    c[1] = (real)cs[b];
                    c[2] = 1;
                    for (i = 0; i < 9; ++i) pt[i] = (real)ps[k] * (real)(1 + (i * 7) % 5) / 5;
                    pt[5] = 0; /* a failed shift */
                    mis_scaled_case(fam, 3, c, pt);
                    if (test_has_failed()) return;
                }
    /* The two-domain merges and the stochastic pairwise terms. */
    CHECK_NEAR(mis_pair_canonical((real)1e30, (real)1e10, (real)1e30, (real)3e10), 0.25, 1e-6);
    CHECK_NEAR(mis_pair_neighbor((real)1e30, (real)3e10, (real)1e30, (real)1e10), 0.75, 1e-6);
    CHECK_NEAR(stochastic_pairwise_m((real)1e30, (real)2e30, (real)1e30, (real)1e10, (real)1e10), 2.0 / 3 * 1.0 / 3,
               1e-6);
    CHECK_NEAR(stochastic_pairwise_b((real)1e30, (real)2e30, (real)1e30, (real)1e10, (real)1e10), 1.0 / 3 * 1.0 / 3,
               1e-6);
}

/* M = 2048 domains (far more than the 255 neighbours a spatial pass takes): Talbot and
 * the pairwise weights still sum to 1 in the precision (float: ~M eps accumulated). */
TEST(extremes_mis_thousands_of_domains)
{
    enum { M = 2048 };
    static real c[M];
    mis_input in;
    int fam, i;
    /* Column j = 0 and j = 1 only (the weights read one column); the rest is never read. */
    real *big;
    big = calloc((size_t)M * M, sizeof *big);
    CHECK(big != NULL);
    for (i = 0; i < M; ++i) {
        c[i] = (real)(1 + i % 7);
        big[(size_t)i * M + 0] = (real)(0.5 + (i % 11) * 0.1);
        big[(size_t)i * M + 1] = (real)(1e-3 + (i % 5));
    }
    in.m = M;
    in.n_canonical = 1;
    in.confidence = c;
    in.ptarget = big;
    for (fam = 0; fam < MIS_FAMILY_COUNT; ++fam) {
        int j;
        for (j = 0; j < 2; ++j) {
            double sum = 0;
            for (i = 0; i < M; ++i) {
                real w = mis_weight((mis_family)fam, &in, i, j, NULL);
                if (!(isfinite((double)w) && w >= 0)) break;
                sum += w;
            }
            if (i < M || !(fabs(sum - 1) <= (sizeof(real) == 4 ? 1e-3 : 1e-12))) {
                free(big);
                CHECKF(0, "%s, M = %d, column %d: weights sum to %.9g (stopped at %d)",
                       mis_family_name((mis_family)fam), M, j, sum, i);
            }
        }
    }
    free(big);
}

/* ---- resource limits ------------------------------------------------------------------ */

/* Exit 2 with "what" in the message and no output file. */
static void expect_refused(const char *args, const char *what)
{
    const char *dest = test_tmp_path("refused.pfm");
    char dest_copy[1024];
    int status;
    snprintf(dest_copy, sizeof dest_copy, "%s", dest);
    remove(dest_copy);
    status = test_cli(out, sizeof out, "%s -o %s --quiet", args, dest_copy);
    CHECKF(status == 2, "'%s': exit %d, output: %s", args, status, out);
    CHECKF(strstr(out, what) != NULL, "'%s': message lacks '%s': %s", args, what, out);
    CHECKF(!test_file_exists(dest_copy), "'%s' left %s", args, dest_copy);
}

TEST(extremes_limits_obj_indices_and_ngons)
{
    const char *obj;
    char *text, args[1100];
    size_t i, n = 16385, len = 0;
    obj = test_write_file("huge-index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 100000000\n");
    snprintf(args, sizeof args, "render %s", obj);
    expect_refused(args, "huge-index.obj:4: vertex index 100000000 out of range");
    if (test_has_failed()) return;
    /* A 16385-gon: one corner over OBJ_MAX_FACE_CORNERS (ear clipping is quadratic). */
    text = malloc(40 * n + 64);
    CHECK(text != NULL);
    for (i = 0; i < n; ++i) len += (size_t)sprintf(text + len, "v %d %d 0\n", (int)(i % 128), (int)(i / 128));
    len += (size_t)sprintf(text + len, "f");
    for (i = 0; i < n; ++i) len += (size_t)sprintf(text + len, " %d", (int)i + 1);
    sprintf(text + len, "\n");
    obj = test_write_file("deep-ngon.obj", text);
    free(text);
    snprintf(args, sizeof args, "render %s", obj);
    expect_refused(args, "deep-ngon.obj:16386: face with more than 16384 corners");
}

/* A 5 MiB line in a file (text_open), and a 1 GB line from a stream: the reader stops at
 * TEXT_MAX_LINE bytes, so the stream is never buffered whole. */
TEST(extremes_limits_long_line)
{
    const char *path = test_tmp_path("long-line.obj");
    char path_copy[1024], cmd[4096];
    FILE *f;
    text_reader t;
    rerror e;
    size_t i;
    int status;
    snprintf(path_copy, sizeof path_copy, "%s", path);
    f = fopen(path_copy, "wb");
    CHECK(f != NULL);
    fputs("v 0 0 0\n# ", f);
    for (i = 0; i < 5u << 20; ++i) fputc('x', f);
    fputs("\n", f);
    fclose(f);
    CHECK(text_open(&t, path_copy, &e) != 0);
    CHECKF(strstr(e.msg, "long-line.obj:2: line longer than 4194304 bytes") != NULL, "%s", e.msg);
    remove(path_copy);
    CHECK(mkfifo(path_copy, 0600) == 0);
    snprintf(cmd, sizeof cmd,
             "(head -c 1073741824 /dev/zero | tr '\\000' v > '%s') 2>/dev/null & %s info '%s' >'%s.txt' 2>&1; "
             "status=$?; kill $! 2>/dev/null; wait; exit $status",
             path_copy, RESTIR_BIN, path_copy, path_copy);
    status = system(cmd);
    remove(path_copy);
    snprintf(cmd, sizeof cmd, "%s.txt", path_copy);
    f = fopen(cmd, "rb");
    CHECK(f != NULL);
    i = fread(out, 1, sizeof out - 1, f);
    out[i] = '\0';
    fclose(f);
    CHECKF(WIFEXITED(status) && WEXITSTATUS(status) == 2, "status %d: %s", status, out);
    CHECKF(strstr(out, "long-line.obj:1: line longer than 4194304 bytes") != NULL, "%s", out);
}

TEST(extremes_limits_image_size)
{
    const char *obj, *scene_path;
    char args[1100];
    obj = test_write_file("limits.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    (void)obj;
    scene_path = test_write_file("limits.scene", "mesh limits.obj\nsize 65536 65536\n");
    snprintf(args, sizeof args, "render %s", scene_path);
    expect_refused(args, "limits.scene:2: size 65536 x 65536: more than 67108864 pixels");
    if (test_has_failed()) return;
    scene_path = test_write_file("limits-ok.scene", "mesh limits.obj\nsize 64 64\n");
    snprintf(args, sizeof args, "render %s --size 100000x100000", scene_path);
    expect_refused(args, "W, H <= 65536, W*H <= 8192*8192");
    if (test_has_failed()) return;
    snprintf(args, sizeof args, "render %s --size 65536x65536", scene_path);
    expect_refused(args, "W, H <= 65536, W*H <= 8192*8192");
}
