/* Image outputs follow the extension (docs/images.md, issue 29): render --sequence
 * frames, --runs moments, check --z-map/--block-z-map and compare --covariance --map
 * write OpenEXR when the name ends in .exr, with the staging rules of PFM (nothing left
 * behind on failure); a name whose extension is not writable as data is refused before
 * any work. And the EXR reader's display-window limit (a tiny file cannot ask for a
 * huge image of zeros). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "restir/core/exr.h"
#include "restir/core/image_io.h"
#include "test.h"

#define SCENE "tests/data/quad-light.scene"

static uint32_t bits_of(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* 1 if the two image files hold the same size and the same float bits (R, G and B). */
static int same_image(const char *a_path, const char *b_path)
{
    image a, b;
    rerror e;
    size_t i, n;
    int same;
    if (image_read(a_path, &a, NULL, &e)) return 0;
    if (image_read(b_path, &b, NULL, &e)) {
        image_free(&a);
        return 0;
    }
    same = a.width == b.width && a.height == b.height;
    n = (size_t)a.width * (size_t)a.height * 3;
    for (i = 0; same && i < n; ++i) same = bits_of(a.px[i]) == bits_of(b.px[i]);
    image_free(&a);
    image_free(&b);
    return same;
}

/* DIR/STEM.exr and DIR/STEM.pfm hold the same image. */
static int exr_matches_pfm(const char *dir, const char *stem)
{
    char a[700], b[700];
    snprintf(a, sizeof a, "%s/%s.exr", dir, stem);
    snprintf(b, sizeof b, "%s/%s.pfm", dir, stem);
    return same_image(a, b);
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* A fresh empty directory under the test's temporary directory. */
static const char *fresh_dir(const char *name, char *buf, size_t size)
{
    char cmd[1200];
    snprintf(buf, size, "%s", test_tmp_path(name));
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", buf, buf);
    return system(cmd) == 0 ? buf : NULL;
}

/* Number of entries of a directory (. and .. excluded). */
static int entries(const char *dir)
{
    char cmd[600], line[64] = "";
    FILE *p;
    snprintf(cmd, sizeof cmd, "ls -A '%s' | wc -l", dir);
    if (!(p = popen(cmd, "r"))) return -1;
    if (!fgets(line, sizeof line, p)) line[0] = '\0';
    pclose(p);
    return atoi(line);
}

static void remove_tree(const char *dir)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
}

/* render --sequence -o x.exr: every frame x.NNNN.exr holds the bits x.NNNN.pfm holds.
 * A frame that cannot be written (its name is a directory) makes the command exit 2
 * and remove the frames it had written. */
TEST(sequence_frames_follow_the_extension)
{
    char dir[256], out[8192], a[700], b[700];
    int f;
    const char *opts = "--method restir --preset gris-realtime --size 12x8 --sequence 0..1 --threads 1 --quiet";
    CHECK(fresh_dir("seq-exr", dir, sizeof dir) != NULL);
    CHECKF(test_cli(out, sizeof out, "render %s %s -o %s/s.exr", SCENE, opts, dir) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "render %s %s --no-png -o %s/s.pfm", SCENE, opts, dir) == 0, "%s", out);
    for (f = 0; f < 2; ++f) {
        snprintf(b, sizeof b, "s.%04d", f);
        CHECKF(exr_matches_pfm(dir, b), "%s/%s.exr differs from its .pfm", dir, b);
        snprintf(a, sizeof a, "%s/s.%04d.png", dir, f);
        CHECKF(exists(a), "no preview %s", a);
    }
    remove_tree(dir);
    CHECK(fresh_dir("seq-exr", dir, sizeof dir) != NULL);
    snprintf(a, sizeof a, "%s/s.0001.exr", dir);
    CHECK(mkdir(a, 0777) == 0);
    CHECK(test_cli(out, sizeof out, "render %s %s -o %s/s.exr", SCENE, opts, dir) == 2);
    snprintf(b, sizeof b, "%s/s.0000.exr", dir);
    CHECKF(!exists(b), "%s left behind: %s", b, out);
    CHECKF(entries(dir) == 1, "%d entries left in %s: %s", entries(dir), dir, out);
    remove_tree(dir);
}

/* render --runs -o x.exr: x.mean.exr and x.var.exr (named by the sidecar) hold the bits
 * of the PFM set, check --a-moments reads them; if one file of the set cannot be
 * written nothing of the set is left (no staged file either). */
