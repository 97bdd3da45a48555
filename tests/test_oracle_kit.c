/* The golden-oracle kit (docs/oracle.md): stage dumps, restart from a dump, diff-dump.
 * Evidence: restart from every stage is bit-identical to the uninterrupted run, and
 * restart really reads the dump (a planted W changes the output); diff-dump of a run
 * against itself is 100% identical; planted differences (one pixel's W scaled in one
 * stage, one stage fed by a run with another seed) are located to that frame, stage and
 * pixel. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/oracle/dump_diff.h"
#include "restir/oracle/stage_dump.h"
#include "dump_util.h"
#include "test.h"

static char out[262144];

/* pillars: animated camera behind bars (disocclusion), 3 frames, temporal + 2 spatial passes */
#define KIT_COMMON "scenes/pillars.scene --method restir --preset gris-realtime --spatial-passes 2 --size 40x28 " \
                   "--sequence 0..2 --quiet --no-png --threads 2"
static const char *const kit_stages[] = {"initial", "temporal", "spatial1", "spatial2"};

static const char *kit_dir(const char *name) { return dump_scratch("", name); }

/* The reference run: every stage dumped into kit/A, frames kit/a.NNNN.pfm (once per run). */
static const char *reference_dump(void) { return dump_once(KIT_COMMON, test_tmp_path("a.pfm"), kit_dir("A")); }

/* Copies src to dst, multiplying W of pixel p (record p; p < 0: every pixel) by `scale`. */
static void copy_scaling_w(const char *src, const char *dst, long p, double scale)
{
    dump_scale_w(src, dst, p, scale, 0);
}

TEST(oracle_dump_layout_and_manifest)
{
    const char *a = reference_dump();
    char path[1200], *manifest;
    size_t n;
    int i;
    gbuffer g;
    uint32_t frame;
    rerror e;
    snprintf(path, sizeof path, "%s/manifest.json", a);
    manifest = test_read_text(path);
    CHECKF(manifest != NULL, "%s missing", path);
    CHECKF(strstr(manifest, "\"stage_order\": [\"initial\", \"temporal\", \"spatial1\", \"spatial2\"]") != NULL, "%s",
           manifest);
    CHECKF(strstr(manifest, "\"format\": \"restir-stage-dump\"") && strstr(manifest, "\"crc32\": \"") &&
               strstr(manifest, "\"rng_spec_version\": 1") && strstr(manifest, "\"mcap\": 20") &&
               strstr(manifest, "\"seed\": 1"),
           "%s", manifest);
    free(manifest);
    for (i = 0; i < 4; ++i) {
        stage_dump_path(path, sizeof path, a, 2, kit_stages[i], "resv");
        CHECKF(test_file_exists(path), "%s missing", path);
    }
    stage_dump_path(path, sizeof path, a, 1, "gbuffer", "gbuf");
    CHECKF(gbuffer_dump_read(path, &g, &frame, &e) == 0, "%s", e.msg);
    if (test_has_failed()) return;
    CHECK(g.width == 40 && g.height == 28 && frame == 1);
    for (i = 0, n = 0; i < 40 * 28; ++i) n += g.texels[i].valid && g.texels[i].prev_valid;
    CHECKF(n > 100, "only %d texels with history in frame 1", (int)n);
    gbuffer_free(&g);
}

/* Restart after every stage equals the uninterrupted run byte for byte (frames and the
 * restarted run's own dumps); a planted W in the dump changes the restarted output, so
 * the restart really runs on the dump. */
