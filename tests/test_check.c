/* Calibration and power of `restir check` (src/metrics/check.c) on synthetic renders
 * with known per-pixel means: equal-mean sources must be called "different" at about
 * the nominal rate alpha (binomial tolerance), and small biases must be found. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/check.h"
#include "restir/metrics/moments.h"
#include "restir/core/rng.h"
#include "pt_util.h"
#include "restir_util.h"
#include "test.h"
#include "restir/core/pfm.h"

/* ---- synthetic renders ---- */

enum noise_kind { NOISE_MIXED = 0, NOISE_GAUSSIAN = 1 };

typedef struct {
    int width, height;
    int samples;           /* samples averaged per pixel per run */
    enum noise_kind noise;
    double rel_sd;         /* Gaussian noise: relative sd of one sample */
    double scale;          /* multiplies the true mean (1 + bias) */
    double tile_sd;        /* >0: a multiplicative factor shared by each 4x4 tile (correlated pixels) */
    int local_x, local_y;  /* a local defect: this 8x8 block scaled by local_scale */
    double local_scale;
} synth;

static synth synth_default(void)
{
    synth s;
    s.width = 32;
    s.height = 32;
    s.samples = 4;
    s.noise = NOISE_MIXED;
    s.rel_sd = 0.3;
    s.scale = 1.0;
    s.tile_sd = 0.0;
    s.local_x = s.local_y = -1;
    s.local_scale = 1.0;
    return s;
}

/* The true mean of pixel (x, y), channel c: a black band (zero in every run: zero
 * variance on both sides), and a smooth pattern with a chromatic tint elsewhere. */
static double true_mean(int x, int y, int c)
{
    static const double tint[3] = {1.0, 0.8, 0.5};
    if (x < 3) return 0.0;
    return tint[c] * (0.2 + 1.5 * (0.5 + 0.5 * sin(0.37 * x + 0.21 * y)));
}

static double uniform01(uint32_t seed, uint32_t pixel, uint32_t sample, uint32_t side, uint32_t slot)
{
    /* In (0, 1]: safe for log. */
    return 1.0 - rng_uniform_double(rng_key_at(rng_key_make(seed, pixel, sample), RNG_TEST, side, slot));
}

