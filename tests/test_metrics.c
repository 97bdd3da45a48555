/* Metrics, FLIP, error maps and `restir compare`. Expected values are computed by hand
 * from the formulas of docs/metrics.md (written out next to each check). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/colormap.h"
#include "restir/metrics/error_map.h"
#include "restir/metrics/flip.h"
#include "restir/metrics/metrics.h"
#include "restir/core/rng.h"
#include "test.h"
#include "restir/core/pfm.h"

static void set_px(image *img, int x, int y, float r, float g, float b)
{
    float *p = image_pixel(img, x, y);
    p[0] = r;
    p[1] = g;
    p[2] = b;
}

static void fill(image *img, float r, float g, float b)
{
    int x, y;
    for (y = 0; y < img->height; ++y)
        for (x = 0; x < img->width; ++x) set_px(img, x, y, r, g, b);
}

/* A 2x1 pair small enough to evaluate every formula by hand.
 * ref  = (1,1,1), (3,3,3)        Y = 1, 3; eps = 0.01 * mean Y = 0.02
 * test = (2,1,1), (3,3,0)        Y = 1.2126, 2.7834 */
TEST(metrics_hand_computed)
{
    image t, r;
    rerror e;
    image_metrics m;
    const double eps = 0.02, yt0 = 0.2126 * 2 + 0.7152 + 0.0722, yt1 = (0.2126 + 0.7152) * 3;
    const double eps_s = 0.005 * ((yt0 + yt1) / 2 + 2);
    CHECK(image_alloc(&t, 2, 1, &e) == 0 && image_alloc(&r, 2, 1, &e) == 0);
    set_px(&r, 0, 0, 1, 1, 1);
    set_px(&r, 1, 0, 3, 3, 3);
    set_px(&t, 0, 0, 2, 1, 1);
    set_px(&t, 1, 0, 3, 3, 0);
    CHECKF(metrics_compute(&t, &r, NULL, &m, &e) == 0, "%s", e.msg);
    CHECK(m.pixels == 2);
    CHECK_NEAR(m.eps, eps, 1e-15);
    /* MSE = (1^2 + 3^2) / 6 */
    CHECK_NEAR(m.value[METRIC_MSE], 10.0 / 6.0, 1e-15);
    CHECK_NEAR(m.value[METRIC_RMSE], sqrt(10.0 / 6.0), 1e-15);
    /* relMSE = ((1/(eps+1))^2 + (3/(eps+3))^2) / 6 */
    CHECK_NEAR(m.value[METRIC_RELMSE], (1 / (1.02 * 1.02) + 9 / (3.02 * 3.02)) / 6, 1e-15);
    /* MAPE = (|1.2126 - 1| / (eps + 1) + |2.7834 - 3| / (eps + 3)) / 2 */
    CHECK_NEAR(m.value[METRIC_MAPE], (fabs(yt0 - 1) / 1.02 + fabs(yt1 - 3) / 3.02) / 2, 1e-15);
    /* SMAPE = (|2-1| / (2+1+eps_s) + |0-3| / (0+3+eps_s)) / 6, eps_s = 0.005 (mean Y(t) + mean Y(r)) */
    CHECK_NEAR(m.value[METRIC_SMAPE], (1 / (3 + eps_s) + 3 / (3 + eps_s)) / 6, 1e-15);
    /* one 16x16 tile holds both pixels: |mean Y(t) - mean Y(r)| / (eps + mean Y(r)) */
    CHECK_NEAR(m.value[METRIC_MARB], fabs((yt0 + yt1) / 2 - 2) / (eps + 2), 1e-15);
    CHECK_NEAR(m.value[METRIC_REL_BIAS], (yt0 + yt1 - 4) / 4, 1e-15);
    CHECK(isnan(m.value[METRIC_FLIP_LDR]) && isnan(m.value[METRIC_FLIP_HDR]));
    image_free(&t);
    image_free(&r);
}

