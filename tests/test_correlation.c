/* Correlation under motion (issue 12; docs/correlation.md): the duplicate count is exact
 * on a constructed reservoir image, the adaptive cap is Enhanced §5's lerp, the boiling
 * filter clears exactly above (10/s - 9) x the group mean, the dual motion vector picks
 * the documented pixel on a constructed scene (analytic occluder motion), dual motion
 * vectors add no bias (paired against single on the same seeds, and --ablate
 * dual-mv-vertex is rejected by the same test), and the biased features say so. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/animation.h"
#include "restir/metrics/bias_runs.h"
#include "restir/restir/boiling_filter.h"
#include "restir/restir/duplication.h"
#include "restir/render/gbuffer.h"
#include "restir/frame/options.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/pipeline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/render/motion.h"

static char out[65536];

/* A reservoir holding initial candidate (seed, pixel, sample) with UCW W. */
static void holder(reservoir *r, uint32_t pixel, uint32_t sample, real W)
{
    reservoir_init(r);
    path_sample_begin(&r->y, 1, pixel, sample);
    r->y.length = 2;
    r->y.technique = PATH_TECH_NEE;
    path_sample_set_contribution(&r->y, rgb_make(1, 1, 1));
    r->W = W;
    r->confidence = 1;
}

/* 24 x 20 image, every pixel its own sample except: sample A at 6 pixels (a 2 x 2 block at
 * (3..4, 3..4), (10, 4) and (20, 4): the last is 16 columns from (4, 4), outside its
 * window), sample B at the 3 x 3 block (15..17, 14..16) whose centre copy has W = 0 (never
 * a duplicate), and a pixel at (0, 0) with A's pixel/seed but another sample index. */
TEST(correlation_duplicate_count_exact)
{
    enum { W = 24, H = 20 };
    reservoir *rs = calloc(W * H, sizeof *rs);
    uint16_t count[W * H], want[W * H];
    int x, y;
    CHECK(rs != NULL);
    if (!rs) return;
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x) holder(&rs[y * W + x], (uint32_t)(y * W + x), 7, 1);
    memset(want, 0, sizeof want);
    {
        static const int a[][2] = {{3, 3}, {4, 3}, {3, 4}, {4, 4}, {10, 4}, {20, 4}};
        int i, j;
        for (i = 0; i < 6; ++i) holder(&rs[a[i][1] * W + a[i][0]], 999, 3, 0.5);
        /* expected: copies within |dx|, |dy| <= 8, self excluded */
        for (i = 0; i < 6; ++i)
            for (j = 0; j < 6; ++j)
                if (i != j && abs(a[i][0] - a[j][0]) <= 8 && abs(a[i][1] - a[j][1]) <= 8)
                    want[a[i][1] * W + a[i][0]]++;
        CHECK(want[3 * W + 3] == 4 && want[4 * W + 10] == 4 && want[4 * W + 20] == 0);
    }
    for (y = 14; y <= 16; ++y)
        for (x = 15; x <= 17; ++x) {
            holder(&rs[y * W + x], 4242, 1, 2);
            want[y * W + x] = 7; /* 8 other holders, one of them with W = 0 */
        }
    rs[15 * W + 16].W = 0;
    want[15 * W + 16] = 0;
    holder(&rs[0], 999, 4, 1); /* same pixel and seed as A, different sample index: not A */
    duplication_counts(rs, W, H, DUPLICATION_RADIUS, 3, count); /* B straddles the 16 x 16 tile corner */
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x)
            CHECKF(count[y * W + x] == want[y * W + x], "pixel (%d, %d): %u duplicates, want %u", x, y,
                   count[y * W + x], want[y * W + x]);
    /* the whole window: 289 identical samples -> 288 = D 1 at the centre */
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x) holder(&rs[y * W + x], 5, 5, 1);
    duplication_counts(rs, W, H, DUPLICATION_RADIUS, 1, count);
    CHECK(count[10 * W + 12] == 288 && count[0] == 80); /* corner: 9 x 9 window minus self */
    CHECK_NEAR(duplication_score(count[10 * W + 12], DUPLICATION_RADIUS), 1.0, 0);
    {
        duplication_summary s;
        duplication_summarize(count, W * H, &s);
        CHECK(s.pixels == W * H && s.duplicated == W * H && s.count_max == 288);
    }
    free(rs);
}

