/* Float RGB images: allocation only (file formats live in pfm.c and png.c). */
#include "restir/core/image.h"

#include <math.h>
#include <stdlib.h>

unsigned long long image_nonfinite_pixels(const image *img)
{
    unsigned long long n = 0;
    size_t i, count = (size_t)img->width * (size_t)img->height;
    for (i = 0; i < count; ++i) {
        const float *p = img->px + 3 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) n++;
    }
    return n;
}

int image_alloc(image *img, int width, int height, rerror *e)
{
    img->width = 0;
    img->height = 0;
    img->px = NULL;
    if (width <= 0 || height <= 0) return rerror_set(e, "image size %d x %d is not positive", width, height);
    /* rcalloc checks count*size for overflow; width*height*3 itself is done in size_t. */
    if ((long)width * (long)height > IMAGE_MAX_PIXELS)
        return rerror_set(e, "image size %d x %d is too large (at most %ld pixels)", width, height, IMAGE_MAX_PIXELS);
    img->px = rcalloc((size_t)width * (size_t)height * 3, sizeof(float), e);
    if (!img->px) return -1;
    img->width = width;
    img->height = height;
    return 0;
}

void image_free(image *img)
{
    free(img->px);
    img->px = NULL;
    img->width = 0;
    img->height = 0;
}
