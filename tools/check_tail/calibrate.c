/* Calibration of check's heavy-tail rule (include/restir/check_tail.h; docs/statistics.md
 * "When check cannot judge"): 40 synthetic run sets per distribution, K runs x S block
 * series each, through check_tail_measure; prints the mean and range of the tail index and
 * how many sets were flagged with the bound alpha (1 + c / sqrt(k)) < 2 for c = 0, 1, 2
 * (the rule uses c = 1). Build and run from the repository root:
 *   make build/librestir.a && cc -O2 -std=c99 -D_DEFAULT_SOURCE -Iinclude tools/check_tail/calibrate.c \
 *       build/librestir.a -lm -o build/check_tail_calibrate && build/check_tail_calibrate */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "restir/metrics/check_tail.h"

#define SETS 40

static double normal(void)
{
    double u = drand48(), v = drand48();
    return sqrt(-2 * log(u + 1e-300)) * cos(6.283185307179586 * v);
}

static double exponential(void) { return -log(1 - drand48()); }

/* Pareto (Lomax) with tail index a: P(X > x) = (1 + x)^-a. */
static double pareto(double a) { return pow(1 - drand48(), -1 / a) - 1; }

static double mean_of(int n, double (*draw)(void))
{
    double s = 0;
    int i;
    for (i = 0; i < n; ++i) s += draw();
    return s / n;
}

static double pareto15(void) { return pareto(1.5); }
static double pareto12(void) { return pareto(1.2); }
static double lognormal(void) { return exp(normal()); }
static double mean16_pareto15(void) { return mean_of(16, pareto15); }
static double mean64_exponential(void) { return mean_of(64, exponential); }
/* A rare spike of one fixed size: 5 % of the values are +100. */
static double spiked(void) { return normal() + (drand48() < 0.05 ? 100 : 0); }

static const struct {
    const char *name;
    double (*draw)(void);
} dists[] = {
    {"normal", normal},
    {"exponential", exponential},
    {"mean of 64 exponentials", mean64_exponential},
    {"lognormal sigma 1", lognormal},
    {"Pareto 1.5", pareto15},
    {"mean of 16 Pareto 1.5", mean16_pareto15},
    {"Pareto 1.2", pareto12},
    {"normal + 5% x 100", spiked},
};

static void calibrate(int d, int runs, int series)
{
    double lo = HUGE_VAL, hi = 0, sum = 0;
    int set, flagged[3] = {0, 0, 0}, c, measured = 0;
    double *x = malloc(sizeof *x * (size_t)runs * (size_t)series);
    if (!x) return;
    for (set = 0; set < SETS; ++set) {
        check_tail t;
        long i;
        for (i = 0; i < (long)runs * series; ++i) x[i] = dists[d].draw();
        check_tail_measure(&t, x, runs, series, series, NULL, 0);
        measured += t.measured;
        if (!t.measured) continue;
        lo = fmin(lo, t.tail_index);
        hi = fmax(hi, t.tail_index);
        sum += t.tail_index;
        for (c = 0; c < 3; ++c) flagged[c] += t.tail_index * (1 + c / sqrt((double)t.tail_count)) < 2;
    }
    printf("%-24s K=%2d series=%3d measured %2d alpha mean %.2f range %.2f..%.2f flagged c0 %2d c1 %2d c2 %2d /%d\n",
           dists[d].name, runs, series, measured, measured ? sum / measured : 0, lo, hi, flagged[0], flagged[1], flagged[2],
           SETS);
    free(x);
}

int main(void)
{
    static const int runs[] = {8, 16, 32}, series[] = {27, 192, 768};
    size_t d, r, s;
    srand48(1);
    for (d = 0; d < sizeof dists / sizeof dists[0]; ++d)
        for (r = 0; r < 3; ++r)
            for (s = 0; s < 3; ++s) calibrate((int)d, runs[r], series[s]);
    return 0;
}
