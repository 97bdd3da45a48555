/* The equal-time harness (see equal_time.h and docs/equal-time.md). */
#include "restir/bench/equal_time.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/metrics/metrics.h"
#include "restir/metrics/plot.h"
#include "restir/metrics/plot_svg.h"

void equal_time_options_default(equal_time_options *o)
{
    o->first_units = 1;
    o->growth = 2;
    o->max_units = 0;
    o->time_budget = 0;
}

int equal_time_options_validate(const equal_time_options *o, rerror *e)
{
    if (o->first_units < 1) return rerror_set(e, "equal time: first_units must be >= 1");
    if (!(o->growth > 1) || !isfinite(o->growth)) return rerror_set(e, "equal time: growth %g must be > 1", o->growth);
    if (!(o->time_budget >= 0) || !isfinite(o->time_budget))
        return rerror_set(e, "equal time: time budget %g must be >= 0", o->time_budget);
    if (!o->max_units && !(o->time_budget > 0))
        return rerror_set(e, "equal time: give a unit limit or a time budget");
    if (o->max_units && o->max_units < o->first_units)
        return rerror_set(e, "equal time: max_units %u < first_units %u", o->max_units, o->first_units);
    return 0;
}

double equal_time_value(const equal_time_point *p, enum equal_time_metric metric)
{
    return metric == EQUAL_TIME_MAPE ? p->mape : p->relmse;
}

/* The running mean sum / units as a float image, and its errors against the reference. */
static int record_point(const double *sum, uint32_t units, double seconds, const image *reference, image *mean,
                        equal_time_point *p, rerror *e)
{
    image_metrics m;
    long i, n = 3L * reference->width * reference->height;
    for (i = 0; i < n; ++i) mean->px[i] = (float)(sum[i] / units);
    if (metrics_compute(mean, reference, NULL, &m, e)) return -1;
    p->units = units;
    p->seconds = seconds;
    p->mape = m.value[METRIC_MAPE];
    p->relmse = m.value[METRIC_RELMSE];
    return 0;
}

/* The unit count of record k + 1 after `units`: ceil(first * growth^(k+1)), at least one more. */
static uint32_t next_units(uint32_t first, double growth, int k, uint32_t units)
{
    double target = ceil(first * pow(growth, k + 1) - 1e-9);
    if (target > 4294967295.0) return UINT32_MAX;
    return (uint32_t)target > units ? (uint32_t)target : units + 1;
}

static int grow_points(equal_time_curve *c, int *capacity, rerror *e)
{
    equal_time_point *p;
    if (c->count < *capacity) return 0;
    *capacity = *capacity ? 2 * *capacity : 16;
    p = realloc(c->points, (size_t)*capacity * sizeof *p);
    if (!p) return rerror_set(e, "equal time: out of memory");
    c->points = p;
    return 0;
}

int equal_time_run(const equal_time_method *m, const image *reference, const equal_time_options *o,
                   equal_time_curve *out, rerror *e)
{
    double *sum = NULL, seconds = 0;
    image mean;
    uint32_t units = 0, target = o->first_units;
    int capacity = 0, k = 0, status = 0;
    memset(out, 0, sizeof *out);
    memset(&mean, 0, sizeof mean);
    if (equal_time_options_validate(o, e)) return -1;
    snprintf(out->name, sizeof out->name, "%s", m->name ? m->name : "method");
    sum = rcalloc(3 * (size_t)reference->width * (size_t)reference->height, sizeof *sum, e);
    if (!sum || image_alloc(&mean, reference->width, reference->height, e)) status = -1;
    while (!status) {
        double start;
        if (o->max_units && target > o->max_units) target = o->max_units;
        start = now_seconds();
        status = m->render(m->ctx, units, target - units, reference->width, reference->height, sum, e);
        seconds += now_seconds() - start;
        if (!status && threads_cancelled()) /* a stop (SIGINT) cut the render short: no curve */
            status = rerror_set(e, "%s: equal-time run cancelled", out->name);
        units = target;
        if (!status) status = grow_points(out, &capacity, e);
        if (!status) status = record_point(sum, units, seconds, reference, &mean, &out->points[out->count], e);
        if (status) break;
        out->count++;
        if ((o->max_units && units >= o->max_units) || (o->time_budget > 0 && seconds >= o->time_budget) ||
            units == UINT32_MAX)
            break;
        target = next_units(o->first_units, o->growth, k++, units);
    }
    free(sum);
    image_free(&mean);
    if (status) equal_time_curve_free(out);
    return status;
}

void equal_time_curve_free(equal_time_curve *c)
{
    free(c->points);
    c->points = NULL;
    c->count = 0;
}

/* ---- output ------------------------------------------------------------------------ */

/* A CSV field: quoted (with "" for ") when it holds a comma, quote or space. */
static void csv_name(FILE *f, const char *name)
{
    const char *p;
    if (!strpbrk(name, ",\" \t")) {
        fputs(name, f);
        return;
    }
    fputc('"', f);
    for (p = name; *p; ++p) {
        if (*p == '"') fputc('"', f);
        fputc(*p, f);
    }
    fputc('"', f);
}

int equal_time_write_csv(const char *path, const equal_time_curve *curves, int n, enum equal_time_metric metric,
                         rerror *e)
{
    atomic_file f;
    int c, i, k;
    if (atomic_file_open(&f, path, e)) return -1;
    fputs("seconds", f.fp);
    for (c = 0; c < n; ++c) {
        fputc(',', f.fp);
        csv_name(f.fp, curves[c].name);
    }
    fputc('\n', f.fp);
    for (c = 0; c < n; ++c)
        for (i = 0; i < curves[c].count; ++i) {
            fprintf(f.fp, "%.9g", curves[c].points[i].seconds);
            for (k = 0; k < n; ++k) {
                fputc(',', f.fp);
                if (k == c) fprintf(f.fp, "%.9g", equal_time_value(&curves[c].points[i], metric));
            }
            fputc('\n', f.fp);
        }
    return atomic_file_commit(&f, e);
}

