/* `restir render --method pt` and `restir merge` through the command line: checkpoints
 * survive SIGINT, resume continues bit-exactly, and runs over adjacent sample ranges merge
 * into the single run. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image.h"
#include "pt_util.h"
#include "test.h"
#include "restir/core/pfm.h"

#define PT_ARGS "render scenes/cornell.scene --method pt --size 24x20 --threads 2 --quiet --no-png --max-depth 6"

static int read_pfm(const char *path, image *img)
{
    rerror e;
    if (pfm_read(path, img, NULL, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    return 0;
}

TEST(pt_cli_resume_equals_single_run)
{
    char out[4096], whole[1024], part[1024], ck[1024];
    image a, b;
    snprintf(whole, sizeof whole, "%s", test_tmp_path("ptcli-whole.pfm"));
    snprintf(part, sizeof part, "%s", test_tmp_path("ptcli-part.pfm"));
    snprintf(ck, sizeof ck, "%s", test_tmp_path("ptcli.ckpt"));
    CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp 12 -o %s", whole) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp 5 --checkpoint %s -o %s", ck, part) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp 12 --resume %s --threads 1 -o %s", ck, part) == 0, "%s", out);
    if (read_pfm(whole, &a) || read_pfm(part, &b)) return;
    CHECK(a.width == b.width && a.height == b.height);
    CHECK(memcmp(a.px, b.px, 3 * sizeof(float) * (size_t)a.width * a.height) == 0);
    image_free(&a);
    image_free(&b);
    /* A checkpoint of other options is refused with status 2. */
    CHECK(test_cli(out, sizeof out, PT_ARGS " --spp 12 --pt-strategy nee --resume %s -o %s", ck, part) == 2);
    CHECKF(strstr(out, "different scene or estimator") != NULL, "%s", out);
}

TEST(pt_cli_merge_sample_ranges)
{
    char out[4096], whole[1024], a_pfm[1024], b_pfm[1024], a_ck[1024], b_ck[1024], m1[1024], m2[1024];
    image w, x, y;
    snprintf(whole, sizeof whole, "%s", test_tmp_path("ptm-whole.pfm"));
    snprintf(a_pfm, sizeof a_pfm, "%s", test_tmp_path("ptm-a.pfm"));
    snprintf(b_pfm, sizeof b_pfm, "%s", test_tmp_path("ptm-b.pfm"));
    snprintf(a_ck, sizeof a_ck, "%s", test_tmp_path("ptm-a.ckpt"));
    snprintf(b_ck, sizeof b_ck, "%s", test_tmp_path("ptm-b.ckpt"));
    snprintf(m1, sizeof m1, "%s", test_tmp_path("ptm-m1.pfm"));
    snprintf(m2, sizeof m2, "%s", test_tmp_path("ptm-m2.pfm"));
    CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp 10 -o %s", whole) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp 4 --checkpoint %s -o %s", a_ck, a_pfm) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp 6 --sample-offset 4 --checkpoint %s -o %s", b_ck, b_pfm) == 0,
           "%s", out);
    /* Checkpoints in any order; images with their counts. */
    CHECKF(test_cli(out, sizeof out, "merge --quiet --no-png -o %s %s %s", m1, b_ck, a_ck) == 0, "%s", out);
    CHECKF(test_cli(out, sizeof out, "merge --quiet --no-png -o %s %s %s --counts 4,6", m2, a_pfm, b_pfm) == 0, "%s",
           out);
    if (read_pfm(whole, &w) || read_pfm(m1, &x) || read_pfm(m2, &y)) return;
    CHECKF(test_image_max_rel_diff(&w, &x) <= 1.2e-7, "checkpoint merge differs by %g", test_image_max_rel_diff(&w, &x));
    CHECKF(test_image_max_rel_diff(&w, &y) <= 4e-7, "image merge differs by %g", test_image_max_rel_diff(&w, &y));
    image_free(&w);
    image_free(&x);
    image_free(&y);
    /* Bad uses: missing counts, overlapping ranges. */
    CHECK(test_cli(out, sizeof out, "merge --quiet -o %s %s %s", m2, a_pfm, b_pfm) == 2);
    CHECK(test_cli(out, sizeof out, "merge --quiet -o %s %s %s", m1, a_ck, a_ck) == 2);
    CHECKF(strstr(out, "are one file") != NULL, "%s", out); /* refused before reading (issue 27's audit) */
    CHECK(test_cli(out, sizeof out, "merge --quiet -o %s %s %s", m1, b_ck, b_ck) == 2);
}

/* SIGINT between passes writes the checkpoint; resuming finishes the run exactly. */
TEST(pt_cli_sigint_checkpoint)
{
    char cmd[4096], out[4096], ck[1024], whole[1024], part[1024];
    image a, b;
    int status;
    snprintf(ck, sizeof ck, "%s", test_tmp_path("ptsig.ckpt"));
    snprintf(whole, sizeof whole, "%s", test_tmp_path("ptsig-whole.pfm"));
    snprintf(part, sizeof part, "%s", test_tmp_path("ptsig-part.pfm"));
    remove(ck);
    snprintf(cmd, sizeof cmd,
             "timeout -s INT 0.4 %s " PT_ARGS " --spp 1000000 --progressive 1 --checkpoint %s -o %s >/dev/null 2>&1",
             RESTIR_BIN, ck, part);
    status = system(cmd);
    (void)status;
    CHECKF(test_file_exists(ck), "no checkpoint after SIGINT (%s)", cmd);
    CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp 1000000 --time-limit 0.01 --resume %s --checkpoint %s -o %s", ck,
                    ck, part) == 0, "%s", out);
    {
        /* The resumed state holds some spp; a fresh run to the same count must match it. */
        FILE *f = fopen(ck, "rb");
        unsigned char h[32];
        unsigned spp;
        CHECK(f && fread(h, 1, 32, f) == 32);
        fclose(f);
        spp = (unsigned)h[28] | (unsigned)h[29] << 8 | (unsigned)h[30] << 16 | (unsigned)h[31] << 24;
        CHECK(spp >= 1);
        CHECKF(test_cli(out, sizeof out, PT_ARGS " --spp %u -o %s", spp, whole) == 0, "%s", out);
    }
    if (read_pfm(whole, &a) || read_pfm(part, &b)) return;
    CHECK(memcmp(a.px, b.px, 3 * sizeof(float) * (size_t)a.width * a.height) == 0);
    image_free(&a);
    image_free(&b);
}
