/* Calibration and power of the paired check (check_compare_paired, docs/statistics.md
 * "Paired check") on synthetic runs whose noise is mostly shared between run k of A and
 * run k of B (as for a reuse feature and its baseline on the same seeds): the false
 * "different" rate stays at or below alpha, and a bias the unpaired Welch check misses is
 * found. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/check.h"
#include "restir/core/image.h"
#include "restir/core/rng.h"
#include "pt_util.h"
#include "test.h"
#include "restir/core/pfm.h"

enum { PW = 16, PH = 16, PBLOCK = 4 };

static double gauss(uint32_t seed, uint32_t a, uint32_t b, uint32_t c)
{
    rng_key k = rng_key_at(rng_key_make(seed, a, b), RNG_TEST, c, 0);
    double u1 = 1.0 - rng_uniform_double(k), u2 = rng_uniform_double(rng_key_at(rng_key_make(seed, a, b), RNG_TEST, c, 1));
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* Run k of one side: pixel = mean x (1 + shared noise of run k and pixel + own noise),
 * scaled by `scale`. The shared part has sd 0.3, the side's own part sd `own`. */
static void synth_run(image *img, uint32_t seed, int k, int side, double own, double scale)
{
    int x, y, c;
    for (y = 0; y < PH; ++y)
        for (x = 0; x < PW; ++x) {
            uint32_t p = (uint32_t)(y * PW + x);
            double shared = 0.3 * gauss(seed, p, (uint32_t)k, 7), mine = own * gauss(seed, p, (uint32_t)k, 11 + (uint32_t)side);
            for (c = 0; c < 3; ++c)
                image_pixel(img, x, y)[c] = (float)(scale * (0.5 + 0.1 * c + 0.02 * x) * (1.0 + shared + mine));
        }
}

static int synth_side(check_side *s, uint32_t seed, int runs, int side, double own, double scale)
{
    image img;
    rerror e;
    int k;
    if (image_alloc(&img, PW, PH, &e) || check_side_begin_runs(s, PW, PH, PBLOCK, &e)) return -1;
    for (k = 0; k < runs; ++k) {
        synth_run(&img, seed, k, side, own, scale);
        if (check_side_add_run(s, &img, "synthetic", &e)) break;
    }
    image_free(&img);
    return k < runs || check_side_end_runs(s, &e) ? -1 : 0;
}

/* One trial: paired and unpaired verdicts of A (scaled) against B. */
static int trial(uint32_t seed, int runs, double scale, double alpha, int *paired_diff, int *unpaired_diff)
{
    check_side a, b;
    check_options o;
    check_result r;
    rerror e;
    int status = -1;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    check_options_default(&o);
    o.alpha = alpha;
    o.block_size = PBLOCK;
    if (synth_side(&a, seed, runs, 0, 0.03, scale) == 0 && synth_side(&b, seed, runs, 1, 0.03, 1.0) == 0 &&
        check_compare_paired(&a, &b, &o, &r, &e) == 0) {
        *paired_diff = r.different;
        check_result_free(&r);
        if (check_compare(&a, &b, &o, &r, &e) == 0) {
            *unpaired_diff = r.different;
            check_result_free(&r);
            status = 0;
        }
    }
    check_side_free(&a);
    check_side_free(&b);
    return status;
}

TEST(check_paired_calibration_and_power)
{
    int t, fp = 0, power_paired = 0, power_unpaired = 0, p, u;
    const int trials = 200;
    /* Null: equal means, alpha = 0.1; binomial(200, 0.1) exceeds 32 with p ~ 0.01. */
    for (t = 0; t < trials; ++t) {
        CHECKF(trial(test_seed() * 1000u + (uint32_t)t, 8, 1.0, 0.1, &p, &u) == 0, "trial %d", t);
        fp += p;
    }
    CHECKF(fp <= 32, "paired check: %d of %d equal-mean trials called different at alpha 0.1", fp, trials);
    /* Power: a 1 % bias; the shared noise (sd 0.3 per pixel) hides it from the unpaired test. */
    for (t = 0; t < 20; ++t) {
        CHECKF(trial(test_seed() * 1000u + 500u + (uint32_t)t, 8, 1.01, 1e-3, &p, &u) == 0, "trial %d", t);
        power_paired += p;
        power_unpaired += u;
    }
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  paired check: %d/%d false alarms at alpha 0.1; 1%% bias found %d/20 (paired), %d/20 (unpaired)\n",
                fp, trials, power_paired, power_unpaired);
    CHECKF(power_paired >= 19 && power_unpaired <= 10, "1%% bias: paired %d/20, unpaired %d/20", power_paired,
           power_unpaired);
}

/* Bad input: different run counts, or a side without per-run means. */
TEST(check_paired_rejects_unpaired_sides)
{
    check_side a, b;
    check_options o;
    check_result r;
    rerror e;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    check_options_default(&o);
    o.block_size = PBLOCK;
    CHECK(synth_side(&a, 1, 4, 0, 0.03, 1.0) == 0 && synth_side(&b, 1, 5, 1, 0.03, 1.0) == 0);
    CHECK(check_compare_paired(&a, &b, &o, &r, &e) != 0 && strstr(e.msg, "runs"));
    check_side_free(&a);
    check_side_free(&b);
}

/* Writes `runs` synthetic runs of one side as PFM files; list receives their names. */
typedef struct {
    uint32_t seed;
    int side;
    double scale;
} file_side;

static void file_side_run(void *user, int k, image *img)
{
    const file_side *q = user;
    synth_run(img, q->seed, k, q->side, 0.03, q->scale);
}

static int write_side(char *list, size_t n, uint32_t seed, int runs, int side, double scale, const char *stem)
{
    file_side q;
    q.seed = seed;
    q.side = side;
    q.scale = scale;
    return test_write_runs(list, n, PW, PH, runs, stem, file_side_run, &q);
}

/* restir check --paired: the 1 % bias that the unpaired check calls consistent is called
 * different, the JSON says "paired": true, and unequal run counts are a usage error. */
TEST(check_paired_cli)
{
    static char a_list[4096], b_list[4096], c_list[4096], out[16384];
    char json[1100];
    int status;
    snprintf(json, sizeof json, "%s", test_tmp_path("paired.json"));
    CHECK(write_side(a_list, sizeof a_list, 77, 8, 0, 1.01, "pa") == 0);
    CHECK(write_side(b_list, sizeof b_list, 77, 8, 1, 1.0, "pb") == 0);
    CHECK(write_side(c_list, sizeof c_list, 77, 7, 1, 1.0, "pc") == 0);
    status = test_cli(out, sizeof out, "check --a %s --b %s --block 4 --alpha 0.001", a_list, b_list);
    CHECKF(status == 0, "unpaired: status %d: %s", status, out);
    status = test_cli(out, sizeof out, "check --a %s --b %s --block 4 --alpha 0.001 --paired --json %s", a_list, b_list,
                      json);
    CHECKF(status == 1 && strstr(out, "verdict: different") && strstr(out, "paired: run k of A with run k of B"),
           "paired: status %d: %s", status, out);
    {
        char *text = test_read_text(json);
        CHECK(text != NULL);
        CHECK(strstr(text, "\"paired\": true"));
        free(text);
    }
    status = test_cli(out, sizeof out, "check --a %s --b %s --paired", a_list, c_list);
    CHECKF(status == 2 && strstr(out, "--paired"), "unequal runs: status %d: %s", status, out);
}
