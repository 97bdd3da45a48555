/* PNG evidence for docs/images.md: NOT part of the build (make never compiles it; the
 * project does not depend on libpng). Needs Debian's libpng-dev and ImageMagick:
 *
 *   gcc -O2 -std=c99 -Itests tools/images/make_png_corpus.c $(pkg-config --cflags --libs libpng) \
 *       -o /tmp/make_png_corpus
 *   /tmp/make_png_corpus tests/data/images /tmp/png-src   # lp_*.png, png_cases.inc, PNM/PAM sources
 *   sh tools/images/make_png_corpus.sh /tmp/png-src tests/data/images   # im_*.png with ImageMagick convert
 *
 * Every file is 7 x 5 pixels; sample (x, y, c) is corpus_png(x, y, c, depth) of
 * tests/image_corpus.h (palette images: that is the index; entry i is corpus_palette(i, c)).
 * With tRNS: grey and RGB use the colour of pixel (0, 0) as the key; palette entries
 * i < 2^depth - 1 with i % 3 == 0 get alpha corpus_palette(i, 3), the others 255 (the
 * last entry has no tRNS byte at all). png_cases.inc lists every file for the test. */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "image_corpus.h"

#define W 7
#define H 5

static FILE *cases;

static int channels_of(int colour) { return colour == 0 || colour == 3 ? 1 : colour == 4 ? 2 : colour == 2 ? 3 : 4; }

static void write_png(const char *dir, const char *name, int colour, int depth, int interlace, int trns, int filter)
{
    char path[512];
    FILE *f;
    png_structp png;
    png_infop info;
    unsigned char rows[H][W * 4 * 2];
    png_bytep rowp[H];
    int x, y, c, n = channels_of(colour);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "wb");
    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    info = png_create_info_struct(png);
    if (!f || !png || !info || setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "%s: libpng failed\n", path);
        exit(1);
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, W, H, depth, colour, interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (filter >= 0) png_set_filter(png, 0, filter);
    if (colour == 3) {
        png_color pal[256];
        png_byte alpha[256];
        int i, size = 1 << depth;
        for (i = 0; i < size; ++i) {
            pal[i].red = (png_byte)corpus_palette(i, 0);
            pal[i].green = (png_byte)corpus_palette(i, 1);
            pal[i].blue = (png_byte)corpus_palette(i, 2);
            alpha[i] = (png_byte)(i % 3 == 0 ? corpus_palette(i, 3) : 255);
        }
        png_set_PLTE(png, info, pal, size);
        if (trns) png_set_tRNS(png, info, alpha, size - 1, NULL);
    } else if (trns) {
        png_color_16 key;
        memset(&key, 0, sizeof key);
        key.gray = (png_uint_16)corpus_png(0, 0, 0, depth);
        key.red = (png_uint_16)corpus_png(0, 0, 0, depth);
        key.green = (png_uint_16)corpus_png(0, 0, 1, depth);
        key.blue = (png_uint_16)corpus_png(0, 0, 2, depth);
        png_set_tRNS(png, info, NULL, 0, &key);
    }
    png_write_info(png, info);
    memset(rows, 0, sizeof rows);
    for (y = 0; y < H; ++y) {
        for (x = 0; x < W; ++x)
            for (c = 0; c < n; ++c) {
                unsigned v = corpus_png(x, y, c, depth);
                int i = x * n + c;
                if (depth == 16) {
                    rows[y][2 * i] = (unsigned char)(v >> 8);
                    rows[y][2 * i + 1] = (unsigned char)(v & 0xff);
                } else if (depth == 8) {
                    rows[y][i] = (unsigned char)v;
                } else {
                    rows[y][i * depth / 8] |= (unsigned char)(v << (8 - depth - i * depth % 8));
                }
            }
        rowp[y] = rows[y];
    }
    png_write_image(png, rowp);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(f);
    fprintf(cases, "{\"%s\", %d, %d, %d, %d},\n", name, colour, depth, interlace, trns);
    printf("wrote %s\n", path);
}

/* Netpbm sources for ImageMagick: P5/P6 (grey, RGB) and P7 (RGBA), maxval 255 or 65535. */
static void write_pnm(const char *dir, const char *name, int n, int depth, int palette)
{
    char path[512];
    FILE *f;
    int x, y, c;
    unsigned max = (1u << depth) - 1;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "wb");
    if (!f) exit(1);
    if (n == 4) fprintf(f, "P7\nWIDTH %d\nHEIGHT %d\nDEPTH 4\nMAXVAL %u\nTUPLTYPE RGB_ALPHA\nENDHDR\n", W, H, max);
    else fprintf(f, "P%d\n%d %d\n%u\n", n == 1 ? 5 : 6, W, H, max);
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x)
            for (c = 0; c < n; ++c) {
                unsigned v = palette ? corpus_palette((int)corpus_png(x, y, 0, 8), c) : corpus_png(x, y, c, depth);
                if (depth == 16) fputc((int)(v >> 8), f);
                fputc((int)(v & 0xff), f);
            }
    fclose(f);
}