/* Enhanced §5 step 3: c_cap = lerp(c_default, c_min, D^alpha). */
TEST(correlation_dedup_cap_lerp)
{
    CHECK_NEAR(duplication_cap(20, 1, 0, 0.1), 20, 0);
    CHECK_NEAR(duplication_cap(20, 1, 1, 0.1), 1, 1e-12);
    CHECK_NEAR(duplication_cap(20, 1, 0.5, 1), 10.5, 1e-12);
    CHECK_NEAR(duplication_cap(20, 1, 1.0 / 288, 0.1), 20 - 19 * pow(1.0 / 288, 0.1), 1e-12);
    CHECK_NEAR(duplication_cap(20, 1, 1.0 / 288, 0.1), 9.21514, 1e-5); /* one copy already halves it */
    CHECK_NEAR(duplication_cap(8, 2, 0.25, 0.5), 5, 1e-12);
    CHECK_NEAR(duplication_score(144, DUPLICATION_RADIUS), 0.5, 1e-15);
    CHECK_NEAR(duplication_score_denominator(DUPLICATION_RADIUS), 288, 0);
}

/* a = 10/s - 9; a reservoir is cleared iff its weight p̂ W exceeds a x the mean of the
 * group's non-zero weights. */
TEST(correlation_boiling_filter_threshold)
{
    enum { W = 20, H = 16 };
    reservoir *rs = calloc(W * H, sizeof *rs);
    int x, y;
    uint64_t cleared;
    CHECK_NEAR(boiling_multiplier(1), 1, 0);
    CHECK_NEAR(boiling_multiplier(0.2), 41, 1e-12);
    CHECK_NEAR(boiling_multiplier(0.5), 11, 1e-12);
    CHECK(boiling_multiplier(0) > 1e6); /* clamped, effectively off */
    CHECK(!boiling_rejects(11, 1, 0.5) && boiling_rejects(11.000001, 1, 0.5));
    CHECK(rs != NULL);
    if (!rs) return;
    /* group (0..15, 0..15): 240 non-empty reservoirs (row 3 emptied: empty ones are not in
     * the mean), 239 of weight 1 and one of weight v; group (16..19, 0..15): 64 of weight 1 */
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x) holder(&rs[y * W + x], (uint32_t)(y * W + x), 0, 1);
    for (x = 0; x < 16; ++x) reservoir_init(&rs[3 * W + x]);
    /* v = 11.5: mean (239 + 11.5) / 240 = 1.04375, threshold 11.48 < 11.5: cleared */
    rs[9 * W + 9].W = 11.5;
    cleared = boiling_filter(rs, W, H, BOILING_GROUP, 0.5);
    CHECK(cleared == 1 && rs[9 * W + 9].W == 0 && !path_sample_is_valid(&rs[9 * W + 9].y));
    /* v = 11.4: threshold 11.4317 > 11.4: kept */
    holder(&rs[9 * W + 9], 0, 0, 11.4);
    cleared = boiling_filter(rs, W, H, BOILING_GROUP, 0.5);
    CHECK(cleared == 0 && rs[9 * W + 9].W == (real)11.4);
    /* the 4 x 16 group at the right edge: v > 11 (63 + v) / 64 iff v > 13.0755 */
    holder(&rs[5 * W + 18], 0, 0, 13.05);
    CHECK(boiling_filter(rs, W, H, BOILING_GROUP, 0.5) == 0);
    holder(&rs[5 * W + 18], 0, 0, 13.1);
    CHECK(boiling_filter(rs, W, H, BOILING_GROUP, 0.5) == 1 && rs[5 * W + 18].W == 0);
    free(rs);
}