TEST(oracle_restart_bit_identical_from_every_stage)
{
    const char *a = reference_dump();
    char fa[1200], fb[1200];
    int i, f;
    for (i = 0; i < 4; ++i) {
        char name[64];
        snprintf(name, sizeof name, "R_%s", kit_stages[i]);
        CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/r.pfm --from-dump %s --from-stage %s --dump-dir %s",
                        test_tmpdir(), a, kit_stages[i], kit_dir(name)) == 0,
               "%s", out);
        for (f = 0; f <= 2; ++f) {
            snprintf(fa, sizeof fa, "%s/a.%04d.pfm", test_tmpdir(), f);
            snprintf(fb, sizeof fb, "%s/r.%04d.pfm", test_tmpdir(), f);
            CHECKF(test_files_equal(fa, fb), "restart from %s: frame %d differs", kit_stages[i], f);
        }
        CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", a, kit_dir(name)) == 0, "restart from %s:\n%s",
               kit_stages[i], out);
    }
    /* planted: pixel (10, 7)'s initial W x 4 in frame 1 -> the restarted frame 1 differs */
    CHECK(dump_copy(a, kit_dir("Wplant")) != NULL);
    stage_dump_path(fa, sizeof fa, a, 1, "initial", "resv");
    stage_dump_path(fb, sizeof fb, kit_dir("Wplant"), 1, "initial", "resv");
    copy_scaling_w(fa, fb, 7 * 40 + 10, 4.0);
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/p.pfm --from-dump %s --from-stage initial",
                    test_tmpdir(), kit_dir("Wplant")) == 0,
           "%s", out);
    snprintf(fa, sizeof fa, "%s/a.0001.pfm", test_tmpdir());
    snprintf(fb, sizeof fb, "%s/p.0001.pfm", test_tmpdir());
    CHECKF(!test_files_equal(fa, fb), "a W planted in the initial dump did not change the restarted frame 1");
    snprintf(fa, sizeof fa, "%s/a.0000.pfm", test_tmpdir());
    snprintf(fb, sizeof fb, "%s/p.0000.pfm", test_tmpdir());
    CHECKF(test_files_equal(fa, fb), "frame 0 changed although the plant is in frame 1");
}

TEST(oracle_diff_dump_self_is_identical)
{
    const char *a = reference_dump();
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --json", a, a) == 0, "%s", out);
    CHECKF(strstr(out, "\"same_sample\": 1,") && !strstr(out, "\"pass\": false") && strstr(out, "\"pass\": true}"),
           "%s", out);
}

/* One pixel's W scaled by 1.5 in frame 1's spatial1 dump: exit 1, located to frame 1,
 * stage spatial1, pixel 23,11, and to nothing else. */
TEST(oracle_diff_dump_finds_planted_w)
{
    const char *a = reference_dump();
    char src[1200], dst[1200];
    /* a stale P from an earlier run: frame 2's spatial2 dump with every W doubled; the fresh
     * copy must replace it (with `cp -r A P` it stayed and a second row differed) */
    CHECK(dump_copy(a, kit_dir("P")) != NULL);
    stage_dump_path(src, sizeof src, a, 2, "spatial2", "resv");
    stage_dump_path(dst, sizeof dst, kit_dir("P"), 2, "spatial2", "resv");
    copy_scaling_w(src, dst, -1, 2.0);
    CHECK(dump_copy(a, kit_dir("P")) != NULL);
    stage_dump_path(src, sizeof src, a, 1, "spatial1", "resv");
    stage_dump_path(dst, sizeof dst, kit_dir("P"), 1, "spatial1", "resv");
    copy_scaling_w(src, dst, 11 * 40 + 23, 1.5);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", a, kit_dir("P")) == 1, "%s", out);
    CHECKF(strstr(out, "first difference: frame 1, stage spatial1, pixel 23,11") != NULL, "%s", out);
    CHECKF(strstr(out, "--pixel 23,11 --seed 1 --first-frame 1") != NULL, "%s", out);
    {
        /* exactly one row differs */
        const char *p = out;
        int rows = 0;
        while ((p = strstr(p, "DIFFERS")) != NULL) ++rows, ++p;
        CHECKF(rows == 1, "%d rows differ:\n%s", rows, out);
    }
    /* a tolerance above the planted error passes */
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --max-rel-w 0.34", a, kit_dir("P")) == 0, "%s", out);
}

