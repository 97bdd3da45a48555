/* The hostile cases of issue 27 ("nothing false"): each one exited 0 with a wrong or
 * missing result, crashed, hung or left files behind before the fix. One test per case:
 * the exit status, the message and the files left. scripts/hostile.sh runs the same cases
 * (and the older ones) through the binary and writes docs/hostile-cases.md. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "test.h"
#include "text_util.h"

#define SMALL "scenes/cornell.scene --size 16x16 --threads 2 --max-depth 4"

static char out[65536];

/* A scene file in the scratch directory (whatever the build directory) whose mesh is the
 * Cornell box by absolute path, then `rest`; returns its path (test_write_file's). */
static const char *cornell_scene(const char *name, const char *rest)
{
    static char text[8192];
    char cwd[4096];
    if (!getcwd(cwd, sizeof cwd)) cwd[0] = '\0';
    snprintf(text, sizeof text, "mesh \"%s/scenes/cornell.obj\"\n%s", cwd, rest);
    return test_write_file(name, text);
}

static int starts_with_bytes(const char *path, const char *magic, size_t n)
{
    char buf[16];
    FILE *f = fopen(path, "rb");
    size_t got = 0;
    if (f) {
        got = fread(buf, 1, n, f);
        fclose(f);
    }
    return got == n && !memcmp(buf, magic, n);
}

/* Keyframes whose interpolated up passes through zero: frame 5 had no camera basis and
 * rendered black with exit 0; now the keyframe line is a load error. */
TEST(hostile_interpolated_camera_up_through_zero)
{
    const char *pfm = test_tmp_path("hostile-up.pfm");
    const char *scene = cornell_scene("hostile-up.scene",
                                      "keyframe 0 eye 278 273 -800 target 278 273 0 up 0 1 0 fov 39\n"
                                      "keyframe 10 eye 278 273 -800 target 278 273 0 up 0 -1 0 fov 39\n"
                                      "size 8 8\n");
    char sc[1024];
    int status;
    snprintf(sc, sizeof sc, "%s", scene);
    remove(pfm);
    status = test_cli(out, sizeof out, "render %s --frame 5 --spp 1 --quiet -o %s", sc, pfm);
    CHECKF(status == 2, "status %d: %s", status, out);
    CHECKF(strstr(out, "hostile-up.scene:3:") && strstr(out, "degenerate at frame 5"), "message: %s", out);
    CHECK(!test_file_exists(pfm));
    /* frames that never pass through zero stay fine (a quarter turn of up) */
    scene = cornell_scene("hostile-up-ok.scene", "keyframe 0 eye 278 273 -800 target 278 273 0 up 0 1 0 fov 39\n"
                                                 "keyframe 10 eye 278 273 -800 target 278 273 0 up 1 0 0 fov 39\n"
                                                 "size 8 8\n");
    snprintf(sc, sizeof sc, "%s", scene);
    status = test_cli(out, sizeof out, "render %s --frame 5 --spp 1 --quiet --no-png -o %s", sc, pfm);
    CHECKF(status == 0, "status %d: %s", status, out);
}

/* A camera or vertex beyond the float geometry's range (eye 1e39, vertices at +-3e38):
 * black image, exit 0; now file:line errors. */
