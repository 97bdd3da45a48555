/* Per-pixel moments of K independent renders (Welford, in double) and the on-disk
 * "moments" file set that `restir check` reads and `restir render --runs K` writes
 * (docs/statistics.md, "Moments files"). */
#ifndef RESTIR_MOMENTS_H
#define RESTIR_MOMENTS_H

#include <stdio.h>
#include "restir/core/error.h"
#include "restir/core/image.h"

/* Per-run block means are kept for at most this many block sizes. */
#define MOMENTS_MAX_BLOCK_SIZES 8

/* Does the renderer correlate the pixels of one run (e.g. ReSTIR's spatial reuse)? */
enum moments_correlation { MOMENTS_CORRELATION_UNKNOWN = 0, MOMENTS_INDEPENDENT = 1, MOMENTS_CORRELATED = 2 };

/* Running per-pixel mean and sum of squared deviations over K images, per channel,
 * plus every run's image mean (so image-mean tests stay exact for correlated pixels)
 * and, for the block sizes set with moments_set_block_sizes, every run's block means
 * (so block tests stay exact for correlated pixels: docs/statistics.md). */
typedef struct {
    int width, height;
    long runs;
    long run_capacity;
    double *mean;       /* 3 per pixel */
    double *m2;         /* 3 per pixel: sum of squared deviations from the mean */
    double *run_means;  /* 3 per run: the image mean of each run (r, g, b) */
    int block_size_count;
    int block_sizes[MOMENTS_MAX_BLOCK_SIZES];
    double *block_means[MOMENTS_MAX_BLOCK_SIZES]; /* per size: [run][block row][block column][channel] */
} moments;

/* What produced the runs, recorded in the sidecar (all fields optional). */
typedef struct {
    const char *method;             /* e.g. "restir", "pt"; NULL: not recorded */
    /* Writes one JSON object describing the renderer's options (the sidecar's "renderer"),
     * or NULL for none; `indent` prefixes continuation lines. */
    void (*write_config)(FILE *fp, const void *ctx, const char *indent);
    const void *ctx;
    enum moments_correlation correlation;
    const char *image_ext; /* "exr": the images are PREFIX.mean.exr, .var.exr; NULL or "pfm": .pfm */
} moments_meta;

/* The block sizes `restir render --runs` keeps per-run block means for. */
extern const int moments_default_block_sizes[4];

/* Blocks of b x b pixels covering a width x height image (edge blocks are smaller). */
long moments_block_count(int width, int height, int b);
/* The block means of one image, in double: out[3 * (by * blocks_x + bx) + c], summed
 * in row-major pixel order (every caller gets bit-identical values). */
void moments_block_means(const image *img, int b, double *out);

int moments_init(moments *m, int width, int height, rerror *e);
void moments_free(moments *m);
/* Keep per-run block means for these block sizes (each 1..4096, no repeats, at most
 * MOMENTS_MAX_BLOCK_SIZES); call before the first moments_add. */
int moments_set_block_sizes(moments *m, const int *sizes, int count, rerror *e);
/* Adds one run (an independent render). Fails on a size mismatch or a non-finite pixel;
 * `name` (may be NULL) names the run in the message ("name: what"). */
int moments_add(moments *m, const image *run, const char *name, rerror *e);
/* The per-pixel mean and unbiased sample variance of ONE run (not of the mean) as float
 * images. Needs runs >= 2 for the variance (runs == 1 gives variance 0). */
int moments_images(const moments *m, image *mean, image *var, rerror *e);

/* The moments file set of `prefix` (docs/statistics.md, "Moments files"):
 *   PREFIX.mean.pfm      per-pixel mean of the K runs
 *   PREFIX.var.pfm       per-pixel unbiased sample variance of ONE run
 *   PREFIX.moments.json  {"format": "restir-moments", "version": 1, "runs": K,
 *                          "width": W, "height": H, "mean": "...", "var": "...",
 *                          "run_means": [[r,g,b], ...]}   (run_means optional)
 * The three files are staged and renamed together (output_set.h): an error leaves
 * no partial file set behind. */
int moments_write(const char *prefix, const moments *m, rerror *e);
/* The same plus, when m has block sizes, PREFIX.blocks.bin (the per-run block means) and
 * the sidecar keys "block_sizes", "block_means", and from `meta` (may be NULL) "method",
 * "renderer", "correlated_pixels" (docs/statistics.md, "Moments files"). */
int moments_write_meta(const char *prefix, const moments *m, const moments_meta *meta, rerror *e);

/* A loaded moments file set. */
typedef struct {
    image mean, var;
    long runs;
    double *run_means; /* 3 * runs values, or NULL if the file had none */
    int block_size_count;  /* per-run block means (0 if the file had none) */
    int block_sizes[MOMENTS_MAX_BLOCK_SIZES];
    double *block_means[MOMENTS_MAX_BLOCK_SIZES]; /* as in `moments` */
    enum moments_correlation correlation; /* "correlated_pixels" (UNKNOWN if absent) */
    char method[64];                       /* "method" ("" if absent) */
} moments_file;

/* Reads PREFIX.moments.json (`path` may be the prefix or the .moments.json file itself)
 * and the two images it names (relative to the JSON's directory). */
int moments_read(const char *path, moments_file *out, rerror *e);
void moments_file_free(moments_file *f);

#endif
