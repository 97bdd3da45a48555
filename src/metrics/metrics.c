/* Pixel-statistics metrics: MSE, RMSE, relMSE, MAPE (GRIS footnote 13), SMAPE and
 * two bias measures. Every formula, with its epsilon, is written out in docs/metrics.md;
 * the comments here name which one each function is. */
#include "restir/metrics/metrics.h"

#include <math.h>
#include <string.h>

static const char *const metric_names[METRIC_COUNT] = {"mse",  "rmse", "relmse",   "mape",    "smape",
                                                        "marb", "rel_bias", "flip_ldr", "flip_hdr"};

const char *metric_name(enum metric_id id) { return (id >= 0 && id < METRIC_COUNT) ? metric_names[id] : "?"; }

int metric_from_name(const char *name)
{
    int i;
    if (!strcmp(name, "flip")) return METRIC_FLIP_HDR;
    for (i = 0; i < METRIC_COUNT; ++i)
        if (!strcmp(name, metric_names[i])) return i;
    return -1;
}

image_rect image_full_rect(const image *img)
{
    image_rect r;
    r.x = 0;
    r.y = 0;
    r.w = img->width;
    r.h = img->height;
    return r;
}

/* Rec. 709 luminance, the weights of luminance() in vec.h, evaluated in double
 * because metrics are double in every build (vec.h's is in `real`). */
static double lum709(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

static int check_finite(const image *img, const char *name, const image_rect *r, rerror *e)
{
    static const char *const channel[3] = {"red", "green", "blue"};
    int x, y, c;
    for (y = r->y; y < r->y + r->h; ++y)
        for (x = r->x; x < r->x + r->w; ++x)
            for (c = 0; c < 3; ++c) {
                float v = image_pixel(img, x, y)[c];
                if (!isfinite(v))
                    return rerror_at(e, name, 0, "pixel (%d, %d) %s is %s (metrics need finite values)", x, y,
                                     channel[c], isnan(v) ? "NaN" : "infinite");
            }
    return 0;
}

int metrics_check_inputs(const image *test, const char *test_name, const image *ref, const char *ref_name,
                         const image_rect *crop, rerror *e)
{
    image_rect r = crop ? *crop : image_full_rect(ref);
    if (test->width != ref->width || test->height != ref->height)
        return rerror_at(e, test_name, 0, "size %d x %d differs from the reference %s (%d x %d)", test->width,
                         test->height, ref_name, ref->width, ref->height);
    if (r.w <= 0 || r.h <= 0 || r.x < 0 || r.y < 0 || r.x > ref->width - r.w || r.y > ref->height - r.h)
        return rerror_at(e, ref_name, 0, "crop %d,%d,%d,%d is empty or outside the %d x %d image", r.x, r.y, r.w, r.h,
                         ref->width, ref->height);
    if (check_finite(test, test_name, &r, e) || check_finite(ref, ref_name, &r, e)) return -1;
    return 0;
}

/* n / d for a non-negative ratio whose denominator may vanish: 0/0 = 0, n/0 = +inf. */
static double safe_ratio(double n, double d) { return d > 0 ? n / d : (n == 0 ? 0.0 : HUGE_VAL); }

/* The scale of the relative metrics: eps = 0.01 * mean |Y(ref)| (GRIS footnote 13;
 * |.| only matters for references with negative values). */
static double reference_eps(const image *ref, const image_rect *r)
{
    double sum = 0;
    int x, y;
    for (y = r->y; y < r->y + r->h; ++y)
        for (x = r->x; x < r->x + r->w; ++x) sum += fabs(lum709(image_pixel(ref, x, y)));
    return METRICS_EPS_FACTOR * sum / ((double)r->w * r->h);
}

/* SMAPE's epsilon is symmetric in the two images: 0.01 * (mean|Y(x)| + mean|Y(r)|) / 2. */
static double symmetric_eps(const image *test, const image *ref, const image_rect *r)
{
    return 0.5 * (reference_eps(test, r) + reference_eps(ref, r));
}

/* ---- per-pixel terms (the metric is the mean of the term over the crop) ---- */

static double term_squared_error(const float *x, const float *r)
{
    double s = 0;
    int c;
    for (c = 0; c < 3; ++c) s += ((double)x[c] - r[c]) * ((double)x[c] - r[c]);
    return s / 3;
}

static double term_relative_squared_error(const float *x, const float *r, double eps)
{
    double s = 0;
    int c;
    for (c = 0; c < 3; ++c) {
        double d = (double)x[c] - r[c], denom = eps + fabs((double)r[c]);
        s += safe_ratio(d * d, denom * denom);
    }
    return s / 3;
}

/* GRIS footnote 13: |I - I_gt| / (0.01 mean(I_gt) + I_gt) on luminance. */
static double term_absolute_percentage_error(const float *x, const float *r, double eps)
{
    double yr = lum709(r);
    return safe_ratio(fabs(lum709(x) - yr), eps + fabs(yr));
}

static double term_symmetric_percentage_error(const float *x, const float *r, double eps)
{
    double s = 0;
    int c;
    for (c = 0; c < 3; ++c) s += safe_ratio(fabs((double)x[c] - r[c]), fabs((double)x[c]) + fabs((double)r[c]) + eps);
    return s / 3;
}

/* ---- tile bias ---- */

/* |relative bias| of one tile: |mean Y(x) - mean Y(r)| / (eps + |mean Y(r)|). */
static double tile_abs_bias(const image *test, const image *ref, int x0, int y0, int x1, int y1, double eps)
{
    double sx = 0, sr = 0, n = (double)(x1 - x0) * (y1 - y0);
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            sx += lum709(image_pixel(test, x, y));
            sr += lum709(image_pixel(ref, x, y));
        }
    return safe_ratio(fabs(sx / n - sr / n), eps + fabs(sr / n));
}