TEST(hostile_coordinates_out_of_range)
{
    const char *pfm = test_tmp_path("hostile-far.pfm");
    char sc[1024];
    int status;
    snprintf(sc, sizeof sc, "%s",
             cornell_scene("hostile-eye.scene", "camera eye 1e39 273 -800 target 278 273 0 up 0 1 0 fov 39\n"));
    remove(pfm);
    status = test_cli(out, sizeof out, "render %s --spp 1 --quiet -o %s", sc, pfm);
    CHECKF(status == 2 && strstr(out, "hostile-eye.scene:2: eye:") && strstr(out, "out of range"), "%d: %s", status,
           out);
    CHECK(!test_file_exists(pfm));
    test_write_file("hostile-big.obj", "v -3e38 -3e38 0\nv 3e38 -3e38 0\nv 0 3e38 0\nf 1 2 3\n");
    snprintf(sc, sizeof sc, "%s",
             test_write_file("hostile-big.scene", "mesh hostile-big.obj\n"
                                                  "camera eye 0 0 -10 target 0 0 0 up 0 1 0 fov 39\n"
                                                  "material default ke 1 1 1\n"));
    status = test_cli(out, sizeof out, "render %s --spp 1 --quiet -o %s", sc, pfm);
    CHECKF(status == 2 && strstr(out, "hostile-big.obj:1: v:") && strstr(out, "out of range"), "%d: %s", status, out);
    CHECK(!test_file_exists(pfm));
    status = test_cli(out, sizeof out, "render " SMALL " --eye 1e39,0,0 --spp 1 --quiet -o %s", pfm);
    CHECKF(status == 2 && strstr(out, "--eye"), "%d: %s", status, out);
}

/* Outputs that would overwrite each other or an input are refused before any work. */
TEST(hostile_outputs_collide)
{
    char pfm[1024], png[1024], c1[1024], c2[1024], merged_png[1024];
    int status;
    snprintf(pfm, sizeof pfm, "%s", test_tmp_path("hostile-col.pfm"));
    snprintf(png, sizeof png, "%s", test_tmp_path("hostile-col.png"));
    remove(pfm);
    remove(png);
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 --quiet -o %s --stats %s", pfm, pfm);
    CHECKF(status == 2 && strstr(out, "--stats") && strstr(out, "is also -o"), "%d: %s", status, out);
    CHECK(!test_file_exists(pfm));
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 --quiet -o %s --checkpoint %s", pfm, png);
    CHECKF(status == 2 && strstr(out, "--checkpoint") && strstr(out, "PNG preview"), "%d: %s", status, out);
    CHECK(!test_file_exists(pfm) && !test_file_exists(png));
    /* another spelling of the same file collides too */
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 --quiet --no-png -o %s --stats ./%s", pfm, pfm);
    CHECKF(status == 2 && strstr(out, "is also -o"), "%d: %s", status, out);
    /* merge -o a.ckpt a.ckpt b.ckpt replaced an input checkpoint by a PFM */
    snprintf(c1, sizeof c1, "%s", test_tmp_path("hostile-c1.ckpt"));
    snprintf(c2, sizeof c2, "%s", test_tmp_path("hostile-c2.ckpt"));
    snprintf(merged_png, sizeof merged_png, "%s", test_tmp_path("hostile-c1.png"));
    CHECK(test_cli(out, sizeof out, "render " SMALL " --spp 1 --quiet --no-png -o %s --checkpoint %s", pfm, c1) == 0);
    CHECK(test_cli(out, sizeof out, "render " SMALL " --spp 1 --sample-offset 1 --quiet --no-png -o %s --checkpoint %s",
                   pfm, c2) == 0);
    status = test_cli(out, sizeof out, "merge -o %s %s %s", c1, c1, c2);
    CHECKF(status == 2 && strstr(out, "would overwrite an input"), "%d: %s", status, out);
    CHECK(starts_with_bytes(c1, "RESTIRPT", 8));
    CHECK(!test_file_exists(merged_png));
}

/* --sample-offset with --resume was silently ignored; the mismatch message printed the
 * checkpoint's fields after freeing them (size 0x0, seed 0). */
TEST(hostile_resume_sample_offset_and_mismatch_message)
{
    char pfm[1024], ck[1024];
    int status;
    snprintf(pfm, sizeof pfm, "%s", test_tmp_path("hostile-res.pfm"));
    snprintf(ck, sizeof ck, "%s", test_tmp_path("hostile-res.ckpt"));
    CHECK(test_cli(out, sizeof out, "render " SMALL " --spp 2 --quiet --no-png -o %s --checkpoint %s", pfm, ck) == 0);
    remove(pfm);
    status = test_cli(out, sizeof out, "render " SMALL " --spp 4 --resume %s --sample-offset 100 --quiet -o %s", ck, pfm);
    CHECKF(status == 2 && strstr(out, "--sample-offset and --resume"), "%d: %s", status, out);
    CHECK(!test_file_exists(pfm));
    status = test_cli(out, sizeof out, "render " SMALL " --seed 5 --spp 4 --resume %s --quiet -o %s", ck, pfm);
    CHECKF(status == 2 && strstr(out, "(size 16x16, seed 1, fingerprint") && !strstr(out, "size 0x0"), "%d: %s",
           status, out);
}