/* MARB averages the bias per 16x16 tile, so zero-mean noise inside a tile cancels while
 * MAPE counts it: left tile +-0.2 checkerboard (mean exact), right tile +0.1 offset. */
TEST(metrics_tile_bias_ignores_zero_mean_noise)
{
    image t, r;
    rerror e;
    image_metrics m;
    int x, y;
    CHECK(image_alloc(&t, 32, 16, &e) == 0 && image_alloc(&r, 32, 16, &e) == 0);
    fill(&r, 1, 1, 1);
    for (y = 0; y < 16; ++y)
        for (x = 0; x < 32; ++x) {
            float v = x < 16 ? ((x + y) % 2 ? 1.25f : 0.75f) : 1.125f;
            set_px(&t, x, y, v, v, v);
        }
    CHECK(metrics_compute(&t, &r, NULL, &m, &e) == 0);
    /* eps = 0.01; MAPE = (0.25 + 0.125) / 2 / 1.01, MARB = (0 + 0.125) / 2 / 1.01 */
    CHECK_NEAR(m.value[METRIC_MAPE], 0.375 / 2 / 1.01, 1e-12);
    CHECK_NEAR(m.value[METRIC_MARB], 0.125 / 2 / 1.01, 1e-12);
    CHECK_NEAR(m.value[METRIC_REL_BIAS], 0.0625, 1e-12);
    /* the MARB map holds each tile's value */
    {
        float *map = malloc(sizeof(float) * 32 * 16);
        CHECK(map);
        CHECK(metrics_error_map(METRIC_MARB, &t, &r, NULL, map, &e) == 0);
        CHECK_NEAR(map[0], 0, 1e-12);
        CHECK_NEAR(map[16 * 32 - 1], 0.125 / 1.01, 1e-6);
        free(map);
    }
    image_free(&t);
    image_free(&r);
}

static void noisy_copy(const image *src, image *dst, double amplitude, uint32_t stream_seed)
{
    int x, y, c;
    for (y = 0; y < src->height; ++y)
        for (x = 0; x < src->width; ++x)
            for (c = 0; c < 3; ++c) {
                rng_key k = rng_key_make(test_seed() ^ stream_seed, (uint32_t)(y * src->width + x), 0);
                double u = rng_uniform_double(rng_key_at(k, RNG_TEST, 0, (uint32_t)c));
                image_pixel(dst, x, y)[c] = (float)(image_pixel(src, x, y)[c] + amplitude * (2 * u - 1));
            }
}

/* A structured test scene: gradient, a bar, a bright spot (values up to 4: HDR). */
static void scene_pattern(image *img)
{
    int x, y;
    for (y = 0; y < img->height; ++y)
        for (x = 0; x < img->width; ++x) {
            float g = (float)x / img->width;
            set_px(img, x, y, 0.2f + 0.6f * g, (x / 8) % 2 ? 0.7f : 0.1f, 0.3f + 0.2f * y / img->height);
        }
    set_px(img, img->width / 2, img->height / 2, 4, 4, 3);
}