/* ---- dual motion vectors on a constructed scene ------------------------------------------ */

/* A wall at z = -5 and a 1 x 1 card at z = -2 (both facing +z) that slides +x by `speed`
 * per frame; a still camera at the origin looking down -z (fov 60, 48 x 32 pixels). */
static const char *dual_obj = "mtllib dual.mtl\n"
                              "o wall\nusemtl white\nv -20 -20 -5\nv 20 -20 -5\nv 20 20 -5\nv -20 20 -5\nf 1 2 3 4\n"
                              "o card\nusemtl white\nv -0.5 -0.5 -2\nv 0.5 -0.5 -2\nv 0.5 0.5 -2\nv -0.5 0.5 -2\nf 5 6 7 8\n"
                              "o light\nusemtl glow\nv -1 4 -1\nv 1 4 -1\nv 1 4 -3\nf 9 10 11\n";
static const char *dual_mtl = "newmtl white\nKd 0.7 0.7 0.7\nnewmtl glow\nKd 0 0 0\nKe 5 5 5\n";

/* Every disoccluded wall pixel whose reprojection lands on the card: the dual source is
 * the texel containing c - v, v = (speed f / 2, 0) the card's analytic screen motion (or
 * the next texel along -v if that one still shows the card: *fallbacks counts those), and
 * it is accepted there. *checked: the number of pixels checked. */
static void dual_case(double speed, int *checked, int *fallbacks)
{
    scene s;
    rerror e;
    gbuffer prev, cur;
    camera pc, cc;
    char path[1024], text[512];
    int frame = 4, x, y;
    double f, v;
    *checked = 0;
    test_write_file("dual.obj", dual_obj);
    test_write_file("dual.mtl", dual_mtl);
    snprintf(text, sizeof text,
             "mesh dual.obj\nsize 48 32\ncamera eye 0 0 0 target 0 0 -1 up 0 1 0 fov 60\n"
             "animate card 0 pivot 0 0 -2\nanimate card 10 translate %g 0 0\n",
             10 * speed);
    snprintf(path, sizeof path, "%s", test_write_file("dual.scene", text));
    CHECKF(!scene_load(&s, path, &e), "%s", e.msg);
    if (test_has_failed()) return;
    f = 0.5 * s.height / tan(30 * PI_R / 180);
    v = speed * f / 2; /* the card's screen motion per frame, pixels (+x) */
    CHECKF(!scene_prepare(&s, &e) && !scene_pose_at(&s, frame - 1, &e), "%s", e.msg);
    camera_init(&pc, scene_camera_at(&s, frame - 1), s.width, s.height);
    CHECKF(!gbuffer_build(&prev, &s, &pc, 3, (uint32_t)frame - 1, 0, 1, &e), "%s", e.msg);
    CHECKF(!scene_pose_at(&s, frame, &e), "%s", e.msg);
    camera_init(&cc, scene_camera_at(&s, frame), s.width, s.height);
    CHECKF(!gbuffer_build(&cur, &s, &cc, 3, (uint32_t)frame, 0, 1, &e), "%s", e.msg);
    CHECKF(!gbuffer_motion(&cur, &s, frame, &pc, frame - 1, &prev, NULL, 1, &e), "%s", e.msg);
    for (y = 0; y < s.height; ++y)
        for (x = 0; x < s.width; ++x) {
            const gbuffer_texel *t = gbuffer_at(&cur, x, y);
            int sx, sy, dx, dy, ok, wx, wy;
            double px;
            gbuffer_previous_pixel(t, &sx, &sy);
            ok = gbuffer_dual_previous_pixel(t, &s, frame, &cc, frame - 1, &prev, &dx, &dy);
            if (t->prev_valid || strcmp(s.object_names[t->hit.object], "wall") ||
                strcmp(s.object_names[gbuffer_at(&prev, sx, sy)->hit.object], "card")) {
                CHECKF(!ok, "pixel (%d, %d) is no disoccluded wall pixel but got a dual source", x, y);
                continue;
            }
            /* still camera: the wall's own motion is 0, so the standard source is the pixel itself */
            CHECK(sx == x && sy == y);
            px = t->pixel[0] - v;
            wx = (int)floor(px);
            wy = (int)floor(t->pixel[1]);
            if (!strcmp(s.object_names[gbuffer_at(&prev, wx, wy)->hit.object], "card")) {
                wx = (int)floor(px - 1);
                ++*fallbacks;
            }
            CHECKF(ok && dx == wx && dy == wy, "speed %g, pixel (%d, %d): dual source %s(%d, %d), want (%d, %d)",
                   speed, x, y, ok ? "" : "refused ", dx, dy, wx, wy);
            CHECK(!strcmp(s.object_names[gbuffer_at(&prev, dx, dy)->hit.object], "wall"));
            ++*checked;
        }
    gbuffer_free(&prev);
    gbuffer_free(&cur);
    scene_free(&s);
}

