/* Spatial neighbour selection (include/restir/restir/neighbors.h, docs/spatial-reuse.md):
 * uniformity over the disk (rings x sectors of the continuous points, and the exact
 * per-pixel probabilities of the rounded offsets), the low-discrepancy spread of the r2
 * pattern, determinism, never the centre or outside, and the symmetry of the
 * geometric rejection on a real G-buffer. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/render/camera.h"
#include "restir/restir/neighbors.h"
#include "pt_util.h"
#include "test.h"

#define RINGS 8
#define SECTORS 16

/* The key of the t-th test draw: a fresh pixel for every draw, sample from the seed. */
static rng_key draw_key(uint32_t t, uint32_t salt) { return rng_key_make(test_seed() * 2654435761u + salt, t, 7); }

/* Bins a unit-disk point into equal-area cells: ring floor(RINGS r^2), sector by angle. */
static int disk_cell(double x, double y)
{
    double r2 = x * x + y * y, a = atan2(y, x) / (2 * 3.14159265358979323846);
    int ring = (int)(r2 * RINGS), sector = (int)((a < 0 ? a + 1 : a) * SECTORS);
    if (ring >= RINGS) ring = RINGS - 1;
    if (sector >= SECTORS) sector = SECTORS - 1;
    return ring * SECTORS + sector;
}

/* p-value of the rings x sectors chi-square test of n points; broken = 1 replaces the
 * concentric map by the naive polar map (r = u) that crowds the centre. One point per
 * key (neighbour index t mod 6), so the test sees each pattern's marginal law. */
static double disk_uniformity_p(enum neighbor_pattern pattern, int n, int broken)
{
    double observed[RINGS * SECTORS], expected[RINGS * SECTORS];
    int t, c;
    for (c = 0; c < RINGS * SECTORS; ++c) {
        observed[c] = 0;
        expected[c] = (double)n / (RINGS * SECTORS);
    }
    for (t = 0; t < n; ++t) {
        rng_key key = draw_key((uint32_t)t, 1);
        double x, y;
        if (broken) {
            double u = rng_uniform_double(rng_key_at(key, RNG_NEIGHBOR, 0, 0));
            double v = rng_uniform_double(rng_key_at(key, RNG_NEIGHBOR, 0, 1));
            x = u * cos(2 * 3.14159265358979323846 * v);
            y = u * sin(2 * 3.14159265358979323846 * v);
        } else {
            neighbor_disk_point(pattern, key, t % 6, &x, &y);
        }
        observed[disk_cell(x, y)] += 1;
    }
    return chi2_test(observed, expected, RINGS * SECTORS, NULL, NULL);
}

TEST(neighbors_disk_points_uniform_rings_sectors)
{
    double p_uniform = disk_uniformity_p(NEIGHBOR_UNIFORM, 64000, 0);
    double p_r2 = disk_uniformity_p(NEIGHBOR_R2, 64000, 0);
    double p_broken = disk_uniformity_p(NEIGHBOR_UNIFORM, 64000, 1);
    CHECKF(p_uniform > 1e-4, "uniform pattern: p = %g", p_uniform);
    CHECKF(p_r2 > 1e-4, "r2 pattern: p = %g", p_r2);
    CHECKF(p_broken < 1e-9, "the naive polar map should be rejected: p = %g", p_broken);
}

/* Area of the rectangle [x0, x1] x [y0, y1] inside the disk of radius r about the origin
 * (midpoint rule over x of the clipped chord; relative error ~1e-7 here). */
static double rect_disk_area(double x0, double x1, double y0, double y1, double r)
{
    const int steps = 2000;
    double sum = 0, h = (x1 - x0) / steps;
    int i;
    for (i = 0; i < steps; ++i) {
        double x = x0 + (i + 0.5) * h, half = r * r - x * x > 0 ? sqrt(r * r - x * x) : 0;
        double lo = fmax(y0, -half), hi = fmin(y1, half);
        if (hi > lo) sum += hi - lo;
    }
    return sum * h;
}

/* The rounded offsets: P(offset = (a, b)) = area of the pixel cell [a-1/2, a+1/2) x
 * [b-1/2, b+1/2) inside the disk of radius R, over pi R^2. Chi-square over all cells. */
