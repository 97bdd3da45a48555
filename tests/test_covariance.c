/* The average box covariance of Mutations Eq. 21 (src/metrics/covariance.c): against
 * a brute-force evaluation of the definition, and against analytic values for white
 * noise and for white noise blurred with a known kernel. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/rng.h"
#include "restir/metrics/covariance.h"
#include "restir/metrics/stats.h"
#include "capture.h"
#include "test.h"
#include "restir/core/pfm.h"

static double gauss(uint32_t seed, uint32_t pixel, uint32_t sample)
{
    rng_key k = rng_key_make(seed, pixel, sample);
    double u1 = 1.0 - rng_uniform_double(rng_key_at(k, RNG_TEST, 0, 0));
    double u2 = rng_uniform_double(rng_key_at(k, RNG_TEST, 0, 1));
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* A per-pixel mean that varies a lot (the estimator must remove it). */
static double pixel_offset(int x, int y) { return 3.0 + 2.0 * sin(0.7 * x) * cos(0.3 * y); }

/* Grey image (luminance = value, the Rec. 709 weights sum to 1). */
static void set_grey(image *img, int x, int y, double v)
{
    float *p = image_pixel(img, x, y);
    p[0] = p[1] = p[2] = (float)v;
}

/* The covariance of pixel (x, y) with its neighbour (x + dx, y + dy). */
typedef double (*pair_cov)(const void *user, int x, int y, int dx, int dy);

/* The metric's averaging, with the estimator's border clipping: the mean over the w x h
 * pixels of the mean of cov over the neighbours in the (2r+1)^2 box around each (without
 * the pixel itself when exclude); map (may be NULL) receives the per-pixel box means. */
static double box_average(int w, int h, int r, int exclude, pair_cov cov, const void *user, double *map)
{
    int x, y, dx, dy;
    double total = 0.0;
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) {
            double box = 0.0;
            long n = 0;
            for (dy = -r; dy <= r; ++dy)
                for (dx = -r; dx <= r; ++dx) {
                    if (x + dx < 0 || x + dx >= w || y + dy < 0 || y + dy >= h) continue;
                    if (exclude && !dx && !dy) continue;
                    box += cov(user, x, y, dx, dy);
                    n++;
                }
            total += box / n;
            if (map) map[y * w + x] = box / n;
        }
    return total / (w * h);
}

/* K luminance images and their per-pixel mean. */
typedef struct {
    const double *lum, *mean;
    int k_count, w, h;
} lum_runs;

/* Mutations Eq. 21: the sample covariance over the K images. */
static double sample_cov(const void *user, int x, int y, int dx, int dy)
{
    const lum_runs *q = user;
    int i = y * q->w + x, j = (y + dy) * q->w + x + dx, k;
    size_t n = (size_t)q->w * (size_t)q->h;
    double cov = 0.0;
    for (k = 0; k < q->k_count; ++k)
        cov += (q->lum[(size_t)k * n + i] - q->mean[i]) * (q->lum[(size_t)k * n + j] - q->mean[j]);
    return cov / (q->k_count - 1);
}

/* Eq. 21 straight from the definition, box-averaged and image-averaged. */
static void brute_force(const double *lum, int k_count, int w, int h, int radius, int exclude, double *per_radius,
                        double *map)
{
    int r, x, k;
    double *mean = calloc((size_t)w * h, sizeof *mean);
    lum_runs q;
    for (k = 0; k < k_count; ++k)
        for (x = 0; x < w * h; ++x) mean[x] += lum[(size_t)k * w * h + x] / k_count;
    q.lum = lum;
    q.mean = mean;
    q.k_count = k_count;
    q.w = w;
    q.h = h;
    for (r = 0; r <= radius; ++r)
        per_radius[r] = box_average(w, h, r, exclude, sample_cov, &q, r == radius ? map : NULL);
    free(mean);
}

