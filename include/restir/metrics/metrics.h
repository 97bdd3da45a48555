/* Image-difference metrics between a test image and a reference (docs/metrics.md has
 * every formula with its epsilon). Arguments are always (test, reference): the
 * relative metrics divide by the reference. All sums run over the pixels of an
 * optional crop rectangle in row-major order, in double precision. */
#ifndef RESTIR_METRICS_H
#define RESTIR_METRICS_H

#include "restir/core/error.h"
#include "restir/core/image.h"

/* A pixel rectangle [x, x+w) x [y, y+h). */
typedef struct {
    int x, y, w, h;
} image_rect;

/* Epsilon factor of the relative metrics: eps = METRICS_EPS_FACTOR * mean luminance
 * of the reference (GRIS footnote 13 uses 0.01 * mean(I_gt)). */
#define METRICS_EPS_FACTOR 0.01
/* Tile edge (pixels) of the mean absolute relative bias. */
#define METRICS_BIAS_TILE 16

enum metric_id {
    METRIC_MSE = 0,
    METRIC_RMSE,
    METRIC_RELMSE,
    METRIC_MAPE,
    METRIC_SMAPE,
    METRIC_MARB,     /* mean absolute relative bias over tiles */
    METRIC_REL_BIAS, /* signed relative bias of the mean luminance */
    METRIC_FLIP_LDR,
    METRIC_FLIP_HDR,
    METRIC_COUNT
};

/* Lower-case names used by the CLI and the JSON output ("mse", "flip_hdr", ...). */
const char *metric_name(enum metric_id id);
/* Looks a name up ("flip" is accepted for flip_hdr). Returns -1 if unknown. */
int metric_from_name(const char *name);

typedef struct {
    double value[METRIC_COUNT]; /* may be +inf (e.g. MAPE against an all-black reference) */
    double eps;                 /* the epsilon the relative metrics used */
    long pixels;                /* pixels in the crop */
} image_metrics;

/* The whole image as a rectangle. */
image_rect image_full_rect(const image *img);

/* Checks that the images have the same size, the rectangle lies inside them and is
 * not empty, and that every value in it is finite. Messages: "NAME: what". */
int metrics_check_inputs(const image *test, const char *test_name, const image *ref, const char *ref_name,
                         const image_rect *crop, rerror *e);

/* All non-FLIP metrics over the crop (NULL = whole image); the FLIP entries are set to NaN
 * (flip.h computes them). Checks the inputs first (names "test" and "reference"). */
int metrics_compute(const image *test, const image *ref, const image_rect *crop, image_metrics *out, rerror *e);

/* Per-pixel map (crop->w * crop->h floats, row-major) of a non-FLIP metric, such that the
 * metric is the mean of the map (RMSE: the map is the per-pixel root of the MSE map;
 * MARB: each pixel holds its tile's |bias|). METRIC_REL_BIAS has no map (error). */
int metrics_error_map(enum metric_id id, const image *test, const image *ref, const image_rect *crop, float *map,
                      rerror *e);

#endif