/* Stage `temporal` fed by a run with seed 2 (restart from that run's temporal dump): the
 * initial rows stay identical, the first difference is frame 0, stage temporal. */
TEST(oracle_diff_dump_finds_stage_with_other_seed)
{
    const char *a = reference_dump();
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " --seed 2 -o %s/s2.pfm --dump-dir %s --dump-stages temporal",
                    test_tmpdir(), kit_dir("S2")) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/b.pfm --from-dump %s --from-stage temporal --dump-dir %s",
                    test_tmpdir(), kit_dir("S2"), kit_dir("B")) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", a, kit_dir("B")) == 1, "%s", out);
    CHECKF(strstr(out, "first difference: frame 0, stage temporal") != NULL, "%s", out);
    CHECKF(strstr(out, "frame    0 initial      same 1.000000") && strstr(out, "frame    2 initial      same 1.000000"),
           "%s", out);
    /* the statistical mode sees the same estimator: means agree within |z| <= 4 */
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", a, kit_dir("B")) == 0, "%s", out);
}

/* The statistical mode, for builds with another RNG: a run with seed 2 agrees with seed 1
 * in every stage (|z| <= 4), and the same run with every W of frame 1's spatial1 scaled by
 * 1.5 is flagged at that frame and stage (z about -7 at 40 x 28). A 10% scale is NOT found at
 * this size (docs/oracle.md §3: the mode sees gross errors only). */
TEST(oracle_diff_dump_stat_finds_scaled_stage)
{
    const char *a = reference_dump();
    char src[1200], dst[1200], cmd[4000];
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " --seed 2 -o %s/t2.pfm --dump-dir %s", test_tmpdir(),
                    kit_dir("T2")) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", a, kit_dir("T2")) == 0, "%s", out);
    snprintf(cmd, sizeof cmd, "rm -rf %s && cp -r %s %s", kit_dir("T2s"), kit_dir("T2"), kit_dir("T2s"));
    CHECK(system(cmd) == 0);
    stage_dump_path(src, sizeof src, kit_dir("T2"), 1, "spatial1", "resv");
    stage_dump_path(dst, sizeof dst, kit_dir("T2s"), 1, "spatial1", "resv");
    copy_scaling_w(src, dst, -1, 1.5);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", a, kit_dir("T2s")) == 1, "%s", out);
    CHECKF(strstr(out, "first difference: frame 1, stage spatial1") != NULL, "%s", out);
}

TEST(oracle_kit_bad_input)
{
    const char *a = reference_dump();
    CHECK(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/x.pfm --from-dump %s --from-stage mutate",
                   test_tmpdir(), a) == 2);
    CHECKF(strstr(out, "no stage 'mutate' (its stages: initial,temporal,spatial1,spatial2)") != NULL, "%s", out);
    CHECK(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/x.pfm --dump-dir %s --dump-stages initial,Spatial1",
                   test_tmpdir(), kit_dir("bad")) == 2);
    CHECKF(strstr(out, "not a stage name") != NULL, "%s", out);
    CHECK(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/x.pfm --from-dump %s", test_tmpdir(), a) == 2);
    CHECK(test_cli(out, sizeof out, "render scenes/pillars.scene --method restir --quiet -o %s/x.pfm --dump-dir %s",
                   test_tmpdir(), kit_dir("bad")) == 2);
    CHECKF(strstr(out, "need --sequence") != NULL, "%s", out);
    CHECK(test_cli(out, sizeof out, "diff-dump %s %s", a, kit_dir("nonexistent")) == 2);
    CHECK(test_cli(out, sizeof out, "diff-dump %s", a) == 2);
}

/* A G-buffer dump whose header claims more texels than the file holds is refused before
 * anything is allocated (the fuzzer's finding: a 32-byte file claiming 8000 x 8000 made
 * the reader allocate 7 GB, and 65536 x 65536 460 GB), and so is one with bytes after the
 * last texel; the exact length is read. */
