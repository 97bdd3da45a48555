/* Paired per-channel statistics of two sets of K runs (diff_dump_runs.h).
 *
 * Run k of A and run k of B are one pair; per frame, stage and channel c the run's image
 * mean of F_c W (over the dumped pixels, an empty reservoir counts 0) gives
 * d_k = mean_A,k - mean_B,k. The K differences are independent (each run has its own seed;
 * a run's pixels may be correlated by spatial reuse, but a run is one sample), so
 * t = mean(d) / (sd(d) / sqrt(K)) is Student-t with K - 1 degrees of freedom when A and B
 * estimate the same per-stage expectation. Pixels are never treated as independent, which
 * is what made the per-pixel --stat flag a temporal bias frames late (issue 31). */
#include "diff_dump_runs.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/json_text.h"
#include "restir/metrics/stats.h"
#include "restir/oracle/stage_dump.h"
#include "restir/restir/reservoir_dump.h"

#define RUNS_MAX 1000

static void run_dir(char *buf, size_t size, const char *dir, int k) { snprintf(buf, size, "%s/run_%02d", dir, k); }

int diff_dump_has_runs(const char *dir)
{
    char path[4200];
    FILE *fp;
    snprintf(path, sizeof path, "%s/run_00/manifest.json", dir);
    fp = fopen(path, "rb");
    if (fp) fclose(fp);
    return fp != NULL;
}

/* The image mean of F_c W of one stage file. */
static int channel_means(const char *dir, long frame, const char *stage, double mean[3], rerror *e)
{
    char path[4200];
    reservoir *rs;
    reservoir_dump_info info;
    long n, i;
    double s[3] = {0, 0, 0};
    stage_dump_path(path, sizeof path, dir, (uint32_t)frame, stage, "resv");
    if (reservoir_dump_read(path, &rs, &info, e)) return -1;
    n = (long)info.width * (long)info.height;
    for (i = 0; i < n; ++i) {
        double W = (double)rs[i].W;
        if (!isfinite(W)) {
            free(rs);
            return rerror_set(e, "%s: pixel record %ld: W is not finite", path, i);
        }
        if (!path_sample_is_valid(&rs[i].y)) continue;
        s[0] += (double)rs[i].y.F.r * W;
        s[1] += (double)rs[i].y.F.g * W;
        s[2] += (double)rs[i].y.F.b * W;
    }
    free(rs);
    for (i = 0; i < 3; ++i) mean[i] = n > 0 ? s[i] / (double)n : 0;
    return 0;
}

int diff_dump_runs(const char *a, const char *b, double z, int json)
{
    static double d[RUNS_MAX][3];
    static const char *const channel[3] = {"R", "G", "B"};
    stage_manifest m;
    char ra[4200], rb[4200];
    int K = 0, k, s, c, all_pass = 1, rows = 0;
    long f, first_frame = -1;
    const char *first_stage = "";
    double crit;
    rerror e;
    while (K < RUNS_MAX) {
        run_dir(ra, sizeof ra, a, K);
        snprintf(rb, sizeof rb, "%.4100s/manifest.json", ra);
        {
            FILE *fp = fopen(rb, "rb");
            if (!fp) break;
            fclose(fp);
        }
        ++K;
    }
    run_dir(ra, sizeof ra, a, 0);
    if (stage_manifest_read(ra, &m, &e)) {
        fprintf(stderr, "restir diff-dump: %s\n", e.msg);
        return 2;
    }
    if (K < 2) {
        fprintf(stderr, "restir diff-dump: %s: the paired mode needs K >= 2 runs (run_00, run_01, ...)\n", a);
        return 2;
    }
    {
        char path[4300];
        FILE *fp;
        run_dir(rb, sizeof rb, b, K - 1);
        snprintf(path, sizeof path, "%.4200s/manifest.json", rb);
        if (!(fp = fopen(path, "rb"))) {
            fprintf(stderr, "restir diff-dump: %s holds %d runs, %s does not (%s)\n", a, K, b, path);
            return 2;
        }
        fclose(fp);
    }
    {
        /* Bonferroni over every row and channel: a false alarm in 1e-3 of the run sets */
        int tests = 0;
        for (f = m.first; f <= m.last; ++f)
            for (s = 0; s < m.n_order; ++s) tests += 3 * stage_manifest_dumped(&m, m.order[s]);
        crit = z > 0 ? z : stats_t_quantile(1 - 0.5e-3 / (tests > 0 ? tests : 1), K - 1);
    }
    if (json) {
        printf("{\"a\": ");
        json_put_string(stdout, a);
        printf(", \"b\": ");
        json_put_string(stdout, b);
        printf(", \"mode\": \"stat-runs\", \"runs\": %d, \"critical_t\": %.6g, \"rows\": [", K, crit);
    } else
        printf("paired runs: %d per side; per frame, stage and channel t = mean(d) / (sd(d) / sqrt(%d)), d = run k's "
               "image mean of F W in A minus B; |t| <= %.4g passes\n", K, K, crit);
    for (f = m.first; f <= m.last; ++f)
        for (s = 0; s < m.n_order; ++s) {
            const char *stage = m.order[s];
            double t[3];
            int pass = 1;
            if (!stage_manifest_dumped(&m, stage)) continue;
            for (k = 0; k < K; ++k) {
                double ma[3], mb[3];
                run_dir(ra, sizeof ra, a, k);
                run_dir(rb, sizeof rb, b, k);
                if (channel_means(ra, f, stage, ma, &e) || channel_means(rb, f, stage, mb, &e)) {
                    if (json) printf("]}\n");
                    fprintf(stderr, "restir diff-dump: %s\n", e.msg);
                    return 2;
                }
                for (c = 0; c < 3; ++c) d[k][c] = ma[c] - mb[c];
            }
            for (c = 0; c < 3; ++c) {
                double mean = 0, var = 0;
                for (k = 0; k < K; ++k) mean += d[k][c] / K;
                for (k = 0; k < K; ++k) var += (d[k][c] - mean) * (d[k][c] - mean) / (K - 1);
                /* identical runs (sd 0): no difference is t = 0, any difference is infinite */
                t[c] = var > 0 ? mean / sqrt(var / K) : mean == 0 ? 0 : (mean > 0 ? INFINITY : -INFINITY);
                if (!(fabs(t[c]) <= crit)) pass = 0;
            }
            rows++;
            if (!pass && all_pass) {
                first_frame = f;
                first_stage = stage;
            }
            if (!pass) all_pass = 0;
            if (json) {
                printf("%s\n  {\"frame\": %ld, \"stage\": \"%s\", \"t\": [", rows > 1 ? "," : "", f, stage);
                for (c = 0; c < 3; ++c) {
                    if (c) printf(", ");
                    json_put_number(stdout, t[c]);
                }
                printf("], \"pass\": %s}", pass ? "true" : "false");
            } else {
                printf("frame %4ld %-12s", f, stage);
                for (c = 0; c < 3; ++c) printf("  t_%s %+9.3f", channel[c], t[c]);
                printf("  %s\n", pass ? "ok" : "DIFFERS");
            }
        }
    if (json) printf("\n], \"pass\": %s}\n", all_pass ? "true" : "false");
    else if (!all_pass) printf("first difference: frame %ld, stage %s\n", first_frame, first_stage);
    return all_pass ? 0 : 1;
}