static int count_entries(const char *dir)
{
    char cmd[1200], buf[64];
    FILE *p;
    int n = -1;
    snprintf(cmd, sizeof cmd, "find '%s' 2>/dev/null | wc -l", dir);
    p = popen(cmd, "r");
    if (p && fgets(buf, sizeof buf, p)) n = atoi(buf);
    if (p) pclose(p);
    return n;
}

/* Exit 2 after frame 0: the dump files and frames written before the error are removed. */
TEST(hostile_sequence_errors_leave_nothing)
{
    const char *dump = test_tmp_keep("hostile-dump"), *good = test_tmp_keep("hostile-dump-good");
    const char *prefix = test_tmp_keep("hostile-seq.pfm"), *frame0 = test_tmp_keep("hostile-seq.0000.pfm");
    char cmd[8192];
    int status;
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s'", dump, good);
    CHECK(system(cmd) == 0);
    status = test_cli(out, sizeof out,
                      "render " SMALL " --method restir --sequence 0..1 --dump-dir %s --dump-stages initial,bogus "
                      "--quiet --no-png -o %s", dump, prefix);
    CHECKF(status == 2 && strstr(out, "no stage 'bogus'"), "%d: %s", status, out);
    CHECKF(count_entries(dump) == 0, "%s left behind", dump);
    CHECK(!test_file_exists(frame0));
    /* a restart whose frame 1 is corrupt: frame 0's image was kept */
    CHECK(test_cli(out, sizeof out, "render " SMALL " --method restir --sequence 0..1 --dump-dir %s --quiet --no-png -o %s",
                   good, prefix) == 0);
    remove(frame0);
    snprintf(cmd, sizeof cmd, "head -c 100 '%s/frame_0001/initial.resv' > '%s.t' && mv '%s.t' '%s/frame_0001/initial.resv'",
             good, good, good, good);
    CHECK(system(cmd) == 0);
    status = test_cli(out, sizeof out,
                      "render " SMALL " --method restir --sequence 0..1 --from-dump %s --from-stage initial --quiet -o %s",
                      good, prefix);
    CHECKF(status == 2 && strstr(out, "frame_0001/initial.resv") && strstr(out, "removed"), "%d: %s", status, out);
    CHECK(!test_file_exists(frame0));
}

/* vectors --check: SIGABRT on a negative RNG input, exit 0 on an empty file, exit 1 (a
 * "difference") on a wrong input count. All are bad vectors: exit 2. */
TEST(hostile_vectors_check_bad_vectors)
{
    static const bad_input cases[] = {
        {"{\"fn\": \"rng_u\", \"case\": \"x\", \"in\": [1, 0, 0, -1, 1, 0], \"out\": [1, 0.5]}", "input 3 is -1"},
        {"{\"fn\": \"rng_u\", \"case\": \"x\", \"in\": [-1, 0, 0, 1, 1, 0], \"out\": [1, 0.5]}", "input 0 is -1"},
        {"{\"fn\": \"rng_u\", \"case\": \"x\", \"in\": [1, 0, 0, 1, 1], \"out\": [1, 0.5]}", "5 inputs do not fit"},
        {"{\"fn\": \"rng_pcg4d\", \"case\": \"x\", \"in\": [1, 2, 3, 4.5], \"out\": [1, 2, 3, 4]}", "input 3 is 4.5"},
        {"{\"fn\": \"stochastic_pairwise_weights\", \"case\": \"x\", \"in\": [1, 1, 1, 1, 1, 0.5, 2, 1, 0.3, 3, 0.9, "
         "0.35, 0.45, 0.5, -1e10], \"out\": [0]}", "expected a random number in [0, 1]"},
        {"", "no vectors"},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char path[1024], text[1024];
        int status;
        snprintf(text, sizeof text, "%s%s", cases[i].input, cases[i].input[0] ? "\n" : "");
        snprintf(path, sizeof path, "%s", test_write_file("hostile-vec.jsonl", text));
        status = test_cli(out, sizeof out, "vectors --check %s", path);
        CHECKF(status == 2 && strstr(out, cases[i].expect), "case %zu: status %d: %s", i, status, out);
    }
}

