/* The command line: usage errors, bad input (exit 2, one "file:line:" line, no output
 * file left behind), AOV output, and byte-identical output for any thread count. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/animation.h"
#include "restir/render/gbuffer.h"
#include "restir/core/image.h"
#include "test.h"
#include "restir/core/pfm.h"
#include "restir/render/motion.h"

static char out[65536];

/* A small closed-enough scene: a floor quad, a box-ish triangle and a light. */
static const char *tiny_obj =
    "mtllib tiny.mtl\n"
    "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
    "v -0.2 1.5 -0.2\nv 0.2 1.5 -0.2\nv 0.2 1.5 0.2\nv -0.2 1.5 0.2\n"
    "v -0.5 0 0\nv 0.5 0 0\nv 0 0.8 0\n"
    "o floor\nusemtl white\nf 1 4 3 2\n"
    "o light\nusemtl light\nf 5 6 7 8\n"
    "o wedge\nusemtl white\nf 9 10 11\n";
static const char *tiny_mtl = "newmtl white\nKd 0.7 0.7 0.7\nnewmtl light\nKd 0 0 0\nKe 5 5 5\n";
static const char *tiny_scene = "mesh tiny.obj\ncamera eye 0 1 4 target 0 0.5 0 up 0 1 0 fov 45\nsize 40 30\n";

static const char *write_tiny_scene(void)
{
    test_write_file("tiny.obj", tiny_obj);
    test_write_file("tiny.mtl", tiny_mtl);
    return test_write_file("tiny.scene", tiny_scene);
}

TEST(cli_version_and_help)
{
    CHECK(test_cli(out, sizeof out, "--version") == 0);
    CHECK(strstr(out, "restir ") != NULL);
    CHECK(test_cli(out, sizeof out, "help") == 0);
    CHECK(strstr(out, "render") != NULL);
    CHECK(test_cli(out, sizeof out, "render --help") == 0);
    CHECK(strstr(out, "--threads") != NULL);
    CHECK(test_cli(out, sizeof out, "info --help") == 0);
}

TEST(cli_usage_errors_exit_2)
{
    CHECK(test_cli(out, sizeof out, "frobnicate") == 2);
    CHECK(test_cli(out, sizeof out, "render") == 2);
    CHECK(test_cli(out, sizeof out, "render x.scene --no-such-option") == 2);
    CHECK(strstr(out, "--no-such-option") != NULL);
    CHECK(test_cli(out, sizeof out, "render x.scene --size 12by4") == 2);
    CHECK(test_cli(out, sizeof out, "render x.scene --threads 0") == 2);
    CHECK(test_cli(out, sizeof out, "render x.scene --eye 1,2") == 2);
    CHECK(test_cli(out, sizeof out, "render x.scene --method warp-drive") == 2);
}

TEST(cli_missing_scene_exit_2_no_output)
{
    const char *dest = test_tmp_path("missing.pfm");
    char dest_copy[1024];
    snprintf(dest_copy, sizeof dest_copy, "%s", dest);
    remove(dest_copy);
    CHECK(test_cli(out, sizeof out, "render %s/does-not-exist.scene -o %s", test_tmpdir(), dest_copy) == 2);
    CHECKF(strstr(out, "does-not-exist.scene") != NULL, "message: %s", out);
    CHECK(strchr(out, '\n') == strrchr(out, '\n')); /* exactly one line */
    CHECK(!test_file_exists(dest_copy));
}

/* A malformed scene line is reported as file:line and nothing is written. */
TEST(cli_bad_scene_line_reported_with_line_number)
{
    char dest[1024];
    const char *path;
    write_tiny_scene();
    path = test_write_file("bad.scene", "mesh tiny.obj\nsize 40 x30\n");
    snprintf(dest, sizeof dest, "%s", test_tmp_path("bad.pfm"));
    remove(dest);
    CHECK(test_cli(out, sizeof out, "render %s -o %s", path, dest) == 2);
    CHECKF(strstr(out, "bad.scene:2:") != NULL, "message: %s", out);
    CHECK(!test_file_exists(dest));
}

TEST(cli_info_reports_scene)
{
    const char *path = write_tiny_scene();
    CHECK(test_cli(out, sizeof out, "info %s", path) == 0);
    CHECKF(strstr(out, "triangles    5") != NULL, "%s", out);
    CHECK(strstr(out, "emitters     2") != NULL);
}

TEST(cli_aov_writes_pfm_and_png)
{
    const char *path = write_tiny_scene();
    char pfm[1024], png[1024];
    const char *aovs[] = {"normal", "albedo", "depth", "object"};
    int i;
    snprintf(pfm, sizeof pfm, "%s", test_tmp_path("aov.pfm"));
    snprintf(png, sizeof png, "%s", test_tmp_path("aov.png"));
    for (i = 0; i < 4; ++i) {
        remove(pfm);
        remove(png);
        CHECKF(test_cli(out, sizeof out, "render %s --method aov --aov %s -o %s --quiet", path, aovs[i], pfm) == 0,
               "%s", out);
        CHECK(test_file_exists(pfm));
        CHECK(test_file_exists(png));
    }
}

