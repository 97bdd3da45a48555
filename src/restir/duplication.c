/* Sample identity and duplication maps (include/restir/restir/duplication.h; Enhanced §5). */
#include "restir/restir/duplication.h"

#include <math.h>
#include "restir/core/threads.h"

int duplication_same_sample(const reservoir *a, const reservoir *b)
{
    return a->W > 0 && b->W > 0 && path_sample_is_valid(&a->y) && path_sample_is_valid(&b->y) &&
           a->y.seed == b->y.seed && a->y.pixel == b->y.pixel && a->y.sample == b->y.sample;
}

/* The identity of a reservoir's sample, compact: a 17 x 17 window of them fits in L1,
 * where the window of 224-B reservoirs does not (issue 17: the map was 14% of a frame). */
typedef struct {
    uint32_t seed, pixel, sample, live; /* live: W > 0 and a valid sample */
} sample_key;

static sample_key key_of(const reservoir *r)
{
    sample_key k;
    k.live = r->W > 0 && path_sample_is_valid(&r->y);
    k.seed = r->y.seed;
    k.pixel = r->y.pixel;
    k.sample = r->y.sample;
    return k;
}

/* duplication_same_sample on keys */
static int same_key(const sample_key *a, const sample_key *b)
{
    return a->live && b->live && a->pixel == b->pixel && a->seed == b->seed && a->sample == b->sample;
}

typedef struct {
    const reservoir *rs;
    int w, h, r;
    uint16_t *count;
} counts_job;

/* Enhanced §5 step 1 on one tile: the keys of the tile and its r-pixel apron (clipped at
 * the image border), then per pixel the copies of its sample in its window, itself
 * excluded. Each pixel writes only its own count: the same bytes for any thread count. */
static void counts_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    enum { SIDE = 16 + 2 * DUPLICATION_RADIUS }; /* tile (16, pipeline below) + apron */
    const counts_job *job = ctx;
    int r = job->r, ax0 = x0 - r < 0 ? 0 : x0 - r, ay0 = y0 - r < 0 ? 0 : y0 - r;
    int ax1 = x1 + r > job->w ? job->w : x1 + r, ay1 = y1 + r > job->h ? job->h : y1 + r;
    sample_key keys[SIDE * SIDE]; /* 16 KB */
    int x, y, i, j;
    (void)worker;
    for (y = ay0; y < ay1; ++y)
        for (x = ax0; x < ax1; ++x) keys[(y - ay0) * SIDE + (x - ax0)] = key_of(&job->rs[(long)y * job->w + x]);
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            const sample_key *self = &keys[(y - ay0) * SIDE + (x - ax0)];
            unsigned n = 0;
            if (self->live)
                for (j = y - r < ay0 ? ay0 : y - r; j <= y + r && j < ay1; ++j)
                    for (i = x - r < ax0 ? ax0 : x - r; i <= x + r && i < ax1; ++i)
                        n += (i != x || j != y) && same_key(self, &keys[(j - ay0) * SIDE + (i - ax0)]);
            job->count[(long)y * job->w + x] = (uint16_t)n;
        }
}

void duplication_counts(const reservoir *rs, int w, int h, int r, int threads, uint16_t *count)
{
    counts_job job;
    job.rs = rs;
    job.w = w;
    job.h = h;
    job.r = r;
    job.count = count;
    parallel_tiles(w, h, 16, threads, counts_tile, &job, NULL, NULL); /* 16: SIDE in counts_tile */
}

double duplication_score_denominator(int r) { return (double)(2 * r + 1) * (double)(2 * r + 1) - 1; }

double duplication_score(unsigned count, int r)
{
    double d = (double)count / duplication_score_denominator(r);
    return d > 1 ? 1 : d;
}

/* Enhanced §5 step 3 */
double duplication_cap(double cap_default, double cap_min, double d, double alpha)
{
    double t = d > 0 ? pow(d, alpha) : 0;
    return cap_default + (cap_min - cap_default) * t;
}

void duplication_summarize(const uint16_t *count, long n, duplication_summary *s)
{
    long i;
    s->pixels = (uint64_t)n;
    s->duplicated = s->count_sum = 0;
    s->count_max = 0;
    for (i = 0; i < n; ++i) {
        s->duplicated += count[i] > 0;
        s->count_sum += count[i];
        if (count[i] > s->count_max) s->count_max = count[i];
    }
}

void duplication_summary_add(duplication_summary *acc, const duplication_summary *add)
{
    acc->pixels += add->pixels;
    acc->duplicated += add->duplicated;
    acc->count_sum += add->count_sum;
    if (add->count_max > acc->count_max) acc->count_max = add->count_max;
}

void duplication_heat_colour(double d, double d_max, unsigned char rgb[3])
{
    double t = d_max > 0 ? d / d_max : 1;
    if (!(t > 0)) t = 0;
    if (t > 1) t = 1;
    rgb[0] = (unsigned char)lround(255.0 * t);
    rgb[1] = rgb[2] = 0;
}
