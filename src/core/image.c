/* Float RGB images: allocation only (file formats live in pfm.c and png.c). */
#include "restir/image.h"

#include <stdlib.h>

int image_alloc(image *img, int width, int height, rerror *e)
{
    img->width = 0;
    img->height = 0;
    img->px = NULL;
    if (width <= 0 || height <= 0) return rerror_set(e, "image size %d x %d is not positive", width, height);
    /* rcalloc checks count*size for overflow; width*height*3 itself is done in size_t. */
    if ((size_t)width > (size_t)-1 / 3 / (size_t)height)
        return rerror_set(e, "image size %d x %d is too large", width, height);
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
