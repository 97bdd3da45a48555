/* SVG line plots (plot.h). The drawing is a fixed layout: title on top, the plot area
 * with a light grid, axis labels below and to the left, the legend in the upper right
 * corner of the plot area. Coordinates are written with two decimals. */
#include "restir/metrics/plot_svg.h"

#include "restir/metrics/plot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"

void plot_options_default(plot_options *o)
{
    memset(o, 0, sizeof *o);
    o->x_scale = PLOT_LOG;
    o->y_scale = PLOT_LOG;
    o->width = 640;
    o->height = 440;
}

/* ---- text ---- */

/* Length of a well-formed UTF-8 sequence starting at s, or 0. */
static int utf8_length(const unsigned char *s)
{
    int n, i;
    if (s[0] < 0x80) return 1;
    if ((s[0] & 0xe0) == 0xc0 && s[0] >= 0xc2) n = 2;
    else if ((s[0] & 0xf0) == 0xe0) n = 3;
    else if ((s[0] & 0xf8) == 0xf0 && s[0] <= 0xf4) n = 4;
    else return 0;
    for (i = 1; i < n; ++i)
        if ((s[i] & 0xc0) != 0x80) return 0;
    return n;
}

/* Character data / attribute value: the five XML specials escaped, control characters
 * (not allowed in XML 1.0) and malformed UTF-8 replaced by '?'. */
static void put_xml_text(FILE *fp, const char *text)
{
    const unsigned char *s = (const unsigned char *)text;
    while (*s) {
        int n = utf8_length(s);
        if (n == 0) {
            fputc('?', fp);
            s++;
            continue;
        }
        if (n > 1) {
            fwrite(s, 1, (size_t)n, fp);
            s += n;
            continue;
        }
        switch (*s) {
        case '&': fputs("&amp;", fp); break;
        case '<': fputs("&lt;", fp); break;
        case '>': fputs("&gt;", fp); break;
        case '"': fputs("&quot;", fp); break;
        case '\'': fputs("&apos;", fp); break;
        default: fputc(*s < 0x20 ? '?' : *s, fp); break;
        }
        s++;
    }
}

/* ---- axes ---- */

typedef struct {
    enum plot_scale scale;
    double lo, hi;      /* in axis units: log10(value) for log axes */
    double step;        /* linear: tick spacing */
    double px0, px1;    /* screen coordinates of lo and hi */
} axis;

static int drawable(const axis *a, double v) { return isfinite(v) && (a->scale == PLOT_LINEAR || v > 0.0); }

static double axis_unit(const axis *a, double v) { return a->scale == PLOT_LOG ? log10(v) : v; }

static double axis_px(const axis *a, double v)
{
    return a->px0 + (axis_unit(a, v) - a->lo) / (a->hi - a->lo) * (a->px1 - a->px0);
}

/* 1, 2 or 5 times a power of ten, at least raw. */
static double nice_step(double raw)
{
    double p = pow(10.0, floor(log10(raw)));
    if (p >= raw) return p;
    if (2.0 * p >= raw) return 2.0 * p;
    if (5.0 * p >= raw) return 5.0 * p;
    return 10.0 * p;
}

/* Range over the drawable values: whole decades (log) or whole 1-2-5 steps (linear). */
static void axis_fit(axis *a, double vmin, double vmax)
{
    if (a->scale == PLOT_LOG) {
        a->lo = floor(log10(vmin));
        a->hi = ceil(log10(vmax));
        if (a->hi <= a->lo) {
            a->lo -= 1.0;
            a->hi += 1.0;
        }
        return;
    }
    if (vmax <= vmin) {
        double pad = fabs(vmin) > 0.0 ? 0.1 * fabs(vmin) : 1.0;
        vmin -= pad;
        vmax += pad;
    }
    a->step = nice_step((vmax - vmin) / 5.0);
    a->lo = floor(vmin / a->step) * a->step;
    a->hi = ceil(vmax / a->step) * a->step;
    if (a->hi <= a->lo) a->hi = a->lo + a->step;
}

/* A tick label: 10<sup>k</sup> on log axes, %g of the 1-2-5 value on linear ones. */
static void put_tick_label(FILE *fp, const axis *a, double unit, double x, double y, const char *anchor)
{
    fprintf(fp, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"%s\">", x, y, anchor);
    if (a->scale == PLOT_LOG) {
        fprintf(fp, "10<tspan dy=\"-6\" font-size=\"9\">%d</tspan>", (int)lround(unit));
    } else {
        double v = fabs(unit) < 1e-9 * a->step ? 0.0 : unit;
        fprintf(fp, "%.6g", v);
    }
    fputs("</text>\n", fp);
}

