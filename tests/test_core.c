/* Core: addressed RNG, sampling warps and their inverses, atomic files, threads. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/rng.h"
#include "restir/core/threads.h"
#include "restir/core/warp.h"
#include "restir/restir/path_sample.h"
#include "test.h"

/* Bit-exact vectors: a GPU port of docs/rng.md must reproduce these. */
TEST(rng_known_values)
{
    uint32_t v[4] = {0, 0, 0, 0};
    rng_key k = rng_key_make(1, 2, 3);
    rng_pcg4d(v);
    /* Recorded test vectors; docs/rng.md lists the same ones. */
    CHECKF(v[0] == 0x0f02f829u && v[1] == 0x2d568769u && v[2] == 0x32b0c43bu && v[3] == 0xd32548eau,
           "pcg4d(0,0,0,0) = %08x %08x %08x %08x", v[0], v[1], v[2], v[3]);
    k = rng_key_at(k, RNG_BSDF, 4, 5);
    CHECKF(rng_bits(k) == 0x957199b9u, "bits = %08x", rng_bits(k));
    CHECK_NEAR(rng_uniform_double(k), 0.58376465584209603, 0);
    CHECK_NEAR(rng_uniform_float(k), 0.583764613f, 0);
}

/* Every field of the address changes the number (no two fields alias). */
TEST(rng_address_fields_independent)
{
    rng_key base = rng_key_at(rng_key_make(7, 100, 3), RNG_BSDF, 2, 1);
    rng_key k;
    uint32_t b = rng_bits(base);
    k = base; k.seed++; CHECK(rng_bits(k) != b);
    k = base; k.pixel++; CHECK(rng_bits(k) != b);
    k = base; k.sample++; CHECK(rng_bits(k) != b);
    k = base; k.stream++; CHECK(rng_bits(k) != b);
    k = base; k.vertex++; CHECK(rng_bits(k) != b);
    k = base; k.slot++; CHECK(rng_bits(k) != b);
}

/* docs/rng.md's definition, literally: the key's four words, rng_pcg4d, the conversions. */
static void reference_words(rng_key k, uint32_t v[4])
{
    v[0] = k.pixel;
    v[1] = k.sample;
    v[2] = (k.stream << 24) | (k.vertex << 16) | k.slot;
    v[3] = k.seed;
    rng_pcg4d(v);
}

static double reference_double(rng_key k)
{
    uint32_t v[4];
    reference_words(k, v);
    return (double)(((uint64_t)v[0] << 21) | (v[1] >> 11)) * (1.0 / 9007199254740992.0);
}

static float reference_float(rng_key k)
{
    uint32_t v[4];
    reference_words(k, v);
    return (float)(v[0] >> 8) * (1.0f / 16777216.0f);
}

static real rng_reference(rng_key k)
{
    return sizeof(real) == sizeof(double) ? (real)reference_double(k) : (real)reference_float(k);
}

/* Every key-based function (rng.c computes pcg4d with words shared between numbers and the
 * dead words skipped) returns exactly the definition's numbers: rng_u_slots for every batch
 * length, rng_uniform, rng_uniform_double/float and rng_bits, on many addresses. */
TEST(rng_u_slots_equals_rng_u)
{
    long i;
    for (i = 0; i < 20000; ++i) {
        rng_key base = rng_key_make(test_seed() + (uint32_t)(i % 7), (uint32_t)(i * 2654435761u), (uint32_t)(i / 3));
        /* Small slots as the samplers use them, and every field up to its largest value
         * (a wrong share shows anywhere). */
        uint32_t stream = (uint32_t)(i % 9), vertex = (uint32_t)(i & 1 ? (i * 37) % 256 : i % 17);
        uint32_t first = (uint32_t)(i & 1 ? (i * 7919) % (65537 - RNG_SLOTS_MAX) : i % 11);
        int n = 1 + (int)(i % RNG_SLOTS_MAX), l;
        real u[RNG_SLOTS_MAX];
        rng_u_slots(base, stream, vertex, first, n, u);
        for (l = 0; l < n; ++l) {
            rng_key k = rng_key_at(base, stream, vertex, first + (uint32_t)l);
            uint32_t w[4];
            reference_words(k, w);
            if (u[l] != rng_reference(k) || rng_uniform(k) != rng_reference(k) || rng_bits(k) != w[0] ||
                rng_uniform_double(k) != reference_double(k) || rng_uniform_float(k) != reference_float(k)) {
                CHECKF(0, "address %ld lane %d: slots %.17g, rng_uniform %.17g, definition %.17g", i, l, (double)u[l],
                       (double)rng_uniform(k), (double)rng_reference(k));
                return;
            }
        }
    }
}

