/* PNG output (src/core/png.c): 8-bit previews of radiance images (exposure, sRGB) and raw
 * 8-bit RGB, written atomically with stored deflate blocks. */
#ifndef RESTIR_CORE_PNG_H
#define RESTIR_CORE_PNG_H

#include "restir/core/image.h"

/* 8-bit sRGB preview: multiply by 2^exposure, clamp, sRGB transfer curve. Atomic. */
int png_write_preview(const char *path, const image *img, double exposure, rerror *e);
/* Raw 8-bit RGB writer (stored deflate blocks, CRC-32, Adler-32). Atomic. */
int png_write_rgb8(const char *path, int width, int height, const unsigned char *rgb8, rerror *e);

#endif
