/* The achieved standard deviation of reuse-texture offsets under every reading of the
 * garbled Enhanced Eq. 3 (include/restir/bench/pairing_sigma.h). Since a reading only
 * chooses the whole number of shuffle passes n, the measurement is made per n once and
 * shared by every (sigma, reading) that asks for it. */
#include "restir/bench/pairing_sigma.h"

#include <math.h>
#include <stdlib.h>
#include "restir/core/threads.h"
#include "restir/metrics/stats.h"
#include "restir/restir/pairing.h"

static const double sigma_grid[] = {0.8, 1, 1.25, 1.5, 2, 2.5, 3, 4, 5.32, 6, 8, 11, 16, 22, 27, 32};
#define SIGMA_GRID_COUNT ((int)(sizeof sigma_grid / sizeof sigma_grid[0]))

typedef struct {
    int passes;
    stats_estimate axis[2]; /* x, y: per-texture standard deviations, summarised */
} pass_result;

/* The offsets' standard deviation per axis of one texture (their mean is 0: the pairing is
 * an involution, so every offset d has its partner's -d). */
static void texture_std(const reuse_texture *t, double sd[2])
{
    size_t i, n = (size_t)t->size * (size_t)t->size;
    double sx = 0, sy = 0;
    for (i = 0; i < n; ++i) {
        sx += (double)t->dx[i] * t->dx[i];
        sy += (double)t->dy[i] * t->dy[i];
    }
    sd[0] = sqrt(sx / (double)n);
    sd[1] = sqrt(sy / (double)n);
}

static int measure_passes(int passes, int textures, int size, uint32_t seed, pass_result *r, rerror *e)
{
    double *sd = malloc(2 * (size_t)textures * sizeof *sd);
    int k, a;
    if (!sd) return rerror_set(e, "bench pairing-sigma: out of memory");
    for (k = 0; k < textures; ++k) {
        reuse_texture t;
        double s[2];
        if (threads_cancelled()) { /* a stop (SIGINT, threads.h): the run is discarded, end it now */
            free(sd);
            return rerror_set(e, "bench pairing-sigma: cancelled");
        }
        if (reuse_texture_build_passes(&t, size, 1, passes, seed, (uint32_t)k, e)) {
            free(sd);
            return -1;
        }
        texture_std(&t, s);
        sd[k] = s[0];
        sd[textures + k] = s[1];
        reuse_texture_free(&t);
    }
    r->passes = passes;
    for (a = 0; a < 2; ++a) {
        double mean, var;
        stats_mean_var(sd + (size_t)a * (size_t)textures, textures, &mean, &var);
        r->axis[a] = stats_estimate_from_samples(mean, var, textures);
    }
    free(sd);
    return 0;
}

/* The result for n passes, measured on first use (cache of `count` entries). */
static const pass_result *result_for(pass_result *cache, int *count, int passes, int textures, int size, uint32_t seed,
                                     rerror *e)
{
    int i;
    for (i = 0; i < *count; ++i)
        if (cache[i].passes == passes) return &cache[i];
    if (measure_passes(passes, textures, size, seed, &cache[*count], e)) return NULL;
    return &cache[(*count)++];
}

static void write_axis(FILE *out, const char *name, stats_estimate a, double sigma)
{
    double lo, hi;
    stats_mean_ci(a, 0.99, &lo, &hi);
    fprintf(out, "\"%s\": {\"mean\": %.5f, \"lo\": %.5f, \"hi\": %.5f, \"rel_err\": %.5f, \"rel_lo\": %.5f, "
                 "\"rel_hi\": %.5f}",
            name, a.mean, lo, hi, a.mean / sigma - 1, lo / sigma - 1, hi / sigma - 1);
}

int bench_pairing_sigma(FILE *out, int textures, int size, uint32_t seed, int *first, rerror *e)
{
    pass_result cache[SIGMA_GRID_COUNT * PAIRING_EQ3_COUNT];
    int count = 0, g, r;
    if (textures < 2) return rerror_set(e, "bench pairing-sigma: %d textures (an interval needs at least 2)", textures);
    for (g = 0; g < SIGMA_GRID_COUNT; ++g)
        for (r = 0; r < PAIRING_EQ3_COUNT; ++r) {
            double sigma = sigma_grid[g];
            int n = pairing_shuffle_count_as(sigma, (enum pairing_eq3)r);
            const pass_result *p = result_for(cache, &count, n, textures, size, seed, e);
            if (!p) return -1;
            fprintf(out, "%s  {\"bench\": \"pairing-sigma\", \"sigma\": %g, \"reading\": \"%s\", \"passes\": %d, "
                         "\"textures\": %d, \"size\": %d, ",
                    *first ? "" : ",\n", sigma, pairing_eq3_names[r], n, textures, size);
            write_axis(out, "std_x", p->axis[0], sigma);
            fputs(", ", out);
            write_axis(out, "std_y", p->axis[1], sigma);
            fputc('}', out);
            *first = 0;
        }
    return 0;
}
