/* OpenEXR and PNG readers, the EXR writer, inflate/deflate and half <-> float
 * (docs/images.md). The corpus of tests/data/images was written by libOpenEXR, libpng and
 * ImageMagick from the values of tests/image_corpus.h (tools/images/); each file must
 * read back bit for bit. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "image_corpus.h"
#include "restir/core/checksum.h"
#include "restir/core/exr.h"
#include "restir/core/image_io.h"
#include "restir/core/inflate.h"
#include "restir/core/png_read.h"
#include "restir/core/pfm.h"
#include "test.h"

#define IMAGES "tests/data/images"

static uint32_t float_bits(float f)
{
    uint32_t b;
    memcpy(&b, &f, 4);
    return b;
}

/* ---- EXR ---- */

typedef struct {
    const char *file;
    int data[4], display[4]; /* xMin yMin xMax yMax */
    int channels;
    int type[4]; /* pixel type of the file's channel feeding output channel k (corpus channel k) */
    int ramp;    /* values from corpus_ramp_half (the 16-bit wavelet file) */
} exr_case;

static uint32_t exr_expected(int type, int x, int y, int c, int tame)
{
    if (type == EXR_HALF) return float_bits(half_to_float(corpus_half(x, y, c, tame)));
    if (type == EXR_FLOAT) return corpus_float(x, y, c, tame);
    return float_bits((float)corpus_uint(x, y, c, tame));
}