/* MARB: pixel-weighted mean of the tiles' |relative bias|. Tiles are anchored at the crop's
 * corner, partial at the right and bottom edges. If map is non-NULL, each pixel receives
 * its tile's value. */
static double marb_over_tiles(const image *test, const image *ref, const image_rect *r, double eps, float *map)
{
    const int t = METRICS_BIAS_TILE;
    double weighted = 0;
    int tx, ty, x, y;
    for (ty = r->y; ty < r->y + r->h; ty += t)
        for (tx = r->x; tx < r->x + r->w; tx += t) {
            int x1 = tx + t < r->x + r->w ? tx + t : r->x + r->w;
            int y1 = ty + t < r->y + r->h ? ty + t : r->y + r->h;
            double b = tile_abs_bias(test, ref, tx, ty, x1, y1, eps);
            weighted += b * (double)(x1 - tx) * (y1 - ty);
            if (map)
                for (y = ty; y < y1; ++y)
                    for (x = tx; x < x1; ++x) map[(size_t)(y - r->y) * r->w + (x - r->x)] = (float)b;
        }
    return weighted / ((double)r->w * r->h);
}

int metrics_compute(const image *test, const image *ref, const image_rect *crop, image_metrics *out, rerror *e)
{
    image_rect r = crop ? *crop : image_full_rect(ref);
    double se = 0, rse = 0, ape = 0, sape = 0, sum_yx = 0, sum_yr = 0, eps, eps_sym;
    int x, y, i;
    if (metrics_check_inputs(test, "test", ref, "reference", &r, e)) return -1;
    eps = reference_eps(ref, &r);
    eps_sym = symmetric_eps(test, ref, &r);
    for (y = r.y; y < r.y + r.h; ++y)
        for (x = r.x; x < r.x + r.w; ++x) {
            const float *px = image_pixel(test, x, y), *pr = image_pixel(ref, x, y);
            se += term_squared_error(px, pr);
            rse += term_relative_squared_error(px, pr, eps);
            ape += term_absolute_percentage_error(px, pr, eps);
            sape += term_symmetric_percentage_error(px, pr, eps_sym);
            sum_yx += lum709(px);
            sum_yr += lum709(pr);
        }
    out->pixels = (long)r.w * r.h;
    out->eps = eps;
    for (i = 0; i < METRIC_COUNT; ++i) out->value[i] = NAN;
    out->value[METRIC_MSE] = se / out->pixels;
    out->value[METRIC_RMSE] = sqrt(se / out->pixels);
    out->value[METRIC_RELMSE] = rse / out->pixels;
    out->value[METRIC_MAPE] = ape / out->pixels;
    out->value[METRIC_SMAPE] = sape / out->pixels;
    out->value[METRIC_MARB] = marb_over_tiles(test, ref, &r, eps, NULL);
    /* signed: sum Y(x) / sum Y(r) - 1 (NaN or +-inf against an all-black reference) */
    out->value[METRIC_REL_BIAS] = (sum_yx - sum_yr) / sum_yr;
    return 0;
}

int metrics_error_map(enum metric_id id, const image *test, const image *ref, const image_rect *crop, float *map,
                      rerror *e)
{
    image_rect r = crop ? *crop : image_full_rect(ref);
    double eps, eps_sym, v = 0;
    int x, y;
    if (metrics_check_inputs(test, "test", ref, "reference", &r, e)) return -1;
    if (id == METRIC_REL_BIAS || id == METRIC_FLIP_LDR || id == METRIC_FLIP_HDR || id < 0 || id >= METRIC_COUNT)
        return rerror_set(e, "metric '%s' has no per-pixel map here", metric_name(id));
    eps = reference_eps(ref, &r);
    eps_sym = symmetric_eps(test, ref, &r);
    if (id == METRIC_MARB) {
        marb_over_tiles(test, ref, &r, eps, map);
        return 0;
    }
    for (y = r.y; y < r.y + r.h; ++y)
        for (x = r.x; x < r.x + r.w; ++x) {
            const float *px = image_pixel(test, x, y), *pr = image_pixel(ref, x, y);
            switch (id) {
            case METRIC_MSE: v = term_squared_error(px, pr); break;
            case METRIC_RMSE: v = sqrt(term_squared_error(px, pr)); break;
            case METRIC_RELMSE: v = term_relative_squared_error(px, pr, eps); break;
            case METRIC_MAPE: v = term_absolute_percentage_error(px, pr, eps); break;
            case METRIC_SMAPE: v = term_symmetric_percentage_error(px, pr, eps_sym); break;
            default: break;
            }
            map[(size_t)(y - r.y) * r.w + (x - r.x)] = (float)v;
        }
    return 0;
}
