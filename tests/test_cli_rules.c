/* The command line's rules (docs/cli.md, "Rules for scripts"), one test each: the exit
 * status, the message on stderr and the files left behind. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include "../src/cli/output.h"
#include "restir/core/image.h"
#include "restir/render/aov.h"
#include "capture.h"
#include "test.h"
#include "text_util.h"
#include "restir/core/pfm.h"

#define SCENE "scenes/cornell.scene --size 24x20 --threads 2"
#define SMALL SCENE " --max-depth 4"

static char out[65536];

/* A render stopped by a signal: `render SMALL ARGS -o STEM.pfm` (STEM in the scratch
 * directory; ARGS may name that path once, by %s) gets SIG after SECONDS. */
typedef struct {
    const char *rule; /* the test it belongs to */
    const char *stem, *args, *sig;
    double seconds;
    const char *said[3]; /* every one in the message (%s: the stem's path; NULL: no more) */
    const char *files[3]; /* STEM + each, removed first; then all there (keep) or none */
    int keep;
} stopped_render;

/* The stopped renders of the rules below, in the order each rule runs them. pt: 1.5 s, a
 * pass must be complete before the signal (since issue 27 a signal cancels the pass in
 * progress), and under ASan on a loaded machine the first one took over 0.6 s. */
static const stopped_render stopped[] = {
    {"pt", "rule-int", "--method pt --spp 100000000 --quiet --no-png --checkpoint %s.ckpt", "INT", 1.5,
     {"interrupted by SIGINT", " spp", "%s.ckpt"}, {".pfm", ".ckpt"}, 1},
    {"pt", "rule-int", "--method pt --spp 100000000 --quiet --no-png --checkpoint %s.ckpt", "TERM", 1.5,
     {"interrupted by SIGTERM"}, {".pfm", ".ckpt"}, 1},
    {"restir", "rule-restir-int", "--method restir --frames 100000000 --quiet", "TERM", 0.6,
     {"interrupted by SIGTERM", "frame(s)"}, {".pfm", ".png"}, 1},
    {"restir", "rule-seq-int", "--method restir --sequence 0..99999999 --quiet --no-png", "INT", 0.6,
     {"interrupted by SIGINT", "frame(s)"}, {".0000.pfm"}, 1},
    {"runs", "rule-runs-int", "--method pt --spp 100000000 --runs 3 --quiet --no-png", "INT", 0.6,
     {"after 0 finished run(s)", "nothing written"}, {".mean.pfm", ".moments.json"}, 0},
    {"runs", "rule-runs-int", "--method pt --spp 1 --runs 1000000 --quiet --no-png", "TERM", 1.0,
     {"runs finished so far"}, {".mean.pfm"}, 1},
};

/* The render of c must exit with the signal's status 128 + n (SIGINT 130, SIGTERM 143), say
 * what c says and leave c's files or not; a test failure otherwise. */
static int expect_stopped(const stopped_render *c)
{
    char stem[1024], fmt[4096], args[8192], file[1100];
    int want = strcmp(c->sig, "INT") ? 143 : 130, status, i;
    snprintf(stem, sizeof stem, "%s", test_tmp_path(c->stem));
    for (i = 0; i < 3 && c->files[i]; ++i) {
        snprintf(file, sizeof file, "%s%s", stem, c->files[i]);
        remove(file);
    }
    snprintf(fmt, sizeof fmt, "render %s %s -o %%s.pfm", SMALL, c->args);
    if (strstr(c->args, "%s")) snprintf(args, sizeof args, fmt, stem, stem);
    else snprintf(args, sizeof args, fmt, stem);
    status = test_cli_signal(out, sizeof out, c->sig, c->seconds, args);
    if (status != want) {
        test_fail(__FILE__, __LINE__, "%s: status %d, expected %d: %s", args, status, want, out);
        return -1;
    }
    for (i = 0; i < 3 && c->said[i]; ++i) {
        snprintf(file, sizeof file, c->said[i], stem); /* %s: the stem's path */
        if (!strstr(out, file)) {
            test_fail(__FILE__, __LINE__, "%s: no '%s' in the message: %s", args, file, out);
            return -1;
        }
    }
    for (i = 0; i < 3 && c->files[i]; ++i) {
        snprintf(file, sizeof file, "%s%s", stem, c->files[i]);
        if (test_file_exists(file) != c->keep) {
            test_fail(__FILE__, __LINE__, "%s: %s %s", args, file, c->keep ? "missing" : "written");
            return -1;
        }
    }
    return 0;
}

/* Every stopped render of `rule`, in order, until one fails. */
static int expect_rule(const char *rule)
{
    size_t i;
    for (i = 0; i < sizeof stopped / sizeof stopped[0]; ++i)
        if (!strcmp(stopped[i].rule, rule) && expect_stopped(&stopped[i])) return -1;
    return 0;
}

/* SIGINT stops `pt` between passes: checkpoint and partial image kept, exit 130, stderr
 * says how many samples; SIGTERM gives 143. */
