/* restir compare --bias RUN.pfm... --ref REF.pfm: the bias of K independent renders
 * against a reference, as Enhanced §5 reports it (mean(|bias| / ref)), with intervals and
 * the noise floor of an unbiased estimator (include/restir/metrics/bias_runs.h; docs/cli.md).
 * `restir compare` hands its whole argument list here when --bias is present. */
#include "cmd_bias.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/image.h"
#include "restir/core/pfm.h"
#include "restir/core/vec.h"
#include "restir/metrics/bias_runs.h"
#include "restir/metrics/stats.h"

static const char usage[] =
    "usage: restir compare --bias RUN.pfm... --ref REF.pfm [options]\n"
    "  K >= 2 independent renders against a reference taken as exact: rel_bias (signed, of the\n"
    "  image mean, 95% t interval), mean_abs_rel = mean over blocks of |mean_k run - ref| / ref\n"
    "  (Enhanced 5's mean(|bias|/ref), raw: includes noise), its noise_floor (its value for an\n"
    "  unbiased estimator with the same spread), mean_abs_rel_corrected (the noise's inflation\n"
    "  removed by the bootstrap, with the 95% basic bootstrap interval); nmse = per run sum (run - ref)^2 / sum ref^2\n"
    "  over the (masked) pixels, mean and 95% t interval over the runs; on luminance\n"
    "options:\n"
    "  --block N             block edge in pixels (default 4; 1 = per pixel)\n"
    "  --mask M.pfm          only pixels whose luminance in M lies in --mask-range\n"
    "  --mask-range LO,HI    (default 0.5,inf)\n"
    "  --resamples B         bootstrap resamples (default 400)\n"
    "  --json OUT.json       machine-readable result\n";

typedef struct {
    const char **files;
    int file_count, block, resamples;
    const char *ref, *mask, *json;
    double lo, hi;
} bias_args;

static int usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "restir compare --bias: %s%s\n(restir compare --bias --help for usage)\n", what, arg);
    return 2;
}