/* A fast card (3.1 pixels per frame: c - v lands past the edge) and a slow one (1.4 pixels:
 * c - v often lands in the edge texel, the one-pixel step of the rule is exercised). */
TEST(correlation_dual_mv_source_pixel_constructed)
{
    int fast_fallbacks = 0, slow_fallbacks = 0, fast, slow;
    dual_case(0.3, &fast, &fast_fallbacks);
    if (test_has_failed()) return;
    dual_case(0.1, &slow, &slow_fallbacks);
    if (test_has_failed()) return;
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  fast: %d pixels (%d steps), slow: %d pixels (%d steps)\n", fast, fast_fallbacks, slow,
                slow_fallbacks);
    CHECKF(fast >= 20 && slow >= 8, "only %d / %d disoccluded pixels", fast, slow);
    CHECKF(slow_fallbacks > 0, "the slow card never exercised the one-pixel step (%d pixels)", slow);
}

/* ---- dual motion vectors add no bias: paired against single ----------------------------- */

enum { MAX_FRAMES = 8 };

/* The image-mean luminance of frame `frame` of the sequence 0..frame with o; NAN if the
 * sequence failed (a test failure is recorded). */
static double frame_luminance(const scene *s, const restir_options *o, int frame)
{
    image img[MAX_FRAMES];
    size_t i, n;
    double sum = 0;
    int f;
    if (frame >= MAX_FRAMES) {
        test_fail(__FILE__, __LINE__, "frame %d: at most %d frames", frame, MAX_FRAMES - 1);
        return NAN;
    }
    if (rt_sequence_images(s, o, 0, frame, img)) return NAN;
    n = (size_t)img[frame].width * (size_t)img[frame].height;
    for (i = 0; i < n; ++i) {
        const float *p = img[frame].px + 3 * i;
        sum += luminance(rgb_make(p[0], p[1], p[2]));
    }
    for (f = 0; f <= frame; ++f) image_free(&img[f]);
    return sum / (double)n;
}

/* The options side B of a paired comparison changes against the unbiased single-MV side A. */
typedef struct {
    int motion_vectors, ablation, dedup;
    double boiling;
} variant;

/* z of the paired difference B - A of frame `frame`'s image-mean luminance over K runs
 * (same seeds: e.g. with dual MVs everything but the disoccluded pixels' history is shared). */