/* Uniformity: chi-square over 64 bins and serial correlation of consecutive slots. */
TEST(rng_uniformity)
{
    enum { BINS = 64, N = 640000 };
    static long counts[BINS];
    double chi2 = 0, expected = (double)N / BINS, sxy = 0, sx = 0, sxx = 0, prev = 0;
    long i;
    memset(counts, 0, sizeof counts);
    for (i = 0; i < N; ++i) {
        rng_key k = rng_key_at(rng_key_make(test_seed(), (uint32_t)(i / 1000), 0), RNG_TEST, 0, (uint32_t)(i % 1000));
        double u = rng_uniform_double(k);
        counts[(int)(u * BINS)]++;
        sx += u;
        sxx += u * u;
        if (i) sxy += u * prev;
        prev = u;
    }
    for (i = 0; i < BINS; ++i) chi2 += (counts[i] - expected) * (counts[i] - expected) / expected;
    /* chi2 with 63 dof: 0.1% quantile upper bound is about 103.4. */
    CHECKF(chi2 < 103.4, "chi2 = %g", chi2);
    {
        double mean = sx / N, var = sxx / N - mean * mean;
        double corr = (sxy / (N - 1) - mean * mean) / var;
        CHECKF(fabs(corr) < 4.0 / sqrt((double)N), "serial correlation %g", corr);
    }
}

static int vec2_close(vec2 a, vec2 b, double tol) { return fabs(a.x - b.x) <= tol && fabs(a.y - b.y) <= tol; }

/* warp^-1(warp(u)) = u for every warp, over a grid that avoids the measure-zero seams. */
TEST(warp_inverses_roundtrip)
{
    int i, j;
    for (i = 0; i < 97; ++i) {
        for (j = 0; j < 89; ++j) {
            vec2 u = v2((i + (real)0.37) / 97, (j + (real)0.61) / 89);
            double tol = sizeof(real) == 4 ? 2e-4 : 1e-9;
            CHECKF(vec2_close(warp_disk_concentric_inverse(warp_disk_concentric(u)), u, tol), "disk %d %d", i, j);
            CHECKF(vec2_close(warp_cosine_hemisphere_inverse(warp_cosine_hemisphere(u)), u, tol), "cos %d %d", i, j);
            CHECKF(vec2_close(warp_uniform_sphere_inverse(warp_uniform_sphere(u)), u, tol), "sphere %d %d", i, j);
            CHECKF(vec2_close(warp_uniform_hemisphere_inverse(warp_uniform_hemisphere(u)), u, tol), "hemi %d %d", i, j);
            CHECKF(vec2_close(warp_uniform_cone_inverse(warp_uniform_cone(u, (real)0.7), (real)0.7), u, tol * 10),
                   "cone %d %d", i, j);
            CHECKF(vec2_close(warp_uniform_triangle_inverse(warp_uniform_triangle(u)), u, tol), "tri %d %d", i, j);
        }
    }
}

/* Each warp's pdf integrates its own histogram: the fraction of samples falling in
 * a cap z > z0 matches the pdf integrated over the cap. */
TEST(warp_pdfs_match_histograms)
{
    enum { N = 200000 };
    long in_cos = 0, in_sphere = 0, in_cone = 0, in_tri = 0;
    real z0 = (real)0.5, cone = (real)0.3;
    long i;
    for (i = 0; i < N; ++i) {
        rng_key k = rng_key_make(test_seed(), (uint32_t)i, 1);
        vec2 u = v2(rng_uniform(rng_key_at(k, RNG_TEST, 0, 0)), rng_uniform(rng_key_at(k, RNG_TEST, 0, 1)));
        vec2 b = warp_uniform_triangle(u);
        if (warp_cosine_hemisphere(u).z > z0) in_cos++;
        if (warp_uniform_sphere(u).z > z0) in_sphere++;
        if (warp_uniform_cone(u, cone).z > (real)0.65) in_cone++;
        if (b.x > (real)0.5) in_tri++; /* region b0 > 1/2 has a quarter of the area */
    }
    /* cosine: P(z > z0) = 1 - z0^2; sphere: (1 - z0)/2; cone: (1-0.65)/(1-0.3); triangle: 1/4. */
    CHECK_NEAR((double)in_cos / N, 1 - z0 * z0, 5 * sqrt(0.25 / N));
    CHECK_NEAR((double)in_sphere / N, (1 - z0) / 2, 5 * sqrt(0.25 / N));
    CHECK_NEAR((double)in_cone / N, 0.35 / 0.7, 5 * sqrt(0.25 / N));
    CHECK_NEAR((double)in_tri / N, 0.25, 5 * sqrt(0.25 / N));
}