/* `vectors -o` printed nothing and needed the repository root (elsewhere: an empty
 * directory and exit 2). */
TEST(hostile_vectors_write_from_anywhere)
{
    char cwd[2048], dir[3200], cmd[16384];
    int status;
    FILE *p;
    size_t n;
    CHECK(getcwd(cwd, sizeof cwd) != NULL);
    snprintf(dir, sizeof dir, "%s/%s", cwd, test_tmp_path("hostile-elsewhere"));
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s' && cd '%s' && '%s/%s' vectors -o v 2>&1", dir, dir, dir, cwd,
             RESTIR_BIN);
    p = popen(cmd, "r");
    CHECK(p != NULL);
    n = fread(out, 1, sizeof out - 1, p);
    out[n] = '\0';
    status = pclose(p);
    CHECKF(WIFEXITED(status) && WEXITSTATUS(status) == 0, "status %d: %s", status, out);
    CHECKF(strstr(out, "wrote 14 files"), "output: %s", out);
    snprintf(cmd, sizeof cmd, "%s/v/shift.jsonl", dir);
    CHECK(test_file_exists(cmd));
}

/* /dev/urandom as a mesh grew memory without bound: now the first NUL byte stops it. */
TEST(hostile_mesh_from_endless_binary_stream)
{
    char sc[1024];
    int status;
    snprintf(sc, sizeof sc, "%s", test_write_file("hostile-urandom.scene", "mesh /dev/urandom\n"));
    status = test_cli(out, sizeof out, "info %s", sc);
    CHECKF(status == 2 && strstr(out, "/dev/urandom:") && strstr(out, "NUL byte"), "%d: %s", status, out);
    status = test_cli(out, sizeof out, "info /dev/zero");
    CHECKF(status == 2 && strstr(out, "/dev/zero:1: NUL byte"), "%d: %s", status, out);
}

/* A manifest with frames.last = 2e9 made diff-dump look for 2e9 frames (a hang). */
TEST(hostile_manifest_frame_range)
{
    char dump[1024], cmd[4096];
    int status;
    snprintf(dump, sizeof dump, "%s", test_tmp_path("hostile-manifest"));
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dump);
    CHECK(system(cmd) == 0);
    CHECK(test_cli(out, sizeof out, "render " SMALL " --method restir --sequence 0..0 --dump-dir %s --quiet --no-png -o %s",
                   dump, test_tmp_path("hostile-manifest.pfm")) == 0);
    snprintf(cmd, sizeof cmd, "sed -i 's/\"last\": 0/\"last\": 2000000000/' '%s/manifest.json'", dump);
    CHECK(system(cmd) == 0);
    status = test_cli(out, sizeof out, "diff-dump %s %s", dump, dump);
    CHECKF(status == 2 && strstr(out, "out of range"), "%d: %s", status, out);
}

