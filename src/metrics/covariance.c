/* Average box covariance between pixels, Mutations Eq. 21 (covariance.h).
 *
 * For the box B_r(i) of radius r around pixel i (clipped to the image, n_r(i) pixels)
 *     sum_{j in B_r(i)} Cov(i, j)
 *       = 1/(K-1) sum_{j in B} [ sum_k y_ki y_kj - K ybar_i ybar_j ]
 *       = 1/(K-1) [ sum_k y_ki S_k(i, r) - K ybar_i Sbar(i, r) ]
 * where S_k(i, r) is the box sum of image k and Sbar that of the mean. Covariance is
 * unchanged by shifting each pixel by a constant, so y = luminance - (first image's
 * luminance) keeps the sums of products small and free of cancellation. Box sums come
 * from a summed-area table, so each image costs O(pixels x radii). */
#include "restir/metrics/covariance.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/vec.h"

int covariance_init(covariance_accum *c, int width, int height, int radius, int exclude_center, rerror *e)
{
    size_t n = (size_t)width * (size_t)height;
    memset(c, 0, sizeof *c);
    if (width <= 0 || height <= 0) return rerror_set(e, "covariance: image size %d x %d is not positive", width, height);
    if (radius < 0 || radius > 4096) return rerror_set(e, "covariance: radius %d must be in 0..4096", radius);
    if (exclude_center && radius < 1) return rerror_set(e, "covariance: excluding the centre needs radius >= 1");
    c->width = width;
    c->height = height;
    c->radius = radius;
    c->exclude_center = exclude_center;
    c->shift = rcalloc(n, sizeof(double), e);
    c->sum = rcalloc(n, sizeof(double), e);
    c->map_cross = rcalloc(n, sizeof(double), e);
    c->map_self = rcalloc(n, sizeof(double), e);
    c->y = rcalloc(n, sizeof(double), e);
    c->sat = rcalloc((size_t)(width + 1) * (size_t)(height + 1), sizeof(double), e);
    c->cross = rcalloc((size_t)radius + 1, sizeof(double), e);
    c->self = rcalloc((size_t)radius + 1, sizeof(double), e);
    if (!c->shift || !c->sum || !c->map_cross || !c->map_self || !c->y || !c->sat || !c->cross || !c->self) {
        covariance_free(c);
        return -1;
    }
    return 0;
}

void covariance_free(covariance_accum *c)
{
    free(c->shift);
    free(c->sum);
    free(c->map_cross);
    free(c->map_self);
    free(c->y);
    free(c->sat);
    free(c->cross);
    free(c->self);
    memset(c, 0, sizeof *c);
}

/* sat[(y)(w+1) + x] = sum of v over [0, x) x [0, y). */
static void build_sat(double *sat, const double *v, int width, int height)
{
    int x, y;
    size_t stride = (size_t)width + 1;
    memset(sat, 0, stride * sizeof *sat);
    for (y = 0; y < height; ++y) {
        double row = 0.0;
        sat[(size_t)(y + 1) * stride] = 0.0;
        for (x = 0; x < width; ++x) {
            row += v[(size_t)y * width + x];
            sat[(size_t)(y + 1) * stride + x + 1] = sat[(size_t)y * stride + x + 1] + row;
        }
    }
}

/* The clipped box of radius r around (x, y): its sum from the table, and its pixel count. */
static double box_sum(const double *sat, int width, int height, int x, int y, int r, long *count)
{
    size_t stride = (size_t)width + 1;
    int x0 = x - r < 0 ? 0 : x - r, y0 = y - r < 0 ? 0 : y - r;
    int x1 = x + r + 1 > width ? width : x + r + 1, y1 = y + r + 1 > height ? height : y + r + 1;
    *count = (long)(x1 - x0) * (y1 - y0);
    return sat[(size_t)y1 * stride + x1] - sat[(size_t)y0 * stride + x1] - sat[(size_t)y1 * stride + x0] +
           sat[(size_t)y0 * stride + x0];
}

/* The weight of pixel i in the image average at radius r: 1/n (or 1/(n-1) without the centre). */
static double box_weight(long count, int exclude_center) { return 1.0 / (double)(exclude_center ? count - 1 : count); }