static double offset_distribution_p(enum neighbor_pattern pattern, double radius, int n)
{
    neighbor_options o;
    int span = (int)ceil(radius) + 1, side = 2 * span + 1, t, a, b;
    double *observed = calloc((size_t)side * side, sizeof *observed);
    double *expected = calloc((size_t)side * side, sizeof *expected), p;
    neighbor_options_default(&o);
    o.pattern = pattern;
    o.radius = radius;
    for (b = -span; b <= span; ++b)
        for (a = -span; a <= span; ++a)
            expected[(b + span) * side + a + span] =
                n * rect_disk_area(a - 0.5, a + 0.5, b - 0.5, b + 0.5, radius) / (3.14159265358979323846 * radius * radius);
    for (t = 0; t < n; ++t) {
        int dx, dy;
        neighbor_offset(&o, draw_key((uint32_t)t, 2), t % 6, &dx, &dy);
        if (abs(dx) > span || abs(dy) > span) {
            p = 0;
            goto done;
        }
        observed[(dy + span) * side + dx + span] += 1;
    }
    p = chi2_test(observed, expected, (size_t)side * side, NULL, NULL);
done:
    free(observed);
    free(expected);
    return p;
}

TEST(neighbors_offsets_follow_pixel_overlap_areas)
{
    const double radii[] = {10, 3.5};
    int i;
    for (i = 0; i < 2; ++i) {
        double pu = offset_distribution_p(NEIGHBOR_UNIFORM, radii[i], 60000);
        double pr = offset_distribution_p(NEIGHBOR_R2, radii[i], 60000);
        CHECKF(pu > 1e-4 && pr > 1e-4, "R = %g: p uniform %g, r2 %g", radii[i], pu, pr);
    }
}

/* The n points of one pixel: mean (over pixels) of the smallest pairwise distance. */
static double mean_min_distance(enum neighbor_pattern pattern, int n, int pixels)
{
    double total = 0;
    int t, i, j;
    for (t = 0; t < pixels; ++t) {
        double x[16], y[16], best = 1e9;
        for (i = 0; i < n; ++i) neighbor_disk_point(pattern, draw_key((uint32_t)t, 3), i, &x[i], &y[i]);
        for (i = 0; i < n; ++i)
            for (j = i + 1; j < n; ++j) best = fmin(best, hypot(x[i] - x[j], y[i] - y[j]));
        total += best;
    }
    return total / pixels;
}

/* The low-discrepancy pattern spreads the 6 neighbours of a pixel out: the closest pair
 * is much farther apart than for independent points. */
TEST(neighbors_r2_spreads_the_points_of_a_pixel)
{
    double uniform = mean_min_distance(NEIGHBOR_UNIFORM, 6, 4000), r2 = mean_min_distance(NEIGHBOR_R2, 6, 4000);
    CHECKF(r2 > 1.5 * uniform, "mean closest pair: r2 %g, uniform %g", r2, uniform);
}

/* A G-buffer of w x h texels, all hits with normal +z seen from -z at depth 1 (so the
 * geometric test accepts every pair). */
static gbuffer flat_gbuffer(int w, int h)
{
    gbuffer g;
    int i;
    g.width = w;
    g.height = h;
    g.texels = calloc((size_t)w * h, sizeof *g.texels);
    for (i = 0; i < w * h; ++i) {
        g.texels[i].valid = 1;
        g.texels[i].hit.ng = v3f(0, 0, -1);
        g.texels[i].view_dir = v3f(0, 0, 1);
        g.texels[i].depth = 1;
    }
    return g;
}

TEST(neighbors_select_never_centre_outside_or_repeated)
{
    const enum neighbor_pattern patterns[] = {NEIGHBOR_UNIFORM, NEIGHBOR_R2, NEIGHBOR_BOX};
    gbuffer g = flat_gbuffer(37, 23);
    uint32_t out[400];
    rerror e;
    int p;
    for (p = 0; p < 3; ++p) {
        neighbor_options o;
        neighbor_stats stats;
        int x, y, pass;
        neighbor_options_default(&o);
        o.pattern = patterns[p];
        o.count = 12;
        o.radius = p == 2 ? 3 : 6.5;
        CHECK(neighbor_options_validate(&o, &e) == 0);
        memset(&stats, 0, sizeof stats);
        for (pass = 0; pass < 3; ++pass)
            for (y = 0; y < g.height; ++y)
                for (x = 0; x < g.width; ++x) {
                    int n = neighbor_select(&o, &g, test_seed(), neighbor_sample_index(2, 3, (uint32_t)pass), x, y, out,
                                            400, &stats, &e), i, j;
                    CHECKF(n >= 0 && n <= neighbor_candidate_count(&o), "%s", e.msg);
                    for (i = 0; i < n; ++i) {
                        int nx = (int)(out[i] % (uint32_t)g.width), ny = (int)(out[i] / (uint32_t)g.width);
                        CHECK(out[i] < (uint32_t)(g.width * g.height));
                        CHECKF(nx != x || ny != y, "pattern %d: the centre (%d, %d) was selected", p, x, y);
                        CHECK(hypot(nx - x, ny - y) <= (p == 2 ? 3 * sqrt(2.0) : o.radius + 0.7072));
                        for (j = 0; j < i; ++j) CHECK(out[j] != out[i]);
                    }
                }
        {
            uint64_t sum = 0;
            int v;
            for (v = 0; v < NEIGHBOR_VERDICT_COUNT; ++v) sum += stats.verdict[v];
            CHECK(sum == stats.candidates);
            CHECK(stats.verdict[NEIGHBOR_OUTSIDE] > 0 && stats.verdict[NEIGHBOR_ACCEPTED] > 0);
            CHECK(stats.verdict[NEIGHBOR_NORMAL] == 0 && stats.verdict[NEIGHBOR_DEPTH] == 0);
            if (p == 2) CHECK(stats.verdict[NEIGHBOR_CENTRE] == 0 && stats.verdict[NEIGHBOR_REPEAT] == 0);
            else CHECKF(stats.verdict[NEIGHBOR_CENTRE] > 0 && (p == 1 || stats.verdict[NEIGHBOR_REPEAT] > 0),
                        "pattern %d: %llu centre, %llu repeats", p, (unsigned long long)stats.verdict[NEIGHBOR_CENTRE],
                        (unsigned long long)stats.verdict[NEIGHBOR_REPEAT]);
        }
    }
    /* Too little room is an error, not an overflow. */
    {
        neighbor_options o;
        neighbor_options_default(&o);
        CHECK(neighbor_select(&o, &g, 1, 0, 3, 3, out, 5, NULL, &e) < 0);
    }
    free(g.texels);
}