/* --aov motion at --frame F writes what gbuffer_build_with_motion computes (R, G = motion in
 * pixels, B = prev_valid): here the moving box of scenes/shadow.scene. */
TEST(cli_aov_motion_matches_library)
{
    char pfm[1024];
    image img;
    scene s;
    gbuffer g;
    rerror e;
    int channels, x, y, moving = 0;
    snprintf(pfm, sizeof pfm, "%s", test_tmp_path("motion.pfm"));
    CHECKF(test_cli(out, sizeof out, "render scenes/shadow.scene --method aov --aov motion --frame 8 --size 24x24 -o %s --no-png --quiet",
                    pfm) == 0, "%s", out);
    CHECKF(!pfm_read(pfm, &img, &channels, &e), "%s", e.msg);
    CHECKF(!scene_load(&s, "scenes/shadow.scene", &e), "%s", e.msg);
    s.width = s.height = 24;
    CHECKF(!scene_pose_at(&s, 8, &e) && !gbuffer_build_with_motion(&g, &s, 8, 1, 0, 1, &e), "%s", e.msg);
    for (y = 0; y < 24; ++y)
        for (x = 0; x < 24; ++x) {
            const float *p = image_pixel(&img, x, y);
            const gbuffer_texel *t = gbuffer_at(&g, x, y);
            CHECK(p[0] == t->motion[0] && p[1] == t->motion[1] && p[2] == (float)t->prev_valid);
            moving += t->valid && fabsf(t->motion[0]) > 0.1f;
        }
    CHECK(moving > 4); /* the box moves about 0.125 m per frame */
    gbuffer_free(&g);
    image_free(&img);
    scene_free(&s);
}

/* `bench animation SCENE`: JSON with the per-frame posing and BVH rebuild times. */
TEST(cli_bench_animation_smoke)
{
    CHECKF(test_cli(out, sizeof out, "bench animation scenes/shadow.scene") == 0, "%s", out);
    CHECK(strstr(out, "\"pose_ms_median\"") != NULL && strstr(out, "\"animated_objects\": 1") != NULL);
}

/* Output bytes do not depend on the thread count (docs/design.md, Conventions). */
TEST(cli_threads_bit_identical)
{
    const char *path = write_tiny_scene();
    char a[1024], b[1024];
    int threads[] = {2, 7};
    int i;
    snprintf(a, sizeof a, "%s", test_tmp_path("threads1.pfm"));
    CHECK(test_cli(out, sizeof out, "render %s --threads 1 --jitter -o %s --no-png --quiet", path, a) == 0);
    for (i = 0; i < 2; ++i) {
        snprintf(b, sizeof b, "%s/threads%d.pfm", test_tmpdir(), threads[i]);
        CHECK(test_cli(out, sizeof out, "render %s --threads %d --jitter -o %s --no-png --quiet", path, threads[i],
                       b) == 0);
        CHECKF(test_files_equal(a, b), "%d threads differ from 1 thread", threads[i]);
    }
}

/* `bench rays` produces JSON with the three ray kinds (numbers are not asserted). */
TEST(cli_bench_rays_smoke)
{
    CHECKF(test_cli(out, sizeof out, "bench rays --generated 4 --size 16x16 --repeats 1 --threads 2") == 0, "%s", out);
    CHECK(strstr(out, "primary_mrays") != NULL);
    CHECK(strstr(out, "secondary_mrays") != NULL);
    CHECK(strstr(out, "shadow_mrays") != NULL);
    CHECK(test_cli(out, sizeof out, "bench warp") == 2);
}

/* The whole diff-test pipeline from the command line: `render --runs K` writes moments,
 * `check` calls NEE-only vs MIS path tracing consistent (exit 0) and rejects the
 * deliberately wrong light pdf (exit 1). */
TEST(cli_render_runs_feed_check)
{
    const char *common = "render scenes/cornell.scene --size 24x24 --spp 16 --runs 8 --quiet --max-depth 2 --no-png";
    char a[1024], b[1024], bad[1024];
    snprintf(a, sizeof a, "%s", test_tmp_path("runs-mis.pfm"));
    snprintf(b, sizeof b, "%s", test_tmp_path("runs-nee.pfm"));
    snprintf(bad, sizeof bad, "%s", test_tmp_path("runs-bad.pfm"));
    CHECK(test_cli(out, sizeof out, "%s --seed %u -o %s", common, test_seed(), a) == 0);
    CHECK(test_cli(out, sizeof out, "%s --seed %u --pt-strategy nee -o %s", common, test_seed() + 1000, b) == 0);
    CHECK(test_cli(out, sizeof out, "%s --seed %u --ablate light-pdf -o %s", common, test_seed() + 2000, bad) == 0);
    a[strlen(a) - 4] = b[strlen(b) - 4] = bad[strlen(bad) - 4] = '\0'; /* prefixes */
    CHECKF(test_cli(out, sizeof out, "check --a-moments %s --b-moments %s --quiet", a, b) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "check --a-moments %s --b-moments %s --quiet", a, bad) == 1, "%s", out);
}