TEST(covariance_matches_definition)
{
    enum { W = 11, H = 9, K = 5, R = 3 };
    static double lum[K * W * H];
    double got[R + 1], want[R + 1], want_map[W * H];
    covariance_accum c;
    image img, map;
    rerror e;
    int k, x, y, r, exclude;
    CHECK(image_alloc(&img, W, H, &e) == 0);
    for (exclude = 0; exclude <= 1; ++exclude) {
        CHECK(covariance_init(&c, W, H, R, exclude, &e) == 0);
        for (k = 0; k < K; ++k) {
            for (y = 0; y < H; ++y)
                for (x = 0; x < W; ++x) {
                    /* Coloured pixels with correlated neighbours: a shared term per row. */
                    float *p = image_pixel(&img, x, y);
                    double g = gauss(test_seed(), (uint32_t)(y * W + x), (uint32_t)k);
                    double row = gauss(test_seed(), 1000u + (uint32_t)y, (uint32_t)k);
                    p[0] = (float)(pixel_offset(x, y) + g + row);
                    p[1] = (float)(0.5 * pixel_offset(x, y) + 0.3 * g);
                    p[2] = (float)(2.0 + row * row);
                    lum[(size_t)k * W * H + y * W + x] = (double)luminance(rgb_make(p[0], p[1], p[2]));
                }
            CHECK(covariance_add(&c, &img, "test", &e) == 0);
        }
        CHECK(covariance_result(&c, got, &map, &e) == 0);
        brute_force(lum, K, W, H, R, exclude, want, want_map);
        for (r = exclude; r <= R; ++r) CHECK_NEAR(got[r], want[r], 1e-10 * fabs(want[0 + exclude]));
        if (exclude) CHECK(isnan(got[0]));
        for (x = 0; x < W * H; ++x) CHECK_NEAR(map.px[3 * x], want_map[x], 1e-5 * fabs(want_map[x]) + 1e-6);
        image_free(&map);
        covariance_free(&c);
    }
    image_free(&img);
}

/* Mean and standard error of the metric over independent data sets. */
typedef struct {
    double sum[9], sum2[9];
    int sets;
} spread;

static void spread_add(spread *s, const double *v, int radius)
{
    int r;
    for (r = 0; r <= radius; ++r) {
        s->sum[r] += v[r];
        s->sum2[r] += v[r] * v[r];
    }
    s->sets++;
}

static double spread_mean(const spread *s, int r) { return s->sum[r] / s->sets; }
static double spread_se(const spread *s, int r)
{
    double m = spread_mean(s, r);
    return sqrt((s->sum2[r] / s->sets - m * m) * s->sets / (s->sets - 1) / s->sets);
}

/* The blur kernel [1 2 1] x [1 2 1] / 16 and its autocorrelation R(d) = sum_m h(m) h(m+d). */
static double kernel(int dx, int dy)
{
    static const double k1[3] = {0.25, 0.5, 0.25};
    if (dx < -1 || dx > 1 || dy < -1 || dy > 1) return 0.0;
    return k1[dx + 1] * k1[dy + 1];
}

static double kernel_autocorrelation(int dx, int dy)
{
    int mx, my;
    double s = 0.0;
    for (my = -1; my <= 1; ++my)
        for (mx = -1; mx <= 1; ++mx) s += kernel(mx, my) * kernel(mx + dx, my + dy);
    return s;
}

/* The expected metric for stationary noise with covariance function cov(dx, dy), with
 * the same border clipping and averaging as the estimator. */
typedef struct {
    double (*cov)(int dx, int dy);
} stationary;

static double stationary_cov(const void *user, int x, int y, int dx, int dy)
{
    (void)x;
    (void)y;
    return ((const stationary *)user)->cov(dx, dy);
}

static double expected_metric(int w, int h, int r, int exclude, double (*cov)(int, int))
{
    stationary st;
    st.cov = cov;
    return box_average(w, h, r, exclude, stationary_cov, &st, NULL);
}

static double white_cov(int dx, int dy) { return dx == 0 && dy == 0 ? 1.0 : 0.0; }

/* Renders K images of (offset + noise); blur = 1 convolves the white noise (circularly)
 * with the kernel. Returns the metric per radius. */
static int noise_metric(int w, int h, int k_count, int radius, int exclude, int blur, uint32_t seed, double *out)
{
    covariance_accum c;
    image img;
    rerror e;
    double *noise = malloc((size_t)w * h * sizeof *noise);
    int k, x, y, dx, dy;
    if (!noise || image_alloc(&img, w, h, &e) || covariance_init(&c, w, h, radius, exclude, &e)) return -1;
    for (k = 0; k < k_count; ++k) {
        for (y = 0; y < h; ++y)
            for (x = 0; x < w; ++x) noise[y * w + x] = gauss(seed, (uint32_t)(y * w + x), (uint32_t)k);
        for (y = 0; y < h; ++y)
            for (x = 0; x < w; ++x) {
                double v = 0.0;
                if (!blur)
                    v = noise[y * w + x];
                else
                    for (dy = -1; dy <= 1; ++dy)
                        for (dx = -1; dx <= 1; ++dx)
                            v += kernel(dx, dy) * noise[((y - dy + h) % h) * w + (x - dx + w) % w];
                set_grey(&img, x, y, pixel_offset(x, y) + v);
            }
        if (covariance_add(&c, &img, "noise", &e)) return -1;
    }
    if (covariance_result(&c, out, NULL, &e)) return -1;
    covariance_free(&c);
    image_free(&img);
    free(noise);
    return 0;
}

