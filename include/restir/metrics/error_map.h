/* False-colour error images: the per-pixel map in a colour map, and under it a colour
 * bar with its two end values printed in a small built-in bitmap font. */
#ifndef RESTIR_ERROR_MAP_H
#define RESTIR_ERROR_MAP_H

#include "restir/core/error.h"

typedef enum { PALETTE_MAGMA, PALETTE_VIRIDIS } error_palette;

typedef struct {
    int width, height;
    unsigned char *rgb; /* width*height*3 bytes, row 0 at the top */
} rgb8_image;

/* Renders map (w*h values, row-major) with values lo..hi mapped linearly onto the palette
 * (values outside are clamped). The canvas is at least ERROR_MAP_MIN_WIDTH wide; the
 * map sits at its top-left, the bar and the labels "lo" (left) and "hi" (right) below. */
#define ERROR_MAP_MIN_WIDTH 160
int error_map_render(const float *map, int w, int h, double lo, double hi, error_palette palette, rgb8_image *out,
                     rerror *e);
void rgb8_image_free(rgb8_image *img);

/* Draws text (characters "0123456789.-+eainf " ; others are skipped as blanks) with its
 * top-left corner at (x, y), each glyph 5x7 pixels scaled by `scale`, 6*scale apart. */
void draw_text(rgb8_image *img, int x, int y, int scale, const char *text, const unsigned char color[3]);
/* Width in pixels of text drawn by draw_text. */
int text_width(const char *text, int scale);

#endif