/* Every output value against the corpus formula; 0 outside the data window. */
static int check_exr_case(const exr_case *k)
{
    char path[256];
    fimage img;
    rerror e;
    int x, y, c, bad = 0;
    snprintf(path, sizeof path, IMAGES "/%s", k->file);
    if (exr_read(path, &img, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return 1;
    }
    if (img.width != k->display[2] - k->display[0] + 1 || img.height != k->display[3] - k->display[1] + 1 ||
        img.channels != k->channels) {
        test_fail(__FILE__, __LINE__, "%s: %d x %d x %d", path, img.width, img.height, img.channels);
        fimage_free(&img);
        return 1;
    }
    for (y = 0; y < img.height; ++y)
        for (x = 0; x < img.width; ++x)
            for (c = 0; c < img.channels; ++c) {
                int fx = x + k->display[0], fy = y + k->display[1];
                int inside = fx >= k->data[0] && fx <= k->data[2] && fy >= k->data[1] && fy <= k->data[3];
                uint32_t want = !inside ? 0
                                : k->ramp ? float_bits(half_to_float(corpus_ramp_half(fx, fy, c)))
                                          : exr_expected(k->type[c], fx, fy, c, strstr(k->file, "_piz_") != NULL);
                uint32_t got = float_bits(img.px[((size_t)y * img.width + x) * img.channels + c]);
                if (got != want && bad++ < 3)
                    test_fail(__FILE__, __LINE__, "%s (%d,%d) channel %d: 0x%08x, expected 0x%08x", path, x, y, c, got,
                              want);
            }
    fimage_free(&img);
    return bad != 0;
}

TEST(exr_corpus_bit_exact)
{
    static const char *comps[] = {"none", "rle", "zips", "zip", "piz"};
    const int H = EXR_HALF, F = EXR_FLOAT, U = EXR_UINT;
    char names[5][5][64];
    exr_case cases[40];
    int n = 0, i, failed = 0;
    for (i = 0; i < 5; ++i) {
        exr_case rgba_h = {NULL, {0, 0, 6, 36}, {0, 0, 6, 36}, 4, {H, H, H, H}, 0};
        exr_case rgba_f = {NULL, {0, 0, 6, 36}, {0, 0, 6, 36}, 4, {F, F, F, F}, 0};
        exr_case rgb_u = {NULL, {0, 0, 4, 2}, {0, 0, 4, 2}, 3, {U, U, U, 0}, 0};
        exr_case y_h = {NULL, {0, 0, 5, 3}, {0, 0, 5, 3}, 1, {H, 0, 0, 0}, 0};
        exr_case mixed = {NULL, {0, 0, 8, 34}, {0, 0, 8, 34}, 3, {H, F, U, 0}, 0};
        exr_case *all[5];
        int j;
        all[0] = &rgba_h, all[1] = &rgba_f, all[2] = &rgb_u, all[3] = &y_h, all[4] = &mixed;
        snprintf(names[i][0], 64, "oe_%s_half_rgba.exr", comps[i]);
        snprintf(names[i][1], 64, "oe_%s_float_rgba.exr", comps[i]);
        snprintf(names[i][2], 64, "oe_%s_uint_rgb.exr", comps[i]);
        snprintf(names[i][3], 64, "oe_%s_half_y.exr", comps[i]);
        snprintf(names[i][4], 64, "oe_%s_mixed.exr", comps[i]);
        for (j = 0; j < 5; ++j) {
            all[j]->file = names[i][j];
            if (!strcmp(comps[i], "piz")) { /* wider: PIZ must compress them (tools/images) */
                int box[4] = {0, 0, 38, j == 4 ? 34 : 36}, b;
                for (b = 0; b < 4; ++b) all[j]->data[b] = all[j]->display[b] = box[b];
            }
            cases[n++] = *all[j];
        }
    }
    {
        const exr_case extra[] = {
            {"oe_zip_decreasing.exr", {0, 0, 6, 36}, {0, 0, 6, 36}, 4, {H, H, H, H}, 0},
            {"oe_piz_decreasing.exr", {0, 0, 38, 36}, {0, 0, 38, 36}, 4, {F, F, F, F}, 0},
            {"oe_piz_window.exr", {-2, 3, 8, 20}, {0, 0, 9, 14}, 4, {H, H, H, H}, 0},
            {"oe_zip_window.exr", {4, -6, 12, 9}, {0, 0, 9, 14}, 4, {F, F, F, F}, 0},
            /* our writer's file (37 x 23 half RGB, ZIP) rewritten by exrmakepreview / exrstdattr */
            {"tool_preview.exr", {0, 0, 36, 22}, {0, 0, 36, 22}, 3, {H, H, H, 0}, 0},
            {"tool_stdattr.exr", {0, 0, 36, 22}, {0, 0, 36, 22}, 3, {H, H, H, 0}, 0},
            {"oe_piz_wav16.exr", {0, 0, 255, 32}, {0, 0, 255, 32}, 3, {H, H, H, 0}, 1},
        };
        for (i = 0; i < (int)(sizeof extra / sizeof extra[0]); ++i) cases[n++] = extra[i];
    }
    for (i = 0; i < n; ++i) failed += check_exr_case(&cases[i]);
    CHECKF(failed == 0, "%d of %d EXR corpus files differ", failed, n);
}

/* ImageMagick's EXR files: every value as libOpenEXR reads it (im_exr_expected.txt,
 * written by tools/images/make_exr_corpus dump: "file w h", then per pixel R G B A half bits). */
TEST(exr_other_writer_bit_exact)
{
    FILE *f = fopen(IMAGES "/im_exr_expected.txt", "r");
    char name[128];
    int w, h, files = 0;
    CHECK(f != NULL);
    while (fscanf(f, "%127s %d %d", name, &w, &h) == 3) {
        char path[256];
        fimage img;
        rerror e;
        int i, c, bad = 0;
        snprintf(path, sizeof path, IMAGES "/%s", name);
        CHECKF(exr_read(path, &img, &e) == 0, "%s", e.msg);
        CHECK(img.width == w && img.height == h && img.channels >= 3);
        for (i = 0; i < w * h; ++i) {
            unsigned v[4];
            CHECK(fscanf(f, "%x %x %x %x", &v[0], &v[1], &v[2], &v[3]) == 4);
            for (c = 0; c < img.channels; ++c)
                bad += float_bits(img.px[i * img.channels + c]) != float_bits(half_to_float((uint16_t)v[c]));
        }
        fimage_free(&img);
        CHECKF(bad == 0, "%s: %d values differ from libOpenEXR's", path, bad);
        files++;
    }
    fclose(f);
    CHECK(files == 3);
}

/* Files OpenEXR wrote that we refuse: the message names what is not supported. */
TEST(exr_refused_by_name)
{
    static const struct {
        const char *file, *words;
    } cases[] = {{"refused_pxr24.exr", "PXR24"}, {"refused_b44.exr", "B44"},     {"refused_b44a.exr", "B44A"},
                 {"refused_dwaa.exr", "DWAA"},   {"refused_dwab.exr", "DWAB"},   {"refused_tiled.exr", "tiled"},
                 {"refused_multipart.exr", "multi-part"}};
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char path[256];
        fimage img;
        rerror e;
        snprintf(path, sizeof path, IMAGES "/%s", cases[i].file);
        CHECKF(exr_read(path, &img, &e) != 0, "%s was accepted", path);
        CHECKF(strstr(e.msg, cases[i].words) && strstr(e.msg, path), "%s: message '%s' lacks '%s'", path, e.msg,
               cases[i].words);
    }
}