/* metric(A, A) = 0 for every metric; MSE, RMSE, SMAPE and LDR-FLIP are symmetric. */
TEST(metrics_identity_and_symmetry)
{
    image a, b;
    rerror e;
    image_metrics ab, ba, aa;
    flip_params p;
    double f_ab, f_ba, f_aa, h_aa;
    int i;
    CHECK(image_alloc(&a, 24, 20, &e) == 0 && image_alloc(&b, 24, 20, &e) == 0);
    scene_pattern(&a);
    noisy_copy(&a, &b, 0.1, 1);
    CHECK(metrics_compute(&a, &a, NULL, &aa, &e) == 0);
    CHECK(metrics_compute(&a, &b, NULL, &ab, &e) == 0);
    CHECK(metrics_compute(&b, &a, NULL, &ba, &e) == 0);
    for (i = 0; i <= METRIC_REL_BIAS; ++i) CHECKF(aa.value[i] == 0, "%s(A,A) = %g", metric_name(i), aa.value[i]);
    CHECK(ab.value[METRIC_MSE] > 0 && ab.value[METRIC_MSE] == ba.value[METRIC_MSE]);
    CHECK(ab.value[METRIC_RMSE] == ba.value[METRIC_RMSE]);
    CHECK(ab.value[METRIC_SMAPE] > 0 && ab.value[METRIC_SMAPE] == ba.value[METRIC_SMAPE]);
    CHECK(ab.value[METRIC_MAPE] != ba.value[METRIC_MAPE]); /* relative to the reference */
    flip_default_params(&p);
    CHECK(flip_ldr(&a, &a, &p, NULL, &f_aa, &e) == 0);
    CHECK(flip_hdr(&a, &a, &p, NULL, &h_aa, NULL, NULL, NULL, &e) == 0);
    CHECK(f_aa == 0 && h_aa == 0);
    CHECK(flip_ldr(&a, &b, &p, NULL, &f_ab, &e) == 0);
    CHECK(flip_ldr(&b, &a, &p, NULL, &f_ba, &e) == 0);
    CHECK(f_ab > 0);
    CHECK_NEAR(f_ab, f_ba, 1e-7);
    image_free(&a);
    image_free(&b);
}

TEST(metrics_reject_bad_inputs)
{
    image a, b, c;
    rerror e;
    image_metrics m;
    image_rect r;
    CHECK(image_alloc(&a, 4, 4, &e) == 0 && image_alloc(&b, 4, 4, &e) == 0 && image_alloc(&c, 4, 3, &e) == 0);
    CHECK(metrics_check_inputs(&a, "a.pfm", &c, "c.pfm", NULL, &e) != 0);
    CHECKF(strstr(e.msg, "a.pfm: ") && strstr(e.msg, "4 x 3"), "%s", e.msg);
    image_pixel(&b, 2, 1)[1] = NAN;
    CHECK(metrics_check_inputs(&a, "a.pfm", &b, "b.pfm", NULL, &e) != 0);
    CHECKF(strstr(e.msg, "b.pfm: pixel (2, 1) green is NaN"), "%s", e.msg);
    CHECK(metrics_compute(&a, &b, NULL, &m, &e) != 0);
    image_pixel(&b, 2, 1)[1] = HUGE_VALF;
    CHECK(metrics_check_inputs(&b, "b.pfm", &a, "a.pfm", NULL, &e) != 0 && strstr(e.msg, "infinite"));
    /* a crop that excludes the bad pixel is fine; crops outside the image are not */
    r.x = 0, r.y = 2, r.w = 4, r.h = 2;
    CHECK(metrics_compute(&a, &b, &r, &m, &e) == 0);
    r.x = 1, r.y = 1, r.w = 4, r.h = 1;
    CHECK(metrics_compute(&a, &b, &r, &m, &e) != 0 && strstr(e.msg, "crop"));
    r.x = 0, r.y = 0, r.w = 0, r.h = 1;
    CHECK(metrics_compute(&a, &a, &r, &m, &e) != 0);
    image_free(&a);
    image_free(&b);
    image_free(&c);
}

/* Against an all-black reference the relative metrics are +inf when the test is not black
 * (0/0 counts as 0), and SMAPE stays bounded by 1. */
TEST(metrics_black_reference)
{
    image t, r;
    rerror e;
    image_metrics m;
    CHECK(image_alloc(&t, 3, 3, &e) == 0 && image_alloc(&r, 3, 3, &e) == 0);
    CHECK(metrics_compute(&t, &r, NULL, &m, &e) == 0);
    CHECK(m.value[METRIC_MAPE] == 0 && m.value[METRIC_RELMSE] == 0 && m.value[METRIC_SMAPE] == 0);
    set_px(&t, 1, 1, 0.5f, 0, 0);
    CHECK(metrics_compute(&t, &r, NULL, &m, &e) == 0);
    CHECK(isinf(m.value[METRIC_MAPE]) && isinf(m.value[METRIC_RELMSE]));
    /* eps_s = 0.005 * 0.2126*0.5/9; the one red term is 0.5/(0.5 + eps_s) */
    CHECK_NEAR(m.value[METRIC_SMAPE], 0.5 / (0.5 + 0.005 * 0.2126 * 0.5 / 9) / 27, 1e-15);
    image_free(&t);
    image_free(&r);
}

