/* Image files by name: the extension picks PFM, OpenEXR or PNG (docs/images.md). */
#include "restir/core/image_io.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/exr.h"
#include "restir/core/pfm.h"
#include "restir/core/png_read.h"

int fimage_alloc(fimage *img, int width, int height, int channels, rerror *e)
{
    memset(img, 0, sizeof *img);
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
        return rerror_set(e, "image size %d x %d x %d is invalid", width, height, channels);
    if ((long)width * (long)height > IMAGE_MAX_PIXELS)
        return rerror_set(e, "image size %d x %d is too large (at most %ld pixels)", width, height, IMAGE_MAX_PIXELS);
    img->px = rcalloc((size_t)width * (size_t)height * (size_t)channels, sizeof(float), e);
    if (!img->px) return -1;
    img->width = width;
    img->height = height;
    img->channels = channels;
    return 0;
}

void fimage_free(fimage *img)
{
    free(img->px);
    memset(img, 0, sizeof *img);
}

unsigned char *image_file_load(const char *path, size_t max_size, size_t *size, rerror *e)
{
    FILE *fp = fopen(path, "rb");
    struct stat st;
    unsigned char *buf;
    size_t n;
    if (!fp) {
        rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
        return NULL;
    }
    if (fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(fp);
        rerror_at(e, path, 0, "not a regular file");
        return NULL;
    }
    if ((unsigned long long)st.st_size > max_size) {
        fclose(fp);
        rerror_at(e, path, 0, "file of %lld bytes is too large (at most %llu)", (long long)st.st_size,
                  (unsigned long long)max_size);
        return NULL;
    }
    n = (size_t)st.st_size;
    buf = rmalloc(n + 1, 1, e); /* +1: a zero-length file still gets a buffer */
    if (buf && fread(buf, 1, n, fp) != n) {
        free(buf);
        buf = NULL;
        rerror_at(e, path, 0, "read failed: %s", strerror(errno));
    }
    fclose(fp);
    *size = n;
    return buf;
}

int image_path_is(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext), i;
    if (n <= k || path[n - k - 1] != '.') return 0;
    for (i = 0; i < k; ++i)
        if (tolower((unsigned char)path[n - k + i]) != ext[i]) return 0;
    return 1;
}

/* Y -> R = G = B; alpha dropped. */
static int to_rgb(const fimage *f, image *out, rerror *e)
{
    size_t i, n = (size_t)f->width * (size_t)f->height;
    if (image_alloc(out, f->width, f->height, e)) return -1;
    for (i = 0; i < n; ++i) {
        const float *s = f->px + i * (size_t)f->channels;
        float *d = out->px + 3 * i;
        if (f->channels >= 3) {
            d[0] = s[0];
            d[1] = s[1];
            d[2] = s[2];
        } else {
            d[0] = d[1] = d[2] = s[0];
        }
    }
    return 0;
}

int image_read(const char *path, image *out, int *channels, rerror *e)
{
    fimage f;
    int status;
    out->width = out->height = 0;
    out->px = NULL;
    if (image_path_is(path, "exr")) status = exr_read(path, &f, e);
    else if (image_path_is(path, "png")) status = png_read(path, PNG_SRGB, &f, e);
    else return pfm_read(path, out, channels, e);
    if (status) return -1;
    status = to_rgb(&f, out, e);
    if (!status && channels) *channels = f.channels;
    fimage_free(&f);
    if (status) {
        char why[sizeof e->msg];
        snprintf(why, sizeof why, "%s", e->msg);
        rerror_at(e, path, 0, "%s", why);
    }
    return status;
}

int image_write(const char *path, const image *img, rerror *e) { return image_write_as(path, path, img, e); }

int image_write_as(const char *path, const char *name, const image *img, rerror *e)
{
    if (image_path_is(name, "exr")) return exr_write(path, img, EXR_ZIP, EXR_FLOAT, e);
    return pfm_write(path, img, e);
}

const char *image_output_ext(const char *path) { return image_path_is(path, "exr") ? "exr" : "pfm"; }

/* Formats restir reads (PNG) or that a user may expect, but that it does not write as
 * data: naming one for a float output is a mistake, refused before any work. */
static const char *const unwritable[] = {"png", "jpg", "jpeg", "hdr", "tif", "tiff", "bmp", "tga", "webp", "gif", NULL};

int image_output_check(const char *path, rerror *e)
{
    int i;
    for (i = 0; unwritable[i]; ++i)
        if (image_path_is(path, unwritable[i]))
            return rerror_at(e, path, 0, "restir does not write float data as .%s (name the file .exr or .pfm)",
                             unwritable[i]);
    return 0;
}