TEST(neighbors_deterministic_and_keyed)
{
    neighbor_options o;
    int k, same_sample = 1, differs_sample = 0, differs_seed = 0, dx, dy;
    neighbor_options_default(&o);
    o.count = 8;
    for (k = 0; k < 2; ++k) {
        int i;
        o.pattern = k ? NEIGHBOR_R2 : NEIGHBOR_UNIFORM;
        for (i = 0; i < o.count; ++i) {
            int ax, ay, bx, by, cx, cy, d2x, d2y;
            rng_key key = rng_key_make(test_seed(), 1234, 5);
            neighbor_offset(&o, key, i, &ax, &ay);
            neighbor_offset(&o, key, i, &bx, &by);
            same_sample &= ax == bx && ay == by;
            key.sample = 6;
            neighbor_offset(&o, key, i, &cx, &cy);
            differs_sample |= ax != cx || ay != cy;
            key.sample = 5;
            key.seed += 1;
            neighbor_offset(&o, key, i, &d2x, &d2y);
            differs_seed |= ax != d2x || ay != d2y;
        }
    }
    CHECK(same_sample && differs_sample && differs_seed);
    /* The box pattern is the window in row-major order without its centre. */
    o.pattern = NEIGHBOR_BOX;
    o.radius = 2.9;
    CHECK(neighbor_candidate_count(&o) == 24);
    for (k = 0; k < 24; ++k) {
        int cell = k < 12 ? k : k + 1;
        neighbor_offset(&o, rng_key_make(0, 0, 0), k, &dx, &dy);
        CHECK(dx == cell % 5 - 2 && dy == cell / 5 - 2);
    }
    CHECK(neighbor_sample_index(3, 3, 2) == 11);
}

/* The authors' rule as the notes record it: the depth tolerance scales with the
 * centre's depth only (|d_c - d_n| < 0.1 d_c). Used to show the symmetry test can fail. */
static int centre_relative_depth_accepts(const gbuffer_texel *c, const gbuffer_texel *n)
{
    return c->valid && n->valid && fabsf(c->depth - n->depth) < 0.1f * c->depth;
}

/* Symmetry of the geometric test on every pair within 6 pixels of a real G-buffer
 * (the Cornell box: walls at grazing angles, block edges, background misses), with the
 * default and with tight thresholds; the centre-relative rule is not symmetric there. */
