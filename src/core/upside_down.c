/* Warn when an image matches the reference far better upside down (upside_down.h). */
#include "restir/core/upside_down.h"

#include <math.h>
#include <stdio.h>

void image_mse_flipped(const image *test, const image *ref, double *mse, double *mse_flipped)
{
    double sum = 0, sum_flipped = 0;
    long n = 0;
    int x, y, c;
    *mse = *mse_flipped = 0;
    if (test->width != ref->width || test->height != ref->height) return;
    for (y = 0; y < ref->height; ++y)
        for (x = 0; x < ref->width; ++x)
            for (c = 0; c < 3; ++c) {
                double r = image_pixel(ref, x, y)[c], t = image_pixel(test, x, y)[c];
                double f = image_pixel(test, x, ref->height - 1 - y)[c];
                if (!isfinite(r) || !isfinite(t) || !isfinite(f)) continue;
                sum += (t - r) * (t - r);
                sum_flipped += (f - r) * (f - r);
                n++;
            }
    if (n) {
        *mse = sum / (double)n;
        *mse_flipped = sum_flipped / (double)n;
    }
}

int image_warn_upside_down(const image *test, const char *test_name, const image *ref, const char *ref_name)
{
    double mse, mse_flipped;
    image_mse_flipped(test, ref, &mse, &mse_flipped);
    /* a quarter: noise alone makes both errors alike; a symmetric scene makes them equal */
    if (!(mse > 0) || !(mse_flipped < 0.25 * mse)) return 0;
    fprintf(stderr,
            "warning: %s matches %s far better upside down (MSE %.4g as read, %.4g with its rows reversed): it was "
            "probably written with the top row first, while PFM stores the bottom row first. Fix its writer, or "
            "convert it (e.g. to .exr, which has no such ambiguity)\n",
            test_name, ref_name, mse, mse_flipped);
    return 1;
}