static double paired_z(const scene *s, int frame, int runs, const variant *v, double *rel)
{
    double sum = 0, sum2 = 0, base = 0;
    int k;
    for (k = 0; k < runs; ++k) {
        restir_options o;
        double a, b, d;
        restir_options_default(&o);
        restir_options_preset_gris_realtime(&o);
        o.candidates = 2;
        o.max_depth = 4;
        o.threads = 2;
        o.seed = test_seed() * 7717u + 13u * (uint32_t)k;
        if (isnan(a = frame_luminance(s, &o, frame))) return 0;
        o.temporal.motion_vectors = v->motion_vectors;
        o.ablation = v->ablation;
        o.correlation.dedup = v->dedup;
        o.correlation.boiling_filter = v->boiling;
        if (isnan(b = frame_luminance(s, &o, frame))) return 0;
        d = b - a;
        sum += d;
        sum2 += d * d;
        base += a;
    }
    {
        double mean = sum / runs, var = (sum2 - runs * mean * mean) / (runs - 1);
        *rel = mean / (base / runs);
        return var > 0 ? mean / sqrt(var / runs) : 0;
    }
}

TEST(correlation_dual_mv_paired_no_bias_and_ablation_detected)
{
    scene s;
    double z, zab, rel, relab;
    variant dual = {RESTIR_MV_DUAL, RESTIR_ABLATE_NONE, 0, 0}, broken = {RESTIR_MV_DUAL, RESTIR_ABLATE_DUAL_MV_VERTEX, 0, 0};
    if (rt_load_scene("scenes/pillars.scene", 32, &s)) return;
    z = paired_z(&s, 5, 24, &dual, &rel);
    zab = paired_z(&s, 5, 24, &broken, &relab);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  dual - single: z %.2f (rel %.5f); dual-mv-vertex: z %.2f (rel %.5f)\n", z, rel, zab, relab);
    CHECKF(fabs(z) < 4, "dual motion vectors differ from single: paired z %.2f (relative %.4g)", z, rel);
    CHECKF(fabs(zab) > 4, "--ablate dual-mv-vertex not detected: paired z %.2f (relative %.4g)", zab, relab);
    scene_free(&s);
}

/* The biased features say so: --help, --stats ("biased": true); --aov duplicates writes the
 * count image + heat map, and is refused without --method restir. */
TEST(correlation_cli_biased_labels_and_duplicates_aov)
{
    char prefix[1024], stats[1024], f[1200];
    snprintf(prefix, sizeof prefix, "%s", test_tmp_path("corr-dup"));
    snprintf(stats, sizeof stats, "%s", test_tmp_path("corr-stats.json"));
    CHECK(test_cli(out, sizeof out, "render --help") == 0);
    CHECK(strstr(out, "--dedup") && strstr(out, "--boiling-filter") && strstr(out, "--motion-vectors"));
    CHECK(strstr(strstr(out, "--dedup"), "BIASED") && strstr(strstr(out, "--boiling-filter"), "BIASED"));
    CHECKF(test_cli(out, sizeof out,
                    "render scenes/pillars.scene --size 16x16 --method restir --preset gris-realtime --sequence 0..2 "
                    "--dedup --boiling-filter 0.5 --motion-vectors dual --aov duplicates -o %s.pfm --stats %s --quiet",
                    prefix, stats) == 0,
           "%s", out);
    snprintf(f, sizeof f, "%s.0002.png", prefix);
    CHECK(test_file_exists(f));
    {
        FILE *fp = fopen(stats, "rb");
        size_t n = fp ? fread(out, 1, sizeof out - 1, fp) : 0;
        out[n] = '\0';
        if (fp) fclose(fp);
        CHECK(strstr(out, "\"biased\": true") && strstr(out, "\"correlation\"") && strstr(out, "\"dual_mv\""));
    }
    /* compare --bias reads runs and a reference (here: count images, only its mechanics) */
    CHECKF(test_cli(out, sizeof out, "compare --bias %s.0001.pfm %s.0002.pfm --ref %s.0002.pfm --block 2", prefix, prefix,
                    prefix) == 0,
           "%s", out);
    CHECK(strstr(out, "mean_abs_rel") && strstr(out, "noise_floor") && strstr(out, "runs 2"));
    CHECK(test_cli(out, sizeof out, "compare --bias %s.0001.pfm %s.0002.pfm", prefix, prefix) == 2 &&
          strstr(out, "--ref"));
    CHECK(test_cli(out, sizeof out, "render scenes/pillars.scene --size 16x16 --method aov --aov duplicates -o %s.pfm",
                   prefix) == 2);
    CHECK(strstr(out, "--aov applies to --method restir, not --method aov") != NULL);
    CHECK(test_cli(out, sizeof out, "render scenes/pillars.scene --size 16x16 --method restir --aov age -o %s.pfm",
                   prefix) == 2);
    CHECK(test_cli(out, sizeof out,
                   "render scenes/pillars.scene --size 16x16 --method restir --sequence 0..1 --dedup --mcap inf -o %s.pfm",
                   prefix) == 2);
    CHECK(test_cli(out, sizeof out,
                   "render scenes/pillars.scene --size 16x16 --method restir --sequence 0..1 --boiling-filter 2 -o %s.pfm",
                   prefix) == 2);
}