TEST(neighbors_rejection_symmetric_on_cornell)
{
    scene s;
    camera c;
    gbuffer g;
    rerror e;
    neighbor_options o;
    long pairs = 0, asymmetric = 0, rejected = 0, broken_asymmetric = 0;
    int variant, x, y, dx, dy;
    CHECKF(scene_load(&s, "scenes/cornell.scene", &e) == 0 && scene_prepare(&s, &e) == 0, "%s", e.msg);
    camera_init(&c, scene_camera_at(&s, 0), 48, 48);
    CHECKF(gbuffer_build(&g, &s, &c, test_seed(), 0, 1, 1, &e) == 0, "%s", e.msg);
    for (variant = 0; variant < 2; ++variant) {
        neighbor_options_default(&o);
        if (variant) {
            o.min_normal_cos = 0.99f;
            o.max_relative_depth = 0.01f;
        }
        for (y = 0; y < g.height; ++y)
            for (x = 0; x < g.width; ++x)
                for (dy = -6; dy <= 6; ++dy)
                    for (dx = -6; dx <= 6; ++dx) {
                        const gbuffer_texel *a = gbuffer_at(&g, x, y), *b;
                        enum neighbor_verdict ab, ba;
                        if (x + dx < 0 || y + dy < 0 || x + dx >= g.width || y + dy >= g.height) continue;
                        b = gbuffer_at(&g, x + dx, y + dy);
                        ab = neighbor_geometry_test(&o, a, b);
                        ba = neighbor_geometry_test(&o, b, a);
                        pairs++;
                        asymmetric += ab != ba;
                        rejected += ab != NEIGHBOR_ACCEPTED;
                        broken_asymmetric += centre_relative_depth_accepts(a, b) != centre_relative_depth_accepts(b, a);
                    }
    }
    CHECKF(asymmetric == 0, "%ld of %ld pairs asymmetric", asymmetric, pairs);
    CHECKF(rejected > pairs / 20, "only %ld of %ld pairs rejected: the test data is too easy", rejected, pairs);
    CHECKF(broken_asymmetric > 0, "the centre-relative depth rule should be asymmetric somewhere");
    gbuffer_free(&g);
    scene_free(&s);
}

/* Each threshold at its boundary: normals at 60 degrees (cos 0.5) and a 10 % depth step
 * measured against the nearer depth; turned normals (the back of a face) count as the
 * side the camera sees. */
TEST(neighbors_thresholds)
{
    neighbor_options o;
    gbuffer_texel a, b;
    memset(&a, 0, sizeof a);
    neighbor_options_default(&o);
    a.valid = 1;
    a.hit.ng = v3f(0, 0, -1);
    a.view_dir = v3f(0, 0, 1);
    a.depth = 10;
    b = a;
    b.hit.ng = v3f(0, 0, 1); /* the same plane seen from behind its front face */
    CHECK(neighbor_geometry_test(&o, &a, &b) == NEIGHBOR_ACCEPTED);
    b.hit.ng = v3f(0.8660254f, 0, -0.49f);
    CHECK(neighbor_geometry_test(&o, &a, &b) == NEIGHBOR_NORMAL);
    b.hit.ng = v3f(0.8660254f, 0, -0.51f);
    CHECK(neighbor_geometry_test(&o, &a, &b) == NEIGHBOR_ACCEPTED);
    b.depth = 11.05f; /* 1.05 > 0.1 * 10 */
    CHECK(neighbor_geometry_test(&o, &a, &b) == NEIGHBOR_DEPTH && neighbor_geometry_test(&o, &b, &a) == NEIGHBOR_DEPTH);
    b.depth = 10.95f;
    CHECK(neighbor_geometry_test(&o, &a, &b) == NEIGHBOR_ACCEPTED);
    o.reject_geometry = 0;
    b.depth = 100;
    CHECK(neighbor_geometry_test(&o, &a, &b) == NEIGHBOR_ACCEPTED);
    b.valid = 0;
    CHECK(neighbor_geometry_test(&o, &a, &b) == NEIGHBOR_NO_HIT && neighbor_geometry_test(&o, &b, &a) == NEIGHBOR_NO_HIT);
}

TEST(neighbors_options_validated)
{
    neighbor_options o;
    rerror e;
    neighbor_options_default(&o);
    CHECK(neighbor_options_validate(&o, &e) == 0 && o.pattern == NEIGHBOR_R2 && o.count == 6 && o.radius == 10);
    o.count = 0;
    CHECK(neighbor_options_validate(&o, &e) != 0);
    o.count = 256;
    CHECK(neighbor_options_validate(&o, &e) != 0);
    o.count = 6;
    o.radius = 0;
    CHECK(neighbor_options_validate(&o, &e) != 0);
    o.radius = NAN;
    CHECK(neighbor_options_validate(&o, &e) != 0);
    o.pattern = NEIGHBOR_BOX;
    o.radius = 0.5;
    CHECK(neighbor_options_validate(&o, &e) != 0);
    o.radius = 65;
    CHECK(neighbor_options_validate(&o, &e) != 0);
    o.radius = 64.9;
    CHECK(neighbor_options_validate(&o, &e) == 0);
    o.max_relative_depth = -1;
    CHECK(neighbor_options_validate(&o, &e) != 0);
    CHECK(!strcmp(neighbor_pattern_names[NEIGHBOR_R2], "r2") && !strcmp(neighbor_verdict_names[NEIGHBOR_DEPTH], "depth"));
}
