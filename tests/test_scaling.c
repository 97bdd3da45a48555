/* Thread scaling of the real-time pipeline (issue 17; docs/performance.md "ReSTIR thread
 * scaling"): what became parallel gives the same bytes as the serial definition, and the
 * accounting that measures the serial part counts what it should. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/duplication.h"
#include "restir/core/threads.h"
#include "test.h"

/* The duplicate count of Enhanced §5 step 1 straight from its definition. */
static unsigned brute_count(const reservoir *rs, int w, int h, int r, int x, int y)
{
    unsigned n = 0;
    int i, j;
    for (j = y - r; j <= y + r; ++j)
        for (i = x - r; i <= x + r; ++i)
            if (i >= 0 && j >= 0 && i < w && j < h && (i != x || j != y) &&
                duplication_same_sample(&rs[(long)y * w + x], &rs[(long)j * w + i]))
                ++n;
    return n;
}

/* duplication_counts (16 x 16 tiles with an r-pixel apron of compact keys, in parallel)
 * against the definition on a 53 x 37 image (tiles cut at 16, 32, 48; partial tiles at
 * both borders) whose samples come from 7 identities, so copies sit at every distance,
 * exactly r = 8 across tile edges included; some holders have W = 0 or no sample. */
TEST(scaling_duplication_counts_match_definition)
{
    enum { W = 53, H = 37 };
    reservoir *rs = calloc(W * H, sizeof *rs);
    uint16_t *count = calloc(W * H, sizeof *count);
    int x, y, threads, bad = 0;
    CHECK(rs && count);
    for (y = 0; rs && count && y < H; ++y)
        for (x = 0; x < W; ++x) {
            reservoir *r = &rs[y * W + x];
            rng_key key = rng_key_make(test_seed(), (uint32_t)(y * W + x), 17);
            uint32_t id = (uint32_t)(rng_u(key, RNG_TEST, 0, 0) * 7);
            reservoir_init(r);
            if (rng_u(key, RNG_TEST, 0, 1) < 0.05) continue; /* empty */
            path_sample_begin(&r->y, 1, 100 + id, id % 3);
            r->y.length = 2;
            r->y.technique = PATH_TECH_NEE;
            path_sample_set_contribution(&r->y, rgb_make(1, 1, 1));
            r->W = rng_u(key, RNG_TEST, 0, 2) < 0.1 ? 0 : 1;
        }
    for (threads = 1; threads <= 3 && !bad && rs && count; threads += 2) {
        memset(count, 0xFF, W * H * sizeof *count);
        duplication_counts(rs, W, H, DUPLICATION_RADIUS, threads, count);
        for (y = 0; y < H && !bad; ++y)
            for (x = 0; x < W && !bad; ++x) {
                unsigned want = brute_count(rs, W, H, DUPLICATION_RADIUS, x, y);
                bad = count[y * W + x] != want;
                CHECKF(!bad, "%d threads, pixel (%d, %d): %u duplicates, by definition %u", threads, x, y,
                       count[y * W + x], want);
            }
    }
    free(rs);
    free(count);
}

typedef struct {
    volatile double sink;
} spin_ctx;

static void spin_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    spin_ctx *c = ctx;
    double s = 0;
    long i, n = 600L * (long)(x1 - x0) * (long)(y1 - y0);
    (void)worker;
    for (i = 0; i < n; ++i) s += (double)(i & 7);
    c->sink += s * 0; /* workers write the same value: no race on the result */
}

/* threads_parallel_cpu_seconds grows by the workers' CPU inside parallel_tiles (with 1
 * and 2 threads alike: the sum of the workers' time, not the wall time), and not by CPU
 * spent outside parallel regions. */
TEST(scaling_parallel_cpu_accounting)
{
    spin_ctx c;
    double p0, p1, p2, p3, s = 0;
    long i;
    c.sink = 0;
    p0 = threads_parallel_cpu_seconds();
    parallel_tiles(256, 256, 16, 1, spin_tile, &c, NULL, NULL);
    p1 = threads_parallel_cpu_seconds();
    parallel_tiles(256, 256, 16, 2, spin_tile, &c, NULL, NULL);
    p2 = threads_parallel_cpu_seconds();
    for (i = 0; i < 600L * 256 * 256; ++i) s += (double)(i & 7); /* outside: not counted */
    p3 = threads_parallel_cpu_seconds();
    CHECKF(p1 - p0 > 0.02, "1 thread: %.4f s counted", p1 - p0);
    /* the same work on 2 workers: the same CPU (generous bounds: a loaded machine) */
    CHECKF(p2 - p1 > 0.5 * (p1 - p0) && p2 - p1 < 2 * (p1 - p0), "2 threads: %.4f s, 1 thread %.4f s", p2 - p1,
           p1 - p0);
    CHECKF(p3 - p2 < 0.1 * (p1 - p0), "outside the parallel regions %.4f s were counted (sum %g)", p3 - p2, s);
}
