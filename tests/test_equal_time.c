/* The equal-time harness (include/restir/bench/equal_time.h, docs/equal-time.md): the record
 * schedule and running mean with a synthetic method, time-to-target interpolation and
 * extrapolation on exact power laws, and the path tracer on the Cornell box (errors fall
 * with time, CSV/table/SVG written, `restir plot` reads the CSV). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "restir/bench/equal_time.h"
#include "restir/metrics/plot.h"
#include "test.h"
#include "restir/metrics/plot_csv.h"

static char out[8192];

/* A synthetic method on a constant reference of 1: unit 0 adds 1.5, every other unit 1,
 * so the mean after n units is 1 + 0.5/n; it logs the ranges it was asked for. */
typedef struct {
    uint32_t first[64], count[64];
    int calls, fail_at;
} fake_ctx;

static int fake_units(void *ctx, uint32_t first, uint32_t count, int width, int height, double *sum, rerror *e)
{
    fake_ctx *f = ctx;
    long i;
    if (f->calls == f->fail_at) return rerror_set(e, "fake failure");
    f->first[f->calls] = first;
    f->count[f->calls] = count;
    f->calls++;
    for (i = 0; i < 3L * width * height; ++i) sum[i] += count + (first == 0 ? 0.5 : 0);
    return 0;
}

static void constant_image(image *img, int w, int h, float v)
{
    long i;
    rerror e;
    image_alloc(img, w, h, &e);
    for (i = 0; i < 3L * w * h; ++i) img->px[i] = v;
}

TEST(equal_time_schedule_and_running_mean)
{
    image ref;
    fake_ctx f;
    equal_time_method m;
    equal_time_options o;
    equal_time_curve c;
    rerror e;
    const uint32_t expected_units[] = {1, 2, 4, 8, 16, 20};
    int i;
    constant_image(&ref, 5, 4, 1);
    memset(&f, 0, sizeof f);
    f.fail_at = -1;
    m.name = "fake";
    m.render = fake_units;
    m.ctx = &f;
    equal_time_options_default(&o);
    o.max_units = 20;
    CHECKF(equal_time_run(&m, &ref, &o, &c, &e) == 0, "%s", e.msg);
    CHECK(c.count == 6 && f.calls == 6 && !strcmp(c.name, "fake"));
    for (i = 0; i < 6; ++i) {
        CHECK(c.points[i].units == expected_units[i]);
        CHECK(f.first[i] == (i ? expected_units[i - 1] : 0) && f.first[i] + f.count[i] == expected_units[i]);
        CHECK(i == 0 || c.points[i].seconds >= c.points[i - 1].seconds);
        /* Relative error 0.5/n of the luminance against (1 + eps), eps = 0.01 * 1. */
        CHECK_NEAR(c.points[i].mape, 0.5 / expected_units[i] / 1.01, 1e-6);
        CHECK_NEAR(c.points[i].relmse, pow(0.5 / expected_units[i] / 1.01, 2), 1e-6);
    }
    equal_time_curve_free(&c);
    /* Growth 3 from 2 units. */
    memset(&f, 0, sizeof f);
    f.fail_at = -1;
    o.first_units = 2;
    o.growth = 3;
    o.max_units = 50;
    CHECKF(equal_time_run(&m, &ref, &o, &c, &e) == 0, "%s", e.msg);
    CHECK(c.count == 4 && c.points[0].units == 2 && c.points[1].units == 6 && c.points[2].units == 18 &&
          c.points[3].units == 50);
    equal_time_curve_free(&c);
    /* Failures propagate; options are checked. */
    memset(&f, 0, sizeof f);
    f.fail_at = 2;
    CHECK(equal_time_run(&m, &ref, &o, &c, &e) != 0 && strstr(e.msg, "fake failure") && c.points == NULL);
    o.max_units = 0;
    CHECK(equal_time_run(&m, &ref, &o, &c, &e) != 0);
    o.max_units = 10;
    o.growth = 1;
    CHECK(equal_time_run(&m, &ref, &o, &c, &e) != 0);
    image_free(&ref);
}

/* A curve with mape = t^-1/2 and relmse = 1/t at t = 1, 2, 4, 8 s. */
static equal_time_curve power_law_curve(equal_time_point *p)
{
    equal_time_curve c;
    int i;
    for (i = 0; i < 4; ++i) {
        p[i].units = 1u << i;
        p[i].seconds = (double)(1 << i);
        p[i].mape = 1 / sqrt(p[i].seconds);
        p[i].relmse = 1 / p[i].seconds;
    }
    snprintf(c.name, sizeof c.name, "power law");
    c.points = p;
    c.count = 4;
    return c;
}