TEST(runs_moments_follow_the_extension)
{
    char dir[256], out[8192], a[700];
    const char *opts = "--method pt --spp 2 --size 12x8 --runs 2 --threads 1 --quiet --no-png";
    CHECK(fresh_dir("runs-exr", dir, sizeof dir) != NULL);
    CHECKF(test_cli(out, sizeof out, "render %s %s -o %s/r.exr", SCENE, opts, dir) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "render %s %s -o %s/r.pfm", SCENE, opts, dir) == 0, "%s", out);
    CHECK(exr_matches_pfm(dir, "r.mean") && exr_matches_pfm(dir, "r.var"));
    CHECKF(test_cli(out, sizeof out, "check --a-moments %s/r --b-moments %s/r", dir, dir) == 0, "%s", out);
    remove_tree(dir);
    CHECK(fresh_dir("runs-exr", dir, sizeof dir) != NULL);
    snprintf(a, sizeof a, "%s/r.var.exr", dir);
    CHECK(mkdir(a, 0777) == 0);
    CHECK(test_cli(out, sizeof out, "render %s %s -o %s/r.exr", SCENE, opts, dir) == 2);
    CHECKF(entries(dir) == 1, "%d entries left in %s: %s", entries(dir), dir, out);
    remove_tree(dir);
}

/* check --z-map/--block-z-map and compare --covariance --map: .exr holds the PFM's bits. */
TEST(z_and_covariance_maps_follow_the_extension)
{
    char dir[256], out[8192], runs[1500];
    const char *opts = "--method pt --spp 2 --size 12x8 --threads 1 --quiet --no-png";
    int k;
    CHECK(fresh_dir("maps-exr", dir, sizeof dir) != NULL);
    for (k = 0; k < 4; ++k)
        CHECK(test_cli(out, sizeof out, "render %s %s --seed %d -o %s/run%d.pfm", SCENE, opts, k + 1, dir, k) == 0);
    snprintf(runs, sizeof runs, "--a %s/run0.pfm %s/run1.pfm --b %s/run2.pfm %s/run3.pfm", dir, dir, dir, dir);
    CHECKF(test_cli(out, sizeof out, "check %s --block 4 --z-map %s/z.exr --block-z-map %s/bz.exr", runs, dir,
                    dir) != 2, "%s", out);
    CHECKF(test_cli(out, sizeof out, "check %s --block 4 --z-map %s/z.pfm --block-z-map %s/bz.pfm", runs, dir,
                    dir) != 2, "%s", out);
    CHECK(exr_matches_pfm(dir, "z") && exr_matches_pfm(dir, "bz"));
    for (k = 0; k < 2; ++k)
        CHECKF(test_cli(out, sizeof out, "compare --covariance %s/run0.pfm %s/run1.pfm %s/run2.pfm --radius 2 --map %s/cov.%s",
                        dir, dir, dir, dir, k ? "pfm" : "exr") == 0, "%s", out);
    CHECK(exr_matches_pfm(dir, "cov"));
    remove_tree(dir);
}

/* A data output named in a format restir does not write is refused (exit 2, the
 * extension named) before any work: nothing appears in the directory. */
TEST(unwritable_output_extensions_refused)
{
    char dir[256], out[8192], runs[1100];
    CHECK(fresh_dir("refused-ext", dir, sizeof dir) != NULL);
    CHECK(test_cli(out, sizeof out, "render %s --size 8x6 --spp 1 -o %s/x.jpg", SCENE, dir) == 2);
    CHECKF(strstr(out, "x.jpg") && strstr(out, ".jpg"), "%s", out);
    CHECK(test_cli(out, sizeof out, "render %s --method restir --preset gris-realtime --size 8x6 --sequence 0..1 -o %s/s.TIF",
                   SCENE, dir) == 2);
    CHECKF(strstr(out, ".tif"), "%s", out);
    CHECK(test_cli(out, sizeof out, "render %s --size 8x6 --spp 1 --runs 2 -o %s/r.hdr", SCENE, dir) == 2);
    CHECK(test_cli(out, sizeof out, "render %s --size 8x6 --spp 1 -o %s/x.png", SCENE, dir) == 2);
    snprintf(runs, sizeof runs, "tests/data/images/oe_zip_half_y.exr tests/data/images/oe_piz_half_y.exr");
    CHECK(test_cli(out, sizeof out, "compare --covariance %s --map %s/c.png", runs, dir) == 2);
    CHECKF(strstr(out, "--map") && strstr(out, ".png"), "%s", out);
    CHECK(test_cli(out, sizeof out, "check --a %s --b %s --z-map %s/z.jpg", runs, runs, dir) == 2);
    CHECKF(strstr(out, "--z-map") && strstr(out, ".jpg"), "%s", out);
    CHECK(test_cli(out, sizeof out, "merge --counts 1,1 -o %s/m.webp %s", dir, runs) == 2);
    CHECKF(strstr(out, ".webp"), "%s", out);
    CHECKF(entries(dir) == 0, "%d entries in %s", entries(dir), dir);
    remove_tree(dir);
}