/* Uniform images have no features, so FLIP is the redistributed colour difference alone.
 * Expected values from an independent (non-separable, NumPy) evaluation of the published
 * formulas; black vs white also in closed form: 0.95 + (100^0.7 - 0.4 c)/(0.6 c) * 0.05
 * with c = c_max = HyAB(green, blue)^0.7 = 41.27609841 -> 0.96737976149. */
TEST(flip_uniform_known_values)
{
    static const struct {
        float a[3], b[3];
        double flip;
    } cases[] = {
        {{0, 0, 0}, {1, 1, 1}, 0.9673797615},
        {{0.25f, 0.25f, 0.25f}, {0.5f, 0.5f, 0.5f}, 0.4518496203},
        {{1, 0, 0}, {0, 1, 0}, 0.9866622753},
        {{0.2f, 0.4f, 0.6f}, {0.21f, 0.4f, 0.6f}, 0.0440166289},
    };
    image a, b;
    rerror e;
    flip_params p;
    float map[64];
    double mean;
    size_t i;
    flip_default_params(&p);
    CHECK_NEAR(p.ppd, 67.02064327658225, 1e-9);
    CHECK(image_alloc(&a, 8, 8, &e) == 0 && image_alloc(&b, 8, 8, &e) == 0);
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        fill(&a, cases[i].a[0], cases[i].a[1], cases[i].a[2]);
        fill(&b, cases[i].b[0], cases[i].b[1], cases[i].b[2]);
        CHECK(flip_ldr(&a, &b, &p, map, &mean, &e) == 0);
        CHECKF(fabs(mean - cases[i].flip) < 1e-6, "case %zu: FLIP %.10f, expected %.10f", i, mean, cases[i].flip);
        CHECK_NEAR(map[0], map[63], 1e-6);
    }
    image_free(&a);
    image_free(&b);
}

/* A structured pair (sine, step edge, ramp; a brightened block and a firefly) exercises the
 * CSF filters and both feature detectors. Expected values from the independent non-separable
 * NumPy evaluation of the published formulas (2-D kernels, 2-D normalisation). */
TEST(flip_structured_known_values)
{
    image r, t;
    rerror e;
    flip_params p;
    float map[32 * 24];
    double ldr, hdr, start, stop;
    int x, y, c, count;
    flip_default_params(&p);
    CHECK(image_alloc(&r, 32, 24, &e) == 0 && image_alloc(&t, 32, 24, &e) == 0);
    for (y = 0; y < 24; ++y)
        for (x = 0; x < 32; ++x) {
            set_px(&r, x, y, (float)(0.5 + 0.4 * sin(x / 3.0)), x >= 16 ? 0.9f : 0.1f, (float)(0.3 + 0.5 * y / 24.0));
            for (c = 0; c < 3; ++c) {
                float v = image_pixel(&r, x, y)[c];
                image_pixel(&t, x, y)[c] = (x >= 8 && x < 20 && y >= 6 && y < 14) ? (float)(v * 1.3) : v;
            }
        }
    set_px(&t, 25, 18, 3, 3, 3);
    CHECK(flip_ldr(&t, &r, &p, map, &ldr, &e) == 0);
    CHECK_NEAR(ldr, 0.0699788535, 2e-6);
    CHECK_NEAR(map[18 * 32 + 25], 0.09787610, 2e-6);
    CHECK_NEAR(map[8 * 32 + 10], 0.37338058, 2e-6);
    CHECK_NEAR(map[0], 0.00035230, 2e-6);
    CHECK(flip_hdr(&t, &r, &p, NULL, &hdr, &start, &stop, &count, &e) == 0);
    CHECK_NEAR(hdr, 0.0479255246, 2e-6);
    CHECK_NEAR(start, 1.250818, 1e-5);
    CHECK_NEAR(stop, 2.053032, 1e-5);
    CHECK(count == 2);
    image_free(&r);
    image_free(&t);
}