/* IEEE binary16: exact widening, round-to-nearest-even narrowing (the cases a broken
 * rounding gets wrong: ties, the subnormal boundary, overflow, NaN), and every half
 * surviving half -> float -> half. tools/images (halfcheck) compares all 2^32 floats with Imath. */
TEST(half_float_conversion)
{
    static const struct {
        uint32_t f;
        uint16_t h;
    } cases[] = {
        {0x3f800000u, 0x3c00}, /* 1 */
        {0x3f801000u, 0x3c00}, /* 1 + 2^-11: tie, to even (down) */
        {0x3f803000u, 0x3c02}, /* 1 + 3 * 2^-11: tie, to even (up) */
        {0x3f801001u, 0x3c01}, /* just above the tie */
        {0x477fe000u, 0x7bff}, /* 65504, the largest half */
        {0x477fefffu, 0x7bff}, /* just below 65520 */
        {0x477ff000u, 0x7c00}, /* 65520: tie, to even = infinity */
        {0x33800000u, 0x0001}, /* 2^-24, the smallest subnormal */
        {0x33000000u, 0x0000}, /* 2^-25: tie, to even = 0 */
        {0x33000001u, 0x0001}, /* just above 2^-25 */
        {0x387fc000u, 0x03ff}, /* the largest subnormal, 1023 * 2^-24 */
        {0x387fe000u, 0x0400}, /* 1023.5 * 2^-24: tie between it and 2^-14, to even (up) */
        {0x38800000u, 0x0400}, /* 2^-14, the smallest normal */
        {0xc0000000u, 0xc000}, /* -2 */
        {0x80000000u, 0x8000}, /* -0 */
        {0x7f800000u, 0x7c00}, /* inf */
        {0xff800000u, 0xfc00}, /* -inf */
        {0x7fc00000u, 0x7e00}, /* quiet NaN */
        {0x7f800001u, 0x7c01}, /* NaN whose payload is below the half's: stays NaN */
        {0x4b000000u, 0x7c00}, /* 2^23: overflow */
    };
    size_t i;
    uint32_t h;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        float f;
        memcpy(&f, &cases[i].f, 4);
        CHECKF(float_to_half(f) == cases[i].h, "float 0x%08x -> half 0x%04x, expected 0x%04x", cases[i].f,
               float_to_half(f), cases[i].h);
    }
    CHECK(float_bits(half_to_float(0x0001)) == 0x33800000u);
    CHECK(float_bits(half_to_float(0x83ff)) == 0xb87fc000u);
    CHECK(float_bits(half_to_float(0x7bff)) == 0x477fe000u);
    CHECK(float_bits(half_to_float(0x7e01)) == 0x7fc02000u);
    for (h = 0; h < 65536; ++h) CHECKF(float_to_half(half_to_float((uint16_t)h)) == h, "half 0x%04x", h);
}