/* Without --stats the CLI skips the duplication map unless something reads it: --dedup's
 * cap and --aov duplicates still get it (the frames equal those rendered with --stats),
 * and a plain sequence's frames are the same bytes either way. */
TEST(correlation_duplication_map_only_when_read)
{
    static const char *const variants[] = {"--dedup", "--aov duplicates", ""};
    char a[1024], b[1024], fa[1200], fb[1200];
    size_t i;
    snprintf(a, sizeof a, "%s", test_tmp_path("corr-map-stats"));
    snprintf(b, sizeof b, "%s", test_tmp_path("corr-map-nostats"));
    for (i = 0; i < sizeof variants / sizeof variants[0]; ++i) {
        const char *common = "render scenes/pillars.scene --size 24x24 --method restir --preset gris-realtime "
                             "--sequence 0..3 --max-depth 3 --no-png --quiet";
        CHECKF(test_cli(out, sizeof out, "%s %s -o %s.pfm --stats %s.json", common, variants[i], a, a) == 0, "%s",
               out);
        CHECKF(test_cli(out, sizeof out, "%s %s -o %s.pfm", common, variants[i], b) == 0, "%s", out);
        snprintf(fa, sizeof fa, "%s.0003.pfm", a);
        snprintf(fb, sizeof fb, "%s.0003.pfm", b);
        CHECKF(test_files_equal(fa, fb), "'%s': frame 3 differs without --stats", variants[i]);
    }
}

/* compare --bias's statistics (bias_runs.h) on synthetic runs: unbiased noise measures
 * mean(|bias|/ref) at its noise floor and a rel_bias interval containing 0; a planted +3%
 * is measured as 3% with an interval that excludes 0 and lies above the floor. */
