/* Reading and writing images by file name: .pfm, .exr and .png (docs/images.md).
 *
 * image_read / image_write pick the format from the extension (case-insensitive);
 * anything else is read and written as PFM, as before. They are what every command
 * that takes an image path uses (compare, check, merge, render -o, ...). */
#ifndef RESTIR_IMAGE_IO_H
#define RESTIR_IMAGE_IO_H

#include <stddef.h>
#include "restir/core/image.h"

/* A float image with its own channel count, as the readers return it:
 * 1 = Y, 2 = Y + alpha, 3 = RGB, 4 = RGBA. Row 0 is the top row; channels interleaved. */
typedef struct {
    int width, height, channels;
    float *px;
} fimage;

/* Refuses width*height above IMAGE_MAX_PIXELS before allocating; zero-filled. */
int fimage_alloc(fimage *img, int width, int height, int channels, rerror *e);
void fimage_free(fimage *img);

/* Reads a whole file (at most max_size bytes, checked with fstat before allocating).
 * Errors "path: what". */
unsigned char *image_file_load(const char *path, size_t max_size, size_t *size, rerror *e);

/* By extension: .exr (exr_read), .png (png_read with PNG_SRGB: a PNG given where a
 * radiance image is expected is taken as an sRGB-encoded picture), else PFM. The
 * result is RGB: Y is copied to R, G and B, alpha is dropped. *channels (may be NULL)
 * receives the file's channel count. */
int image_read(const char *path, image *out, int *channels, rerror *e);
/* By extension: .exr (float channels, ZIP), else PFM. Atomic, like pfm_write. */
int image_write(const char *path, const image *img, rerror *e);
/* image_write to `path` in the format that `name`'s extension picks: an output staged
 * under a temporary name (output_set.h) keeps the format of its final name. */
int image_write_as(const char *path, const char *name, const image *img, rerror *e);
/* "exr" if an output named `path` is written as OpenEXR, else "pfm" (the extension of
 * the files derived from it: sequence frames, moments images). */
const char *image_output_ext(const char *path);
/* 0 if a float image (radiance, variance, z) may be written under `path`; an error
 * "path: ..." if its extension names a format restir does not write as data (.png,
 * which is the preview, .jpg, .hdr, .tif, ...). Callers check every output first. */
int image_output_check(const char *path, rerror *e);
/* 1 if the path ends in .exr, .png or .pfm respectively (any case). */
int image_path_is(const char *path, const char *ext);

#endif
