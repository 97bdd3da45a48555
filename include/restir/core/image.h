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

#endif
