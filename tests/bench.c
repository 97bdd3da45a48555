/* The paired bench (tests/bench.h). */
#include "bench.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/stats.h"
#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"
#include "pt_util.h"
#include "sequence_util.h"
#include "test.h"

static const char *const channel_names[3] = {"R", "G", "B"};

void bench_paired_init(bench_paired *p, const char *name)
{
    memset(p, 0, sizeof *p);
    p->name = name;
}

void bench_paired_add(bench_paired *p, const double a[3], const double b[3])
{
    int c;
    for (c = 0; c < 3; ++c) {
        double d = a[c] - b[c];
        if (p->runs == 0) p->first_d[c] = d;
        d -= p->first_d[c]; /* shifted sums: no cancellation when d is nearly constant */
        p->sum_a[c] += a[c];
        p->sum_b[c] += b[c];
        p->sum_d[c] += d;
        p->sum_dd[c] += d * d;
    }
    p->runs++;
}

static void report(const bench_paired *p)
{
    const char *log = getenv("RESTIR_BENCH_LOG");
    char line[1024];
    int c, n;
    n = snprintf(line, sizeof line, "bench %s: K %d", p->name, p->runs);
    for (c = 0; c < 3 && n > 0 && (size_t)n < sizeof line; ++c)
        n += snprintf(line + n, sizeof line - (size_t)n, " | %s A %.6g B %.6g rel %+.4f%% z %+.2f detectable %.3f%%",
                      channel_names[c], p->mean_a[c], p->mean_b[c], 100 * p->rel[c], p->z[c], 100 * p->detectable[c]);
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  %s\n", line);
    if (log && *log) {
        FILE *f = fopen(log, "a");
        if (f) {
            fprintf(f, "%s\n", line);
            fclose(f);
        }
    }
}

void bench_paired_finish(bench_paired *p)
{
    int c, K = p->runs;
    double dof = K - 1;
    double tcrit = K >= 2 ? stats_t_quantile(1 - BENCH_ALPHA / 2, dof) + stats_t_quantile(0.8, dof) : INFINITY;
    for (c = 0; c < 3; ++c) {
        double m = K > 0 ? p->sum_d[c] / K : 0, var = 0, t;
        if (K >= 2) var = (p->sum_dd[c] - K * m * m) / (K - 1);
        if (var < 0) var = 0;
        p->mean_a[c] = K > 0 ? p->sum_a[c] / K : 0;
        p->mean_b[c] = K > 0 ? p->sum_b[c] / K : 0;
        p->diff[c] = m + p->first_d[c];
        p->se[c] = K >= 2 ? sqrt(var / K) : INFINITY;
        if (p->se[c] > 0 && isfinite(p->se[c])) {
            t = p->diff[c] / p->se[c];
            p->z[c] = stats_t_to_z(t, dof);
        } else {
            p->z[c] = p->diff[c] == 0 || !isfinite(p->se[c]) ? 0 : (p->diff[c] > 0 ? 40 : -40);
        }
        p->rel[c] = p->mean_b[c] != 0 ? p->diff[c] / fabs(p->mean_b[c]) : 0;
        p->detectable[c] = p->mean_b[c] != 0 ? tcrit * p->se[c] / fabs(p->mean_b[c]) : INFINITY;
    }
    report(p);
}

double bench_paired_max_abs_z(const bench_paired *p, int *channel)
{
    int c, best = 0;
    for (c = 1; c < 3; ++c)
        if (fabs(p->z[c]) > fabs(p->z[best])) best = c;
    if (channel) *channel = best;
    return fabs(p->z[best]);
}

double bench_paired_detectable(const bench_paired *p)
{
    double d = p->detectable[0];
    int c;
    for (c = 1; c < 3; ++c)
        if (p->detectable[c] < d) d = p->detectable[c];
    return d;
}

int bench_paired_expect_consistent(const bench_paired *p, double zmax)
{
    int c;
    double z = bench_paired_max_abs_z(p, &c);
    if (z < zmax) return 0;
    test_margin(z);
    test_fail(__FILE__, __LINE__,
              "%s: A differs from B on the same %d seeds in %s: z %+.2f (relative %+.4f%%; R %+.2f G %+.2f B %+.2f), "
              "limit %.1f",
              p->name, p->runs, channel_names[c], p->z[c], 100 * p->rel[c], p->z[0], p->z[1], p->z[2], zmax);
    return -1;
}

int bench_paired_expect_detected(const bench_paired *p, double zmin)
{
    int c;
    double z = bench_paired_max_abs_z(p, &c);
    if (z >= zmin) return 0;
    test_fail(__FILE__, __LINE__, "%s: the planted difference was not detected: max |z| %.2f in %s (R %+.2f G %+.2f B %+.2f) < %.1f",
              p->name, z, channel_names[c], p->z[0], p->z[1], p->z[2], zmin);
    return -1;
}

int bench_paired_run(bench_paired *p, int runs, uint32_t seed0, bench_run_fn a, void *ua, bench_run_fn b, void *ub)
{
    int k;
    for (k = 0; k < runs; ++k) {
        double ma[3], mb[3];
        uint32_t seed = seed0 + 7919u * (uint32_t)k;
        if (a(ua, seed, ma) || b(ub, seed, mb)) return -1;
        bench_paired_add(p, ma, mb);
    }
    bench_paired_finish(p);
    return 0;
}

void bench_image_mean(const image *img, double mean[3])
{
    size_t n = (size_t)img->width * (size_t)img->height;
    double s[3];
    int c;
    test_image_sums(img, s);
    for (c = 0; c < 3; ++c) mean[c] = n ? s[c] / (double)n : 0;
}

int bench_restir_mean(const scene *s, const restir_options *o, double mean[3])
{
    restir_result r;
    rerror e;
    if (restir_render(s, o, &r, &e)) {
        test_fail(__FILE__, __LINE__, "restir_render: %s", e.msg);
        return -1;
    }
    bench_image_mean(&r.mean, mean);
    restir_result_free(&r);
    return 0;
}

int bench_sequence_mean(const scene *s, const restir_options *o, int frame, double mean[3])
{
    image *img = calloc((size_t)frame + 1, sizeof *img);
    int f, status = -1;
    if (!img) {
        test_fail(__FILE__, __LINE__, "out of memory");
        return -1;
    }
    if (rt_sequence_images(s, o, 0, frame, img) == 0) {
        if (img[frame].px) {
            bench_image_mean(&img[frame], mean);
            status = 0;
        } else {
            test_fail(__FILE__, __LINE__, "restir_render_sequence: frame %d was not rendered", frame);
        }
        for (f = 0; f <= frame; ++f) image_free(&img[f]);
    }
    free(img);
    return status;
}

int bench_sequence_run(void *user, uint32_t seed, double mean[3])
{
    const bench_sequence_config *c = user;
    restir_options o = c->o;
    o.seed = seed;
    if (c->frame == BENCH_OFFLINE) return bench_restir_mean(c->s, &o, mean);
    return bench_sequence_mean(c->s, &o, c->frame, mean);
}