static int parse_int(const char *val, int lo, int hi, int *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(val, &end, 10);
    if (end == val || *end || errno || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

static int parse_args(int argc, char **argv, bias_args *a, int *done)
{
    int i;
    *done = 0;
    memset(a, 0, sizeof *a);
    a->block = 4;
    a->resamples = 400;
    a->lo = 0.5;
    a->hi = 1e300;
    if (!(a->files = calloc((size_t)argc, sizeof *a->files))) return usage_error("out of memory", "");
    for (i = 1; i < argc; ++i) {
        const char *opt = argv[i], *val;
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            fputs(usage, stdout);
            *done = 1;
            return 0;
        }
        if (!strcmp(opt, "--bias")) continue;
        if (strncmp(opt, "--", 2)) {
            a->files[a->file_count++] = opt;
            continue;
        }
        val = i + 1 < argc ? argv[++i] : NULL;
        if (!val) return usage_error("unknown option or missing value: ", opt);
        if (!strcmp(opt, "--ref")) a->ref = val;
        else if (!strcmp(opt, "--mask")) a->mask = val;
        else if (!strcmp(opt, "--json")) a->json = val;
        else if (!strcmp(opt, "--block")) {
            if (parse_int(val, 1, 4096, &a->block)) return usage_error("--block must be an integer in 1..4096, not ", val);
        } else if (!strcmp(opt, "--resamples")) {
            if (parse_int(val, 10, 100000, &a->resamples))
                return usage_error("--resamples must be an integer in 10..100000, not ", val);
        } else if (!strcmp(opt, "--mask-range")) {
            char *end;
            a->lo = strtod(val, &end);
            if (end == val || *end != ',' || (a->hi = strtod(end + 1, &end), *end) || !(a->lo <= a->hi))
                return usage_error("--mask-range must be LO,HI with LO <= HI, not ", val);
        } else
            return usage_error("unknown option ", opt);
    }
    if (a->file_count < 2 || a->file_count > 65535) return usage_error("needs 2..65535 runs (independent renders)", "");
    if (!a->ref) return usage_error("needs --ref REF.pfm", "");
    return 0;
}

static double lum_at(const image *img, long i)
{
    return (double)luminance(rgb_make(img->px[3 * i], img->px[3 * i + 1], img->px[3 * i + 2]));
}

/* Block means of img's luminance over the masked pixels (weight = their count). */
static void block_means(const image *img, const bias_args *a, const image *mask, long bw, double *out, double *weight)
{
    long x, y, n = bw * (((long)img->height + a->block - 1) / a->block);
    for (x = 0; x < n; ++x) out[x] = 0;
    for (y = 0; y < img->height; ++y)
        for (x = 0; x < img->width; ++x) {
            long i = y * img->width + x, b = (y / a->block) * bw + x / a->block;
            double m = mask ? lum_at(mask, i) : 1;
            if (mask && !(m >= a->lo && m <= a->hi)) continue;
            out[b] += lum_at(img, i);
            if (weight) weight[b] += 1;
        }
}

/* Normalised MSE of one run over the masked pixels with ref > 0. */
static double run_nmse(const image *img, const image *ref, const bias_args *a, const image *mask)
{
    double num = 0, den = 0;
    long i, n = (long)img->width * img->height;
    for (i = 0; i < n; ++i) {
        double m = mask ? lum_at(mask, i) : 1, rv = lum_at(ref, i), d = lum_at(img, i) - rv;
        if ((mask && !(m >= a->lo && m <= a->hi)) || !(rv > 0)) continue;
        num += d * d;
        den += rv * rv;
    }
    return den > 0 ? num / den : 0;
}

/* Mean and 95% t half-width over the n runs (stats_mean_ci; 0 with one run). */
static void mean_t95(const double *v, int n, double *mean, double *half)
{
    double var, lo, hi;
    stats_mean_var(v, n, mean, &var);
    stats_mean_ci(stats_estimate_from_samples(*mean, var, n), 0.95, &lo, &hi);
    *half = 0.5 * (hi - lo);
}

static int run(const bias_args *a, bias_result *r, double *nmse, rerror *e)
{
    image ref, mask, img;
    long bw, blocks, j;
    double *ref_b = NULL, *weight = NULL, *runs = NULL;
    int k, status = -1;
    memset(&mask, 0, sizeof mask);
    if (pfm_read(a->ref, &ref, NULL, e)) return -1;
    if (a->mask && pfm_read(a->mask, &mask, NULL, e)) goto done;
    if (a->mask && (mask.width != ref.width || mask.height != ref.height)) {
        rerror_set(e, "%s: %dx%d, the reference is %dx%d", a->mask, mask.width, mask.height, ref.width, ref.height);
        goto done;
    }
    bw = (ref.width + a->block - 1) / a->block;
    blocks = bw * ((ref.height + a->block - 1) / a->block);
    ref_b = calloc((size_t)blocks, sizeof *ref_b);
    weight = calloc((size_t)blocks, sizeof *weight);
    runs = calloc((size_t)blocks * (size_t)a->file_count, sizeof *runs);
    if (!ref_b || !weight || !runs) {
        rerror_set(e, "out of memory");
        goto done;
    }
    block_means(&ref, a, a->mask ? &mask : NULL, bw, ref_b, weight);
    for (k = 0; k < a->file_count; ++k) {
        if (pfm_read(a->files[k], &img, NULL, e)) goto done;
        if (img.width != ref.width || img.height != ref.height) {
            rerror_set(e, "%s: %dx%d, the reference is %dx%d", a->files[k], img.width, img.height, ref.width, ref.height);
            image_free(&img);
            goto done;
        }
        block_means(&img, a, a->mask ? &mask : NULL, bw, runs + (long)k * blocks, NULL);
        nmse[k] = run_nmse(&img, &ref, a, a->mask ? &mask : NULL);
        image_free(&img);
    }
    for (j = 0; j < blocks; ++j) { /* sums -> means */
        if (!(weight[j] > 0)) continue;
        ref_b[j] /= weight[j];
        for (k = 0; k < a->file_count; ++k) runs[(long)k * blocks + j] /= weight[j];
    }
    status = bias_measure(runs, ref_b, weight, a->file_count, blocks, a->resamples, 1, r, e);
done:
    free(ref_b);
    free(weight);
    free(runs);
    image_free(&ref);
    if (a->mask) image_free(&mask);
    return status;
}

static int write_json(const char *path, const bias_result *r, int block, double nm, double nh, rerror *e)
{
    atomic_file f;
    if (atomic_file_open(&f, path, e)) return -1;
    fprintf(f.fp,
            "{\"runs\": %d, \"block\": %d, \"blocks\": %ld, \"rel_bias\": [%.9g, %.9g, %.9g], "
            "\"mean_abs_rel\": %.9g, \"mean_abs_rel_corrected\": [%.9g, %.9g, %.9g], \"noise_floor\": %.9g, "
            "\"nmse\": [%.9g, %.9g, %.9g]}\n",
            r->runs, block, r->blocks, r->rel_bias.value, r->rel_bias.lo, r->rel_bias.hi, r->mean_abs_rel.value,
            r->corrected, r->mean_abs_rel.lo, r->mean_abs_rel.hi, r->noise_floor, nm, nm - nh, nm + nh);
    return atomic_file_commit(&f, e);
}

int cmd_compare_bias(int argc, char **argv)
{
    bias_args a;
    bias_result r;
    rerror e;
    double *nmse, nm, nh;
    int done, status = parse_args(argc, argv, &a, &done);
    if (status || done) {
        free(a.files);
        return status;
    }
    if (!(nmse = calloc((size_t)a.file_count, sizeof *nmse))) {
        free(a.files);
        return usage_error("out of memory", "");
    }
    status = run(&a, &r, nmse, &e);
    if (!status) mean_t95(nmse, a.file_count, &nm, &nh);
    if (status || (a.json && write_json(a.json, &r, a.block, nm, nh, &e))) {
        fprintf(stderr, "%s\n", e.msg);
        free(a.files);
        free(nmse);
        return 2;
    }
    printf("runs %d\nblocks %ld\nrel_bias %.6g [%.6g, %.6g]\nmean_abs_rel %.6g\nmean_abs_rel_corrected %.6g [%.6g, %.6g]\n"
           "noise_floor %.6g\nnmse %.6g [%.6g, %.6g]\n",
           r.runs, r.blocks, r.rel_bias.value, r.rel_bias.lo, r.rel_bias.hi, r.mean_abs_rel.value, r.corrected,
           r.mean_abs_rel.lo, r.mean_abs_rel.hi, r.noise_floor, nm, nm - nh, nm + nh);
    free(a.files);
    free(nmse);
    return 0;
}
