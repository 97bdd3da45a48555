/* The reconnection Jacobian at a vertex at infinity (docs/environment.md, "The Jacobian"):
 * a path x_0 x_1 ... x_{d-1} w ending at the sky, reconnected from the offset's y_{d-1}
 * to the same direction w, has |dT/du| = p^y_{d-1}(w) / p^x_{d-1}(w) (Enhanced Eq. 2 with
 * G = 1 on both sides); for an NEE light vertex J = 1.
 *
 * Finite differences: the numbers u^x = (lobe, u1, u2) at x_1 give w through the path
 * sampler; the offset's numbers u^y are those with which y_1 samples the same w (the lobe
 * number mapped affinely between the lobes' intervals, the direction numbers by inverse
 * sampling, bsdf_lobe_sample_inverse); det(du^y/du^x) by central differences with
 * Richardson extrapolation must equal the J of the shift to 1e-4. The shift code is not
 * called by the differences. Round trip: J(a -> b) J(b -> a) = 1 and F comes back. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/restir/reconnection.h"
#include "restir/restir/reservoir_dump.h"

#ifdef RESTIR_REAL_FLOAT
#define FD_RTOL 1e-2
#else
#define FD_RTOL 1e-4
#endif

/* The offset's (u1', u2') for the direction sampled at vx with (lobe, u1, u2); 0 if none. */
static int offset_numbers(const path_vertex *vx, const path_vertex *vy, int lobe, double u1, double u2, double *o1,
                          double *o2)
{
    bsdf_sample_record r;
    vec3 w;
    vec2 u;
    if (!bsdf_lobe_sample(&vx->b, lobe, vx->wo_local, v2((real)u1, (real)u2), &r)) return 0;
    w = shading_frame_to_world(&vx->frame, r.wi);
    if (!bsdf_lobe_sample_inverse(&vy->b, lobe, vy->wo_local, shading_frame_to_local(&vy->frame, w), &u)) return 0;
    *o1 = u.x;
    *o2 = u.y;
    return 1;
}

/* det of the 2 x 2 map (u1, u2) -> (u1', u2') by central differences at step h. */
static int fd_det(const path_vertex *vx, const path_vertex *vy, int lobe, double u1, double u2, double h, double *det)
{
    double a[2][2], p1, p2, m1, m2;
    if (!offset_numbers(vx, vy, lobe, u1 + h, u2, &p1, &p2) || !offset_numbers(vx, vy, lobe, u1 - h, u2, &m1, &m2))
        return 0;
    a[0][0] = (p1 - m1) / (2 * h);
    a[1][0] = (p2 - m2) / (2 * h);
    if (!offset_numbers(vx, vy, lobe, u1, u2 + h, &p1, &p2) || !offset_numbers(vx, vy, lobe, u1, u2 - h, &m1, &m2))
        return 0;
    a[0][1] = (p1 - m1) / (2 * h);
    a[1][1] = (p2 - m2) / (2 * h);
    *det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    return 1;
}

typedef struct {
    scene s;
    light_set lights;
    restir_context c;
} sky_bench;

static int bench_open(sky_bench *b, int shift)
{
    if (rt_load_scene_lights("scenes/courtyard.scene", 32, &b->s, &b->lights)) return -1;
    rt_context(&b->c, &b->s, &b->lights, shift);
    return 0;
}

static void bench_close(sky_bench *b)
{
    lights_free(&b->lights);
    scene_free(&b->s);
}

/* Counts of the cases checked, for the test's own sanity. */
typedef struct {
    int bsdf, nee, round_trips, kinks, grazing, dumped;
    double worst_fd, worst_trip;
} fd_counts;

/* The vertex at infinity survives the reservoir dump record (format version 1, rc_flags bit
 * 1), and path_sample_check rejects the bit on a vertex that is not the last. */
static void dump_round_trip(const path_sample *x, fd_counts *n)
{
    unsigned char buf[4096];
    reservoir r, back;
    real pss[PATH_MAX_PSS];
    path_sample bad;
    reservoir_init(&r);
    r.y = *x;
    r.W = 1;
    r.confidence = 1;
    if (reservoir_record_size(0) > sizeof buf) return;
    reservoir_record_encode(&r, 0, buf);
    reservoir_record_decode(buf, 0, &back, pss);
    CHECK(path_sample_check(&back.y, "decoded", NULL) == 0);
    CHECK(back.y.rc_flags == x->rc_flags && back.y.rc_triangle == LIGHT_TRIANGLE_DISTANT);
    CHECK(back.y.rc_position.x == x->rc_position.x && back.y.rc_position.y == x->rc_position.y &&
          back.y.rc_position.z == x->rc_position.z && back.y.rc_geom == 1 && back.y.rc_pdf == 1);
    bad = *x;
    bad.length = 3; /* k = 2 < d: an infinite vertex in the middle */
    bad.lobe[2] = 0;
    CHECK(path_sample_check(&bad, "bad", NULL) != 0);
    n->dumped++;
}