/* Ticks, grid lines and labels of one axis. horizontal: the x axis. */
static void draw_axis(FILE *fp, const axis *a, int horizontal, double cross0, double cross1)
{
    double u, span = a->hi - a->lo;
    if (a->scale == PLOT_LOG) {
        int decades = (int)lround(span), every = decades > 8 ? (decades + 7) / 8 : 1, k;
        for (k = (int)a->lo; k <= (int)a->hi; ++k) {
            double p = axis_px(a, pow(10.0, k));
            int m;
            if (horizontal) {
                fprintf(fp, "<line class=\"grid\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", p, cross0, p, cross1);
                fprintf(fp, "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", p, cross0, p, cross0 - 6);
                if ((k - (int)a->lo) % every == 0) put_tick_label(fp, a, k, p, cross0 + 20, "middle");
            } else {
                fprintf(fp, "<line class=\"grid\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", cross0, p, cross1, p);
                fprintf(fp, "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", cross0, p, cross0 + 6, p);
                if ((k - (int)a->lo) % every == 0) put_tick_label(fp, a, k, cross0 - 8, p + 4, "end");
            }
            if (k == (int)a->hi || decades > 12) continue;
            for (m = 2; m <= 9; ++m) { /* minor ticks at m x 10^k */
                double q = axis_px(a, m * pow(10.0, k));
                if (horizontal)
                    fprintf(fp, "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", q, cross0, q, cross0 - 3);
                else
                    fprintf(fp, "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", cross0, q, cross0 + 3, q);
            }
        }
        return;
    }
    for (u = a->lo; u <= a->hi + 1e-9 * a->step; u += a->step) {
        double p = a->px0 + (u - a->lo) / span * (a->px1 - a->px0);
        if (horizontal) {
            fprintf(fp, "<line class=\"grid\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", p, cross0, p, cross1);
            fprintf(fp, "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", p, cross0, p, cross0 - 6);
            put_tick_label(fp, a, u, p, cross0 + 18, "middle");
        } else {
            fprintf(fp, "<line class=\"grid\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", cross0, p, cross1, p);
            fprintf(fp, "<line class=\"tick\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>\n", cross0, p, cross0 + 6, p);
            put_tick_label(fp, a, u, cross0 - 8, p + 4, "end");
        }
    }
}

/* ---- series styles ---- */

/* Okabe & Ito (2008) colour-blind-safe palette (yellow left out: too light on white). */
static const char *const colours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"};
static const char *const dashes[] = {"", "7,4", "2,3", "9,3,2,3", "4,2"};
#define COLOUR_COUNT 7
#define DASH_COUNT 5
#define MARKER_COUNT 6

static void put_marker(FILE *fp, int kind, double x, double y, const char *colour)
{
    const double s = 3.6;
    switch (kind) {
    case 0: fprintf(fp, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"%.2f\" fill=\"%s\"/>\n", x, y, s, colour); break;
    case 1: fprintf(fp, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"%s\"/>\n", x - s, y - s, 2 * s, 2 * s, colour); break;
    case 2: fprintf(fp, "<polygon points=\"%.2f,%.2f %.2f,%.2f %.2f,%.2f\" fill=\"%s\"/>\n", x, y - 1.2 * s, x - 1.1 * s, y + 0.8 * s, x + 1.1 * s, y + 0.8 * s, colour); break;
    case 3: fprintf(fp, "<polygon points=\"%.2f,%.2f %.2f,%.2f %.2f,%.2f %.2f,%.2f\" fill=\"%s\"/>\n", x, y - 1.3 * s, x + 1.1 * s, y, x, y + 1.3 * s, x - 1.1 * s, y, colour); break;
    case 4: fprintf(fp, "<polygon points=\"%.2f,%.2f %.2f,%.2f %.2f,%.2f\" fill=\"%s\"/>\n", x, y + 1.2 * s, x - 1.1 * s, y - 0.8 * s, x + 1.1 * s, y - 0.8 * s, colour); break;
    default:
        fprintf(fp, "<path d=\"M%.2f,%.2fL%.2f,%.2fM%.2f,%.2fL%.2f,%.2f\" stroke=\"%s\" stroke-width=\"1.8\" fill=\"none\"/>\n",
                x - s, y - s, x + s, y + s, x - s, y + s, x + s, y - s, colour);
        break;
    }
}

