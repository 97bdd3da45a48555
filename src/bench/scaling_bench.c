/* Thread scaling of the real-time pipeline: 1 vs T threads, alternately (scaling_bench.h). */
#include "restir/bench/scaling_bench.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/frame/pipeline.h"

#define SCALING_MAX_ROUNDS 64

/* One run's accounting. */
typedef struct {
    double wall, cpu, parallel_cpu; /* seconds */
    double stage_ms[9];             /* pose, gbuffer, motion, initial, temporal, spatial, mutate, shade, correlation */
} scaling_run;

#define SCALING_STAGES 9
static const char *const stage_names[SCALING_STAGES] = {"pose", "gbuffer", "motion", "initial", "temporal",
                                                        "spatial", "mutate", "shade", "correlation"};

static double process_cpu_seconds(void)
{
    struct timespec t;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0;
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int run_once(const scene *s, const restir_options *o, int frames, int threads, scaling_run *r, rerror *e)
{
    restir_options ot = *o;
    restir_sequence q;
    restir_stats st;
    double w0, c0, p0;
    int i;
    memset(&q, 0, sizeof q);
    q.first = 0;
    q.last = frames - 1;
    ot.threads = threads;
    w0 = now_seconds();
    c0 = process_cpu_seconds();
    p0 = threads_parallel_cpu_seconds();
    if (restir_render_sequence(s, &ot, &q, NULL, NULL, &st, e)) return -1;
    r->parallel_cpu = threads_parallel_cpu_seconds() - p0;
    r->cpu = process_cpu_seconds() - c0;
    r->wall = now_seconds() - w0;
    r->stage_ms[0] = st.ms_pose;
    r->stage_ms[1] = st.ms_gbuffer;
    r->stage_ms[2] = st.ms_motion;
    r->stage_ms[3] = st.ms_initial;
    r->stage_ms[4] = st.ms_temporal;
    r->stage_ms[5] = 0;
    for (i = 0; i < RESTIR_MAX_SPATIAL_PASSES; ++i) r->stage_ms[5] += st.ms_spatial[i];
    r->stage_ms[6] = st.ms_mutate;
    r->stage_ms[7] = st.ms_shade;
    r->stage_ms[8] = st.ms_correlation;
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Median of v[0..n-1] (sorted in place). */
static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Writes "name": [v of every round] and returns the median. */
static double write_series(FILE *out, const char *name, const scaling_run *r, int n, size_t offset)
{
    double v[SCALING_MAX_ROUNDS];
    int i;
    fprintf(out, "\"%s\": [", name);
    for (i = 0; i < n; ++i) {
        v[i] = *(const double *)(const void *)((const char *)&r[i] + offset);
        fprintf(out, "%s%.4f", i ? ", " : "", v[i]);
    }
    fprintf(out, "], ");
    return median(v, n);
}

static void write_config(FILE *out, int threads, const scaling_run *r, int n, double *serial_fraction)
{
    double serial[SCALING_MAX_ROUNDS], stage[SCALING_MAX_ROUNDS], cpu, par;
    int i, k;
    fprintf(out, "    {\"threads\": %d, ", threads);
    write_series(out, "wall_s", r, n, offsetof(scaling_run, wall));
    cpu = write_series(out, "cpu_s", r, n, offsetof(scaling_run, cpu));
    par = write_series(out, "parallel_cpu_s", r, n, offsetof(scaling_run, parallel_cpu));
    fprintf(out, "\"serial_cpu_s\": [");
    for (i = 0; i < n; ++i) {
        serial[i] = r[i].cpu - r[i].parallel_cpu;
        fprintf(out, "%s%.4f", i ? ", " : "", serial[i]);
    }
    fprintf(out, "],\n     \"median_cpu_s\": %.4f, \"median_parallel_cpu_s\": %.4f, \"median_serial_cpu_s\": %.4f, ",
            cpu, par, median(serial, n));
    for (i = 0; i < n; ++i) serial[i] = r[i].cpu > 0 ? (r[i].cpu - r[i].parallel_cpu) / r[i].cpu : 0;
    *serial_fraction = median(serial, n);
    fprintf(out, "\"serial_fraction\": %.5f,\n     \"stage_ms_median\": {", *serial_fraction);
    for (k = 0; k < SCALING_STAGES; ++k) {
        for (i = 0; i < n; ++i) stage[i] = r[i].stage_ms[k];
        fprintf(out, "%s\"%s\": %.1f", k ? ", " : "", stage_names[k], median(stage, n));
    }
    for (i = 0; i < n; ++i) { /* wall time outside every stage timer */
        stage[i] = 1000 * r[i].wall;
        for (k = 0; k < SCALING_STAGES; ++k) stage[i] -= r[i].stage_ms[k];
    }
    fprintf(out, ", \"outside_stages\": %.1f}}", median(stage, n));
}

int bench_scaling(FILE *out, const scene *s, const char *name, const restir_options *o, int frames, int threads,
                  int rounds, int *first, rerror *e)
{
    scaling_run one[SCALING_MAX_ROUNDS], many[SCALING_MAX_ROUNDS];
    double speedup[SCALING_MAX_ROUNDS], cpu_ratio[SCALING_MAX_ROUNDS], s1, sT, bound;
    char load[128] = "";
    FILE *f;
    int i;
    if (rounds < 1) rounds = 1;
    if (rounds > SCALING_MAX_ROUNDS) rounds = SCALING_MAX_ROUNDS;
    if ((f = fopen("/proc/loadavg", "r")) != NULL) { /* the load at the start (Linux) */
        if (!fgets(load, sizeof load, f)) load[0] = '\0';
        load[strcspn(load, "\n\"\\")] = '\0';
        fclose(f);
    }
    for (i = 0; i < rounds; ++i) { /* alternately: 1 T, T 1, ... */
        int a = i % 2 ? threads : 1, b = i % 2 ? 1 : threads;
        if (run_once(s, o, frames, a, a == 1 ? &one[i] : &many[i], e) ||
            run_once(s, o, frames, b, b == 1 ? &one[i] : &many[i], e))
            return -1;
        speedup[i] = many[i].wall > 0 ? one[i].wall / many[i].wall : 0;
        cpu_ratio[i] = one[i].cpu > 0 ? many[i].cpu / one[i].cpu : 0;
    }
    if (!*first) fprintf(out, ",\n");
    *first = 0;
    fprintf(out, "  {\"bench\": \"scaling\", \"scene\": \"%s\", \"size\": [%d, %d], \"frames\": %d, \"rounds\": %d, "
                 "\"load_at_start\": \"%s\",\n   \"runs\": [\n",
            name, s->width, s->height, frames, rounds, load);
    write_config(out, 1, one, rounds, &s1);
    fprintf(out, ",\n");
    write_config(out, threads, many, rounds, &sT);
    bound = 1 / (s1 + (1 - s1) / threads);
    fprintf(out, "],\n   \"speedup_wall\": {\"median\": %.3f, ", median(speedup, rounds));
    fprintf(out, "\"min\": %.3f, \"max\": %.3f}, \"cpu_ratio_median\": %.4f, \"serial_fraction_1\": %.5f, "
                 "\"amdahl_bound\": %.3f}",
            speedup[0], speedup[rounds - 1], median(cpu_ratio, rounds), s1, bound);
    return 0;
}