int covariance_add(covariance_accum *c, const image *img, const char *name, rerror *e)
{
    int x, y, r;
    size_t i, n = (size_t)c->width * (size_t)c->height;
    if (img->width != c->width || img->height != c->height)
        return rerror_at(e, name ? name : "image", 0, "image is %d x %d, the others are %d x %d", img->width,
                         img->height, c->width, c->height);
    for (i = 0; i < n; ++i) {
        const float *p = img->px + 3 * i;
        double lum;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return rerror_at(e, name ? name : "image", 0, "pixel (%ld, %ld) is not finite", (long)(i % (size_t)c->width),
                             (long)(i / (size_t)c->width));
        lum = (double)luminance(rgb_make(p[0], p[1], p[2]));
        if (c->images == 0) c->shift[i] = lum;
        c->y[i] = lum - c->shift[i];
    }
    c->images++;
    build_sat(c->sat, c->y, c->width, c->height);
    for (y = 0; y < c->height; ++y)
        for (x = 0; x < c->width; ++x) {
            size_t idx = (size_t)y * c->width + x;
            double v = c->y[idx];
            long count;
            c->sum[idx] += v;
            c->map_self[idx] += v * v;
            for (r = c->exclude_center ? 1 : 0; r <= c->radius; ++r) {
                double s = box_sum(c->sat, c->width, c->height, x, y, r, &count);
                double w = box_weight(count, c->exclude_center);
                c->cross[r] += w * v * s;
                c->self[r] += w * v * v;
                if (r == c->radius) c->map_cross[idx] += v * s;
            }
        }
    return 0;
}

/* Mutations Eq. 21, box-averaged per pixel and then over the image (Mutations §5). */
int covariance_result(const covariance_accum *c, double *per_radius, image *map, rerror *e)
{
    double k = (double)c->images, *mean;
    size_t i, n = (size_t)c->width * (size_t)c->height;
    int x, y, r;
    if (c->images < 2) return rerror_set(e, "covariance needs at least 2 images, got %ld", c->images);
    mean = rmalloc(n, sizeof *mean, e);
    if (!mean) return -1;
    for (i = 0; i < n; ++i) mean[i] = c->sum[i] / k;
    if (map && image_alloc(map, c->width, c->height, e)) {
        free(mean);
        return -1;
    }
    /* The K ybar_i Sbar(i, r) terms, weighted as the accumulated ones. */
    {
        double *sat = rmalloc((size_t)(c->width + 1) * (size_t)(c->height + 1), sizeof(double), e);
        double *cross_mean = rcalloc((size_t)c->radius + 1, sizeof(double), e);
        double *self_mean = rcalloc((size_t)c->radius + 1, sizeof(double), e);
        if (!sat || !cross_mean || !self_mean) {
            free(sat);
            free(cross_mean);
            free(self_mean);
            free(mean);
            if (map) image_free(map);
            return -1;
        }
        build_sat(sat, mean, c->width, c->height);
        for (y = 0; y < c->height; ++y)
            for (x = 0; x < c->width; ++x) {
                size_t idx = (size_t)y * c->width + x;
                double m = mean[idx];
                long count = 0;
                double s = 0.0;
                for (r = c->exclude_center ? 1 : 0; r <= c->radius; ++r) {
                    double w;
                    s = box_sum(sat, c->width, c->height, x, y, r, &count);
                    w = box_weight(count, c->exclude_center);
                    cross_mean[r] += w * k * m * s;
                    self_mean[r] += w * k * m * m;
                }
                if (map) {
                    double total = c->map_cross[idx] - k * m * s;
                    if (c->exclude_center) total -= c->map_self[idx] - k * m * m;
                    map->px[3 * idx] = map->px[3 * idx + 1] = map->px[3 * idx + 2] =
                        (float)(total / ((k - 1.0) * (double)(c->exclude_center ? count - 1 : count)));
                }
            }
        for (r = 0; r <= c->radius; ++r) {
            double total = c->cross[r] - cross_mean[r];
            if (c->exclude_center) total -= c->self[r] - self_mean[r];
            per_radius[r] = total / ((k - 1.0) * (double)n);
        }
        if (c->exclude_center) per_radius[0] = NAN;
        free(sat);
        free(cross_mean);
        free(self_mean);
    }
    free(mean);
    return 0;
}