TEST(atomic_file_commit_and_abort)
{
    atomic_file f;
    rerror e;
    const char *path = test_tmp_path("atomic.txt");
    char copy[1024];
    snprintf(copy, sizeof copy, "%s", path);
    remove(copy);
    CHECK(atomic_file_open(&f, copy, &e) == 0);
    fputs("partial", f.fp);
    atomic_file_abort(&f);
    CHECK(!test_file_exists(copy));
    CHECK(!test_file_exists(f.tmp_path));
    CHECK(atomic_file_open(&f, copy, &e) == 0);
    fputs("done", f.fp);
    CHECK(atomic_file_commit(&f, &e) == 0);
    CHECK(test_file_exists(copy));
    CHECK(!test_file_exists(f.tmp_path));
}

static void mark_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    int *cells = ctx, x, y;
    (void)worker;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) cells[y * 37 + x] += 1;
}

/* Every pixel is visited exactly once, whatever the thread count. */
TEST(parallel_tiles_cover_once)
{
    static int cells[37 * 23];
    int threads[] = {1, 2, 7};
    int t, i;
    for (t = 0; t < 3; ++t) {
        memset(cells, 0, sizeof cells);
        CHECK(parallel_tiles(37, 23, 8, threads[t], mark_tile, cells, NULL, NULL) == 0);
        for (i = 0; i < 37 * 23; ++i) CHECKF(cells[i] == 1, "cell %d visited %d times with %d threads", i, cells[i], threads[t]);
    }
}

/* docs/rng.md's table of the RNG_RIS vertex ranges ("ReSTIR's addresses") against the
 * RNG_VERTEX_* constants of rng.h: every documented constant has the documented range,
 * every constant is documented, and no two ranges overlap. */
TEST(rng_vertex_table_matches_docs)
{
    static const struct {
        const char *name;
        uint32_t lo, hi;
    } constants[] = {
        {"RNG_VERTEX_INITIAL_RIS(d)", RNG_VERTEX_INITIAL_RIS(2), RNG_VERTEX_INITIAL_RIS(PATH_MAX_LENGTH)},
        {"RNG_VERTEX_SPATIAL_RIS(p)", RNG_VERTEX_SPATIAL_RIS(0), RNG_VERTEX_SPATIAL_RIS(RNG_VERTEX_PASSES - 1)},
        {"RNG_VERTEX_TEMPORAL_RIS", RNG_VERTEX_TEMPORAL_RIS, RNG_VERTEX_TEMPORAL_RIS},
        {"RNG_VERTEX_STOCHASTIC_PICK(p)", RNG_VERTEX_STOCHASTIC_PICK(0), RNG_VERTEX_STOCHASTIC_PICK(RNG_VERTEX_PASSES - 1)},
        {"RNG_VERTEX_STOCHASTIC_CANONICAL(p)", RNG_VERTEX_STOCHASTIC_CANONICAL(0),
         RNG_VERTEX_STOCHASTIC_CANONICAL(RNG_VERTEX_PASSES - 1)},
    };
    enum { N = sizeof constants / sizeof constants[0] };
    int seen[N] = {0}, i, k;
    char *doc = test_read_text("docs/rng.md"), *line;
    CHECK(doc != NULL);
    if (!doc) return;
    for (line = doc; line && *line; line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        unsigned lo, hi;
        char name[64];
        /* rows "| lo..hi | `NAME` | ..." or "| v | `NAME` | ..." */
        if (sscanf(line, "| %u..%u | `%63[^`]`", &lo, &hi, name) != 3) {
            if (sscanf(line, "| %u | `%63[^`]`", &lo, name) != 2) continue;
            hi = lo;
        }
        if (strncmp(name, "RNG_VERTEX_", 11)) continue;
        for (k = 0; k < N && strcmp(constants[k].name, name); ++k) {}
        CHECKF(k < N, "docs/rng.md names %s, which rng.h does not define", name);
        if (k == N) continue;
        seen[k]++;
        CHECKF(constants[k].lo == lo && constants[k].hi == hi, "%s: docs/rng.md says %u..%u, rng.h gives %u..%u",
               name, lo, hi, (unsigned)constants[k].lo, (unsigned)constants[k].hi);
    }
    for (k = 0; k < N; ++k) {
        CHECKF(seen[k] == 1, "%s: %d rows in docs/rng.md (want 1)", constants[k].name, seen[k]);
        for (i = 0; i < k; ++i)
            CHECKF(constants[i].hi < constants[k].lo || constants[k].hi < constants[i].lo, "%s overlaps %s",
                   constants[i].name, constants[k].name);
        CHECKF(constants[k].hi < 256, "%s beyond the 8-bit vertex field", constants[k].name);
    }
    free(doc);
}