/* FLIP grows with the amplitude of added noise (same noise pattern, scaled). */
TEST(flip_monotone_in_noise_amplitude)
{
    static const double amplitude[] = {0.005, 0.01, 0.02, 0.05, 0.1, 0.2};
    image ref, t;
    rerror e;
    flip_params p;
    double prev_ldr = 0, prev_hdr = 0, ldr, hdr;
    size_t i;
    flip_default_params(&p);
    CHECK(image_alloc(&ref, 48, 40, &e) == 0 && image_alloc(&t, 48, 40, &e) == 0);
    scene_pattern(&ref);
    for (i = 0; i < sizeof amplitude / sizeof amplitude[0]; ++i) {
        noisy_copy(&ref, &t, amplitude[i], 7);
        CHECK(flip_ldr(&t, &ref, &p, NULL, &ldr, &e) == 0);
        CHECK(flip_hdr(&t, &ref, &p, NULL, &hdr, NULL, NULL, NULL, &e) == 0);
        CHECKF(ldr > prev_ldr && hdr > prev_hdr, "amplitude %g: LDR %g (prev %g), HDR %g (prev %g)", amplitude[i], ldr,
               prev_ldr, hdr, prev_hdr);
        CHECK(ldr < 1 && hdr < 1);
        prev_ldr = ldr;
        prev_hdr = hdr;
    }
    image_free(&ref);
    image_free(&t);
}

/* LDR-FLIP sees the displayed image (clamped to [0,1]); HDR-FLIP sees differences at any
 * brightness: above 1 (invisible to LDR) and deep in the shadows (small in LDR). */
TEST(flip_ldr_vs_hdr)
{
    image ref, t;
    rerror e;
    flip_params p;
    double ldr, hdr, start, stop;
    int count, x, y;
    flip_default_params(&p);
    CHECK(image_alloc(&ref, 32, 32, &e) == 0 && image_alloc(&t, 32, 32, &e) == 0);
    fill(&ref, 4, 4, 4);
    fill(&t, 4, 4, 4);
    for (y = 8; y < 24; ++y)
        for (x = 8; x < 24; ++x) set_px(&t, x, y, 8, 8, 8);
    CHECK(flip_ldr(&t, &ref, &p, NULL, &ldr, &e) == 0);
    CHECK(flip_hdr(&t, &ref, &p, NULL, &hdr, &start, &stop, &count, &e) == 0);
    CHECKF(ldr == 0 && hdr > 0.05, "bright: LDR %g HDR %g", ldr, hdr);
    fill(&ref, 0.001f, 0.001f, 0.001f);
    fill(&t, 0.001f, 0.001f, 0.001f);
    for (y = 8; y < 24; ++y)
        for (x = 8; x < 24; ++x) set_px(&t, x, y, 0.002f, 0.002f, 0.002f);
    CHECK(flip_ldr(&t, &ref, &p, NULL, &ldr, &e) == 0);
    CHECK(flip_hdr(&t, &ref, &p, NULL, &hdr, NULL, NULL, NULL, &e) == 0);
    CHECKF(hdr > 3 * ldr && hdr > 0.05, "dark: LDR %g HDR %g", ldr, hdr);
    image_free(&ref);
    image_free(&t);
}

/* The automatic exposure range: 2^start * Y_max and 2^stop * Y_median are the inputs at
 * which the ACES curve reaches 0.85; count = max(2, ceil(stop - start)). */