/* ---- the EXR display window limit ---- */

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8), p[2] = (unsigned char)(v >> 16),
    p[3] = (unsigned char)(v >> 24);
}

static size_t attr(unsigned char *p, const char *name, const char *type, const unsigned char *v, uint32_t n)
{
    size_t k = 0;
    memcpy(p, name, strlen(name) + 1), k += strlen(name) + 1;
    memcpy(p + k, type, strlen(type) + 1), k += strlen(type) + 1;
    put32(p + k, n), k += 4;
    memcpy(p + k, v, n);
    return k + n;
}

static void put_box(unsigned char *b, int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    put32(b, (uint32_t)x0), put32(b + 4, (uint32_t)y0), put32(b + 8, (uint32_t)x1), put32(b + 12, (uint32_t)y1);
}

/* A hand-made uncompressed EXR: one HALF channel Y, a 2 x 1 data window at (0,0) holding
 * 1.0 and 2.0, and the display window given (about 200 bytes whatever its size). */
static int write_tiny_exr(const char *path, int32_t dx1, int32_t dy1)
{
    unsigned char f[512], v[32], box[16];
    size_t k = 8, table;
    FILE *fp;
    memcpy(f, "\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
    memset(v, 0, sizeof v);
    v[0] = 'Y';        /* name "Y", NUL */
    put32(v + 2, 1);   /* HALF */
    put32(v + 10, 1);  /* xSampling */
    put32(v + 14, 1);  /* ySampling; v[18] = 0 ends the list */
    k += attr(f + k, "channels", "chlist", v, 19);
    v[0] = 0;
    k += attr(f + k, "compression", "compression", v, 1);
    put_box(box, 0, 0, 1, 0);
    k += attr(f + k, "dataWindow", "box2i", box, 16);
    put_box(box, 0, 0, dx1, dy1);
    k += attr(f + k, "displayWindow", "box2i", box, 16);
    k += attr(f + k, "lineOrder", "lineOrder", v, 1);
    f[k++] = 0; /* end of header */
    table = k;
    k += 8;
    memset(f + table, 0, 8);
    put32(f + table, (uint32_t)k); /* the one chunk's offset (64-bit, high half 0) */
    put32(f + k, 0), put32(f + k + 4, 4), k += 8; /* y 0, 4 bytes */
    f[k++] = 0x00, f[k++] = 0x3c, f[k++] = 0x00, f[k++] = 0x40; /* half 1.0, 2.0 */
    if (!(fp = fopen(path, "wb"))) return -1;
    if (fwrite(f, 1, k, fp) != k) {
        fclose(fp);
        return -1;
    }
    return fclose(fp);
}

/* The display window may exceed the data window by up to 2^24 pixels, or 1024 per byte
 * of the file: a 200-byte file with a 4097 x 4096 display window is refused by name
 * before anything is allocated; a 64 x 64 one reads with zeros around the data; the
 * caller's bound of exr_read_bounded refuses what exceeds it. */
TEST(exr_display_window_limit)
{
    char path[512];
    fimage img;
    rerror e;
    snprintf(path, sizeof path, "%s", test_tmp_path("tiny-display.exr"));
    CHECK(write_tiny_exr(path, 63, 63) == 0);
    CHECKF(exr_read(path, &img, &e) == 0, "%s", e.msg);
    CHECK(img.width == 64 && img.height == 64 && img.channels == 1);
    CHECK(img.px[0] == 1.0f && img.px[1] == 2.0f && img.px[2] == 0.0f && img.px[64] == 0.0f);
    fimage_free(&img);
    CHECK(exr_read_bounded(path, 64 * 64 * 4, &img, &e) == 0);
    fimage_free(&img);
    CHECK(exr_read_bounded(path, 64 * 64 * 4 - 1, &img, &e) != 0);
    CHECKF(strstr(e.msg, "bytes allowed") != NULL, "%s", e.msg);
    CHECK(write_tiny_exr(path, 4096, 4095) == 0);
    CHECK(exr_read(path, &img, &e) != 0);
    CHECKF(strstr(e.msg, "tiny-display.exr: EXR: displayWindow leaves 16781310 pixels outside the dataWindow") != NULL,
           "%s", e.msg);
    CHECK(img.px == NULL);
    /* 4096 x 4096: within 2^24, so past the limit; the caller's 1 MiB bound then refuses
     * it (the test does not allocate the 64 MiB image) */
    CHECK(write_tiny_exr(path, 4095, 4095) == 0);
    CHECKF(exr_read_bounded(path, (size_t)1 << 20, &img, &e) != 0 && strstr(e.msg, "bytes allowed"), "%s", e.msg);
    remove(path);
}