TEST(equal_time_time_to_reach_and_fit)
{
    equal_time_point p[4];
    equal_time_curve c = power_law_curve(p);
    double t, slope, intercept;
    rerror e;
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_MAPE, 0.5, &t) == EQUAL_TIME_INTERPOLATED && t == 4);
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_MAPE, 0.6, &t) == EQUAL_TIME_INTERPOLATED);
    CHECK_NEAR(t, 1 / 0.36, 1e-12);
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_RELMSE, 0.3, &t) == EQUAL_TIME_INTERPOLATED);
    CHECK_NEAR(t, 1 / 0.3, 1e-12);
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_MAPE, 0.1, &t) == EQUAL_TIME_EXTRAPOLATED);
    CHECK_NEAR(t, 100, 1e-9);
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_MAPE, 2, &t) == EQUAL_TIME_EXTRAPOLATED);
    CHECK_NEAR(t, 0.25, 1e-12);
    CHECK(equal_time_fit(&c, EQUAL_TIME_MAPE, &slope, &intercept, &e) == 0);
    CHECK_NEAR(slope, -0.5, 1e-12);
    CHECK_NEAR(intercept, 0, 1e-12);
    /* A noisy curve: the first crossing counts. */
    p[2].mape = 0.8;
    p[1].mape = 0.6;
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_MAPE, 0.62, &t) == EQUAL_TIME_INTERPOLATED);
    CHECK(t > 1 && t < 2);
    /* No usable fit: one point, or errors that grow. */
    c.count = 1;
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_MAPE, 0.1, &t) == EQUAL_TIME_UNREACHABLE && isnan(t));
    c.count = 4;
    p[0].relmse = 0.1, p[1].relmse = 0.2, p[2].relmse = 0.4, p[3].relmse = 0.8;
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_RELMSE, 0.01, &t) == EQUAL_TIME_UNREACHABLE);
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_RELMSE, 0, &t) == EQUAL_TIME_UNREACHABLE);
}

/* The path tracer on a 20 x 20 Cornell box against a 256-spp reference from another
 * seed: 1, 2, ..., 64 spp; the error falls about like 1/sqrt(time). */
TEST(equal_time_pt_cornell)
{
    scene s;
    rerror e;
    pt_options o;
    pt_result ref;
    equal_time_pt_ctx ctx;
    equal_time_method m;
    equal_time_options eo;
    equal_time_curve c;
    plot_table table;
    double slope, intercept, t;
    const char *csv = test_tmp_path("equal_time/pt.csv"), *svg = test_tmp_path("equal_time/pt.svg");
    const char *all = test_tmp_path("equal_time/all.csv"), *svg2 = test_tmp_path("equal_time/plot.svg");
    int i;
    CHECKF(scene_load(&s, "scenes/cornell.scene", &e) == 0 && scene_prepare(&s, &e) == 0, "%s", e.msg);
    s.width = s.height = 20;
    pt_options_default(&o);
    o.threads = 2;
    o.quiet = 1;
    o.seed = test_seed() + 1000;
    o.spp = 256;
    CHECKF(pt_render(&s, &o, &ref, &e) == 0, "%s", e.msg);
    o.seed = test_seed();
    equal_time_pt_method(&ctx, &s, &o, "PT", &m);
    equal_time_options_default(&eo);
    eo.max_units = 64;
    CHECKF(equal_time_run(&m, &ref.mean, &eo, &c, &e) == 0, "%s", e.msg);
    CHECK(c.count == 7 && c.points[6].units == 64 && c.points[6].seconds > c.points[0].seconds);
    CHECKF(c.points[6].mape < 0.4 * c.points[0].mape, "MAPE %g at 1 spp, %g at 64 spp", c.points[0].mape,
           c.points[6].mape);
    for (i = 1; i < 7; ++i) CHECKF(c.points[i].mape < c.points[i - 1].mape * 1.05, "MAPE rises at point %d", i);
    CHECK(equal_time_fit(&c, EQUAL_TIME_MAPE, &slope, &intercept, &e) == 0);
    CHECKF(slope < -0.3 && slope > -0.8, "MAPE ~ time^%g", slope);
    CHECK(equal_time_time_to_reach(&c, EQUAL_TIME_MAPE, sqrt(c.points[3].mape * c.points[4].mape), &t) ==
          EQUAL_TIME_INTERPOLATED);
    CHECK(t >= c.points[3].seconds && t <= c.points[4].seconds);
    /* Outputs. */
    CHECKF(equal_time_write_csv(csv, &c, 1, EQUAL_TIME_MAPE, &e) == 0, "%s", e.msg);
    CHECKF(equal_time_write_table(all, &c, 1, &e) == 0, "%s", e.msg);
    CHECKF(equal_time_write_svg(svg, &c, 1, EQUAL_TIME_RELMSE, "PT on Cornell", &e) == 0, "%s", e.msg);
    CHECKF(plot_csv_read(csv, &table, &e) == 0, "%s", e.msg);
    CHECK(table.rows == 7 && table.columns == 2 && !strcmp(table.names[0], "seconds") && !strcmp(table.names[1], "PT"));
    CHECK_NEAR(table.values[7 + 6], c.points[6].mape, 1e-8 * c.points[6].mape);
    plot_table_free(&table);
    CHECK(test_file_exists(svg) && test_file_exists(all));
    CHECKF(test_cli(out, sizeof out, "plot %s -o %s", csv, svg2) == 0, "%s", out);
    CHECK(test_file_exists(svg2));
    /* A reference of another size is refused. */
    equal_time_curve_free(&c);
    s.width = 21;
    CHECK(equal_time_run(&m, &ref.mean, &eo, &c, &e) != 0 && strstr(e.msg, "reference") && c.points == NULL);
    pt_result_free(&ref);
    scene_free(&s);
}