/* |mean - expected| must be below this many standard errors: the two-sided 1e-4
 * quantile of t with NOISE_SETS - 1 dof (the standard error is itself estimated). */
static double tolerance_in_se(int sets) { return stats_t_quantile(1.0 - 0.5e-4, sets - 1.0); }

/* The data sets of covariance_white_noise and covariance_blurred_noise. */
enum { NOISE_W = 40, NOISE_H = 32, NOISE_K = 12, NOISE_R = 4, NOISE_SETS = 40 };

/* The metric at radii 0..NOISE_R over NOISE_SETS data sets of white (blurred 0) or blurred
 * noise, data set s from the seed test_seed() * seed_factor + s + 100 exclude. */
static int noise_spread(spread *sp, int exclude, int blurred, uint32_t seed_factor)
{
    int s;
    memset(sp, 0, sizeof *sp);
    for (s = 0; s < NOISE_SETS; ++s) {
        double v[NOISE_R + 1];
        uint32_t seed = test_seed() * seed_factor + (uint32_t)(s + 100 * exclude);
        if (noise_metric(NOISE_W, NOISE_H, NOISE_K, NOISE_R, exclude, blurred, seed, v)) return -1;
        spread_add(sp, v, NOISE_R);
    }
    return 0;
}

/* Independent pixels: with the centre excluded the metric is 0, with it included it is
 * the pixel variance over the box size, both within tolerance over 40 data sets. */
TEST(covariance_white_noise)
{
    int exclude, r;
    for (exclude = 0; exclude <= 1; ++exclude) {
        spread sp;
        CHECK(noise_spread(&sp, exclude, 0, 977u) == 0);
        for (r = exclude; r <= NOISE_R; ++r) {
            double want = expected_metric(NOISE_W, NOISE_H, r, exclude, white_cov);
            CHECKF(fabs(spread_mean(&sp, r) - want) < tolerance_in_se(NOISE_SETS) * spread_se(&sp, r) + 1e-12,
                   "exclude %d radius %d: %g +- %g, expected %g", exclude, r, spread_mean(&sp, r), spread_se(&sp, r),
                   want);
        }
        if (exclude)
            printf("     white noise, no centre, r=%d: %.3g +- %.3g (expected 0)\n", NOISE_R, spread_mean(&sp, NOISE_R),
                   spread_se(&sp, NOISE_R));
    }
}

/* Blurred white noise has covariance R_h(d), the kernel's autocorrelation: the metric
 * must match its box average at every radius (0: the variance 36/256). */
TEST(covariance_blurred_noise)
{
    int exclude, r;
    CHECK_NEAR(kernel_autocorrelation(0, 0), 36.0 / 256.0, 1e-15);
    for (exclude = 0; exclude <= 1; ++exclude) {
        spread sp;
        CHECK(noise_spread(&sp, exclude, 1, 1013u) == 0);
        for (r = exclude; r <= NOISE_R; ++r) {
            double want = expected_metric(NOISE_W, NOISE_H, r, exclude, kernel_autocorrelation);
            CHECKF(fabs(spread_mean(&sp, r) - want) < tolerance_in_se(NOISE_SETS) * spread_se(&sp, r),
                   "exclude %d radius %d: %g +- %g, expected %g", exclude, r, spread_mean(&sp, r), spread_se(&sp, r),
                   want);
            if (r == 1 || r == NOISE_R)
                printf("     blurred noise, exclude %d, r=%d: %.5f +- %.5f (expected %.5f)\n", exclude, r,
                       spread_mean(&sp, r), spread_se(&sp, r), want);
        }
    }
}