TEST(cli_rule_pt_interrupted_exit_130_143)
{
    expect_rule("pt");
}

/* restir follows the same rule: the mean of the frames so far (offline), or the frames
 * written so far (--sequence), and 143 / 130. */
TEST(cli_rule_restir_interrupted_exit_143)
{
    expect_rule("restir");
}

/* --runs follows it too: a run cut short is dropped (it would mix two estimators); with
 * fewer than 2 finished runs nothing is written, with more the file set holds them. */
TEST(cli_rule_runs_interrupted_keeps_finished_runs)
{
    const char *json, *r;
    char *text;
    long runs = -1;
    if (expect_rule("runs")) return;
    json = test_tmp_path("rule-runs-int.moments.json");
    text = test_read_text(json);
    CHECKF(text != NULL, "%s missing", json);
    r = strstr(text, "\"runs\":");
    if (r) runs = strtol(r + 7, NULL, 10);
    free(text);
    CHECKF(runs >= 2 && runs < 1000000, "runs in the sidecar: %ld", runs);
}

/* An option of another method is an error with a hint, before anything is written. */
TEST(cli_rule_options_of_another_method_refused)
{
    static const bad_input cases[] = {
        {"--method restir --spp 4", "--spp applies to --method pt, not --method restir (restir averages --frames"},
        {"--method pt --spatial-passes 1", "--spatial-passes applies to --method restir, not --method pt"},
        {"--method pt --preset gris-offline", "--preset applies to --method restir"},
        {"--aov depth", "--aov applies to --method aov, not --method pt (--method aov --aov CHANNEL)"},
        {"--method aov --time-limit 3", "--time-limit applies to --method pt and --method restir, not --method aov"},
        {"--method restir --checkpoint x.ckpt", "--checkpoint and --resume apply to --method pt and to --method restir with --sequence"},
    };
    const char *pfm = test_tmp_path("rule-method.pfm");
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        int status;
        remove(pfm);
        status = test_cli(out, sizeof out, "render " SCENE " %s -o %s", cases[i].input, pfm);
        CHECKF(status == 2 && strstr(out, cases[i].expect), "%s: status %d, %s", cases[i].input, status, out);
        CHECKF(!test_file_exists(pfm), "%s left %s", cases[i].input, pfm);
    }
    /* the shared rows stay valid for restir */
    CHECKF(test_cli(out, sizeof out, "render " SMALL " --method restir --max-depth 3 --time-limit 0.01 --quiet -o %s", pfm) == 0,
           "%s", out);
}

/* Output paths are checked before rendering; -o x.png is refused with a hint. */
TEST(cli_rule_output_paths_checked_first)
{
    char file[1024], bad[1200], png[1024];
    const char *pfm = test_tmp_path("rule-out.pfm");
    int status;
    snprintf(file, sizeof file, "%s", test_write_file("rule-plain-file", "x"));
    snprintf(bad, sizeof bad, "%s/a/b/c.pfm", test_tmpdir());
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 -o %s", bad);
    CHECKF(status == 2 && strstr(out, "does not exist"), "status %d: %s", status, out);
    snprintf(bad, sizeof bad, "%s/x.pfm", file);
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 -o %s", bad);
    CHECKF(status == 2 && strstr(out, "is not a directory"), "status %d: %s", status, out);
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 -o %s --stats %s/a/b/s.json", pfm, test_tmpdir());
    CHECKF(status == 2 && strstr(out, "s.json") && !test_file_exists(pfm), "status %d: %s", status, out);
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 -o %s", test_tmpdir());
    CHECKF(status == 2 && strstr(out, "is a directory"), "status %d: %s", status, out);
    snprintf(png, sizeof png, "%s", test_tmp_path("rule-out.png"));
    remove(png);
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 -o %s", png);
    CHECKF(status == 2 && strstr(out, "-o names the PFM") && strstr(out, "rule-out.pfm"), "status %d: %s", status, out);
    CHECK(!test_file_exists(png));
    snprintf(bad, sizeof bad, "%s.png", png);
    CHECK(!test_file_exists(bad));
    if (geteuid() != 0) { /* root may write anywhere */
        char cmd[1200];
        snprintf(cmd, sizeof cmd, "mkdir -p '%s/ro' && chmod 555 '%s/ro'", test_tmpdir(), test_tmpdir());
        CHECK(system(cmd) == 0);
        status = test_cli(out, sizeof out, "render " SMALL " --spp 1 -o %s/ro/x.pfm", test_tmpdir());
        CHECKF(status == 2 && strstr(out, "not writable"), "status %d: %s", status, out);
    }
}

/* A PNG that cannot be written takes the PFM of the same call with it (exit 2 leaves
 * nothing); write_outputs is what every render path writes through. */
