/* CSV tables for restir plot (src/metrics/plot_csv.c): a header row of column names, then
 * numbers. */
#ifndef RESTIR_METRICS_PLOT_CSV_H
#define RESTIR_METRICS_PLOT_CSV_H

#include "restir/metrics/plot.h"

int plot_csv_read(const char *path, plot_table *t, rerror *e);
void plot_table_free(plot_table *t);

#endif