static const char *gbuffer_file(const char *name, uint32_t w, uint32_t h, size_t texels, size_t extra)
{
    static char path[1200];
    unsigned char head[GBUFFER_DUMP_HEADER_SIZE], *p = head;
    const uint32_t fields[7] = {GBUFFER_DUMP_VERSION, GBUFFER_DUMP_HEADER_SIZE, GBUFFER_DUMP_RECORD_SIZE, 0, 0, 3, 0};
    size_t i;
    FILE *fp;
    memcpy(p, GBUFFER_DUMP_MAGIC, 8);
    for (i = 0; i < 6; ++i) { /* little-endian u32: version, sizes, width, height, frame */
        uint32_t v = i == 3 ? w : i == 4 ? h : fields[i];
        p[8 + 4 * i] = (unsigned char)v, p[9 + 4 * i] = (unsigned char)(v >> 8);
        p[10 + 4 * i] = (unsigned char)(v >> 16), p[11 + 4 * i] = (unsigned char)(v >> 24);
    }
    snprintf(path, sizeof path, "%s/%s", test_tmpdir(), name);
    if (!(fp = fopen(path, "wb"))) return path;
    fwrite(head, 1, sizeof head, fp);
    for (i = 0; i < texels * GBUFFER_DUMP_RECORD_SIZE + extra; ++i) fputc(0, fp);
    fclose(fp);
    return path;
}

TEST(oracle_gbuffer_dump_length_checked_before_allocating)
{
    gbuffer g;
    uint32_t frame;
    rerror e;
    CHECK(gbuffer_dump_read(gbuffer_file("huge.gbuf", 8000, 8000, 0, 0), &g, &frame, &e) != 0);
    CHECKF(strstr(e.msg, "file has 32 bytes, the header implies") != NULL, "%s", e.msg);
    CHECK(gbuffer_dump_read(gbuffer_file("long.gbuf", 2, 1, 2, 1), &g, &frame, &e) != 0);
    CHECKF(strstr(e.msg, "file has 249 bytes, the header implies 248") != NULL, "%s", e.msg);
    CHECKF(gbuffer_dump_read(gbuffer_file("exact.gbuf", 2, 1, 2, 0), &g, &frame, &e) == 0, "%s", e.msg);
    if (test_has_failed()) return;
    CHECK(g.width == 2 && g.height == 1 && frame == 3);
    gbuffer_free(&g);
}

/* A manifest number beyond +-2^53 is refused by name before its conversion to long (the
 * fuzzer's finding: "y": 1e33 was converted, undefined behaviour). */
TEST(oracle_manifest_huge_number_refused)
{
    char dir[1200], path[1300];
    stage_manifest *m = malloc(sizeof *m);
    FILE *fp;
    rerror e;
    snprintf(dir, sizeof dir, "%s/manifest-huge", test_tmpdir());
    snprintf(path, sizeof path, "mkdir -p '%s'", dir);
    CHECK(m && system(path) == 0);
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    fp = fopen(path, "w");
    CHECK(fp != NULL);
    if (!fp || !m) {
        free(m);
        return;
    }
    fputs("{\"format\": \"restir-stage-dump\", \"frames\": {\"first\": 0, \"last\": 1},\n"
          "\"stage_order\": [\"initial\"], \"region\": {\"x\": 0, \"y\": 1e33, \"width\": 1, \"height\": 1}}\n",
          fp);
    fclose(fp);
    CHECK(stage_manifest_read(dir, m, &e) != 0);
    CHECKF(strstr(e.msg, "manifest.json:2: number 1e+33 is out of range") != NULL, "%s", e.msg);
    free(m);
}

