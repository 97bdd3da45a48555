/* restir plot DATA.csv -o FIG.svg: line plots of CSV tables (docs/statistics.md, "plot"). */
#include "cmd_plot.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/plot.h"
#include "restir/metrics/plot_csv.h"
#include "restir/metrics/plot_svg.h"
#include "args.h"
#include "outputs_ready.h"

/* What the option table cannot say (printed after it by --help). */
static const char help_notes[] =
    "\nDATA.csv: a header row, then rows 'x,y1,y2,...' (first column x, one column per\n"
    "series, empty cell = missing point). Axes: --loglog (default), --linear, --logx, --logy.\n";

static int usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "restir plot: %s%s\n(restir plot --help for usage)\n", what, arg);
    return 2;
}

/* --loglog | --linear | --logx | --logy: at most one. */
static int apply_scales(const int given[4], plot_options *o)
{
    static const enum plot_scale x[4] = {PLOT_LOG, PLOT_LINEAR, PLOT_LOG, PLOT_LINEAR};
    static const enum plot_scale y[4] = {PLOT_LOG, PLOT_LINEAR, PLOT_LINEAR, PLOT_LOG};
    int i, chosen = -1;
    for (i = 0; i < 4; ++i) {
        if (!given[i]) continue;
        if (chosen >= 0) return usage_error("give one of --loglog, --linear, --logx, --logy", "");
        chosen = i;
    }
    if (chosen >= 0) {
        o->x_scale = x[chosen];
        o->y_scale = y[chosen];
    }
    return 0;
}

/* A linear axis maps [min, max] of the finite values to pixels: a span beyond the double
 * range (1e308 and -1e308) would draw every point at NaN, so it is an input error, and so
 * are spans the tick loop cannot step through (below). A log axis is always drawable. */
static int spans_finite(const plot_table *t, const plot_options *o, const char *input)
{
    int c, r;
    for (c = 0; c < 2; ++c) {
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        int first = c ? 1 : 0, end = c ? t->columns : 1;
        if ((c ? o->y_scale : o->x_scale) != PLOT_LINEAR) continue;
        for (; first < end; ++first)
            for (r = 0; r < t->rows; ++r) {
                double v = t->values[(size_t)first * t->rows + r];
                if (!isfinite(v)) continue;
                if (v < lo) lo = v;
                if (v > hi) hi = v;
            }
        /* ticks step by a 1-2-5 fraction of the span from a rounded end: near the double
         * limit the rounded end overflows, and a span below the values' rounding unit
         * leaves the tick loop adding nothing (both hung the plot) */
        if (hi >= lo && (fabs(lo) > 1e300 || fabs(hi) > 1e300 || (hi > lo && hi - lo < 1e-12 * fmax(fabs(lo), fabs(hi))))) {
            fprintf(stderr, "%s: the %s values span %.17g .. %.17g: a linear axis cannot draw them (|value| <= 1e300 "
                            "and a span >= 1e-12 of it; use a log axis, or scale the data)\n", input, c ? "y" : "x", lo, hi);
            return 2;
        }
    }
    return 0;
}

int cmd_plot(int argc, char **argv)
{
    plot_options o;
    plot_table t;
    plot_series *series;
    const char *input = NULL, *output = NULL, *positional[1];
    rerror e;
    long skipped = 0;
    int i, status, count, scale[4] = {0, 0, 0, 0};
    plot_options_default(&o);
    {
        const cli_option options[] = {
            {"-o", OPT_STRING, &output, "FIG.svg: the output (written atomically)", NULL, 0, 0, NULL},
            {"--title", OPT_STRING, &o.title, "title text", NULL, 0, 0, NULL},
            {"--xlabel", OPT_STRING, &o.xlabel, "x axis label (default: the first header)", NULL, 0, 0, NULL},
            {"--ylabel", OPT_STRING, &o.ylabel, "y axis label", NULL, 0, 0, NULL},
            {"--loglog", OPT_FLAG, &scale[0], "log x, log y (default)", NULL, 0, 0, NULL},
            {"--linear", OPT_FLAG, &scale[1], "linear x, linear y", NULL, 0, 0, NULL},
            {"--logx", OPT_FLAG, &scale[2], "log x, linear y", NULL, 0, 0, NULL},
            {"--logy", OPT_FLAG, &scale[3], "linear x, log y", NULL, 0, 0, NULL},
            {"--width", OPT_INT, &o.width, "width in pixels (default 640)", NULL, 200, 20000, NULL},
            {"--height", OPT_INT, &o.height, "height in pixels (default 440)", NULL, 200, 20000, NULL},
            {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
        };
        status = cli_parse("plot", argc, argv, options, positional, 1, &count);
        if (status == 1) {
            cli_print_help(stdout, "plot", "DATA.csv -o FIG.svg [options]", options);
            fputs(help_notes, stdout);
            return 0;
        }
        if (status) return status;
    }
    if (apply_scales(scale, &o)) return 2;
    if (count == 1) input = positional[0];
    if (!input || !output) return usage_error("needs DATA.csv and -o FIG.svg", "");
    {
        const named_file out = {output, "-o"}, in = {input, "DATA.csv"};
        if (outputs_ready("plot", &out, 1, &in, 1)) return 2;
    }
    if (plot_csv_read(input, &t, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (spans_finite(&t, &o, input)) {
        plot_table_free(&t);
        return 2;
    }
    if (!o.xlabel) o.xlabel = t.names[0];
    series = calloc((size_t)t.columns - 1, sizeof *series);
    if (!series) {
        plot_table_free(&t);
        fprintf(stderr, "restir plot: out of memory\n");
        return 2;
    }
    for (i = 1; i < t.columns; ++i) {
        series[i - 1].name = t.names[i];
        series[i - 1].x = t.values;
        series[i - 1].y = t.values + (size_t)i * t.rows;
        series[i - 1].count = t.rows;
    }
    status = plot_svg_write(output, &o, series, t.columns - 1, &skipped, &e);
    if (status)
        fprintf(stderr, "%s: %s\n", input, e.msg);
    else if (skipped)
        fprintf(stderr, "restir plot: %s: %ld point(s) not drawn (not finite, or <= 0 on a log axis)\n", input, skipped);
    free(series);
    plot_table_free(&t);
    return status ? 2 : 0;
}