TEST(flip_auto_exposure_range)
{
    image ref;
    rerror e;
    double start, stop;
    int count, i;
    CHECK(image_alloc(&ref, 5, 4, &e) == 0);
    fill(&ref, 0.5f, 0.5f, 0.5f);         /* Y = 0.5 */
    set_px(&ref, 0, 0, 40, 40, 40);       /* Y_max = 40 */
    for (i = 0; i < 9; ++i) set_px(&ref, 1 + i % 4, 1 + i / 4, 0.1f, 0.1f, 0.1f); /* 9 of 20 darker */
    CHECK(flip_auto_exposure(&ref, &start, &stop, &count, &e) == 0);
    /* sorted: 9 x 0.1, 10 x 0.5, 40 -> median of 20 values = (0.5 + 0.5) / 2 */
    CHECK_NEAR(flip_tonemap_aces(pow(2, start) * 40.0), 0.85, 1e-6);
    CHECK_NEAR(flip_tonemap_aces(pow(2, stop) * 0.5), 0.85, 1e-6);
    CHECK_NEAR(stop - start, log2(80.0), 1e-6);
    CHECK(count == 7); /* ceil(6.32) */
    CHECK(flip_tonemap_aces(0) == 0 && flip_tonemap_aces(1e29) == 1 && flip_tonemap_aces(1e300) == 1);
    CHECK(flip_tonemap_aces(-1) == 0 && flip_tonemap_aces(HUGE_VAL) == 1 && flip_tonemap_aces(NAN) == 0);
    fill(&ref, 0, 0, 0);
    CHECK(flip_auto_exposure(&ref, &start, &stop, &count, &e) == 0);
    CHECK(start == 0 && stop == 0 && count == 2);
    image_free(&ref);
}

/* The error-map image: colour bar ends in the palette's end colours, labels drawn. */
TEST(error_map_render_layout)
{
    float map[4] = {0, 0.25f, 0.5f, 1};
    rgb8_image img;
    rerror e;
    unsigned char c0[3], c1[3];
    int x, y, ink = 0;
    const unsigned char *p;
    CHECK(error_map_render(map, 2, 2, 0, 1, PALETTE_MAGMA, &img, &e) == 0);
    CHECK(img.width == ERROR_MAP_MIN_WIDTH && img.height > 2 + 12 + 7);
    colormap_magma(0, c0);
    colormap_magma(1, c1);
    CHECK(c0[0] == 0 && c0[2] == 4 && c1[0] == 252 && c1[1] == 253 && c1[2] == 191); /* magma ends */
    CHECK(!memcmp(img.rgb, c0, 3));                                           /* map pixel (0,0) = 0 */
    CHECK(!memcmp(img.rgb + 3 * (size_t)(img.width + 1), c1, 3));             /* map pixel (1,1) = 1 */
    p = img.rgb + 3 * ((size_t)(2 + 4 + 6) * img.width + 4);                  /* bar, left end */
    CHECK(!memcmp(p, c0, 3));
    p = img.rgb + 3 * ((size_t)(2 + 4 + 6) * img.width + img.width - 5);      /* bar, right end */
    CHECK(!memcmp(p, c1, 3));
    for (y = 2 + 4 + 12 + 4; y < img.height; ++y)
        for (x = 0; x < img.width; ++x) ink += img.rgb[3 * ((size_t)y * img.width + x)] == 0;
    CHECKF(ink > 20, "label ink pixels: %d", ink);
    rgb8_image_free(&img);
}

/* ---- the CLI ---- */

static const char *write_pfm(const char *name, const image *img)
{
    static char paths[4][1024];
    static int next;
    char *path = paths[next++ & 3];
    rerror e;
    snprintf(path, sizeof paths[0], "%s", test_tmp_path(name));
    if (pfm_write(path, img, &e)) return "";
    return path;
}

