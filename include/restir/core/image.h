/* Float RGB images, PFM read/write and PNG previews.
 * Memory layout: row 0 is the TOP row, 3 floats per pixel (r, g, b).
 * (PFM stores rows bottom-to-top; the reader/writer flip.) */
#ifndef RESTIR_IMAGE_H
#define RESTIR_IMAGE_H

#include "restir/core/error.h"

/* Largest image (8192 x 8192 = 2^26 pixels): image_alloc, the PFM reader, `--size` and
 * the scene file's `size` refuse more before allocating (docs/formats.md "Limits"). */
#define IMAGE_MAX_PIXELS ((long)1 << 26)

typedef struct {
    int width, height;
    float *px; /* width*height*3 floats */
} image;

int image_alloc(image *img, int width, int height, rerror *e); /* zero-filled */
void image_free(image *img);
/* Pixels with a NaN or Inf channel (the NaN/Inf policy counts them; docs/precision.md). */
unsigned long long image_nonfinite_pixels(const image *img);
static inline float *image_pixel(const image *img, int x, int y)
{
    return img->px + 3 * ((long)y * img->width + x);
}

/* PFM ("PF" colour, "Pf" greyscale). A "Pf" file is read into all three channels;
 * *channels (may be NULL) receives 1 or 3. The scale's sign gives the byte order
 * (negative = little-endian); its magnitude is ignored. Errors: "file: what". */
int pfm_read(const char *path, image *out, int *channels, rerror *e);
/* Writes "PF", little-endian (scale -1.0), atomically. */
int pfm_write(const char *path, const image *img, rerror *e);

/* 8-bit sRGB preview: multiply by 2^exposure, clamp, sRGB transfer curve. Atomic. */
int png_write_preview(const char *path, const image *img, double exposure, rerror *e);
/* Raw 8-bit RGB writer (stored deflate blocks, CRC-32, Adler-32). Atomic. */
int png_write_rgb8(const char *path, int width, int height, const unsigned char *rgb8, rerror *e);

#endif