/* Unit checks of the comparison itself. */
TEST(oracle_dump_diff_unit)
{
    reservoir a[2], b[2];
    dump_diff_tolerance t;
    dump_diff_result r;
    rerror e;
    dump_diff_tolerance_default(&t);
    reservoir_init(&a[0]);
    reservoir_init(&a[1]);
    path_sample_begin(&a[1].y, 1, 5, 7);
    a[1].y.length = 3;
    a[1].y.technique = PATH_TECH_NEE;
    a[1].W = 2;
    a[1].y.target = 0.5;
    a[1].confidence = 1;
    b[0] = a[0];
    b[1] = a[1];
    CHECK(dump_diff(a, b, 2, 1, &t, &r, &e) == 0 && r.same == 2 && dump_diff_pass(&r, &t));
    dump_diff_result_free(&r);
    b[1].y.sample = 8; /* another tree: another sample */
    CHECK(dump_diff(a, b, 2, 1, &t, &r, &e) == 0 && r.same == 1 && !dump_diff_pass(&r, &t) && r.n_first == 1 &&
          r.firsts[0].x == 1 && r.firsts[0].kind == DUMP_PIXEL_OTHER);
    dump_diff_result_free(&r);
    b[1] = a[1];
    b[1].y.technique = PATH_TECH_BSDF; /* same tree, other candidate */
    CHECK(!dump_same_sample(&a[1].y, &b[1].y));
    b[1] = a[1];
    b[1].W = (real)(2 * (1 + 1e-6));
    CHECK(dump_diff(a, b, 2, 1, &t, &r, &e) == 0 && !dump_diff_pass(&r, &t));
    dump_diff_result_free(&r);
    t.max_rel[DF_W] = 1e-5;
    CHECK(dump_diff(a, b, 2, 1, &t, &r, &e) == 0 && dump_diff_pass(&r, &t));
    dump_diff_result_free(&r);
    CHECK(dump_rel_error(0, 0) == 0 && dump_rel_error(1, 0) == 1 && dump_rel_error(2, 1) == 0.5);
}

/* Restart starts after S for real: the stages at or before S are not computed (the --stats
 * counters of initial and temporal stay 0 when restarting from spatial1), and a dump that
 * holds only S's files and the manifest (what a GPU build that dumps one pass hands over)
 * restarts bit-identically too. */
TEST(oracle_restart_skips_earlier_stages)
{
    const char *a = reference_dump();
    char cmd[4000], fa[1200], fb[1200], stats[1200];
    static char json[262144];
    FILE *f;
    size_t n;
    int fr;
    snprintf(stats, sizeof stats, "%s/skip.json", test_tmpdir());
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/s.pfm --from-dump %s --from-stage spatial1 --stats %s",
                    test_tmpdir(), a, stats) == 0,
           "%s", out);
    f = fopen(stats, "rb");
    CHECK(f != NULL);
    if (!f) return;
    n = fread(json, 1, sizeof json - 1, f);
    fclose(f);
    json[n] = '\0';
    CHECKF(strstr(json, "\"initial\": {\"pixels\": 0,") && strstr(json, "\"temporal\": {\"pixels\": 0,"),
           "initial or temporal ran although the restart is from spatial1:\n%.2000s", json);
    /* only spatial1 and the manifest */
    snprintf(cmd, sizeof cmd, "rm -rf %s && mkdir -p %s && cp %s/manifest.json %s/", kit_dir("only1"), kit_dir("only1"),
             a, kit_dir("only1"));
    CHECK(system(cmd) == 0);
    for (fr = 0; fr <= 2; ++fr) {
        snprintf(cmd, sizeof cmd, "mkdir -p %s/frame_%04d && cp %s/frame_%04d/spatial1.resv %s/frame_%04d/",
                 kit_dir("only1"), fr, a, fr, kit_dir("only1"), fr);
        CHECK(system(cmd) == 0);
    }
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/o.pfm --from-dump %s --from-stage spatial1",
                    test_tmpdir(), kit_dir("only1")) == 0,
           "%s", out);
    for (fr = 0; fr <= 2; ++fr) {
        snprintf(fa, sizeof fa, "%s/a.%04d.pfm", test_tmpdir(), fr);
        snprintf(fb, sizeof fb, "%s/o.%04d.pfm", test_tmpdir(), fr);
        CHECKF(test_files_equal(fa, fb), "restart from a dump of spatial1 alone: frame %d differs", fr);
    }
    /* a dump without the manifest cannot be restarted from (its stage order is unknown) */
    snprintf(cmd, sizeof cmd, "rm %s/manifest.json", kit_dir("only1"));
    CHECK(system(cmd) == 0);
    CHECK(test_cli(out, sizeof out, "render " KIT_COMMON " -o %s/o.pfm --from-dump %s --from-stage spatial1",
                   test_tmpdir(), kit_dir("only1")) == 2);
    CHECKF(strstr(out, "manifest.json") != NULL, "%s", out);
}