int equal_time_write_table(const char *path, const equal_time_curve *curves, int n, rerror *e)
{
    atomic_file f;
    int c, i;
    if (atomic_file_open(&f, path, e)) return -1;
    fputs("method,units,seconds,mape,relmse\n", f.fp);
    for (c = 0; c < n; ++c)
        for (i = 0; i < curves[c].count; ++i) {
            const equal_time_point *p = &curves[c].points[i];
            csv_name(f.fp, curves[c].name);
            fprintf(f.fp, ",%u,%.9g,%.9g,%.9g\n", p->units, p->seconds, p->mape, p->relmse);
        }
    return atomic_file_commit(&f, e);
}

int equal_time_write_svg(const char *path, const equal_time_curve *curves, int n, enum equal_time_metric metric,
                         const char *title, rerror *e)
{
    plot_options o;
    plot_series *series = rcalloc((size_t)(n > 0 ? n : 1), sizeof *series, e);
    double *values;
    size_t total = 0, at = 0;
    int c, i, status;
    if (!series) return -1;
    for (c = 0; c < n; ++c) total += 2 * (size_t)curves[c].count;
    values = rmalloc(total ? total : 1, sizeof *values, e);
    if (!values) {
        free(series);
        return -1;
    }
    for (c = 0; c < n; ++c) {
        series[c].name = curves[c].name;
        series[c].count = curves[c].count;
        series[c].x = values + at;
        for (i = 0; i < curves[c].count; ++i) values[at++] = curves[c].points[i].seconds;
        series[c].y = values + at;
        for (i = 0; i < curves[c].count; ++i) values[at++] = equal_time_value(&curves[c].points[i], metric);
    }
    plot_options_default(&o);
    o.title = title;
    o.xlabel = "render time (seconds)";
    o.ylabel = metric == EQUAL_TIME_MAPE ? "MAPE" : "relMSE";
    status = plot_svg_write(path, &o, series, n, NULL, e);
    free(values);
    free(series);
    return status;
}

/* ---- reading the curves ------------------------------------------------------------ */

static int usable(double seconds, double error) { return seconds > 0 && error > 0 && isfinite(seconds) && isfinite(error); }

int equal_time_fit(const equal_time_curve *c, enum equal_time_metric metric, double *slope, double *intercept,
                   rerror *e)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0, det;
    int i;
    for (i = 0; i < c->count; ++i) {
        double t = c->points[i].seconds, v = equal_time_value(&c->points[i], metric), x, y;
        if (!usable(t, v)) continue;
        x = log(t);
        y = log(v);
        sx += x, sy += y, sxx += x * x, sxy += x * y, n += 1;
    }
    det = n * sxx - sx * sx;
    if (n < 2 || !(det > 0)) return rerror_set(e, "%s: fewer than two usable points for a power-law fit", c->name);
    *slope = (n * sxy - sx * sy) / det;
    *intercept = (sy - *slope * sx) / n;
    return 0;
}

enum equal_time_reach equal_time_time_to_reach(const equal_time_curve *c, enum equal_time_metric metric,
                                               double target, double *seconds)
{
    double slope, intercept;
    rerror e;
    int i, previous = -1;
    *seconds = NAN;
    if (!(target > 0)) return EQUAL_TIME_UNREACHABLE;
    for (i = 0; i < c->count; ++i) {
        double t = c->points[i].seconds, v = equal_time_value(&c->points[i], metric);
        if (!usable(t, v)) continue;
        if (v <= target) {
            if (v == target) {
                *seconds = t;
                return EQUAL_TIME_INTERPOLATED;
            }
            if (previous >= 0) {
                double t0 = c->points[previous].seconds, v0 = equal_time_value(&c->points[previous], metric);
                double f = (log(target) - log(v0)) / (log(v) - log(v0));
                *seconds = exp(log(t0) + f * (log(t) - log(t0)));
                return EQUAL_TIME_INTERPOLATED;
            }
            break;
        }
        previous = i;
    }
    if (equal_time_fit(c, metric, &slope, &intercept, &e) || !(slope < 0)) return EQUAL_TIME_UNREACHABLE;
    *seconds = exp((log(target) - intercept) / slope);
    return EQUAL_TIME_EXTRAPOLATED;
}

/* ---- the path tracer as a method ---------------------------------------------------- */

static int pt_units(void *ctx, uint32_t first, uint32_t count, int width, int height, double *sum, rerror *e)
{
    equal_time_pt_ctx *c = ctx;
    pt_options o = c->options;
    pt_result r;
    long i, n = 3L * width * height;
    if (c->s->width != width || c->s->height != height)
        return rerror_set(e, "%s: renders %dx%d, the reference is %dx%d", c->s->path, c->s->width, c->s->height, width,
                          height);
    o.sample_offset = c->options.sample_offset + first;
    o.spp = count;
    o.time_limit = 0;
    o.checkpoint_path = NULL;
    o.resume_path = NULL;
    o.callback_every = 0;
    o.on_passes = NULL;
    o.quiet = 1;
    if (pt_render(c->s, &o, &r, e)) return -1;
    for (i = 0; i < n; ++i) sum[i] += r.state.sum[i];
    pt_result_free(&r);
    return 0;
}

void equal_time_pt_method(equal_time_pt_ctx *ctx, const scene *s, const pt_options *options, const char *name,
                          equal_time_method *m)
{
    ctx->s = s;
    ctx->options = *options;
    m->name = name ? name : "pt";
    m->render = pt_units;
    m->ctx = ctx;
}
