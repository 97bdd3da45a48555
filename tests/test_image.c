/* Images: PFM read/write (both byte orders, real third-party files, malformed input)
 * and the PNG writer (checksums, and the file's structure decoded independently). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/checksum.h"
#include "restir/core/image.h"
#include "pt_util.h"
#include "test.h"
#include "restir/core/pfm.h"
#include "restir/core/png.h"

#define SHARED_PFM "../shared/data/pfm"

static int write_bytes(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    size_t n;
    if (!f) return -1;
    n = fwrite(data, 1, size, f);
    fclose(f);
    return n == size ? 0 : -1;
}

static unsigned char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    size_t cap = 0, n = 0;
    if (!f) return NULL;
    for (;;) {
        size_t got;
        if (n == cap) {
            unsigned char *grown = realloc(buf, cap ? 2 * cap : 65536);
            if (!grown) break;
            buf = grown;
            cap = cap ? 2 * cap : 65536;
        }
        got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0) break;
    }
    fclose(f);
    *size = n;
    return buf;
}

/* A deterministic test image with awkward values: negative, tiny, huge, fractions. */
static void fill_pattern(image *img)
{
    int x, y, c;
    for (y = 0; y < img->height; ++y)
        for (x = 0; x < img->width; ++x)
            for (c = 0; c < 3; ++c)
                image_pixel(img, x, y)[c] = (float)((x + 1) * 0.37 - (y * 3 + c) * 1.1e-3) * (c == 2 ? -1e20f : 1.0f);
    image_pixel(img, 0, 0)[0] = 1e-40f; /* a denormal survives bit-exactly */
}

static int images_bit_equal(const image *a, const image *b)
{
    return a->width == b->width && a->height == b->height &&
           memcmp(a->px, b->px, sizeof(float) * 3 * (size_t)a->width * (size_t)a->height) == 0;
}

TEST(pfm_roundtrip_bit_exact)
{
    image a, b;
    rerror e;
    int channels = 0;
    const char *path = test_tmp_path("roundtrip.pfm");
    char copy[1024];
    snprintf(copy, sizeof copy, "%s", path);
    CHECK(image_alloc(&a, 7, 5, &e) == 0);
    fill_pattern(&a);
    CHECKF(pfm_write(copy, &a, &e) == 0, "%s", e.msg);
    CHECKF(pfm_read(copy, &b, &channels, &e) == 0, "%s", e.msg);
    CHECK(channels == 3);
    CHECK(images_bit_equal(&a, &b));
    image_free(&a);
    image_free(&b);
}

/* The writer's exact bytes: header, little-endian floats, rows bottom to top. */
TEST(pfm_writer_layout)
{
    image a;
    rerror e;
    size_t size = 0;
    unsigned char *bytes;
    static const char header[] = "PF\n1 2\n-1.0\n";
    char copy[1024];
    snprintf(copy, sizeof copy, "%s", test_tmp_path("layout.pfm"));
    CHECK(image_alloc(&a, 1, 2, &e) == 0);
    image_pixel(&a, 0, 0)[0] = 1.0f; /* top row: 1.0 = 0x3f800000 */
    image_pixel(&a, 0, 1)[0] = 2.0f; /* bottom row: 2.0 = 0x40000000, stored first */
    CHECK(pfm_write(copy, &a, &e) == 0);
    image_free(&a);
    bytes = read_all(copy, &size);
    CHECK(bytes);
    CHECKF(size == strlen(header) + 24, "size %zu", size);
    CHECK(memcmp(bytes, header, strlen(header)) == 0);
    CHECK(bytes[12] == 0x00 && bytes[13] == 0x00 && bytes[14] == 0x00 && bytes[15] == 0x40);
    CHECK(bytes[24] == 0x00 && bytes[25] == 0x00 && bytes[26] == 0x80 && bytes[27] == 0x3f);
    free(bytes);
}

