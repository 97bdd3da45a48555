/* Equal-time comparisons (docs/equal-time.md): render a scene with a
 * method for growing budgets, record (seconds, MAPE, relMSE) against a reference image
 * (metrics.h), write the curves as CSV for `restir plot` and as a log-log SVG, and read
 * off the time each method needs to reach a given error.
 *
 * A method is a callback that renders "units" — independent, equally weighted estimates
 * of the image: one sample per pixel of the path tracer, one frame of offline ReSTIR
 * (GRIS §6.5: the result is the explicit mean of the frames, GRIS Eq. 47). The harness
 * asks for units [first, first + count), accumulates their per-pixel sum, and after
 * count_k = ceil(first_units * growth^k) units in total (log-spaced) records the time
 * spent inside the callbacks and the errors of the running mean. Rendering continues
 * where it stopped, so the whole curve costs one render of the largest budget. */
#ifndef RESTIR_EQUAL_TIME_H
#define RESTIR_EQUAL_TIME_H

#include <stdint.h>
#include "restir/core/error.h"
#include "restir/core/image.h"
#include "restir/render/pt.h"
#include "restir/scene/scene.h"

/* Adds to sum (width x height pixels, 3 doubles each, RGB, row-major, row 0 at the top)
 * the sum over the units [first, first + count) of their image estimates, or fails if
 * it renders another size. Units with different indices must be independent (e.g.
 * disjoint sample ranges of the addressed RNG). */
typedef int (*equal_time_render_fn)(void *ctx, uint32_t first, uint32_t count, int width, int height, double *sum,
                                    rerror *e);

typedef struct {
    const char *name; /* curve name: CSV column and legend entry */
    equal_time_render_fn render;
    void *ctx;
} equal_time_method;

typedef struct {
    uint32_t first_units; /* units before the first record (default 1) */
    double growth;        /* > 1: the unit count of the next record (default 2) */
    uint32_t max_units;   /* stop at this many units (the last record is exactly here); 0 = no limit */
    double time_budget;   /* stop after the record that reaches this many seconds; 0 = no limit */
} equal_time_options;

typedef struct {
    uint32_t units;
    double seconds; /* cumulative time inside the render callbacks */
    double mape, relmse;
} equal_time_point;

typedef struct {
    char name[128];
    equal_time_point *points;
    int count;
} equal_time_curve;

enum equal_time_metric { EQUAL_TIME_MAPE = 0, EQUAL_TIME_RELMSE = 1 };

void equal_time_options_default(equal_time_options *o);
/* At least one of max_units and time_budget must be set. */
int equal_time_options_validate(const equal_time_options *o, rerror *e);

/* Runs method m against the reference (its size is the image size the callback must
 * produce). Fills *out (free with equal_time_curve_free). */
int equal_time_run(const equal_time_method *m, const image *reference, const equal_time_options *o,
                   equal_time_curve *out, rerror *e);
void equal_time_curve_free(equal_time_curve *c);

double equal_time_value(const equal_time_point *p, enum equal_time_metric metric);

/* The CSV `restir plot` reads: header "seconds,NAME1,NAME2,...", then one row per point of
 * every curve (curve after curve) with the metric in that curve's column and the other
 * columns empty. Written atomically. */
int equal_time_write_csv(const char *path, const equal_time_curve *curves, int n, enum equal_time_metric metric,
                         rerror *e);
/* All recorded values: "method,units,seconds,mape,relmse", one row per point. */
int equal_time_write_table(const char *path, const equal_time_curve *curves, int n, rerror *e);
/* The log-log plot of the metric against seconds (plot.h), written atomically. */
int equal_time_write_svg(const char *path, const equal_time_curve *curves, int n, enum equal_time_metric metric,
                         const char *title, rerror *e);

/* Least-squares line through (log seconds, log error) of the points with positive finite
 * values: error ~ exp(intercept) * seconds^slope (slope -1/2 for MAPE, -1 for relMSE
 * when the error is pure variance). Fails with fewer than two usable points. */
int equal_time_fit(const equal_time_curve *c, enum equal_time_metric metric, double *slope, double *intercept,
                   rerror *e);

enum equal_time_reach {
    EQUAL_TIME_INTERPOLATED = 0, /* the curve crosses the target between two records */
    EQUAL_TIME_EXTRAPOLATED = 1, /* it does not: the fitted power law gives the time */
    EQUAL_TIME_UNREACHABLE = -1  /* no usable fit (fewer than two points, or slope >= 0) */
};
/* Time at which the curve first reaches `target`: at the first record k with
 * error_k <= target, linear interpolation of log seconds against log error between
 * records k-1 and k (the curve is close to a straight line on the log-log plot); the
 * first record itself if k = 0 and error_0 == target; otherwise (k = 0 with error_0 <
 * target, or never reached) the power-law fit, marked as an extrapolation. *seconds is
 * NaN when unreachable. */
enum equal_time_reach equal_time_time_to_reach(const equal_time_curve *c, enum equal_time_metric metric,
                                               double target, double *seconds);

/* The reference path tracer as a method: unit u = sample index sample_offset + u of
 * pt_render with the given options (spp, sample_offset, checkpoints, callbacks and
 * time limit are set by the harness). ctx must stay alive while the method is used. */
typedef struct {
    const scene *s;
    pt_options options;
} equal_time_pt_ctx;
void equal_time_pt_method(equal_time_pt_ctx *ctx, const scene *s, const pt_options *options, const char *name,
                          equal_time_method *m);

#endif