/* Our writer: float bit-exact (NaN payloads, subnormals, -0), half from exact halves;
 * NONE and ZIP; read back by our reader (libOpenEXR reads them too: tools/images, oracle). */
TEST(exr_write_roundtrip)
{
    const int w = 37, h = 23;
    image img;
    rerror e;
    int t, comp, x, y, c;
    CHECK(image_alloc(&img, w, h, &e) == 0);
    for (t = 0; t < 2; ++t) {
        for (y = 0; y < h; ++y)
            for (x = 0; x < w; ++x)
                for (c = 0; c < 3; ++c) {
                    uint32_t bits = t ? float_bits(half_to_float(corpus_half(x, y, c, 0))) : corpus_float(x, y, c, 0);
                    memcpy(&image_pixel(&img, x, y)[c], &bits, 4);
                }
        for (comp = 0; comp < 2; ++comp) {
            char path[256];
            fimage back;
            int bad = 0;
            snprintf(path, sizeof path, RESTIR_TMP "/exr_write_%d_%d.exr", t, comp);
            CHECKF(exr_write(path, &img, comp ? EXR_ZIP : EXR_NONE, t ? EXR_HALF : EXR_FLOAT, &e) == 0, "%s", e.msg);
            CHECKF(exr_read(path, &back, &e) == 0, "%s", e.msg);
            CHECK(back.width == w && back.height == h && back.channels == 3);
            for (x = 0; x < w * h * 3; ++x) bad += float_bits(back.px[x]) != float_bits(img.px[x]);
            fimage_free(&back);
            remove(path);
            CHECKF(bad == 0, "%s: %d values differ", path, bad);
        }
    }
    image_free(&img);
}

/* ---- inflate / deflate ---- */

static void fill_bytes(unsigned char *b, size_t n, int kind)
{
    size_t i;
    for (i = 0; i < n; ++i) {
        uint32_t r = corpus_mix((uint32_t)i * 7u + (uint32_t)kind);
        b[i] = kind == 0 ? (unsigned char)r : kind == 1 ? (unsigned char)(i / 300) : (unsigned char)"abcab  \n"[r % 8];
    }
}

/* A zlib stream with a dynamic-Huffman block (Python's zlib.compress, level 9, of the
 * 1000 bytes fill_bytes(kind 2) makes), decoded to those bytes. */
TEST(inflate_dynamic_block)
{
    static const unsigned char z[] = {
#include "data/images/dynamic.zlib.inc"
    };
    unsigned char text[1000], out[1000];
    size_t n = 0;
    rerror e;
    fill_bytes(text, sizeof text, 2);
    CHECK((z[2] >> 1 & 3) == 2); /* BTYPE 10: dynamic */
    CHECKF(inflate_zlib(z, sizeof z, out, sizeof out, &n, &e) == 0, "%s", e.msg);
    CHECK(n == sizeof text && memcmp(out, text, n) == 0);
    /* one byte short: the output limit is an error, not an overrun */
    CHECK(inflate_zlib(z, sizeof z, out, sizeof out - 1, &n, &e) != 0);
}

/* deflate_zlib -> inflate_zlib is the identity (random bytes fall back to stored blocks,
 * runs and text use fixed-Huffman matches); every truncation and many bit flips of a
 * stream are rejected or decode within the limit, never overrun. */