/* The `reproduce:` arguments diff-dump lists for a differing pixel of an `initial` stage
 * make `restir inspect` print exactly that pixel's reservoir from A (W and p̂ to 17 digits),
 * also in a later frame of the animated scene (its camera and pose at --first-frame). */
TEST(oracle_diff_dump_reproduce_arguments_reproduce)
{
    const char *a = reference_dump();
    static char diff[262144];
    char args[2048], *p, *q;
    double w_a, t_a, w_i, t_i;
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " --seed 3 -o %s/s3.pfm --dump-dir %s", test_tmpdir(),
                    kit_dir("S3")) == 0,
           "%s", out);
    CHECK(test_cli(diff, sizeof diff, "diff-dump %s %s --json --first 1", a, kit_dir("S3")) == 1);
    p = strstr(diff, "{\"frame\": 2, \"stage\": \"initial\"");
    CHECKF(p != NULL, "%.3000s", diff);
    if (!p) return;
    p = strstr(p, "\"first_differing\": [{");
    CHECK(p != NULL);
    if (!p) return;
    w_a = strtod(strstr(p, "\"W\": [") + 6, NULL);
    t_a = strtod(strstr(p, "\"target\": [") + 11, NULL);
    p = strstr(p, "\"inspect_args\": \"");
    CHECK(p != NULL);
    if (!p) return;
    p += strlen("\"inspect_args\": \"");
    q = strchr(p, '"');
    CHECK(q != NULL && (size_t)(q - p) < sizeof args);
    if (!q || (size_t)(q - p) >= sizeof args) return;
    memcpy(args, p, (size_t)(q - p));
    args[q - p] = '\0';
    CHECKF(strstr(args, "--first-frame 2") && strstr(args, "--size 40x28"), "%s", args);
    CHECKF(test_cli(out, sizeof out, "inspect %s --json", args) == 0, "%s\n%s", args, out);
    p = strstr(out, "\"initial\": {");
    CHECKF(p != NULL, "%s", out);
    if (!p) return;
    w_i = strtod(strstr(p, "\"W\": ") + 5, NULL);
    t_i = strtod(strstr(p, "\"target\": ") + 10, NULL);
    CHECKF(w_i == w_a && t_i == t_a, "inspect %s: W %.17g p^ %.17g, the dump has W %.17g p^ %.17g", args, w_i, t_i, w_a,
           t_a);
}

/* The statistical mode also compares the mean confidence and the non-empty fraction: a build
 * with another RNG and a wrong M-cap (2 instead of the preset's 20) has the same image means
 * of luminance(F) W (|z| < 1) but is found at a temporal stage (mean c: z = +4.1 in frame 1,
 * +14.9 in frame 2), which the F W test alone passes. */
TEST(oracle_diff_dump_stat_finds_wrong_mcap)
{
    const char *a = reference_dump();
    CHECKF(test_cli(out, sizeof out, "render " KIT_COMMON " --seed 2 --mcap 2 -o %s/m2.pfm --dump-dir %s", test_tmpdir(),
                    kit_dir("M2")) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s --stat", a, kit_dir("M2")) == 1, "%s", out);
    CHECKF(strstr(out, "first difference: frame ") && strstr(out, ", stage temporal\n"), "%s", out);
}
