/* SVG line plots (src/metrics/plot_svg.c; restir plot): log-log axes by default, one polyline
 * per series. */
#ifndef RESTIR_METRICS_PLOT_SVG_H
#define RESTIR_METRICS_PLOT_SVG_H

#include "restir/metrics/plot.h"

void plot_options_default(plot_options *o);

/* Writes the plot as a standalone SVG document. *skipped (may be NULL) receives the
 * number of points that could not be drawn (NaN, or <= 0 on a log axis). Fails if no
 * series has a drawable point. */
int plot_svg_fprint(FILE *fp, const plot_options *o, const plot_series *series, int series_count, long *skipped,
                    rerror *e);
/* The same, written atomically to `path`. */
int plot_svg_write(const char *path, const plot_options *o, const plot_series *series, int series_count,
                   long *skipped, rerror *e);

#endif