int main(int argc, char **argv)
{
    static const int grey_depths[] = {1, 2, 4, 8, 16}, pal_depths[] = {1, 2, 4, 8};
    char path[512], name[64];
    size_t i;
    int f;
    if (argc != 3) {
        fprintf(stderr, "usage: make_png_corpus OUTDIR PNM_SOURCE_DIR\n");
        return 2;
    }
    snprintf(path, sizeof path, "%s/png_cases.inc", argv[1]);
    cases = fopen(path, "w");
    if (!cases) return 1;
    fprintf(cases, "/* written by tools/images/make_png_corpus.c: file, colour type, depth, Adam7, tRNS */\n");
    for (i = 0; i < 5; ++i) {
        snprintf(name, sizeof name, "lp_grey%d.png", grey_depths[i]);
        write_png(argv[1], name, 0, grey_depths[i], 0, 0, -1);
    }
    for (i = 0; i < 4; ++i) {
        snprintf(name, sizeof name, "lp_pal%d.png", pal_depths[i]);
        write_png(argv[1], name, 3, pal_depths[i], 0, 0, -1);
        snprintf(name, sizeof name, "lp_pal%d_trns.png", pal_depths[i]);
        write_png(argv[1], name, 3, pal_depths[i], 0, 1, -1);
    }
    write_png(argv[1], "lp_rgb8.png", 2, 8, 0, 0, -1);
    write_png(argv[1], "lp_rgb16.png", 2, 16, 0, 0, -1);
    write_png(argv[1], "lp_ga8.png", 4, 8, 0, 0, -1);
    write_png(argv[1], "lp_ga16.png", 4, 16, 0, 0, -1);
    write_png(argv[1], "lp_rgba8.png", 6, 8, 0, 0, -1);
    write_png(argv[1], "lp_rgba16.png", 6, 16, 0, 0, -1);
    write_png(argv[1], "lp_grey8_trns.png", 0, 8, 0, 1, -1);
    write_png(argv[1], "lp_grey2_trns.png", 0, 2, 0, 1, -1);
    write_png(argv[1], "lp_rgb8_trns.png", 2, 8, 0, 1, -1);
    write_png(argv[1], "lp_rgb16_trns.png", 2, 16, 0, 1, -1);
    write_png(argv[1], "lp_rgb8_adam7.png", 2, 8, 1, 0, -1);
    write_png(argv[1], "lp_grey1_adam7.png", 0, 1, 1, 0, -1);
    write_png(argv[1], "lp_rgba16_adam7.png", 6, 16, 1, 0, -1);
    write_png(argv[1], "lp_pal4_adam7.png", 3, 4, 1, 1, -1);
    {
        static const int filters[] = {PNG_FILTER_NONE, PNG_FILTER_SUB, PNG_FILTER_UP, PNG_FILTER_AVG,
                                      PNG_FILTER_PAETH};
        for (f = 0; f < 5; ++f) {
            snprintf(name, sizeof name, "lp_rgb8_filter%d.png", f);
            write_png(argv[1], name, 2, 8, 0, 0, filters[f]);
            snprintf(name, sizeof name, "lp_ga16_filter%d.png", f);
            write_png(argv[1], name, 4, 16, 0, 0, filters[f]);
            snprintf(name, sizeof name, "lp_grey4_filter%d.png", f);
            write_png(argv[1], name, 0, 4, 0, 0, filters[f]);
        }
    }
    /* ImageMagick's files (make_png_corpus.sh) are listed here too */
    fprintf(cases, "{\"im_grey8.png\", 0, 8, 0, 0},\n{\"im_grey16.png\", 0, 16, 0, 0},\n");
    fprintf(cases, "{\"im_rgb8.png\", 2, 8, 0, 0},\n{\"im_rgb16.png\", 2, 16, 0, 0},\n");
    fprintf(cases, "{\"im_rgba8.png\", 6, 8, 0, 0},\n{\"im_rgba16.png\", 6, 16, 0, 0},\n");
    fprintf(cases, "{\"im_rgb8_adam7.png\", 2, 8, 1, 0},\n{\"im_pal8.png\", 3, 8, 0, 0},\n");
    fclose(cases);
    write_pnm(argv[2], "grey8.pgm", 1, 8, 0);
    write_pnm(argv[2], "grey16.pgm", 1, 16, 0);
    write_pnm(argv[2], "rgb8.ppm", 3, 8, 0);
    write_pnm(argv[2], "rgb16.ppm", 3, 16, 0);
    write_pnm(argv[2], "rgba8.pam", 4, 8, 0);
    write_pnm(argv[2], "rgba16.pam", 4, 16, 0);
    write_pnm(argv[2], "pal8.ppm", 3, 8, 1);
    return 0;
}