static void put_line_style(FILE *fp, int index)
{
    const char *dash = dashes[(index / COLOUR_COUNT + index) % DASH_COUNT];
    fprintf(fp, "fill=\"none\" stroke=\"%s\" stroke-width=\"1.8\"", colours[index % COLOUR_COUNT]);
    if (dash[0]) fprintf(fp, " stroke-dasharray=\"%s\"", dash);
}

/* One series: a polyline through its drawable points in order (a missing point is
 * skipped, the line joins its neighbours), and markers on at most ~40 of the points. */
static void draw_series(FILE *fp, const plot_series *s, int index, const axis *ax, const axis *ay)
{
    int i, every = s->count > 40 ? (s->count + 39) / 40 : 1;
    const char *colour = colours[index % COLOUR_COUNT];
    fprintf(fp, "<g>\n<polyline ");
    put_line_style(fp, index);
    fprintf(fp, " points=\"");
    for (i = 0; i < s->count; ++i)
        if (drawable(ax, s->x[i]) && drawable(ay, s->y[i]))
            fprintf(fp, "%.2f,%.2f ", axis_px(ax, s->x[i]), axis_px(ay, s->y[i]));
    fprintf(fp, "\"/>\n");
    for (i = 0; i < s->count; i += every)
        if (drawable(ax, s->x[i]) && drawable(ay, s->y[i]))
            put_marker(fp, index % MARKER_COUNT, axis_px(ax, s->x[i]), axis_px(ay, s->y[i]), colour);
    fprintf(fp, "</g>\n");
}

/* How much of the data falls inside a rectangle: points, and 8 samples per segment. */
static long data_inside(const plot_series *series, int count, const axis *ax, const axis *ay, double x0, double y0,
                        double x1, double y1)
{
    long hits = 0;
    int s, i, j;
    for (s = 0; s < count; ++s) {
        double px = 0, py = 0;
        int have_previous = 0;
        for (i = 0; i < series[s].count; ++i) {
            double qx, qy;
            if (!drawable(ax, series[s].x[i]) || !drawable(ay, series[s].y[i])) continue;
            qx = axis_px(ax, series[s].x[i]);
            qy = axis_px(ay, series[s].y[i]);
            for (j = have_previous ? 0 : 8; j <= 8; ++j) {
                double t = j / 8.0, x = px + t * (qx - px), y = py + t * (qy - py);
                hits += x >= x0 && x <= x1 && y >= y0 && y <= y1;
            }
            px = qx;
            py = qy;
            have_previous = 1;
        }
    }
    return hits;
}

/* The legend goes into whichever corner of the plot area covers the least data
 * (upper right first on ties). */
static void draw_legend(FILE *fp, const plot_series *series, int count, const axis *ax, const axis *ay)
{
    size_t longest = 0;
    int i, corner;
    long best_hits = -1;
    double w, h = 18.0 * count + 8.0, x0 = 0, y0 = 0;
    double left = ax->px0, right = ax->px1, top = ay->px1, bottom = ay->px0;
    for (i = 0; i < count; ++i) {
        size_t n = series[i].name ? strlen(series[i].name) : 0;
        if (n > longest) longest = n;
    }
    w = 52.0 + 6.5 * (double)(longest > 60 ? 60 : longest);
    for (corner = 0; corner < 4; ++corner) {
        double cx = corner == 0 || corner == 3 ? right - w - 8.0 : left + 8.0;
        double cy = corner < 2 ? top + 8.0 : bottom - h - 8.0;
        long hits = data_inside(series, count, ax, ay, cx, cy, cx + w, cy + h);
        if (best_hits < 0 || hits < best_hits) {
            best_hits = hits;
            x0 = cx;
            y0 = cy;
        }
    }
    fprintf(fp, "<g class=\"legend\">\n<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"#ffffff\" "
                "fill-opacity=\"0.85\" stroke=\"#999999\"/>\n", x0, y0, w, h);
    for (i = 0; i < count; ++i) {
        double y = y0 + 13.0 + 18.0 * i;
        fprintf(fp, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" ", x0 + 6, y - 4, x0 + 38, y - 4);
        put_line_style(fp, i);
        fprintf(fp, "/>\n");
        put_marker(fp, i % MARKER_COUNT, x0 + 22, y - 4, colours[i % COLOUR_COUNT]);
        fprintf(fp, "<text x=\"%.2f\" y=\"%.2f\">", x0 + 44, y);
        put_xml_text(fp, series[i].name ? series[i].name : "");
        fprintf(fp, "</text>\n");
    }
    fprintf(fp, "</g>\n");
}