/* Every kind of bad input, through `restir render`: exit status 2, exactly one line on
 * stderr that starts with the offending file (and line where there is one), and no output
 * file left behind. */
typedef struct {
    const char *file, *text; /* the scene or OBJ given to render */
    const char *expect;      /* the message must start with this (after the tmp dir) */
} bad_input_case;

static int check_bad_input(const bad_input_case *c, char *why, size_t why_size)
{
    char dest[1024], png[1024], expect[1200];
    const char *path = test_write_file(c->file, c->text);
    int status;
    snprintf(dest, sizeof dest, "%s", test_tmp_path("bad-input.pfm"));
    snprintf(png, sizeof png, "%s", test_tmp_path("bad-input.png"));
    snprintf(expect, sizeof expect, "%s/%s", test_tmpdir(), c->expect);
    remove(dest);
    remove(png);
    status = test_cli(out, sizeof out, "render %s -o %s --spp 1 --size 8x8", path, dest);
    if (status != 2) return snprintf(why, why_size, "%s: exit %d: %.900s", c->file, status, out), 0;
    if (strncmp(out, expect, strlen(expect)) != 0)
        return snprintf(why, why_size, "%s: message '%.600s' does not start with '%.600s'", c->file, out, expect), 0;
    if (strchr(out, '\n') != out + strlen(out) - 1)
        return snprintf(why, why_size, "%s: not exactly one line: %.900s", c->file, out), 0;
    if (test_file_exists(dest) || test_file_exists(png))
        return snprintf(why, why_size, "%s: an output file was left behind", c->file), 0;
    return 1;
}

TEST(cli_bad_inputs_one_line_exit_2_no_output)
{
    static const bad_input_case cases[] = {
        {"bi-missing-mesh.scene", "mesh nowhere.obj\n", "bi-missing-mesh.scene:1:"},
        {"bi-number.obj", "v 0 0 0\nv 1 0 0\nv 0 1x 0\nf 1 2 3\n", "bi-number.obj:3:"},
        {"bi-index-range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "bi-index-range.obj:4:"},
        {"bi-index-zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "bi-index-zero.obj:4:"},
        {"bi-short-face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "bi-short-face.obj:4:"},
        {"bi-nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "bi-nan.obj:2:"},
        {"bi-inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n", "bi-inf.obj:2:"},
        {"bi-directive.scene", "size 8 8\nteleport 1 2 3\n", "bi-directive.scene:2:"},
        {"bi-empty.obj", "# nothing here\nv 0 0 0\n", "bi-empty.obj"},
        {"bi-no-emitters.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bi-no-emitters.obj"},
        /* Object animation (docs/scene-format.md, animate); tiny.obj is written below. */
        {"bi-animate-order.scene", "mesh tiny.obj\nanimate wedge 4\nanimate wedge 2 translate 1 0 0\n",
         "bi-animate-order.scene:3: animate 'wedge': frame 2 after frame 4"},
        {"bi-animate-name.scene", "mesh tiny.obj\nsize 8 8\nanimate door 0\n",
         "bi-animate-name.scene:3: animate: no object named 'door'"},
        {"bi-animate-malformed.scene", "mesh tiny.obj\nanimate wedge 0 rotate 0 1 0\n",
         "bi-animate-malformed.scene:2: rotate: expected 4 numbers"},
        {"bi-animate-axis.scene", "mesh tiny.obj\nanimate wedge 0 rotate 0 0 0 45\n",
         "bi-animate-axis.scene:2: animate: rotate: the axis is zero"},
        {"bi-animate-number.scene", "mesh tiny.obj\nanimate wedge 0 translate 1 2 3x\n",
         "bi-animate-number.scene:2: translate:"},
        {"bi-animate-light.scene", "mesh tiny.obj\nanimate light 0 translate 0 1 0\n",
         "bi-animate-light.scene:2: animate: object 'light' contains an emitter"},
    };
    char why[2048];
    size_t i;
    write_tiny_scene();
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) CHECKF(check_bad_input(&cases[i], why, sizeof why), "%s", why);
}

/* An unreadable file (a directory named like a scene) and a bad PFM given to compare. */
TEST(cli_unreadable_and_bad_pfm_exit_2)
{
    char dir[1024], pfm[1024];
    snprintf(dir, sizeof dir, "%s/dir.scene", test_tmpdir());
    {
        char cmd[1200];
        snprintf(cmd, sizeof cmd, "mkdir -p '%s'", dir);
        CHECK(system(cmd) == 0);
    }
    CHECK(test_cli(out, sizeof out, "render %s --spp 1", dir) == 2);
    CHECKF(strncmp(out, dir, strlen(dir)) == 0, "%s", out);
    snprintf(pfm, sizeof pfm, "%s", test_write_file("bad.pfm", "PF\n4 4\n-1.0\nshort"));
    CHECK(test_cli(out, sizeof out, "compare %s %s", pfm, pfm) == 2);
    CHECKF(strncmp(out, pfm, strlen(pfm)) == 0, "%s", out);
}
