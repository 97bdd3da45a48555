/* Line plots as SVG, written by our own code (docs/statistics.md, "plot"): log-log by
 * default (error against time or samples), decade ticks labelled 10^k with minor
 * ticks at 2..9 x 10^k, linear axes with 1-2-5 ticks, a legend, and per series a
 * distinct colour (Okabe-Ito palette), dash pattern and marker. Also reads the CSV
 * files that `restir plot` takes. */
#ifndef RESTIR_PLOT_H
#define RESTIR_PLOT_H

#include <stdio.h>
#include "restir/core/error.h"

typedef struct {
    const char *name;  /* legend entry */
    const double *x, *y;
    int count;         /* points; NaN coordinates (and non-positive ones on a log axis) are skipped */
} plot_series;

enum plot_scale { PLOT_LOG = 0, PLOT_LINEAR = 1 };

typedef struct {
    const char *title, *xlabel, *ylabel; /* may be NULL */
    enum plot_scale x_scale, y_scale;    /* default: both PLOT_LOG */
    int width, height;                   /* SVG size in pixels (default 640 x 440) */
} plot_options;

/* A CSV table in "wide" format: a header row, then one row per x value:
 *     x,series A,series B
 *     1,0.5,0.7
 *     2,0.25,
 * First column x, every other column one series; an empty cell is a missing point.
 * Fields may be double-quoted ("" inside quotes is a quote). Blank lines and lines
 * starting with '#' are ignored. */
typedef struct {
    int rows, columns;   /* columns includes x */
    char **names;        /* column names (names[0] = the x header) */
    double *values;      /* column-major: column c is values + c * rows; NaN = missing */
} plot_table;

#endif
