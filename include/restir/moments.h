/* Per-pixel moments of K independent renders (Welford, in double) and the on-disk
 * "moments" file set that `restir check` reads and `restir render --runs K` writes
 * (docs/statistics.md, "Moments files"). */
#ifndef RESTIR_MOMENTS_H
#define RESTIR_MOMENTS_H

#include "restir/error.h"
#include "restir/image.h"

/* Running per-pixel mean and sum of squared deviations over K images, per channel,
 * plus every run's image mean (so image-mean tests stay exact for correlated pixels). */
typedef struct {
    int width, height;
    long runs;
    long run_capacity;
    double *mean;       /* 3 per pixel */
    double *m2;         /* 3 per pixel: sum of squared deviations from the mean */
    double *run_means;  /* 3 per run: the image mean of each run (r, g, b) */
} moments;

int moments_init(moments *m, int width, int height, rerror *e);
void moments_free(moments *m);
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
/* Writes a file set from given images (run_means may be NULL, then omitted). */
int moments_write_images(const char *prefix, const image *mean, const image *var, long runs,
                         const double *run_means, rerror *e);

/* A loaded moments file set. */
typedef struct {
    image mean, var;
    long runs;
    double *run_means; /* 3 * runs values, or NULL if the file had none */
} moments_file;

/* Reads PREFIX.moments.json (`path` may be the prefix or the .moments.json file itself)
 * and the two images it names (relative to the JSON's directory). */
int moments_read(const char *path, moments_file *out, rerror *e);
void moments_file_free(moments_file *f);

#endif
