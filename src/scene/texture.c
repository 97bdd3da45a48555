/* Image textures: decode rule and bilinear lookup (include/restir/scene/texture.h). */
#include "restir/scene/texture.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/exr.h"
#include "restir/core/image_io.h"
#include "restir/core/pfm.h"
#include "restir/core/png_read.h"

/* The file as float channels: PNG decoded by the kind's rule (colour maps are sRGB-encoded
 * pictures, data maps hold values), EXR and PFM as stored (linear). */
static int read_file(const char *path, enum texture_kind kind, fimage *f, rerror *e)
{
    image img;
    int status;
    if (image_path_is(path, "png")) return png_read(path, kind == TEXTURE_COLOUR ? PNG_SRGB : PNG_LINEAR, f, e);
    if (image_path_is(path, "exr")) return exr_read(path, f, e);
    if (pfm_read(path, &img, NULL, e)) return -1;
    status = fimage_alloc(f, img.width, img.height, 3, e);
    if (!status) memcpy(f->px, img.px, (size_t)img.width * (size_t)img.height * 3 * sizeof *f->px);
    image_free(&img);
    return status;
}

/* Picks the kind's channels out of the file's (1 Y, 2 YA, 3 RGB, 4 RGBA). */
static void convert(const fimage *f, scene_texture *t)
{
    size_t n = (size_t)f->width * (size_t)f->height, i;
    int c = f->channels, has_alpha = c == 2 || c == 4;
    for (i = 0; i < n; ++i) {
        const float *p = f->px + i * (size_t)c;
        if (t->kind == TEXTURE_COLOUR) {
            int grey = c < 3;
            t->px[3 * i] = p[0];
            t->px[3 * i + 1] = grey ? p[0] : p[1];
            t->px[3 * i + 2] = grey ? p[0] : p[2];
        } else {
            t->px[i] = t->kind == TEXTURE_ALPHA && has_alpha ? p[c - 1] : p[0];
        }
    }
}

int texture_load(scene_texture *t, const char *path, enum texture_kind kind, rerror *e)
{
    fimage f;
    size_t n;
    memset(t, 0, sizeof *t);
    memset(&f, 0, sizeof f);
    if (strlen(path) >= sizeof t->path) return rerror_set(e, "%.200s...: path too long", path);
    if (read_file(path, kind, &f, e)) return -1;
    t->kind = kind;
    t->width = f.width;
    t->height = f.height;
    t->channels = kind == TEXTURE_COLOUR ? 3 : 1;
    n = (size_t)f.width * (size_t)f.height;
    if (!(f.width > 0 && f.height > 0)) {
        fimage_free(&f);
        return rerror_set(e, "%s: empty image", path);
    }
    t->px = rmalloc(n * (size_t)t->channels, sizeof *t->px, e);
    if (!t->px) {
        fimage_free(&f);
        return -1;
    }
    convert(&f, t);
    fimage_free(&f);
    for (n = n * (size_t)t->channels; n-- > 0;)
        if (!isfinite(t->px[n]) || t->px[n] < 0) {
            texture_free(t);
            return rerror_set(e, "%s: texel value %g is negative or not finite", path, (double)t->px[n]);
        }
    memcpy(t->path, path, strlen(path) + 1);
    return 0;
}

void texture_free(scene_texture *t)
{
    free(t->px);
    t->px = NULL;
}

int texture_copy(scene_texture *dst, const scene_texture *src, rerror *e)
{
    size_t n = (size_t)src->width * (size_t)src->height * (size_t)src->channels;
    *dst = *src;
    dst->px = rmalloc(n, sizeof *dst->px, e);
    if (!dst->px) return -1;
    memcpy(dst->px, src->px, n * sizeof *dst->px);
    return 0;
}

/* The two texels a coordinate falls between along an axis of n texels (repeat wrap) and
 * the weight of the second. x is in texel units with texel centres at integers. */
static void axis(real x, int n, int *i0, int *i1, real *f)
{
    real fl = (real)floor(x);
    int i = (int)fl;
    *f = x - fl;
    i %= n;
    if (i < 0) i += n;
    *i0 = i;
    *i1 = i + 1 == n ? 0 : i + 1;
}

/* Bilinear weights and texel offsets of (u, v) (the lookup of texture.h). */
static void footprint(const scene_texture *t, vec2 uv, size_t at[4], real w[4])
{
    real u = isfinite(uv.x) ? uv.x - (real)floor(uv.x) : 0; /* in [0, 1): keeps the floor in int range */
    real v = isfinite(uv.y) ? uv.y - (real)floor(uv.y) : 0;
    int x0, x1, y0, y1;
    real fx, fy;
    axis(u * (real)t->width - (real)0.5, t->width, &x0, &x1, &fx);
    axis((1 - v) * (real)t->height - (real)0.5, t->height, &y0, &y1, &fy); /* row 0 is v = 1 */
    at[0] = (size_t)y0 * (size_t)t->width + (size_t)x0;
    at[1] = (size_t)y0 * (size_t)t->width + (size_t)x1;
    at[2] = (size_t)y1 * (size_t)t->width + (size_t)x0;
    at[3] = (size_t)y1 * (size_t)t->width + (size_t)x1;
    w[0] = (1 - fx) * (1 - fy);
    w[1] = fx * (1 - fy);
    w[2] = (1 - fx) * fy;
    w[3] = fx * fy;
}

rgb texture_rgb(const scene_texture *t, vec2 uv)
{
    size_t at[4];
    real w[4], c[3] = {0, 0, 0};
    int k, ch;
    footprint(t, uv, at, w);
    for (k = 0; k < 4; ++k)
        for (ch = 0; ch < 3; ++ch) c[ch] += w[k] * (real)t->px[at[k] * (size_t)t->channels + (size_t)(t->channels == 3 ? ch : 0)];
    return rgb_make(c[0], c[1], c[2]);
}

real texture_scalar(const scene_texture *t, vec2 uv)
{
    size_t at[4];
    real w[4], c = 0;
    int k;
    footprint(t, uv, at, w);
    for (k = 0; k < 4; ++k) c += w[k] * (real)t->px[at[k] * (size_t)t->channels];
    return c;
}