TEST(deflate_inflate_roundtrip)
{
    static const size_t sizes[] = {0, 1, 3, 100, 65535, 65536, 70000};
    size_t s, k, n;
    int kind;
    rerror e;
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; ++s)
        for (kind = 0; kind < 3; ++kind) {
            size_t size = sizes[s], bound = deflate_zlib_bound(size);
            unsigned char *in = malloc(size + 1), *z = malloc(bound), *out = malloc(size + 1);
            fill_bytes(in, size, kind);
            n = deflate_zlib(in, size, z);
            CHECK(n > 0 && n <= bound);
            CHECKF(inflate_zlib(z, n, out, size, &k, &e) == 0, "%s", e.msg);
            CHECK(k == size && memcmp(in, out, size) == 0);
            if (kind == 1 && size >= 65535) CHECKF(n < size / 20, "runs compress to %zu of %zu bytes", n, size);
            if (size == 65536) {
                size_t cut;
                for (cut = 0; cut < n; cut += 1 + n / 97) CHECK(inflate_zlib(z, cut, out, size, &k, &e) != 0);
                for (cut = 0; cut < 300 && cut < 8 * n; ++cut) {
                    size_t bit = (size_t)corpus_mix((uint32_t)cut) % (8 * n);
                    z[bit / 8] ^= (unsigned char)(1u << bit % 8);
                    if (inflate_zlib(z, n, out, size, &k, &e) == 0) CHECK(k <= size);
                    z[bit / 8] ^= (unsigned char)(1u << bit % 8);
                }
            }
            free(in);
            free(z);
            free(out);
        }
}

TEST(inflate_rejects_malformed)
{
    static const struct {
        unsigned char b[16];
        size_t n;
        const char *why;
    } cases[] = {
        {{0x78, 0x01, 0x07}, 3, "block type 3"},
        {{0x78, 0x02}, 2, "header check"},
        {{0x79, 0x01}, 2, "method"},
        {{0x78, 0xbb, 0, 0, 0, 0}, 6, "dictionary"},
        {{0x78, 0x01, 0x01, 0x05, 0x00, 0xfa, 0xff, 'a', 'b'}, 9, "truncated"},
        {{0x78, 0x01, 0x01, 0x02, 0x00, 0xfa, 0xff, 'a', 'b'}, 9, "length check"},
        {{0x78, 0x01, 0x01, 0x02, 0x00, 0xfd, 0xff, 'a', 'b', 0, 0, 0, 0}, 13, "Adler-32"},
        {{0x78, 0x01, 0x01, 0x02, 0x00, 0xfd, 0xff, 'a', 'b'}, 9, "trailer"},
        /* fixed block: length code 257 (3 bytes) at distance 1 with no byte before it */
        {{0x78, 0x01, 0x03, 0x02, 0x00}, 5, "before the start"},
    };
    size_t i, n;
    unsigned char out[64];
    rerror e;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        CHECKF(inflate_zlib(cases[i].b, cases[i].n, out, sizeof out, &n, &e) != 0, "case %zu accepted", i);
        CHECKF(strstr(e.msg, cases[i].why) != NULL, "case %zu: '%s' lacks '%s'", i, e.msg, cases[i].why);
    }
}

/* ---- PNG ---- */

typedef struct {
    const char *file;
    int colour, depth, interlaced, trns;
} png_case;

/* Expected linear value of channel c of the decoded pixel, from the corpus formula
 * (palette: entries from corpus_palette, index from corpus_png). */
static float png_expected(const png_case *k, int x, int y, int c, int channels)
{
    double max = (double)((1u << k->depth) - 1);
    if (k->colour == 3) {
        unsigned idx = corpus_png(x, y, 0, k->depth);
        if (c < 3) return (float)(corpus_palette((int)idx, c) / 255.0);
        /* tRNS has 2^depth - 1 entries: alpha for i % 3 == 0, 255 for the others and the last */
        return (float)((k->trns && idx % 3 == 0 && idx < (1u << k->depth) - 1 ? corpus_palette((int)idx, 3) : 255) /
                       255.0);
    }
    if ((k->colour == 0 || k->colour == 2) && c == channels - 1 && k->trns) {
        /* key: the colour of pixel (0, 0); alpha 0 there and wherever the colour equals it */
        int cc, n = k->colour == 0 ? 1 : 3, is_key = 1;
        for (cc = 0; cc < n; ++cc) is_key &= corpus_png(x, y, cc, k->depth) == corpus_png(0, 0, cc, k->depth);
        return is_key ? 0.0f : 1.0f;
    }
    return (float)(corpus_png(x, y, c, k->depth) / max);
}