TEST(covariance_errors)
{
    covariance_accum c;
    image a, b;
    rerror e;
    double v[3];
    CHECK(covariance_init(&c, 8, 8, 2, 0, &e) == 0);
    CHECK(image_alloc(&a, 8, 8, &e) == 0 && image_alloc(&b, 9, 8, &e) == 0);
    CHECK(covariance_add(&c, &a, "a.pfm", &e) == 0);
    CHECK(covariance_result(&c, v, NULL, &e) != 0); /* one image */
    CHECK(covariance_add(&c, &b, "b.pfm", &e) != 0);
    CHECKF(strstr(e.msg, "b.pfm") != NULL, "%s", e.msg);
    image_pixel(&a, 3, 4)[1] = INFINITY;
    CHECK(covariance_add(&c, &a, "c.pfm", &e) != 0);
    CHECKF(strstr(e.msg, "c.pfm: pixel (3, 4)") != NULL, "%s", e.msg);
    image_free(&a);
    image_free(&b);
    covariance_free(&c);
    CHECK(covariance_init(&c, 8, 8, 0, 1, &e) != 0);
}

int cmd_compare_covariance(int argc, char **argv);

/* Runs cmd_compare_covariance in-process with a NULL-terminated argument list. */
static int run_covariance_cli(const char *first, ...)
{
    char *argv[64];
    int argc = 0, status;
    va_list ap;
    const char *s = first;
    va_start(ap, first);
    while (s && argc < 63) {
        argv[argc++] = (char *)s;
        s = va_arg(ap, const char *);
    }
    va_end(ap);
    argv[argc] = NULL;
    capture_begin(); /* its messages are checked by status; they are not the suite's output */
    status = cmd_compare_covariance(argc, argv);
    capture_end(NULL, 0);
    return status;
}

TEST(covariance_cli)
{
    char files[4][1100], curve[1100], json[1100], map_path[1100], small[1100];
    covariance_accum c;
    image img, map;
    rerror e;
    double want[4];
    int k, x, y, r;
    FILE *f;
    char line[256];
    CHECK(image_alloc(&img, 20, 16, &e) == 0);
    CHECK(covariance_init(&c, 20, 16, 3, 0, &e) == 0);
    for (k = 0; k < 4; ++k) {
        char name[64];
        snprintf(name, sizeof name, "cov_%d.pfm", k);
        snprintf(files[k], sizeof files[k], "%s", test_tmp_path(name));
        for (y = 0; y < 16; ++y)
            for (x = 0; x < 20; ++x) set_grey(&img, x, y, pixel_offset(x, y) + gauss(test_seed(), (uint32_t)(y * 20 + x / 2), (uint32_t)k));
        CHECK(pfm_write(files[k], &img, &e) == 0);
        CHECK(covariance_add(&c, &img, files[k], &e) == 0);
    }
    CHECK(covariance_result(&c, want, NULL, &e) == 0);
    covariance_free(&c);
    snprintf(curve, sizeof curve, "%s", test_tmp_path("cov_curve.csv"));
    snprintf(json, sizeof json, "%s", test_tmp_path("cov.json"));
    snprintf(map_path, sizeof map_path, "%s", test_tmp_path("cov_map.pfm"));
    CHECK(run_covariance_cli("compare", "--covariance", files[0], files[1], files[2], files[3], "--radius", "3",
                             "--curve", curve, "--json", json, "--map", map_path, (const char *)NULL) == 0);
    f = fopen(curve, "r");
    CHECK(f != NULL);
    CHECK(fgets(line, sizeof line, f) && !strcmp(line, "radius,covariance\n"));
    for (r = 0; r <= 3; ++r) {
        int rr;
        double v;
        CHECK(fgets(line, sizeof line, f) && sscanf(line, "%d,%lf", &rr, &v) == 2);
        CHECK(rr == r);
        CHECK_NEAR(v, want[r], 1e-8 * fabs(want[r]));
    }
    fclose(f);
    CHECK(test_file_exists(json));
    CHECK(pfm_read(map_path, &map, NULL, &e) == 0 && map.width == 20 && map.height == 16);
    image_free(&map);
    /* Errors: one image; a size mismatch leaves no outputs. */
    remove(json);
    CHECK(run_covariance_cli("compare", "--covariance", files[0], "--json", json, (const char *)NULL) == 2);
    image_free(&img);
    CHECK(image_alloc(&img, 21, 16, &e) == 0);
    snprintf(small, sizeof small, "%s", test_tmp_path("cov_other.pfm"));
    CHECK(pfm_write(small, &img, &e) == 0);
    CHECK(run_covariance_cli("compare", "--covariance", files[0], files[1], small, "--json", json,
                             (const char *)NULL) == 2);
    CHECK(!test_file_exists(json));
    CHECK(run_covariance_cli("compare", "--covariance", files[0], files[1], "--radius", "x", (const char *)NULL) == 2);
    image_free(&img);
}