TEST(correlation_bias_over_runs_planted)
{
    enum { K = 256, B = 64 };
    double *runs = malloc(sizeof(double) * K * B), ref[B], weight[B], ref_var[B], half;
    bias_result r;
    bias_options o;
    rerror e;
    int k, j, planted;
    CHECK(runs != NULL);
    if (!runs) return;
    for (planted = 0; planted < 2; ++planted) {
        for (j = 0; j < B; ++j) {
            ref[j] = 1 + j % 5;
            weight[j] = 16;
            for (k = 0; k < K; ++k) {
                rng_key key = rng_key_make(test_seed(), (uint32_t)j, (uint32_t)k);
                double u = rng_u(key, 0, 0, 0) + rng_u(key, 0, 0, 1) + rng_u(key, 0, 0, 2) - 1.5; /* sd 0.5 */
                runs[k * B + j] = ref[j] * ((planted ? 1.03 : 1.0) + 0.4 * u);
            }
        }
        bias_options_default(&o);
        o.resamples = 200;
        o.seed = 5;
        o.level = 0.95; /* the level these bounds were set at (the default is check's 0.99) */
        CHECKF(!bias_measure(runs, ref, weight, K, B, &o, &r, &e), "%s", e.msg);
        if (getenv("RESTIR_TEST_VERBOSE"))
            fprintf(stderr, "  planted %d: rel_bias %.4f [%.4f, %.4f], mean_abs_rel %.4f corrected %.4f [%.4f, %.4f], floor %.4f\n",
                    planted, r.rel_bias.value, r.rel_bias.lo, r.rel_bias.hi, r.mean_abs_rel.value, r.corrected,
                    r.mean_abs_rel.lo, r.mean_abs_rel.hi, r.noise_floor);
        CHECK(r.runs == K && r.blocks == B);
        CHECK_NEAR(r.noise_floor, sqrt(2 / PI_R) * 0.2 / sqrt((double)K), 0.0015);
        if (!planted) {
            CHECK(r.rel_bias.lo < 0 && r.rel_bias.hi > 0);
            CHECK_NEAR(r.mean_abs_rel.value, r.noise_floor, 0.004);
            CHECK(r.corrected < r.noise_floor); /* the noise's share is taken out */
        } else {
            CHECK(r.rel_bias.lo > 0.02 && r.rel_bias.hi < 0.04);
            CHECK(r.mean_abs_rel.lo > 0.02 && r.mean_abs_rel.hi < 0.04 && r.mean_abs_rel.lo > 2 * r.noise_floor);
            CHECK_NEAR(r.corrected, 0.03, 0.004);
        }
    }
    /* A noisy reference (compare --bias --ref-moments): block variance 4x the runs' mean's,
     * so the noise floor grows by sqrt(5) and the interval of rel_bias widens. */
    half = r.rel_bias.hi - r.rel_bias.lo;
    for (j = 0; j < B; ++j) ref_var[j] = 4 * (0.2 * ref[j]) * (0.2 * ref[j]) / K;
    o.ref_var = ref_var;
    o.ref_mean_var = 4 * 0.04 * 9.0 / K / B; /* about 4x the runs' image-mean variance */
    o.ref_dof = 15;
    CHECKF(!bias_measure(runs, ref, weight, K, B, &o, &r, &e), "%s", e.msg);
    CHECK_NEAR(r.noise_floor, sqrt(2 / PI_R) * 0.2 * sqrt(5.0) / sqrt((double)K), 0.003);
    CHECKF(r.rel_bias.hi - r.rel_bias.lo > 1.5 * half, "interval %g, without the reference's noise %g",
           r.rel_bias.hi - r.rel_bias.lo, half);
    free(runs);
}

/* The biased features stay measurable (DESIGN §5): paired against the unbiased pipeline on
 * the same seeds, --dedup and the boiling filter at full strength darken the image
 * (Enhanced §5, §7.4); the image-mean difference is detected. */
TEST_LONG(correlation_dedup_and_boiling_bias_detected_long)
{
    scene s;
    variant dedup = {RESTIR_MV_SINGLE, RESTIR_ABLATE_NONE, 1, 0}, boil = {RESTIR_MV_SINGLE, RESTIR_ABLATE_NONE, 0, 1};
    double zd, zb, rd, rb;
    if (rt_load_scene("scenes/pillars.scene", 32, &s)) return;
    zd = paired_z(&s, 8, 48, &dedup, &rd);
    zb = paired_z(&s, 8, 48, &boil, &rb);
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  dedup - unbiased: z %.2f (rel %.4f); boiling 1: z %.2f (rel %.4f)\n", zd, rd, zb, rb);
    CHECKF(zd < -4, "--dedup not detected as darker: paired z %.2f (relative %.4g)", zd, rd);
    CHECKF(zb < -4, "--boiling-filter 1 not detected as darker: paired z %.2f (relative %.4g)", zb, rb);
    scene_free(&s);
}