static int check_png_case(const png_case *k)
{
    char path[256];
    fimage img;
    rerror e;
    int x, y, c, bad = 0, want_channels = k->colour == 0 ? 1 : k->colour == 4 ? 2 : k->colour == 6 ? 4 : 3;
    if (k->trns) want_channels++;
    snprintf(path, sizeof path, IMAGES "/%s", k->file);
    if (png_read(path, PNG_LINEAR, &img, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return 1;
    }
    if (img.width != 7 || img.height != 5 || img.channels != want_channels) {
        test_fail(__FILE__, __LINE__, "%s: %d x %d x %d", path, img.width, img.height, img.channels);
        fimage_free(&img);
        return 1;
    }
    for (y = 0; y < 5; ++y)
        for (x = 0; x < 7; ++x)
            for (c = 0; c < img.channels; ++c) {
                float want = png_expected(k, x, y, c, img.channels), got = img.px[(y * 7 + x) * img.channels + c];
                if (float_bits(got) != float_bits(want) && bad++ < 3)
                    test_fail(__FILE__, __LINE__, "%s (%d,%d) channel %d: %.9g, expected %.9g", path, x, y, c, got,
                              want);
            }
    fimage_free(&img);
    return bad != 0;
}

/* libpng wrote every colour type and depth, tRNS, Adam7 and each filter type forced;
 * ImageMagick wrote grey, RGB, RGBA (8 and 16 bit) and a palette (tools/images). */
TEST(png_corpus_bit_exact)
{
    static const png_case cases[] = {
#include "data/images/png_cases.inc"
    };
    size_t i;
    int failed = 0;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) failed += check_png_case(&cases[i]);
    CHECKF(failed == 0, "%d of %zu PNG corpus files differ", failed, sizeof cases / sizeof cases[0]);
}

/* PNG_SRGB decodes colour with the IEC 61966-2-1 curve, alpha stays linear. */
TEST(png_srgb_rule)
{
    fimage lin, srgb;
    rerror e;
    int i;
    CHECKF(png_read(IMAGES "/lp_rgba8.png", PNG_LINEAR, &lin, &e) == 0, "%s", e.msg);
    CHECKF(png_read(IMAGES "/lp_rgba8.png", PNG_SRGB, &srgb, &e) == 0, "%s", e.msg);
    for (i = 0; i < 35 * 4; ++i) {
        float want = i % 4 == 3 ? lin.px[i] : (float)srgb_to_linear(lin.px[i]);
        CHECKF(float_bits(srgb.px[i]) == float_bits(want) || fabs(srgb.px[i] - want) < 1e-7, "value %d: %g vs %g", i,
               srgb.px[i], want);
    }
    CHECK(fabs(srgb_to_linear(0.5) - 0.214041140) < 1e-8);
    CHECK(srgb_to_linear(0.04045) == 0.04045 / 12.92);
    fimage_free(&lin);
    fimage_free(&srgb);
}

/* Damaged PNGs: CRC, truncation, bad filter type, an IHDR claiming more than the data,
 * a palette index beyond PLTE: each a clean error naming the file. */