TEST(cli_compare_json_and_map)
{
    image a, b;
    rerror e;
    char out[8192], json[1024], png[1024], *text;
    const char *pa, *pb;
    CHECK(image_alloc(&a, 20, 12, &e) == 0 && image_alloc(&b, 20, 12, &e) == 0);
    fill(&a, 1, 1, 1);
    fill(&b, 1, 1, 1);
    set_px(&a, 3, 2, 2, 1, 1); /* one differing pixel */
    pa = write_pfm("cmp-a.pfm", &a);
    pb = write_pfm("cmp-b.pfm", &b);
    snprintf(json, sizeof json, "%s", test_tmp_path("cmp.json"));
    snprintf(png, sizeof png, "%s", test_tmp_path("cmp.png"));
    remove(json);
    remove(png);
    CHECKF(test_cli(out, sizeof out, "compare %s %s --json %s --error-map %s --metric mse", pa, pb, json, png) == 0,
           "%s", out);
    CHECKF(strstr(out, "mse ") && strstr(out, "flip_hdr"), "%s", out);
    text = test_read_text(json);
    CHECK(text);
    /* MSE = 1 / (3 * 240) */
    CHECKF(strstr(text, "\"mse\": "), "%s", text);
    CHECK_NEAR(strtod(strstr(text, "\"mse\": ") + 7, NULL), 1.0 / 720, 1e-17);
    CHECKF(strstr(text, "\"crop\": [0, 0, 20, 12]") && strstr(text, "\"flip_ldr\": 0,\n"), "%s", text);
    free(text);
    CHECK(test_file_exists(png));
    /* the crop leaves the differing pixel out */
    CHECKF(test_cli(out, sizeof out, "compare %s %s --crop 5,0,15,12 --json %s", pa, pb, json) == 0, "%s", out);
    text = test_read_text(json);
    CHECK(text);
    CHECKF(strstr(text, "\"mse\": 0,") && strstr(text, "\"flip_hdr\": 0\n") && strstr(text, "\"pixels\": 180"), "%s",
           text);
    free(text);
    image_free(&a);
    image_free(&b);
}

TEST(cli_compare_rejects_bad_input)
{
    image a, b, c;
    rerror e;
    char out[8192], json[1024];
    const char *pa, *pb, *pc;
    CHECK(image_alloc(&a, 8, 8, &e) == 0 && image_alloc(&b, 8, 8, &e) == 0 && image_alloc(&c, 8, 6, &e) == 0);
    image_pixel(&b, 5, 6)[2] = NAN;
    pa = write_pfm("bad-a.pfm", &a);
    pb = write_pfm("bad-b.pfm", &b);
    pc = write_pfm("bad-c.pfm", &c);
    snprintf(json, sizeof json, "%s", test_tmp_path("bad.json"));
    remove(json);
    CHECK(test_cli(out, sizeof out, "compare %s %s --json %s", pa, pc, json) == 2);
    CHECKF(strstr(out, "bad-a.pfm: size 8 x 8 differs"), "%s", out);
    CHECK(test_cli(out, sizeof out, "compare %s %s --json %s", pa, pb, json) == 2);
    CHECKF(strstr(out, "bad-b.pfm: pixel (5, 6) blue is NaN"), "%s", out);
    CHECK(!test_file_exists(json));
    CHECK(test_cli(out, sizeof out, "compare %s %s --crop 1,2,3", pa, pa) == 2);
    CHECK(test_cli(out, sizeof out, "compare %s %s --crop 4,4,8,8", pa, pa) == 2 && strstr(out, "crop"));
    CHECK(test_cli(out, sizeof out, "compare %s %s --metric nope", pa, pa) == 2);
    CHECK(test_cli(out, sizeof out, "compare %s %s --ppd -3", pa, pa) == 2);
    CHECK(test_cli(out, sizeof out, "compare %s %s --frobnicate", pa, pa) == 2);
    CHECK(test_cli(out, sizeof out, "compare %s", pa) == 2);
    CHECK(test_cli(out, sizeof out, "compare %s /nonexistent/x.pfm", pa) == 2 && strstr(out, "/nonexistent/x.pfm: "));
    CHECK(test_cli(out, sizeof out, "compare --help") == 0 && strstr(out, "usage: restir compare"));
    CHECK(!test_file_exists(json));
    image_free(&a);
    image_free(&b);
    image_free(&c);
}