/* merge --counts accepted a NaN pixel (and an infinite count). */
TEST(hostile_merge_nan_pixel)
{
    const char *a = test_tmp_keep("hostile-m1.pfm"), *b = test_tmp_keep("hostile-mnan.pfm");
    const char *m = test_tmp_keep("hostile-merged.pfm");
    char cmd[4096];
    int status;
    CHECK(test_cli(out, sizeof out, "render " SMALL " --spp 1 --quiet --no-png -o %s", a) == 0);
    /* the first pixel's red becomes a NaN (the data follow the three header lines) */
    snprintf(cmd, sizeof cmd,
             "python3 -c \"import struct;d=open('%s','rb').read();i=d.index(b'\\\\n',d.index(b'\\\\n',3)+1)+1;"
             "open('%s','wb').write(d[:i]+struct.pack('<f',float('nan'))+d[i+4:])\"", a, b);
    CHECK(system(cmd) == 0);
    remove(m);
    status = test_cli(out, sizeof out, "merge -o %s %s %s --counts 1,1 --no-png", m, a, b);
    CHECKF(status == 2 && strstr(out, "is NaN"), "%d: %s", status, out);
    CHECK(!test_file_exists(m));
    status = test_cli(out, sizeof out, "merge -o %s %s %s --counts 1,inf --no-png", m, a, b);
    CHECKF(status == 2 && strstr(out, "--counts 1,inf"), "%d: %s", status, out); /* two files: one twice is refused first */
}

/* --runs named a file that never exists (PREFIX.pfm); help --help failed. */
TEST(hostile_messages_name_real_files)
{
    char pfm[1024];
    int status;
    snprintf(pfm, sizeof pfm, "%s", test_tmp_path("hostile-runs.pfm"));
    status = test_cli(out, sizeof out, "render " SMALL " --spp 1 --runs 2 --no-png -o %s", pfm);
    CHECKF(status == 0 && strstr(out, "hostile-runs.mean.pfm") && !strstr(out, "hostile-runs.pfm"), "%d: %s", status,
           out);
    status = test_cli(out, sizeof out, "help --help");
    CHECKF(status == 0 && strstr(out, "usage: restir"), "%d: %s", status, out);
}

/* check --z-map OUT.png wrote PFM bytes into the .png (the extension was read from the
 * temporary name). */
TEST(hostile_check_z_map_png_is_png)
{
    char a[4][1024], png[1024];
    int k, status;
    for (k = 0; k < 4; ++k) {
        char name[64];
        snprintf(name, sizeof name, "hostile-z%d.pfm", k);
        snprintf(a[k], sizeof a[k], "%s", test_tmp_path(name));
        CHECK(test_cli(out, sizeof out, "render " SMALL " --spp 1 --seed %d --quiet --no-png -o %s", k + 1, a[k]) == 0);
    }
    snprintf(png, sizeof png, "%s", test_tmp_path("hostile-z.png"));
    status = test_cli(out, sizeof out, "check --a %s %s --b %s %s --z-map %s --quiet", a[0], a[1], a[2], a[3], png);
    CHECKF(status == 0 || status == 1, "%d: %s", status, out);
    CHECKF(starts_with_bytes(png, "\x89PNG", 4), "%s is not a PNG", png);
    /* and an output may not overwrite an input image */
    status = test_cli(out, sizeof out, "check --a %s %s --b %s %s --z-map %s --quiet", a[0], a[1], a[2], a[3], a[0]);
    CHECKF(status == 2 && strstr(out, "would overwrite an input"), "%d: %s", status, out);
}

/* The hostile-case table (scripts/hostile.sh, docs/hostile-cases.md) in CI: every case
 * exits with its expected status. */
TEST(hostile_table_script)
{
    char cmd[2048], *text;
    int status;
    const char *table = test_tmp_path("hostile-table.md");
    /* the binary of this build (build/float/restir in the float suite: build/restir may not exist) */
    snprintf(cmd, sizeof cmd, "HOSTILE_BIN=\"$(pwd)/%s\" HOSTILE_DIR=%s sh scripts/hostile.sh > %s 2>&1", RESTIR_BIN,
             test_tmp_path("hostile-cases"), table);
    status = system(cmd);
    text = test_read_text(table);
    CHECKF(text != NULL, "%s missing", table);
    CHECKF(status == 0 && strstr(text, " 0 with an unexpected exit status"), "status %d:\n%s", status, text);
    free(text);
}