TEST(png_rejects_damage)
{
    size_t size, i;
    unsigned char *good = image_file_load(IMAGES "/lp_rgb8.png", 1 << 20, &size, NULL);
    const char *path = RESTIR_TMP "/damaged.png";
    fimage img;
    rerror e;
    CHECK(good != NULL);
    for (i = 0; i < 3; ++i) {
        unsigned char *b = malloc(size);
        size_t n = size;
        FILE *f;
        memcpy(b, good, size);
        if (i == 0) b[40] ^= 1;       /* inside a chunk: its CRC fails */
        if (i == 1) n = size / 2;     /* truncated */
        if (i == 2) b[8 + 8 + 2] = 1; /* IHDR width grows: CRC fails before any allocation */
        f = fopen(path, "wb");
        CHECK(f && fwrite(b, 1, n, f) == n);
        fclose(f);
        CHECKF(png_read(path, PNG_LINEAR, &img, &e) != 0, "damage %zu accepted", i);
        CHECKF(strstr(e.msg, path) != NULL, "%s", e.msg);
        free(b);
    }
    remove(path);
    free(good);
}

/* ---- by extension ---- */

/* image_read picks the reader from the extension (any case) and gives RGB; image_write
 * of .exr writes an EXR that image_read reads back bit-exactly. */