static double normal01(uint32_t seed, uint32_t pixel, uint32_t sample, uint32_t side)
{
    double u1 = uniform01(seed, pixel, sample, side, 0), u2 = uniform01(seed, pixel, sample, side, 1);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* One sample's multiplier with mean 1: Gaussian, exponential, or the square of an
 * exponential over 2 (heavy right tail, variance 5), by pixel, to resemble MC pixels. */
static double sample_factor(const synth *p, int x, int y, uint32_t seed, uint32_t pixel, uint32_t sample,
                            uint32_t side)
{
    double u;
    if (p->noise == NOISE_GAUSSIAN) return 1.0 + p->rel_sd * normal01(seed, pixel, sample, side);
    switch ((x + 2 * y) % 3) {
    case 0: return 1.0 + p->rel_sd * normal01(seed, pixel, sample, side);
    case 1: return -log(uniform01(seed, pixel, sample, side, 0));
    default: u = -log(uniform01(seed, pixel, sample, side, 0)); return 0.5 * u * u;
    }
}

/* Run `run` of side `side` (0 = A, 1 = B). */
static void synth_run(image *img, const synth *p, uint32_t seed, uint32_t side, uint32_t run)
{
    int x, y, c, s;
    for (y = 0; y < p->height; ++y)
        for (x = 0; x < p->width; ++x) {
            uint32_t pixel = (uint32_t)(y * p->width + x);
            double f = 0.0, scale = p->scale;
            for (s = 0; s < p->samples; ++s)
                f += sample_factor(p, x, y, seed, pixel, run * (uint32_t)p->samples + (uint32_t)s, side);
            f /= p->samples;
            if (p->tile_sd > 0.0) {
                uint32_t tile = 0x80000000u | (uint32_t)((y / 4) * 1024 + x / 4);
                f *= 1.0 + p->tile_sd * normal01(seed, tile, run, side);
            }
            if (x / 8 == p->local_x && y / 8 == p->local_y) scale *= p->local_scale;
            for (c = 0; c < 3; ++c) image_pixel(img, x, y)[c] = (float)(scale * true_mean(x, y, c) * f);
        }
}

/* Side from K synthetic runs. */
static int synth_side(check_side *side, const synth *p, int block, uint32_t seed, uint32_t which, int runs,
                      rerror *e)
{
    image img;
    int k;
    if (image_alloc(&img, p->width, p->height, e)) return -1;
    if (check_side_begin_runs(side, p->width, p->height, block, e)) {
        image_free(&img);
        return -1;
    }
    for (k = 0; k < runs; ++k) {
        synth_run(&img, p, seed, which, (uint32_t)k);
        if (check_side_add_run(side, &img, "synthetic", e)) break;
    }
    image_free(&img);
    if (k < runs) return -1;
    return check_side_end_runs(side, e);
}

/* The same runs summarised as a moments file set in memory (with or without run means). */
static int synth_moments_side(check_side *side, const synth *p, uint32_t seed, uint32_t which, int runs,
                              int keep_run_means, rerror *e)
{
    moments m;
    moments_file f;
    image img;
    int k;
    if (moments_init(&m, p->width, p->height, e)) return -1;
    if (image_alloc(&img, p->width, p->height, e)) return -1;
    for (k = 0; k < runs; ++k) {
        synth_run(&img, p, seed, which, (uint32_t)k);
        if (moments_add(&m, &img, "synthetic", e)) return -1;
    }
    image_free(&img);
    memset(&f, 0, sizeof f);
    if (moments_images(&m, &f.mean, &f.var, e)) return -1;
    f.runs = m.runs;
    if (keep_run_means) {
        f.run_means = m.run_means;
        m.run_means = NULL;
    }
    moments_free(&m);
    return check_side_from_moments(side, &f, "synthetic", e);
}

static int exact_side(check_side *side, const synth *p, rerror *e)
{
    image ref;
    int x, y, c;
    if (image_alloc(&ref, p->width, p->height, e)) return -1;
    for (y = 0; y < p->height; ++y)
        for (x = 0; x < p->width; ++x)
            for (c = 0; c < 3; ++c) image_pixel(&ref, x, y)[c] = (float)true_mean(x, y, c);
    return check_side_exact(side, &ref, e);
}

/* ---- trial loops ---- */

enum side_source { FROM_RUNS, FROM_MOMENTS, FROM_MOMENTS_NO_RUN_MEANS, FROM_EXACT };

typedef struct {
    int trials;
    int different;        /* verdicts "different" */
    int global_rejects;   /* image-mean test rejections (level alpha/2) */
    int block_rejects;    /* trials with >= 1 block rejection */
    int equivalent;
} tally;

static int run_trials(tally *t, int trials, const synth *pa, const synth *pb, enum side_source sa,
                      enum side_source sb, int runs_a, int runs_b, const check_options *o, uint32_t salt)
{
    int i;
    rerror e;
    memset(t, 0, sizeof *t);
    for (i = 0; i < trials; ++i) {
        uint32_t seed = test_seed() * 7919u + salt * 104729u + (uint32_t)i;
        check_side a, b;
        check_result r;
        int status = 0;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        status |= sa == FROM_RUNS ? synth_side(&a, pa, o->block_size, seed, 0, runs_a, &e)
                                  : synth_moments_side(&a, pa, seed, 0, runs_a, sa == FROM_MOMENTS, &e);
        if (sb == FROM_EXACT)
            status |= exact_side(&b, pb, &e);
        else if (sb == FROM_RUNS)
            status |= synth_side(&b, pb, o->block_size, seed, 1, runs_b, &e);
        else
            status |= synth_moments_side(&b, pb, seed, 1, runs_b, sb == FROM_MOMENTS, &e);
        if (status || check_compare(&a, &b, o, &r, &e)) {
            check_side_free(&a);
            check_side_free(&b);
            fprintf(stderr, "trial failed: %s\n", e.msg);
            return -1;
        }
        t->trials++;
        t->different += r.different;
        t->global_rejects += r.global_reject;
        t->block_rejects += r.rejected > 0;
        t->equivalent += r.tost.equivalent;
        check_result_free(&r);
        check_side_free(&a);
        check_side_free(&b);
    }
    return 0;
}

/* Accept a count of events under Binomial(n, p) if it is within `sds` standard
 * deviations (plus one count for discreteness) of n p. */
static int binomial_ok(int count, int n, double p, double sds)
{
    double mean = n * p, sd = sqrt(n * p * (1.0 - p));
    return fabs(count - mean) <= sds * sd + 1.0;
}

static void report(const char *what, const tally *t)
{
    printf("     %-44s %3d/%d different (global %d, blocks %d), equivalent %d\n", what, t->different, t->trials,
           t->global_rejects, t->block_rejects, t->equivalent);
}

/* `trials` A/A trials of p (both sides from it) at alpha = 0.1, side A from K = 8 runs
 * (sa), side B from sb (runs_b runs), reported as `what`. */
static int aa_trials(tally *t, const synth *p, int trials, enum side_source sa, enum side_source sb, int runs_b,
                     uint32_t salt, const char *what)
{
    check_options o = rt_check_options(0.1, 0);
    if (run_trials(t, trials, p, p, sa, sb, 8, runs_b, &o, salt)) return -1;
    report(what, t);
    return 0;
}

/* The calibration of the two parts of an A/A verdict at alpha = 0.1 (each at alpha/2 =
 * 0.05): image-mean rejections Binomial(n, 0.05) (within 3 sd), block rejections at most
 * that often. 0 if both hold (a test failure otherwise). */
static int expect_calibrated(const tally *t)
{
    if (!binomial_ok(t->global_rejects, t->trials, 0.05, 3.0)) {
        test_fail(__FILE__, __LINE__, "global rejections %d of %d", t->global_rejects, t->trials);
        return -1;
    }
    if (t->block_rejects > t->trials * 0.05 + 3.0 * sqrt(t->trials * 0.05) + 1) {
        test_fail(__FILE__, __LINE__, "block rejections %d", t->block_rejects);
        return -1;
    }
    return 0;
}

/* A/A: both sides from the same distribution, heavy-tailed pixels, zero-variance band,
 * K = 8 runs each. alpha = 0.1 so 200 trials resolve the rate (expected 20 if the two
 * parts were independent; each part alone at alpha/2 = 0.05, expected 10). */
TEST(check_calibration_runs)
{
    synth p = synth_default();
    tally t;
    CHECK(aa_trials(&t, &p, 200, FROM_RUNS, FROM_RUNS, 8, 1, "A/A runs, heavy tails, K=8") == 0);
    if (expect_calibrated(&t)) return;
    CHECKF(t.different <= t.trials * 0.1 + 3.0 * sqrt(t.trials * 0.09) + 1, "different %d of %d", t.different, t.trials);
}

/* B is the exact true mean image: a one-sample Welch test per block and for the mean. */
TEST(check_calibration_reference)
{
    synth p = synth_default();
    tally t;
    CHECK(aa_trials(&t, &p, 200, FROM_RUNS, FROM_EXACT, 0, 2, "runs vs exact reference, K=8") == 0);
    expect_calibrated(&t);
}

/* Moments files: with per-run means (as `render --runs` writes them) against a
 * reference with only a variance image (independent-pixel bound for the mean). */
TEST(check_calibration_moments)
{
    synth p = synth_default();
    tally t;
    CHECK(aa_trials(&t, &p, 200, FROM_MOMENTS, FROM_MOMENTS_NO_RUN_MEANS, 8, 3,
                    "moments vs moments without run means, K=8") == 0);
    CHECKF(t.global_rejects <= t.trials * 0.05 + 3.0 * sqrt(t.trials * 0.05) + 1, "global %d", t.global_rejects);
    CHECKF(t.block_rejects <= t.trials * 0.05 + 3.0 * sqrt(t.trials * 0.05) + 1, "blocks %d", t.block_rejects);
}

/* Correlated pixels (a random factor shared by each 4x4 tile, like ReSTIR's reuse):
 * raw runs stay calibrated because block and image means are taken per run. Moments
 * without per-run means must assume independent pixels and are then far too eager:
 * this is the documented limitation, and it shows the calibration check can fail. */
TEST(check_correlated_pixels)
{
    synth p = synth_default();
    tally t;
    p.tile_sd = 0.3;
    CHECK(aa_trials(&t, &p, 200, FROM_RUNS, FROM_RUNS, 8, 4, "A/A runs, correlated 4x4 tiles, K=8") == 0);
    if (expect_calibrated(&t)) return;
    CHECK(aa_trials(&t, &p, 50, FROM_MOMENTS_NO_RUN_MEANS, FROM_MOMENTS_NO_RUN_MEANS, 8, 5,
                    "same, moments without run means (expected bad)") == 0);
    CHECKF(t.different > 5 * 0.1 * t.trials, "independence assumption not detected: %d of %d", t.different, t.trials);
}

/* Power: B's mean is 0.5 % higher everywhere. 64x64 pixels, 16 runs per side, 10 %
 * per-pixel noise: the image-mean t is about 9. The bias interval must cover 0.005, and
 * the TOST must call a 0.5 % bias equivalent within 1 % but not within 0.3 %. */
TEST(check_power_global_shift)
{
    synth pa = synth_default(), pb;
    check_options o;
    tally t;
    int i, covered = 0, trials = 20;
    rerror e;
    check_options_default(&o);
    pa.width = pa.height = 64;
    pa.noise = NOISE_GAUSSIAN;
    pa.rel_sd = 0.1;
    pa.samples = 1;
    pb = pa;
    pb.scale = 1.005;
    CHECK(run_trials(&t, trials, &pa, &pb, FROM_RUNS, FROM_RUNS, 16, 16, &o, 6) == 0);
    report("0.5% shift, K=16 (power)", &t);
    CHECKF(t.different == trials, "only %d of %d called different", t.different, trials);
    for (i = 0; i < trials; ++i) {
        check_side a, b;
        check_result r;
        uint32_t seed = test_seed() * 31u + (uint32_t)i;
        CHECK(synth_side(&a, &pa, 8, seed, 0, 16, &e) == 0 && synth_side(&b, &pb, 8, seed, 1, 16, &e) == 0);
        o.margin = 0.01;
        CHECK(check_compare(&a, &b, &o, &r, &e) == 0);
        /* A is the darker side here: bias = 1/1.005 - 1. */
        covered += r.bias_ci_bounded && r.bias_lo <= 1.0 / 1.005 - 1.0 && 1.0 / 1.005 - 1.0 <= r.bias_hi;
        CHECK(r.tost.equivalent);
        check_result_free(&r);
        o.margin = 0.003;
        CHECK(check_compare(&a, &b, &o, &r, &e) == 0);
        CHECK(!r.tost.equivalent);
        check_result_free(&r);
        check_side_free(&a);
        check_side_free(&b);
    }
    /* 99 % intervals: at most 1 or 2 misses in 20. */
    CHECKF(covered >= trials - 2, "bias interval covered the truth %d of %d times", covered, trials);
}

/* Power of the block family: one 8x8 block of 16 is 40 % brighter in B (block t about
 * 10 with 16 heavy-tailed runs per side; the image mean moves by only ~2.5 %): the block
 * test must find it and name the block. */
TEST(check_power_local_defect)
{
    synth pa = synth_default(), pb;
    check_options o;
    tally t;
    rerror e;
    check_side a, b;
    check_result r;
    check_options_default(&o);
    pb = pa;
    pb.local_x = 2;
    pb.local_y = 1;
    pb.local_scale = 1.4;
    CHECK(run_trials(&t, 20, &pa, &pb, FROM_RUNS, FROM_RUNS, 16, 16, &o, 7) == 0);
    report("one block +40%, K=16 (power)", &t);
    CHECKF(t.block_rejects >= 19, "block test found the defect %d of %d times", t.block_rejects, t.trials);
    CHECK(synth_side(&a, &pa, 8, test_seed(), 0, 16, &e) == 0 && synth_side(&b, &pb, 8, test_seed(), 1, 16, &e) == 0);
    CHECK(check_compare(&a, &b, &o, &r, &e) == 0);
    CHECK(r.worst.x == 2 && r.worst.y == 1 && r.worst.z < 0.0);
    check_result_free(&r);
    o.correction = CHECK_BH; /* the false-discovery-rate correction finds it too */
    CHECK(check_compare(&a, &b, &o, &r, &e) == 0);
    CHECK(r.rejected >= 1 && r.different && r.worst.test.p <= r.block_threshold);
    check_result_free(&r);
    check_side_free(&a);
    check_side_free(&b);
}

/* Constant pixels: zero variance on both sides never divides by zero; equal constants
 * are no evidence, different constants are certain. */
TEST(check_zero_variance_pixels)
{
    check_side a, b;
    check_result r;
    check_options o;
    image img;
    rerror e;
    int k, x, y;
    check_options_default(&o);
    for (k = 0; k < 2; ++k) {
        CHECK(check_side_begin_runs(&a, 16, 8, 8, &e) == 0);
        CHECK(check_side_begin_runs(&b, 16, 8, 8, &e) == 0);
        CHECK(image_alloc(&img, 16, 8, &e) == 0);
        for (y = 0; y < 4; ++y) {
            for (x = 0; x < 16 * 8 * 3; ++x) img.px[x] = 0.25f;
            CHECK(check_side_add_run(&a, &img, "a", &e) == 0);
            if (k == 1) image_pixel(&img, 12, 3)[1] = 0.5f; /* one pixel of B differs, always */
            CHECK(check_side_add_run(&b, &img, "b", &e) == 0);
        }
        image_free(&img);
        CHECK(check_side_end_runs(&a, &e) == 0 && check_side_end_runs(&b, &e) == 0);
        CHECK(check_compare(&a, &b, &o, &r, &e) == 0);
        for (x = 0; x < 16 * 8 * 3; ++x) CHECK(isfinite(r.pixel_z.px[x]));
        if (k == 0) {
            CHECK(!r.different && r.rejected == 0 && r.global.p == 1.0);
            CHECK(r.pixel_z.px[0] == 0.0f);
        } else {
            CHECK(r.different && r.rejected == 1 && r.worst.x == 1 && r.worst.channel == 1);
            CHECK(image_pixel(&r.pixel_z, 12, 3)[1] == (float)-CHECK_Z_MAX);
        }
        check_result_free(&r);
        check_side_free(&a);
        check_side_free(&b);
    }
}

/* Longer calibration: 2000 trials per configuration, K = 4 and 16, alpha = 0.1. */
TEST_LONG(check_calibration_long)
{
    synth p = synth_default(), pc = synth_default();
    check_options o = rt_check_options(0.1, 0);
    tally t;
    int k;
    pc.tile_sd = 0.3;
    for (k = 4; k <= 16; k *= 4) {
        char what[100];
        CHECK(run_trials(&t, 2000, &p, &p, FROM_RUNS, FROM_RUNS, k, k, &o, 10) == 0);
        snprintf(what, sizeof what, "A/A runs K=%d", k);
        report(what, &t);
        CHECKF(binomial_ok(t.global_rejects, t.trials, 0.05, 3.5), "global %d of %d", t.global_rejects, t.trials);
        CHECKF(t.different <= 0.1 * t.trials + 3.5 * sqrt(0.09 * t.trials), "different %d", t.different);
        CHECK(run_trials(&t, 2000, &p, &p, FROM_RUNS, FROM_EXACT, k, 0, &o, 11) == 0);
        snprintf(what, sizeof what, "runs vs exact K=%d", k);
        report(what, &t);
        CHECKF(binomial_ok(t.global_rejects, t.trials, 0.05, 3.5), "global %d of %d", t.global_rejects, t.trials);
        CHECKF(t.different <= 0.1 * t.trials + 3.5 * sqrt(0.09 * t.trials), "different %d", t.different);
        CHECK(run_trials(&t, 2000, &pc, &pc, FROM_RUNS, FROM_RUNS, k, k, &o, 12) == 0);
        snprintf(what, sizeof what, "correlated runs K=%d", k);
        report(what, &t);
        CHECKF(binomial_ok(t.global_rejects, t.trials, 0.05, 3.5), "global %d of %d", t.global_rejects, t.trials);
        CHECKF(t.different <= 0.1 * t.trials + 3.5 * sqrt(0.09 * t.trials), "different %d", t.different);
    }
}

/* ---- moments files and the command line ---- */

typedef struct {
    const synth *p;
    uint32_t side;
} synth_files;

static void synth_side_run(void *user, int k, image *img)
{
    const synth_files *q = user;
    synth_run(img, q->p, test_seed(), q->side, (uint32_t)k);
}

/* Writes runs of a synthetic side as PREFIX_k.pfm and returns the file list "a b c". */
static int write_runs(char *list, size_t size, const synth *p, uint32_t side, int runs, const char *prefix)
{
    synth_files q;
    char stem[128];
    q.p = p;
    q.side = side;
    snprintf(stem, sizeof stem, "%s_", prefix);
    return test_write_runs(list, size, p->width, p->height, runs, stem, synth_side_run, &q);
}

TEST(check_moments_file_roundtrip)
{
    synth p = synth_default();
    moments m;
    moments_file f;
    image img;
    rerror e;
    int k;
    size_t i;
    char prefix[1100];
    snprintf(prefix, sizeof prefix, "%s", test_tmp_path("roundtrip"));
    CHECK(moments_init(&m, p.width, p.height, &e) == 0);
    CHECK(image_alloc(&img, p.width, p.height, &e) == 0);
    for (k = 0; k < 5; ++k) {
        synth_run(&img, &p, test_seed(), 0, (uint32_t)k);
        CHECK(moments_add(&m, &img, "run", &e) == 0);
    }
    CHECK(moments_write(prefix, &m, &e) == 0);
    CHECKF(moments_read(prefix, &f, &e) == 0, "%s", e.msg);
    CHECK(f.runs == 5 && f.run_means != NULL);
    for (i = 0; i < 15; ++i) CHECK(f.run_means[i] == m.run_means[i]);
    for (i = 0; i < (size_t)p.width * p.height * 3; ++i) {
        CHECK(f.mean.px[i] == (float)m.mean[i]);
        CHECK(f.var.px[i] == (float)(m.m2[i] / 4.0));
    }
    moments_file_free(&f);
    /* The .moments.json path works as well as the prefix. */
    {
        char json[1200];
        snprintf(json, sizeof json, "%s.moments.json", prefix);
        CHECK(moments_read(json, &f, &e) == 0);
        moments_file_free(&f);
    }
    /* Welford against a two-pass computation at one pixel. */
    {
        double v[5], mean, var;
        for (k = 0; k < 5; ++k) {
            synth_run(&img, &p, test_seed(), 0, (uint32_t)k);
            v[k] = image_pixel(&img, 20, 7)[1];
        }
        stats_mean_var(v, 5, &mean, &var);
        CHECK_NEAR(m.mean[3 * (7 * p.width + 20) + 1], mean, 1e-12 * fabs(mean));
        CHECK_NEAR(m.m2[3 * (7 * p.width + 20) + 1] / 4.0, var, 1e-10 * var);
    }
    /* Broken sidecars: "file: what". */
    {
        const char *bad = test_write_file("bad.moments.json", "{\"format\": \"restir-moments\", \"version\": 1,\n"
                                                              "\"runs\": 3, \"width\": 32, \"height\": 32,\n"
                                                              "\"mean\": \"roundtrip.mean.pfm\", \"var\": "
                                                              "\"roundtrip.var.pfm\", \"run_means\": [[1,2,3]]}");
        CHECK(moments_read(bad, &f, &e) != 0);
        CHECKF(strstr(e.msg, "bad.moments.json") && strstr(e.msg, "run_means"), "%s", e.msg);
        bad = test_write_file("bad2.moments.json", "{\"format\": \"restir-moments\", \"version\": 1,\n\"runs\": 3,,}");
        CHECK(moments_read(bad, &f, &e) != 0);
        CHECKF(strstr(e.msg, "bad2.moments.json:2:"), "%s", e.msg);
        bad = test_write_file("bad3.moments.json", "{\"format\": \"restir-moments\", \"version\": 1,\n"
                                                   "\"runs\": 5, \"width\": 31, \"height\": 32,\n"
                                                   "\"mean\": \"roundtrip.mean.pfm\", \"var\": \"roundtrip.var.pfm\"}");
        CHECK(moments_read(bad, &f, &e) != 0);
        CHECKF(strstr(e.msg, "roundtrip.mean.pfm") && strstr(e.msg, "31"), "%s", e.msg);
    }
    image_free(&img);
    moments_free(&m);
}

TEST(check_cli_verdicts_and_outputs)
{
    static char a_list[8192], b_list[8192], c_list[8192], out[16384];
    synth pa = synth_default(), pc;
    char json[1100], zmap[1100], zpng[1100], bz[1100];
    image z;
    rerror e;
    int status;
    /* test_tmp_path() rotates 8 buffers: keep copies. */
    snprintf(json, sizeof json, "%s", test_tmp_path("check.json"));
    snprintf(zmap, sizeof zmap, "%s", test_tmp_path("z.pfm"));
    snprintf(zpng, sizeof zpng, "%s", test_tmp_path("z.png"));
    snprintf(bz, sizeof bz, "%s", test_tmp_path("bz.pfm"));
    pc = pa;
    pc.scale = 1.3;
    CHECK(write_runs(a_list, sizeof a_list, &pa, 0, 6, "cli_a") == 0);
    CHECK(write_runs(b_list, sizeof b_list, &pa, 1, 6, "cli_b") == 0);
    CHECK(write_runs(c_list, sizeof c_list, &pc, 1, 6, "cli_c") == 0);
    remove(json);
    status = test_cli(out, sizeof out, "check --a %s --b %s --json %s --z-map %s --block-z-map %s", a_list, b_list,
                      json, zmap, bz);
    CHECKF(status == 0, "status %d: %s", status, out);
    CHECK(strstr(out, "verdict: consistent"));
    CHECK(test_file_exists(json) && test_file_exists(zmap) && test_file_exists(bz));
    CHECK(pfm_read(zmap, &z, NULL, &e) == 0 && z.width == 32 && z.height == 32);
    image_free(&z);
    CHECK(pfm_read(bz, &z, NULL, &e) == 0 && z.width == 4 && z.height == 4);
    image_free(&z);
    status = test_cli(out, sizeof out, "check --a %s --b %s --json %s --z-map %s --correction bh --quiet", a_list,
                      c_list, json, zpng);
    CHECKF(status == 1, "status %d: %s", status, out);
    CHECK(strstr(out, "verdict: different"));
    CHECK(test_file_exists(zpng));
    {
        char *text = test_read_text(json);
        CHECK(text != NULL);
        CHECK(strstr(text, "\"verdict\": \"different\"") && strstr(text, "\"exit_status\": 1"));
        CHECK(strstr(text, "\"correction\": \"bh\""));
        free(text);
    }
    /* A against its own moments file set and against an exact reference. */
    {
        moments m;
        image img;
        int k;
        char prefix[1100];
        snprintf(prefix, sizeof prefix, "%s", test_tmp_path("cli_moments"));
        CHECK(moments_init(&m, 32, 32, &e) == 0 && image_alloc(&img, 32, 32, &e) == 0);
        for (k = 0; k < 6; ++k) {
            synth_run(&img, &pa, test_seed(), 1, (uint32_t)k);
            CHECK(moments_add(&m, &img, "run", &e) == 0);
        }
        CHECK(moments_write(prefix, &m, &e) == 0);
        status = test_cli(out, sizeof out, "check --a %s --b-moments %s", a_list, prefix);
        CHECKF(status == 0, "status %d: %s", status, out);
        status = test_cli(out, sizeof out, "check --a-moments %s --b %s", prefix, c_list);
        CHECKF(status == 1, "status %d: %s", status, out);
        /* --ref with a variance: the moments' own mean and variance images. */
        status = test_cli(out, sizeof out, "check --a %s --ref %s.mean.pfm --ref-var %s.var.pfm --ref-runs 6", a_list,
                          prefix, prefix);
        CHECKF(status == 0, "status %d: %s", status, out);
        CHECK(strstr(out, "independent pixels"));
        image_free(&img);
        moments_free(&m);
    }
}

TEST(check_cli_errors_leave_no_outputs)
{
    static char a_list[8192], out[8192];
    synth pa = synth_default(), small = synth_default();
    char json[1100];
    const char *other;
    int status;
    snprintf(json, sizeof json, "%s", test_tmp_path("err.json"));
    small.width = 16;
    CHECK(write_runs(a_list, sizeof a_list, &pa, 0, 3, "err_a") == 0);
    CHECK(write_runs(out, sizeof out, &small, 0, 2, "err_small") == 0);
    remove(json);
    status = test_cli(out, sizeof out, "check --a %s --b %s --json %s", a_list, test_tmp_path("err_small_0.pfm"), json);
    CHECK(status == 2 && !test_file_exists(json));
    status = test_cli(out, sizeof out, "check --a %s --b %s %s --json %s", a_list, test_tmp_path("err_small_0.pfm"),
                      test_tmp_path("err_small_1.pfm"), json);
    CHECKF(status == 2 && strstr(out, "err_small_0.pfm: image is 16 x 32"), "%d %s", status, out);
    CHECK(!test_file_exists(json));
    status = test_cli(out, sizeof out, "check --a %s --b %s --json %s", a_list, test_tmp_path("missing.pfm"), json);
    CHECKF(status == 2 && strstr(out, "missing.pfm"), "%s", out);
    status = test_cli(out, sizeof out, "check --a %s --ref %s --ref-var x.pfm", a_list, test_tmp_path("err_a_0.pfm"));
    CHECK(status == 2);
    status = test_cli(out, sizeof out, "check --a %s --ref %s --alpha 2", a_list, test_tmp_path("err_a_0.pfm"));
    CHECK(status == 2);
    status = test_cli(out, sizeof out, "check --a %s --ref %s --frobnicate", a_list, test_tmp_path("err_a_0.pfm"));
    CHECK(status == 2 && strstr(out, "frobnicate"));
    /* A non-finite pixel is an input error naming the file and pixel. */
    {
        image img;
        rerror e;
        CHECK(image_alloc(&img, 32, 32, &e) == 0);
        image_pixel(&img, 5, 6)[2] = NAN;
        other = test_tmp_path("nan.pfm");
        CHECK(pfm_write(other, &img, &e) == 0);
        image_free(&img);
        status = test_cli(out, sizeof out, "check --a %s %s --ref %s --json %s", a_list, test_tmp_path("nan.pfm"),
                          test_tmp_path("err_a_0.pfm"), json);
        CHECKF(status == 2 && strstr(out, "nan.pfm") && strstr(out, "(5, 6)"), "%s", out);
        CHECK(!test_file_exists(json));
    }
    /* One run only. */
    status = test_cli(out, sizeof out, "check --a %s --ref %s", test_tmp_path("err_a_0.pfm"),
                      test_tmp_path("err_a_1.pfm"));
    CHECKF(status == 2 && strstr(out, "at least 2"), "%s", out);
}