TEST(cli_rule_png_failure_removes_pfm)
{
    image img;
    rerror e;
    char pfm[1024], png[1200];
    int status;
    snprintf(pfm, sizeof pfm, "%s", test_tmp_path("rule-png-fail.pfm"));
    snprintf(png, sizeof png, "%s/no/such/dir/x.png", test_tmpdir());
    remove(pfm);
    CHECK(image_alloc(&img, 4, 3, &e) == 0);
    capture_begin();
    status = write_outputs(&img, pfm, png, 0);
    capture_end(out, sizeof out);
    CHECK(status == 2);
    CHECKF(strstr(out, "cannot create directory") && strstr(out, "removed"), "message: %s", out);
    CHECK(!test_file_exists(pfm));
    snprintf(png, sizeof png, "%s", test_tmp_path("rule-png-ok.png"));
    CHECK(write_outputs(&img, pfm, png, 0) == 0);
    CHECK(test_file_exists(pfm) && test_file_exists(png));
    image_free(&img);
}

/* --opt=value is the same as --opt value; a flag takes no value. */
TEST(cli_rule_option_equals_value)
{
    const char *a = test_tmp_path("rule-eq-a.pfm"), *b = test_tmp_path("rule-eq-b.pfm");
    char a_copy[1024];
    snprintf(a_copy, sizeof a_copy, "%s", a);
    CHECKF(test_cli(out, sizeof out, "render " SMALL " --spp=2 --seed=7 --quiet --no-png -o %s", a_copy) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "render " SMALL " --spp 2 --seed 7 --quiet --no-png -o %s", b) == 0, "%s", out);
    CHECK(test_files_equal(a_copy, b));
    CHECK(test_cli(out, sizeof out, "render " SMALL " --no-png=1 -o %s", b) == 2);
    CHECKF(strstr(out, "--no-png takes no value"), "%s", out);
}

/* A range error states the range. */
TEST(cli_rule_range_errors_state_the_range)
{
    CHECK(test_cli(out, sizeof out, "render " SMALL " --threads 0") == 2);
    CHECKF(strstr(out, "--threads: expected a whole number from 1 to 256, got '0'"), "%s", out);
    CHECK(test_cli(out, sizeof out, "render " SMALL " --method restir --normal-cos 2") == 2);
    CHECKF(strstr(out, "--normal-cos: expected a finite number from -1 to 1, got '2'"), "%s", out);
    CHECK(test_cli(out, sizeof out, "render " SMALL " --progressive -1") == 2);
    CHECKF(strstr(out, "from 0 to 1000000000"), "%s", out);
}

/* --runs 1 has no variance: refused. */
TEST(cli_rule_runs_1_refused)
{
    const char *prefix = test_tmp_path("rule-runs1");
    char mean[1200];
    snprintf(mean, sizeof mean, "%s.mean.pfm", prefix);
    CHECK(test_cli(out, sizeof out, "render " SMALL " --spp 1 --runs 1 -o %s.pfm", prefix) == 2);
    CHECKF(strstr(out, "--runs: expected a whole number from 2 to"), "%s", out);
    CHECK(!test_file_exists(mean));
}

/* The depth preview is normalised: the farthest hit is 1, misses 0; the PFM keeps
 * scene units. */
TEST(cli_rule_depth_preview_normalised)
{
    image depth, preview;
    rerror e;
    float largest = 0, largest_preview = 0;
    size_t i, n;
    const char *pfm = test_tmp_path("rule-depth.pfm");
    char pfm_copy[1024];
    snprintf(pfm_copy, sizeof pfm_copy, "%s", pfm);
    CHECKF(test_cli(out, sizeof out, "render " SCENE " --method aov --aov depth --quiet -o %s", pfm_copy) == 0, "%s", out);
    CHECK(pfm_read(pfm_copy, &depth, NULL, &e) == 0);
    CHECK(aov_preview(&depth, AOV_DEPTH, &preview, &e) == 0);
    n = 3 * (size_t)depth.width * depth.height;
    for (i = 0; i < n; ++i) {
        if (depth.px[i] > largest) largest = depth.px[i];
        if (preview.px[i] > largest_preview) largest_preview = preview.px[i];
        CHECK(preview.px[i] >= 0 && preview.px[i] <= 1);
    }
    CHECKF(largest > 100 && largest_preview == 1, "depth up to %g (scene units), preview up to %g", largest,
           largest_preview);
    image_free(&depth);
    image_free(&preview);
}

/* inspect --preset applies the preset; an option given beside it wins in any order. */
TEST(cli_rule_inspect_applies_preset)
{
    CHECK(test_cli(out, sizeof out, "inspect scenes/cornell.scene --size 16x16 --pixel 8,8 --preset gris-offline") == 0);
    CHECKF(strstr(out, "32 path tree(s)"), "%s", out);
    CHECK(test_cli(out, sizeof out, "inspect scenes/cornell.scene --size 16x16 --pixel 8,8 --candidates 2 --preset gris-offline") == 0);
    CHECKF(strstr(out, " 2 path tree(s)"), "%s", out);
}