TEST(image_io_by_extension)
{
    image img, back;
    int channels = 0, x;
    rerror e;
    const char *path = RESTIR_TMP "/by_extension.EXR";
    CHECKF(image_read(IMAGES "/oe_zip_half_y.exr", &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(channels == 1 && img.width == 6 && img.height == 4);
    CHECK(img.px[0] == img.px[1] && img.px[1] == img.px[2]);
    CHECKF(image_write(path, &img, &e) == 0, "%s", e.msg);
    CHECKF(image_read(path, &back, &channels, &e) == 0, "%s", e.msg);
    CHECK(channels == 3);
    for (x = 0; x < 6 * 4 * 3; ++x) CHECK(float_bits(back.px[x]) == float_bits(img.px[x]));
    image_free(&back);
    image_free(&img);
    remove(path);
    CHECKF(image_read(IMAGES "/lp_rgba8.png", &img, &channels, &e) == 0, "%s", e.msg);
    CHECK(channels == 4 && img.width == 7);
    image_free(&img);
    CHECK(image_read(IMAGES "/refused_tiled.exr", &img, &channels, &e) != 0);
    CHECK(image_read(IMAGES "/missing.png", &img, &channels, &e) != 0 && strstr(e.msg, "missing.png"));
}

/* The CLI: render -o x.exr writes an EXR (and the preview x.png) holding exactly what
 * -o x.pfm holds; compare reads .exr; an unsupported or broken EXR exits 2 naming the file. */
TEST(cli_images_by_extension)
{
    char out[4096];
    image a, b;
    rerror e;
    int x;
    const char *scene = "tests/data/quad-light.scene";
    const char *exr = test_tmp_path("cli-image.exr"), *pfm = test_tmp_path("cli-image.pfm");
    char exr_path[512], pfm_path[512], png_path[512];
    FILE *f;
    snprintf(exr_path, sizeof exr_path, "%s", exr);
    snprintf(pfm_path, sizeof pfm_path, "%s", pfm);
    snprintf(png_path, sizeof png_path, "%s", exr_path);
    strcpy(png_path + strlen(png_path) - 4, ".png");
    CHECK(test_cli(out, sizeof out, "render %s --size 16x12 --spp 2 --seed 3 --quiet -o %s", scene, exr_path) == 0);
    CHECKF((f = fopen(png_path, "rb")) != NULL, "no preview %s", png_path);
    fclose(f);
    remove(png_path);
    CHECK(test_cli(out, sizeof out, "render %s --size 16x12 --spp 2 --seed 3 --quiet -o %s", scene, pfm_path) == 0);
    CHECKF(image_read(exr_path, &a, NULL, &e) == 0, "%s", e.msg);
    CHECKF(image_read(pfm_path, &b, NULL, &e) == 0, "%s", e.msg);
    CHECK(a.width == 16 && b.width == 16 && a.height == 12 && b.height == 12);
    for (x = 0; x < 16 * 12 * 3; ++x) CHECK(float_bits(a.px[x]) == float_bits(b.px[x]));
    image_free(&a);
    image_free(&b);
    CHECK(test_cli(out, sizeof out, "compare %s %s", exr_path, pfm_path) == 0);
    CHECK(test_cli(out, sizeof out, "compare %s %s", IMAGES "/refused_dwaa.exr", pfm_path) == 2);
    CHECKF(strstr(out, "refused_dwaa.exr: EXR: compression DWAA") != NULL, "%s", out);
    f = fopen(exr_path, "r+b"); /* cut the file: a chunk now runs past the end */
    CHECK(f != NULL);
    CHECK(ftruncate(fileno(f), 400) == 0);
    fclose(f);
    CHECK(test_cli(out, sizeof out, "compare %s %s", exr_path, pfm_path) == 2);
    CHECKF(strstr(out, "cli-image.exr: EXR: ") != NULL, "%s", out);
    remove(exr_path);
    remove(pfm_path);
    remove(png_path);
}

/* compare and check warn when the test image matches the reference far better upside
 * down (a PFM written top row first), and stay quiet for the right way up. */
TEST(upside_down_warning)
{
    char out[8192], ref_path[512], up_path[512], down_path[512], run2_path[512];
    image ref, down, up2;
    rerror e;
    int x, y, c;
    snprintf(ref_path, sizeof ref_path, "%s", test_tmp_path("ud-ref.pfm"));
    snprintf(up_path, sizeof up_path, "%s", test_tmp_path("ud-up.pfm"));
    snprintf(down_path, sizeof down_path, "%s", test_tmp_path("ud-down.pfm"));
    snprintf(run2_path, sizeof run2_path, "%s", test_tmp_path("ud-down2.pfm"));
    CHECK(image_alloc(&ref, 24, 16, &e) == 0 && image_alloc(&down, 24, 16, &e) == 0 &&
          image_alloc(&up2, 24, 16, &e) == 0);
    for (y = 0; y < 16; ++y)
        for (x = 0; x < 24; ++x)
            for (c = 0; c < 3; ++c) {
                float noise = (float)(corpus_mix(corpus_key(x, y, c)) % 1000) * 1e-4f; /* 0 .. 0.1 */
                image_pixel(&ref, x, y)[c] = 0.2f + 0.05f * (float)y + 0.01f * (float)c;
                image_pixel(&up2, x, y)[c] = image_pixel(&ref, x, y)[c] + noise;
                image_pixel(&down, x, 15 - y)[c] = image_pixel(&ref, x, y)[c] + noise;
            }
    CHECK(pfm_write(ref_path, &ref, &e) == 0 && pfm_write(up_path, &up2, &e) == 0 &&
          pfm_write(down_path, &down, &e) == 0);
    CHECK(test_cli(out, sizeof out, "compare %s %s", up_path, ref_path) == 0);
    CHECKF(strstr(out, "upside down") == NULL, "%s", out);
    CHECK(test_cli(out, sizeof out, "compare %s %s", down_path, ref_path) == 0);
    CHECKF(strstr(out, "ud-down.pfm matches") && strstr(out, "upside down"), "%s", out);
    /* check: two upside-down runs against the reference */
    for (y = 0; y < 16; ++y)
        for (x = 0; x < 24; ++x) image_pixel(&down, x, y)[0] += 0.01f;
    CHECK(pfm_write(run2_path, &down, &e) == 0);
    test_cli(out, sizeof out, "check --a %s %s --ref %s", down_path, run2_path, ref_path);
    CHECKF(strstr(out, "upside down") != NULL, "%s", out);
    image_free(&ref);
    image_free(&down);
    image_free(&up2);
    remove(ref_path);
    remove(up_path);
    remove(down_path);
    remove(run2_path);
}
