/* Error-map images: palette lookup, a colour bar, and end labels in a 5x7 bitmap font. */
#include "restir/metrics/error_map.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/colormap.h"

/* 5x7 glyphs, one byte per row (top to bottom), bit 4 = leftmost column. */
typedef struct {
    char c;
    unsigned char rows[7];
} glyph;

static const glyph font[] = {
    {'0', {0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e}}, {'1', {0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e}},
    {'2', {0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f}}, {'3', {0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e}},
    {'4', {0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02}}, {'5', {0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e}},
    {'6', {0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e}}, {'7', {0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e}}, {'9', {0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c}}, {'-', {0x00, 0x00, 0x00, 0x1f, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1f, 0x04, 0x04, 0x00}}, {'e', {0x00, 0x00, 0x0e, 0x11, 0x1f, 0x10, 0x0e}},
    {'a', {0x00, 0x00, 0x0e, 0x01, 0x0f, 0x11, 0x0f}}, {'i', {0x04, 0x00, 0x0c, 0x04, 0x04, 0x04, 0x0e}},
    {'n', {0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11}}, {'f', {0x06, 0x09, 0x08, 0x1c, 0x08, 0x08, 0x08}},
};

static const unsigned char *glyph_rows(char c)
{
    size_t i;
    for (i = 0; i < sizeof font / sizeof font[0]; ++i)
        if (font[i].c == c) return font[i].rows;
    return NULL;
}

static void put_pixel(rgb8_image *img, int x, int y, const unsigned char color[3])
{
    if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
    memcpy(img->rgb + 3 * ((size_t)y * img->width + x), color, 3);
}

int text_width(const char *text, int scale)
{
    size_t n = strlen(text);
    return n ? (int)(6 * n - 1) * scale : 0;
}

void draw_text(rgb8_image *img, int x, int y, int scale, const char *text, const unsigned char color[3])
{
    for (; *text; ++text, x += 6 * scale) {
        const unsigned char *rows = glyph_rows(*text);
        int gx, gy, sx, sy;
        if (!rows) continue;
        for (gy = 0; gy < 7; ++gy)
            for (gx = 0; gx < 5; ++gx)
                if (rows[gy] & (0x10 >> gx))
                    for (sy = 0; sy < scale; ++sy)
                        for (sx = 0; sx < scale; ++sx) put_pixel(img, x + gx * scale + sx, y + gy * scale + sy, color);
    }
}

static void palette_color(error_palette p, double t, unsigned char rgb[3])
{
    if (p == PALETTE_MAGMA) colormap_magma(t, rgb);
    else colormap_viridis(t, rgb);
}

static double normalise(double v, double lo, double hi) { return hi > lo ? (v - lo) / (hi - lo) : 0.0; }

/* Compact label of a bar end: %.4g, which the font can draw. */
static void format_label(char *buf, size_t size, double v)
{
    if (isnan(v)) snprintf(buf, size, "nan");
    else if (isinf(v)) snprintf(buf, size, v > 0 ? "inf" : "-inf");
    else snprintf(buf, size, "%.4g", v);
}

enum { MARGIN = 4, BAR_HEIGHT = 12, GAP = 4, LABEL_SPACE = 12 };

int error_map_render(const float *map, int w, int h, double lo, double hi, error_palette palette, rgb8_image *out,
                     rerror *e)
{
    static const unsigned char background[3] = {255, 255, 255}, ink[3] = {0, 0, 0};
    char lo_text[32], hi_text[32];
    int x, y, bar_y, bar_w, label_y, scale;
    size_t i;
    out->rgb = NULL;
    if (w <= 0 || h <= 0) return rerror_set(e, "error map: empty image");
    out->width = w > ERROR_MAP_MIN_WIDTH ? w : ERROR_MAP_MIN_WIDTH;
    format_label(lo_text, sizeof lo_text, lo);
    format_label(hi_text, sizeof hi_text, hi);
    /* double-size labels when both fit side by side */
    scale = text_width(lo_text, 2) + text_width(hi_text, 2) + LABEL_SPACE <= out->width - 2 * MARGIN ? 2 : 1;
    bar_y = h + GAP;
    label_y = bar_y + BAR_HEIGHT + GAP;
    out->height = label_y + 7 * scale + MARGIN;
    out->rgb = rmalloc((size_t)out->width * out->height, 3, e);
    if (!out->rgb) return -1;
    for (i = 0; i < (size_t)out->width * out->height; ++i) memcpy(out->rgb + 3 * i, background, 3);
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) {
            unsigned char c[3];
            palette_color(palette, normalise(map[(size_t)y * w + x], lo, hi), c);
            put_pixel(out, x, y, c);
        }
    /* the bar: left end = lo, right end = hi */
    bar_w = out->width - 2 * MARGIN;
    for (x = 0; x < bar_w; ++x) {
        unsigned char c[3];
        palette_color(palette, bar_w > 1 ? (double)x / (bar_w - 1) : 0.0, c);
        for (y = 0; y < BAR_HEIGHT; ++y) put_pixel(out, MARGIN + x, bar_y + y, c);
    }
    draw_text(out, MARGIN, label_y, scale, lo_text, ink);
    draw_text(out, out->width - MARGIN - text_width(hi_text, scale), label_y, scale, hi_text, ink);
    return 0;
}

void rgb8_image_free(rgb8_image *img)
{
    free(img->rgb);
    img->rgb = NULL;
}