/* ---- the document ---- */

static long data_range(const plot_series *series, int count, const axis *ax, const axis *ay, double *xmin,
                       double *xmax, double *ymin, double *ymax)
{
    long skipped = 0, drawn = 0;
    int s, i;
    *xmin = *ymin = INFINITY;
    *xmax = *ymax = -INFINITY;
    for (s = 0; s < count; ++s)
        for (i = 0; i < series[s].count; ++i) {
            double x = series[s].x[i], y = series[s].y[i];
            if (!drawable(ax, x) || !drawable(ay, y)) {
                skipped += !(isnan(y) && isfinite(x)); /* an empty CSV cell is not a skipped point */
                continue;
            }
            drawn++;
            if (x < *xmin) *xmin = x;
            if (x > *xmax) *xmax = x;
            if (y < *ymin) *ymin = y;
            if (y > *ymax) *ymax = y;
        }
    return drawn ? skipped : -1;
}

int plot_svg_fprint(FILE *fp, const plot_options *o, const plot_series *series, int series_count, long *skipped,
                    rerror *e)
{
    axis ax, ay;
    double xmin, xmax, ymin, ymax;
    double left = 84.0, right = o->width - 24.0, top = o->title ? 46.0 : 22.0, bottom = o->height - 58.0;
    long skip;
    int s;
    if (o->width < 200 || o->height < 150) return rerror_set(e, "plot size %d x %d is too small", o->width, o->height);
    memset(&ax, 0, sizeof ax);
    memset(&ay, 0, sizeof ay);
    ax.scale = o->x_scale;
    ay.scale = o->y_scale;
    skip = data_range(series, series_count, &ax, &ay, &xmin, &xmax, &ymin, &ymax);
    if (skip < 0)
        return rerror_set(e, "nothing to plot: no point has finite coordinates%s",
                          ax.scale == PLOT_LOG || ay.scale == PLOT_LOG ? " that are positive on the log axes" : "");
    if (skipped) *skipped = skip;
    axis_fit(&ax, xmin, xmax);
    axis_fit(&ay, ymin, ymax);
    ax.px0 = left;
    ax.px1 = right;
    ay.px0 = bottom;
    ay.px1 = top;

    fprintf(fp, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    fprintf(fp, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
                "font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">\n", o->width, o->height, o->width, o->height);
    fprintf(fp, "<style>.grid{stroke:#e4e4e4;stroke-width:1}.tick{stroke:#333333;stroke-width:1}</style>\n");
    fprintf(fp, "<rect width=\"100%%\" height=\"100%%\" fill=\"#ffffff\"/>\n");
    if (o->title) {
        fprintf(fp, "<text x=\"%.2f\" y=\"26\" text-anchor=\"middle\" font-size=\"15\">", 0.5 * (left + right));
        put_xml_text(fp, o->title);
        fprintf(fp, "</text>\n");
    }
    draw_axis(fp, &ax, 1, bottom, top);
    draw_axis(fp, &ay, 0, left, right);
    fprintf(fp, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"none\" stroke=\"#333333\"/>\n", left,
            top, right - left, bottom - top);
    if (o->xlabel) {
        fprintf(fp, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">", 0.5 * (left + right), (double)o->height - 14.0);
        put_xml_text(fp, o->xlabel);
        fprintf(fp, "</text>\n");
    }
    if (o->ylabel) {
        fprintf(fp, "<text transform=\"translate(20 %.2f) rotate(-90)\" text-anchor=\"middle\">", 0.5 * (top + bottom));
        put_xml_text(fp, o->ylabel);
        fprintf(fp, "</text>\n");
    }
    for (s = 0; s < series_count; ++s) draw_series(fp, &series[s], s, &ax, &ay);
    draw_legend(fp, series, series_count, &ax, &ay);
    fprintf(fp, "</svg>\n");
    return ferror(fp) ? rerror_set(e, "write failed") : 0;
}

int plot_svg_write(const char *path, const plot_options *o, const plot_series *series, int series_count,
                   long *skipped, rerror *e)
{
    atomic_file f;
    if (atomic_file_open(&f, path, e)) return -1;
    if (plot_svg_fprint(f.fp, o, series, series_count, skipped, e)) {
        char msg[sizeof e->msg];
        atomic_file_abort(&f);
        snprintf(msg, sizeof msg, "%s", e->msg);
        return rerror_set(e, "%s: %s", path, msg);
    }
    return atomic_file_commit(&f, e);
}