/* Sample `sample` of pixel (ax, ay), length 2, technique `tech`, shifted to (bx, by). */
static void one_case(sky_bench *b, int ax, int ay, int bx, int by, uint32_t sample, int tech, fd_counts *n)
{
    path_vertex xa, xb;
    path_sample x, y, back;
    real J, Jb;
    rgb fx;
    if (!rt_primary_vertex(&b->s, ax, ay, &xa) || !rt_primary_vertex(&b->s, bx, by, &xb)) return;
    path_sample_begin(&x, 7u, (uint32_t)(ay * b->s.width + ax), sample);
    x.length = 2;
    x.technique = (uint8_t)tech;
    if (path_record(&b->c, &xa, &x) != SHIFT_OK) return;
    if (!(x.rc_flags & PATH_RC_FLAG_DISTANT) || x.rc_k != 2 || (x.rc_flags & PATH_RC_FLAG_UNSHIFTABLE)) return;
    CHECK(path_sample_check(&x, "recorded", NULL) == 0);
    if (n->dumped < 8) dump_round_trip(&x, n);
    if (shift_path(&b->c, &xb, &x, &y, &J, NULL) != SHIFT_OK) return;
    /* the round trip: J(a -> b) J(b -> a) = 1, and the path comes back */
    if (shift_path(&b->c, &xa, &y, &back, &Jb, NULL) == SHIFT_OK) {
        double trip = fabs((double)J * (double)Jb - 1);
        fx = x.F;
        CHECKF(trip < 1e-5, "round trip J J' - 1 = %g (J %g, J' %g)", trip, (double)J, (double)Jb);
        CHECKF(fabs(back.target - x.target) <= 1e-5 * x.target, "round trip F: %g vs %g", (double)back.target,
               (double)luminance(fx));
        if (trip > n->worst_trip) n->worst_trip = trip;
        n->round_trips++;
    }
    if (tech == PATH_TECH_NEE) { /* the light numbers map to themselves */
        CHECKF(fabs(J - 1) < 1e-6, "NEE light vertex at infinity: J = %.9g, want 1", (double)J);
        n->nee++;
        return;
    }
    {
        real u[3], lo_x, hi_x, lo_y, hi_y;
        int lobe = x.lobe[1];
        double d1, d2, fd, rel;
        path_bsdf_numbers(&x, 1, u);
        bsdf_lobe_interval(&xa.b, xa.wo_local, lobe, &lo_x, &hi_x);
        bsdf_lobe_interval(&xb.b, xb.wo_local, lobe, &lo_y, &hi_y);
        if (!(u[1] > 0.01 && u[1] < 0.99 && u[2] > 0.01 && u[2] < 0.99)) return;
        /* well conditioned only: at grazing angles, or far in a glossy lobe's tail (J < 0.01),
         * the float storage of w (2^-24) moves the pdfs by more than the tolerance (the
         * analytic J sees the stored w, the differences the exact one) */
        if (!(fabs(shading_frame_to_local(&xa.frame, light_distant_direction(x.rc_position)).z) > 0.05 &&
              fabs(shading_frame_to_local(&xb.frame, light_distant_direction(x.rc_position)).z) > 0.05 && J > 0.01 &&
              J < 100)) {
            n->grazing++;
            return;
        }
        if (!fd_det(&xa, &xb, lobe, u[1], u[2], 1e-3, &d1) || !fd_det(&xa, &xb, lobe, u[1], u[2], 5e-4, &d2)) return;
        /* the warps are piecewise smooth (the concentric disk's diagonals): a difference across
         * a kink is no derivative, seen as the two steps disagreeing; such points are skipped */
        if (fabs(d1 - d2) > 1e-3 * fabs(d2)) {
            n->kinks++;
            return;
        }
        fd = (4 * d2 - d1) / 3 * (double)((hi_y - lo_y) / (hi_x - lo_x)); /* Richardson, times the lobe map */
        rel = fabs(fd - (double)J) / fabs(fd);
        test_margin(rel / FD_RTOL * 4);
        CHECKF(rel < FD_RTOL, "directional Jacobian: shift %.8g, finite differences %.8g (relative %.2g), lobe %d, "
                              "pixels (%d,%d) -> (%d,%d)", (double)J, fd, rel, lobe, ax, ay, bx, by);
        if (rel > n->worst_fd) n->worst_fd = rel;
        n->bsdf++;
    }
}

TEST(jacobian_sky_directional_fd_and_round_trip)
{
    static const int shifts[] = {RESTIR_SHIFT_RECONNECTION, RESTIR_SHIFT_HYBRID};
    int si;
    for (si = 0; si < 2 && !test_has_failed(); ++si) {
        sky_bench b;
        fd_counts n;
        int ax, ay;
        uint32_t sample;
        memset(&n, 0, sizeof n);
        if (bench_open(&b, shifts[si])) return;
        for (ay = 2; ay < 30 && !test_has_failed(); ay += 3)
            for (ax = 2; ax < 30 && !test_has_failed(); ax += 3)
                for (sample = 0; sample < 6; ++sample) {
                    int bx = ax + (int)(sample % 3) - 1, by = ay + 2 - (int)(sample % 2) * 3;
                    one_case(&b, ax, ay, bx, by, 1000u * (uint32_t)test_seed() + sample, PATH_TECH_BSDF, &n);
                    one_case(&b, ax, ay, bx, by, 1000u * (uint32_t)test_seed() + sample, PATH_TECH_NEE, &n);
                }
        if (getenv("RESTIR_TEST_VERBOSE"))
            fprintf(stderr, "  shift %s: %d BSDF cases (worst FD relative %.2g; %d at kinks, %d grazing skipped), %d NEE, %d round "
                            "trips (worst %.2g)\n",
                    restir_shift_names[shifts[si]], n.bsdf, n.worst_fd, n.kinks, n.grazing, n.nee, n.round_trips, n.worst_trip);
        CHECKF(n.bsdf >= 50 && n.nee >= 50 && n.round_trips >= 100 && n.dumped == 8,
               "too few cases: %d BSDF, %d NEE, %d round trips, %d dumped", n.bsdf, n.nee, n.round_trips, n.dumped);
        bench_close(&b);
    }
}