/* A big-endian file written by hand, a greyscale one, and free-form whitespace. */
TEST(pfm_read_big_endian_and_greyscale)
{
    /* 2x1 RGB, big-endian (scale +1): left = (1, 2, -0.5), right = (0.25, 0, 3) */
    static const unsigned char be_rgb[] = {'P', 'F', '\n', '2', ' ', '1', '\n', '1', '.', '0', '\n',
                                           0x3f, 0x80, 0, 0, 0x40, 0, 0, 0, 0xbf, 0, 0, 0,
                                           0x3e, 0x80, 0, 0, 0, 0, 0, 0, 0x40, 0x40, 0, 0};
    /* 1x2 greyscale, little-endian, arbitrary whitespace between tokens, |scale| != 1:
     * the bottom row (stored first) is 4.0, the top row 0.5. */
    static const unsigned char le_grey[] = {'P', 'f', ' ', '\t', '\r', '\n', '1', '\n', '\n', ' ', '2',
                                            ' ', ' ', '-', '2', '.', '5', 'e', '0', '\t',
                                            0, 0, 0x80, 0x40, 0, 0, 0, 0x3f};
    image img;
    rerror e;
    int channels = 0;
    char path[1024];
    snprintf(path, sizeof path, "%s", test_tmp_path("be.pfm"));
    CHECK(write_bytes(path, be_rgb, sizeof be_rgb) == 0);
    CHECKF(pfm_read(path, &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(channels == 3 && img.width == 2 && img.height == 1);
    CHECK(img.px[0] == 1.0f && img.px[1] == 2.0f && img.px[2] == -0.5f);
    CHECK(img.px[3] == 0.25f && img.px[4] == 0.0f && img.px[5] == 3.0f);
    image_free(&img);

    snprintf(path, sizeof path, "%s", test_tmp_path("grey.pfm"));
    CHECK(write_bytes(path, le_grey, sizeof le_grey) == 0);
    CHECKF(pfm_read(path, &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(channels == 1 && img.width == 1 && img.height == 2);
    CHECK(image_pixel(&img, 0, 0)[0] == 0.5f && image_pixel(&img, 0, 0)[2] == 0.5f);
    CHECK(image_pixel(&img, 0, 1)[0] == 4.0f && image_pixel(&img, 0, 1)[1] == 4.0f);
    image_free(&img);
}

/* Real files from OpenImageIO-images and Pillow (../shared/data/pfm; README there).
 * Expected values were read independently with Python's struct module. */
TEST(pfm_read_real_files)
{
    image img, be;
    rerror e;
    int channels;
    double s[3];
    FILE *probe = fopen(SHARED_PFM "/pillow/hopper.pfm", "rb");
    if (!probe) {
        printf("     (skipped: %s absent)\n", SHARED_PFM);
        return;
    }
    fclose(probe);

    CHECKF(pfm_read(SHARED_PFM "/oiio-images/test-1.pfm", &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(img.width == 64 && img.height == 64 && channels == 3);
    CHECK(image_pixel(&img, 0, 0)[0] == 0.0010489597916603088f);
    CHECK(image_pixel(&img, 0, 0)[1] == 0.0005244798958301544f);
    CHECK(image_pixel(&img, 32, 31)[2] == 0.019046438857913017f); /* the maximum */
    CHECK(image_pixel(&img, 5, 7)[2] == 4.379277383361409e-18f);
    test_image_sums(&img, s);
    CHECK_NEAR(s[0], 8.534689271589741, 1e-9);
    CHECK_NEAR(s[2], 3.8055140988271887, 1e-9);
    image_free(&img);

    CHECKF(pfm_read(SHARED_PFM "/oiio-images/test-2.pfm", &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(img.width == 240 && img.height == 240 && channels == 3);
    CHECK(image_pixel(&img, 119, 120)[1] == 1.378121256828308f);
    CHECK(image_pixel(&img, 60, 0)[0] == 0.0001040587667375803f);
    test_image_sums(&img, s);
    CHECK_NEAR(s[0], 2441.592633983891, 1e-7);
    image_free(&img);

    /* big-endian (scale +1.0) */
    CHECKF(pfm_read(SHARED_PFM "/oiio-images/test-3.pfm", &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(img.width == 240 && img.height == 240 && channels == 3);
    CHECK(image_pixel(&img, 60, 0)[0] == 0.018210284411907196f);
    CHECK(image_pixel(&img, 118, 40)[0] == 1.0f && image_pixel(&img, 118, 40)[1] == 0.6235294342041016f);
    test_image_sums(&img, s);
    CHECK_NEAR(s[0], 20126.17039936947, 1e-7);
    CHECK_NEAR(s[1], 9762.094406356553, 1e-7);
    CHECK_NEAR(s[2], 3544.0646725980914, 1e-7);
    image_free(&img);

    /* greyscale little-endian vs the same data big-endian with scale 2.5 */
    CHECKF(pfm_read(SHARED_PFM "/pillow/hopper.pfm", &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(img.width == 128 && img.height == 128 && channels == 1);
    CHECK(image_pixel(&img, 0, 0)[0] == 26.0f && image_pixel(&img, 127, 0)[1] == 113.0f);
    CHECK(image_pixel(&img, 127, 127)[2] == 158.0f && image_pixel(&img, 73, 8)[0] == 255.0f);
    test_image_sums(&img, s);
    CHECK(s[0] == 1387784.0 && s[1] == s[0] && s[2] == s[0]);
    CHECKF(pfm_read(SHARED_PFM "/pillow/hopper_be.pfm", &be, &channels, &e) == 0, "%s", e.msg);
    CHECK(channels == 1);
    CHECK(images_bit_equal(&img, &be));
    image_free(&img);
    image_free(&be);
}

/* Writes `header` followed by `data_bytes` zero bytes, reads it, expects an error. */
static int pfm_rejects(const char *header, size_t data_bytes, char *msg, size_t msg_size)
{
    char path[1024];
    unsigned char *buf;
    size_t n = strlen(header);
    image img;
    rerror e;
    int status;
    snprintf(path, sizeof path, "%s", test_tmp_path("bad.pfm"));
    buf = calloc(n + data_bytes + 1, 1);
    if (!buf) return 0;
    memcpy(buf, header, n);
    write_bytes(path, buf, n + data_bytes);
    free(buf);
    e.msg[0] = '\0';
    img.px = (float *)&status; /* must be reset by the reader, not freed */
    status = pfm_read(path, &img, NULL, &e);
    snprintf(msg, msg_size, "%s", e.msg);
    if (status == 0) {
        image_free(&img);
        return 0;
    }
    return img.px == NULL && strstr(e.msg, "bad.pfm:") != NULL;
}

TEST(pfm_rejects_malformed)
{
    char msg[1024];
    static const struct {
        const char *header;
        size_t data;
        const char *expect; /* a word the message must contain */
    } cases[] = {
        {"P6\n1 1\n-1.0\n", 12, "magic"},
        {"PX\n1 1\n-1.0\n", 12, "magic"},
        {"", 0, "magic"},
        {"PF\n0 1\n-1.0\n", 12, "width"},
        {"PF\n1 -1\n-1.0\n", 12, "height"},
        {"PF\n1x 1\n-1.0\n", 12, "width"},
        {"PF\n99999999999999999999999 1\n-1.0\n", 12, "too large"},
        {"PF\n1048576 1048576\n-1.0\n", 12, "too large"},
        {"PF\n100000 100\n-1.0\n", 12, "short"},
        {"PF\n8193 8192\n-1.0\n", 12, "too large"}, /* IMAGE_MAX_PIXELS = 8192 x 8192 */
        {"PF\n1048576 1\n-1.0\n", 12, "short"},   /* a 1048576 x 1 strip is allowed */
        {"PF\n2 2\n-1.0\n", 47, "short"},
        {"Pf\n2 2\n-1.0\n", 15, "short"},
        {"PF\n1 1\n-1.0\n", 13, "after"},
        {"PF\n1 1\n0.0\n", 12, "zero"},
        {"PF\n1 1\n-0\n", 12, "zero"},
        {"PF\n1 1\nnan\n", 12, "finite"},
        {"PF\n1 1\ninf\n", 12, "finite"},
        {"PF\n1 1\n1e999\n", 12, "finite"},
        {"PF\n1 1\n-1.0x\n", 12, "not a number"},
        {"PF\n1 1\nabc\n", 12, "not a number"},
        {"PF\n1 1\n", 0, "ends"},
        {"PF\n1", 0, "ends"},
        {"PF1 1\n-1.0\n", 12, "whitespace"},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        CHECKF(pfm_rejects(cases[i].header, cases[i].data, msg, sizeof msg), "case %zu accepted or bad message: '%s'", i,
               msg);
        CHECKF(strstr(msg, cases[i].expect), "case %zu: message '%s' lacks '%s'", i, msg, cases[i].expect);
    }
    {
        image img;
        rerror e;
        CHECK(pfm_read(test_tmp_path("does-not-exist.pfm"), &img, NULL, &e) != 0);
        CHECK(strstr(e.msg, "does-not-exist.pfm: "));
    }
}

/* ---- PNG ---- */

TEST(png_checksums_known_values)
{
    CHECKF(crc32_update(0, "123456789", 9) == 0xCBF43926u, "crc %08x", crc32_update(0, "123456789", 9));
    /* in two pieces */
    CHECK(crc32_update(crc32_update(0, "1234", 4), "56789", 5) == 0xCBF43926u);
    CHECK(crc32_update(0, "", 0) == 0);
    CHECKF(adler32_update(1, "Wikipedia", 9) == 0x11E60398u, "adler %08x", adler32_update(1, "Wikipedia", 9));
    CHECK(adler32_update(adler32_update(1, "Wiki", 4), "pedia", 5) == 0x11E60398u);
}

/* Independent bitwise CRC-32 (no table), to check the chunk CRCs of the file. */
static uint32_t crc32_bitwise(const unsigned char *b, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    size_t i;
    int k;
    for (i = 0; i < n; ++i) {
        c ^= b[i];
        for (k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1)));
    }
    return ~c;
}

static uint32_t be32(const unsigned char *b)
{
    return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3];
}

/* A tiny PNG decoder for what our writer produces: checks signature, chunk order and
 * CRCs, IHDR, the zlib header and trailer, and inflates stored blocks only.
 * Returns the filtered bytes (malloc'd) and their count, or NULL with a reason. */
static unsigned char *decode_stored_png(const unsigned char *f, size_t size, int *w, int *h, size_t *out_n,
                                        const char **why)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char *z = NULL, *out = NULL;
    size_t zn = 0, pos = 8, zp, on = 0;
    int seen_ihdr = 0, seen_iend = 0, final = 0;
    uint32_t s1 = 1, s2 = 0;
    *why = "ok";
    if (size < 8 || memcmp(f, sig, 8)) return *why = "signature", NULL;
    z = malloc(size);
    out = malloc(size);
    if (!z || !out) goto fail;
    while (pos + 12 <= size && !seen_iend) {
        uint32_t len = be32(f + pos);
        const unsigned char *type = f + pos + 4, *data = f + pos + 8;
        if (pos + 12 + len > size) { *why = "chunk overruns file"; goto fail; }
        if (crc32_bitwise(type, 4 + (size_t)len) != be32(data + len)) { *why = "chunk CRC"; goto fail; }
        if (!memcmp(type, "IHDR", 4)) {
            if (seen_ihdr || pos != 8 || len != 13) { *why = "IHDR"; goto fail; }
            *w = (int)be32(data);
            *h = (int)be32(data + 4);
            if (data[8] != 8 || data[9] != 2 || data[10] || data[11] || data[12]) { *why = "IHDR fields"; goto fail; }
            seen_ihdr = 1;
        } else if (!memcmp(type, "IDAT", 4)) {
            memcpy(z + zn, data, len);
            zn += len;
        } else if (!memcmp(type, "IEND", 4)) {
            if (len != 0) { *why = "IEND"; goto fail; }
            seen_iend = 1;
        } else {
            *why = "unexpected chunk";
            goto fail;
        }
        pos += 12 + len;
    }
    if (!seen_ihdr || !seen_iend || pos != size) { *why = "chunk sequence"; goto fail; }
    /* zlib: CM 8, CINFO <= 7, (CMF*256 + FLG) % 31 == 0, no preset dictionary */
    if (zn < 6 || (z[0] & 0x0f) != 8 || (z[0] >> 4) > 7 || ((z[0] << 8) | z[1]) % 31 || (z[1] & 0x20)) {
        *why = "zlib header";
        goto fail;
    }
    zp = 2;
    while (!final) {
        uint32_t len, nlen;
        if (zp + 5 > zn) { *why = "truncated block"; goto fail; }
        if ((z[zp] & 0x06) != 0) { *why = "not a stored block"; goto fail; }
        final = z[zp] & 1;
        len = z[zp + 1] | (uint32_t)z[zp + 2] << 8;
        nlen = z[zp + 3] | (uint32_t)z[zp + 4] << 8;
        if ((len ^ 0xffffu) != nlen) { *why = "NLEN"; goto fail; }
        zp += 5;
        if (zp + len > zn) { *why = "block overruns"; goto fail; }
        memcpy(out + on, z + zp, len);
        on += len;
        zp += len;
    }
    {
        size_t i;
        for (i = 0; i < on; ++i) {
            s1 = (s1 + out[i]) % 65521;
            s2 = (s2 + s1) % 65521;
        }
    }
    if (zp + 4 != zn || be32(z + zp) != (s2 << 16 | s1)) { *why = "Adler-32 trailer"; goto fail; }
    free(z);
    *out_n = on;
    return out;
fail:
    free(z);
    free(out);
    return NULL;
}

/* Round-trips an image whose filtered stream spans several stored blocks
 * (250 x 100 -> 75,100 bytes: two blocks, the first one full). */
TEST(png_structure_decodes)
{
    enum { W = 250, H = 100 };
    static unsigned char rgb[W * H * 3];
    unsigned char *file, *filtered;
    size_t size, n, i;
    int w = 0, h = 0, x, y;
    const char *why;
    rerror e;
    char path[1024];
    for (i = 0; i < sizeof rgb; ++i) rgb[i] = (unsigned char)((i * 7919u) >> 3);
    snprintf(path, sizeof path, "%s", test_tmp_path("structure.png"));
    CHECKF(png_write_rgb8(path, W, H, rgb, &e) == 0, "%s", e.msg);
    file = read_all(path, &size);
    CHECK(file);
    filtered = decode_stored_png(file, size, &w, &h, &n, &why);
    free(file);
    CHECKF(filtered, "decode failed: %s", why);
    CHECK(w == W && h == H);
    CHECKF(n == (size_t)H * (1 + 3 * W), "n = %zu", n);
    for (y = 0; y < H; ++y) {
        const unsigned char *row = filtered + (size_t)y * (1 + 3 * W);
        if (row[0] != 0) break;
        for (x = 0; x < 3 * W; ++x)
            if (row[1 + x] != rgb[(size_t)y * 3 * W + x]) break;
        if (x < 3 * W) break;
    }
    free(filtered);
    CHECKF(y == H, "row %d differs", y);
    /* the smallest image too: one block, one pixel */
    snprintf(path, sizeof path, "%s", test_tmp_path("one.png"));
    CHECK(png_write_rgb8(path, 1, 1, rgb, &e) == 0);
    file = read_all(path, &size);
    CHECK(file);
    filtered = decode_stored_png(file, size, &w, &h, &n, &why);
    free(file);
    CHECKF(filtered, "decode failed: %s", why);
    CHECK(w == 1 && h == 1 && n == 4 && filtered[0] == 0 && !memcmp(filtered + 1, rgb, 3));
    free(filtered);
}

/* Preview bytes: exposure gain, clamp, the sRGB curve's two pieces, rounding. */
TEST(png_preview_srgb_values)
{
    image img;
    rerror e;
    unsigned char *file, *filtered;
    size_t size, n;
    int w, h;
    const char *why;
    char path[1024];
    /* linear value -> expected byte after exposure +1 (gain 2):
     * 0.5*2 = 1 -> 255; 0.001*2 = 0.002 (linear toe) -> 12.92*0.002*255 = 6.59 -> 7;
     * 0.1*2 = 0.2 -> 1.055*0.2^(1/2.4) - 0.055 = 0.48453 -> 123.55 -> 124; 7 -> clamp 255;
     * -1 -> 0; 0.0015654 * 2 = 0.0031308 -> 0.04045 -> 10.31 -> 10. */
    static const float in[6] = {0.5f, 0.001f, 0.1f, 7.0f, -1.0f, 0.0015654f};
    static const unsigned char expect[6] = {255, 7, 124, 255, 0, 10};
    int i;
    CHECK(image_alloc(&img, 2, 1, &e) == 0);
    for (i = 0; i < 6; ++i) img.px[i] = in[i];
    snprintf(path, sizeof path, "%s", test_tmp_path("preview.png"));
    CHECKF(png_write_preview(path, &img, 1.0, &e) == 0, "%s", e.msg);
    image_free(&img);
    file = read_all(path, &size);
    CHECK(file);
    filtered = decode_stored_png(file, size, &w, &h, &n, &why);
    free(file);
    CHECKF(filtered, "decode failed: %s", why);
    CHECK(n == 7 && filtered[0] == 0);
    for (i = 0; i < 6; ++i) {
        int got = filtered[1 + i];
        if (got != expect[i]) {
            free(filtered);
            CHECKF(0, "value %d: byte %d, expected %d", i, got, expect[i]);
        }
    }
    free(filtered);
}

/* A failing write leaves nothing behind (the directory cannot be created). */
TEST(image_writers_fail_cleanly)
{
    image img;
    rerror e;
    char blocker[1024], path[1100];
    snprintf(blocker, sizeof blocker, "%s", test_write_file("blocker", "x"));
    snprintf(path, sizeof path, "%s/sub/out.pfm", blocker);
    CHECK(image_alloc(&img, 2, 2, &e) == 0);
    CHECK(pfm_write(path, &img, &e) != 0);
    CHECK(png_write_preview(path, &img, 0, &e) != 0);
    CHECK(!test_file_exists(path));
    image_free(&img);
    CHECK(image_alloc(&img, 0, 3, &e) != 0 && img.px == NULL);
    image_free(&img);
}
