/* restir plot DATA.csv -o FIG.svg: line plots of CSV tables (docs/statistics.md, "plot"). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/plot.h"

static const char usage[] =
    "usage: restir plot DATA.csv -o FIG.svg [options]\n"
    "  DATA.csv: a header row, then rows 'x,y1,y2,...' (first column x, one column per\n"
    "  series, empty cell = missing point)\n"
    "options:\n"
    "  --title T, --xlabel X, --ylabel Y   text (default x label: the first header)\n"
    "  --loglog (default) | --linear | --logx | --logy   axis scales\n"
    "  --width W --height H                size in pixels (default 640 x 440)\n";

static int usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "restir plot: %s%s\n(restir plot --help for usage)\n", what, arg);
    return 2;
}

int cmd_plot(int argc, char **argv)
{
    plot_options o;
    plot_table t;
    plot_series *series;
    const char *input = NULL, *output = NULL;
    rerror e;
    long skipped = 0;
    int i, status;
    plot_options_default(&o);
    for (i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(opt, "--loglog")) {
            o.x_scale = o.y_scale = PLOT_LOG;
        } else if (!strcmp(opt, "--linear")) {
            o.x_scale = o.y_scale = PLOT_LINEAR;
        } else if (!strcmp(opt, "--logx")) {
            o.x_scale = PLOT_LOG;
            o.y_scale = PLOT_LINEAR;
        } else if (!strcmp(opt, "--logy")) {
            o.x_scale = PLOT_LINEAR;
            o.y_scale = PLOT_LOG;
        } else if (!strcmp(opt, "-o") || !strcmp(opt, "--output") || !strcmp(opt, "--title") ||
                   !strcmp(opt, "--xlabel") || !strcmp(opt, "--ylabel") || !strcmp(opt, "--width") ||
                   !strcmp(opt, "--height")) {
            const char *val = i + 1 < argc ? argv[++i] : NULL;
            if (!val) return usage_error("missing value after ", opt);
            if (!strcmp(opt, "--title"))
                o.title = val;
            else if (!strcmp(opt, "--xlabel"))
                o.xlabel = val;
            else if (!strcmp(opt, "--ylabel"))
                o.ylabel = val;
            else if (!strcmp(opt, "--width") || !strcmp(opt, "--height")) {
                char *end;
                long v = strtol(val, &end, 10);
                if (end == val || *end || v < 200 || v > 20000) return usage_error("size must be 200..20000, not ", val);
                if (opt[2] == 'w')
                    o.width = (int)v;
                else
                    o.height = (int)v;
            } else
                output = val;
        } else if (!strncmp(opt, "-", 1) && opt[1]) {
            return usage_error("unknown option ", opt);
        } else if (!input) {
            input = opt;
        } else {
            return usage_error("more than one input file: ", opt);
        }
    }
    if (!input || !output) return usage_error("needs DATA.csv and -o FIG.svg", "");
    if (plot_csv_read(input, &t, &e)) {
        fprintf(stderr, "%s\n", e.msg);
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
