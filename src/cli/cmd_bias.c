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
#include "restir/core/image_io.h"
#include "restir/core/pfm.h"
#include "restir/core/vec.h"
#include "restir/metrics/bias_runs.h"
#include "restir/metrics/moments.h"
#include "restir/metrics/stats.h"
#include "outputs_ready.h"

static const char usage[] =
    "usage: restir compare --bias RUN.pfm... (--ref REF.pfm | --ref-moments PREFIX) [options]\n"
    "  K >= 2 independent renders against a reference: rel_bias (signed, of the image mean, t\n"
    "  interval), mean_abs_rel = mean over blocks of |mean_k run - ref| / ref (Enhanced 5's\n"
    "  mean(|bias|/ref), raw: includes noise), its noise_floor (its value for an unbiased\n"
    "  estimator with the same spread and, with --ref-moments, the reference's own noise),\n"
    "  mean_abs_rel_corrected (the noise's inflation removed by the bootstrap, with the basic\n"
    "  bootstrap interval); nmse = per run sum (run - ref)^2 / sum ref^2 over the (masked) pixels,\n"
    "  mean and t interval over the runs; on luminance. Intervals at --level (default 0.99,\n"
    "  the level of restir check).\n"
    "options:\n"
    "  --ref REF.pfm         a reference taken as exact\n"
    "  --ref-moments PREFIX  a reference with its noise: PREFIX.mean.pfm, .var.pfm, .moments.json\n"
    "                        (render --runs N); its variance widens rel_bias's interval and raises\n"
    "                        the noise floor\n"
    "  --level L             interval level in (0, 1) (default 0.99)\n"
    "  --block N             block edge in pixels (default 4; 1 = per pixel)\n"
    "  --mask M.pfm          only pixels whose luminance in M lies in --mask-range\n"
    "  --mask-range LO,HI    (default 0.5,inf)\n"
    "  --resamples B         bootstrap resamples (default 400)\n"
    "  --json OUT.json       machine-readable result\n";

typedef struct {
    const char **files;
    int file_count, block, resamples;
    const char *ref, *ref_moments, *mask, *json;
    double lo, hi, level;
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

/* Before reading any image: the runs are distinct files (one file twice is not two
 * independent renders) and --json is writable and none of the inputs. */
static int check_files(const bias_args *a)
{
    char mean[4200], var[4200], meta[4200];
    named_file out, *ins = calloc((size_t)a->file_count + 5, sizeof *ins);
    int i, n = a->file_count, status;
    if (!ins) return usage_error("out of memory", "");
    for (i = 0; i < n; ++i) ins[i].path = a->files[i], ins[i].role = "a run";
    status = inputs_distinct("compare --bias", ins, n);
    ins[n].path = a->ref, ins[n++].role = "--ref";
    ins[n].path = a->mask, ins[n++].role = "--mask";
    if (a->ref_moments) {
        snprintf(mean, sizeof mean, "%s.mean.pfm", a->ref_moments);
        snprintf(var, sizeof var, "%s.var.pfm", a->ref_moments);
        snprintf(meta, sizeof meta, "%s.moments.json", a->ref_moments);
        ins[n].path = mean, ins[n++].role = "a file of --ref-moments";
        ins[n].path = var, ins[n++].role = "a file of --ref-moments";
        ins[n].path = meta, ins[n++].role = "a file of --ref-moments";
    }
    out.path = a->json, out.role = "--json";
    if (!status) status = outputs_ready("compare --bias", &out, 1, ins, n);
    free(ins);
    return status;
}

static int parse_args(int argc, char **argv, bias_args *a, int *done)
{
    int i, range_given = 0;
    *done = 0;
    memset(a, 0, sizeof *a);
    a->block = 4;
    a->resamples = 400;
    a->lo = 0.5;
    a->hi = 1e300;
    a->level = 0.99;
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
        else if (!strcmp(opt, "--ref-moments")) a->ref_moments = val;
        else if (!strcmp(opt, "--level")) {
            char *end;
            a->level = strtod(val, &end);
            if (end == val || *end || !(a->level > 0 && a->level < 1))
                return usage_error("--level must be a number in (0, 1), not ", val);
        }
        else if (!strcmp(opt, "--mask")) a->mask = val;
        else if (!strcmp(opt, "--json")) a->json = val;
        else if (!strcmp(opt, "--block")) {
            if (parse_int(val, 1, 4096, &a->block)) return usage_error("--block must be an integer in 1..4096, not ", val);
        } else if (!strcmp(opt, "--resamples")) {
            if (parse_int(val, 10, 100000, &a->resamples))
                return usage_error("--resamples must be an integer in 10..100000, not ", val);
        } else if (!strcmp(opt, "--mask-range")) {
            char *end;
            range_given = 1;
            a->lo = strtod(val, &end);
            if (end == val || *end != ',' || (a->hi = strtod(end + 1, &end), *end) || !(a->lo <= a->hi))
                return usage_error("--mask-range must be LO,HI with LO <= HI, not ", val);
        } else
            return usage_error("unknown option ", opt);
    }
    if (a->file_count < 2 || a->file_count > 65535) return usage_error("needs 2..65535 runs (independent renders)", "");
    if (!a->ref == !a->ref_moments) return usage_error("needs one of --ref REF.pfm or --ref-moments PREFIX", "");
    if (range_given && !a->mask) return usage_error("--mask-range needs --mask M.pfm (without a mask it has no effect)", "");
    return check_files(a);
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

/* Mean and t half-width at `level` over the n runs (stats_mean_ci; 0 with one run). */
static void mean_t(const double *v, int n, double level, double *mean, double *half)
{
    double var, lo, hi;
    stats_mean_var(v, n, mean, &var);
    if (n < 2) {
        *half = 0;
        return;
    }
    stats_mean_ci(stats_estimate_from_samples(*mean, var, n), level, &lo, &hi);
    *half = 0.5 * (hi - lo);
}

/* The reference's noise from its moments file set: per block the variance of its block
 * mean of luminance, sum_i var(lum_i) / (n^2 N) with var(lum_i) <= (sum_c w_c sd_ic)^2
 * (independent pixels, channels taken as fully correlated: an upper bound, as check's
 * luminance bound); the image mean's variance from the per-run image means when the file
 * has them and no mask is set (exact for any pixel correlation), else the sum over blocks. */
static void reference_noise(const moments_file *mf, const bias_args *a, const image *mask, long bw,
                            const double *weight, double *ref_var, bias_options *o)
{
    long x, y, j, blocks = bw * (((long)mf->var.height + a->block - 1) / a->block);
    double wsum = 0, sum = 0, n = (double)mf->runs;
    for (y = 0; y < mf->var.height; ++y)
        for (x = 0; x < mf->var.width; ++x) {
            long i = y * mf->var.width + x, b = (y / a->block) * bw + x / a->block;
            const float *v = mf->var.px + 3 * i;
            double m = mask ? lum_at(mask, i) : 1, sd;
            if (mask && !(m >= a->lo && m <= a->hi)) continue;
            sd = (double)luminance(rgb_make(1, 0, 0)) * sqrt(v[0]) + (double)luminance(rgb_make(0, 1, 0)) * sqrt(v[1]) +
                 (double)luminance(rgb_make(0, 0, 1)) * sqrt(v[2]);
            ref_var[b] += sd * sd / n;
        }
    for (j = 0; j < blocks; ++j) {
        if (!(weight[j] > 0)) continue;
        sum += ref_var[j]; /* = weight^2 x the block mean's variance */
        wsum += weight[j];
        ref_var[j] /= weight[j] * weight[j];
    }
    o->ref_var = ref_var;
    o->ref_mean_var = wsum > 0 ? sum / (wsum * wsum) : 0;
    o->ref_dof = n - 1;
    if (mf->run_means && !mask && mf->runs >= 2) {
        double s = 0, s2 = 0, l;
        long k;
        for (k = 0; k < mf->runs; ++k) {
            const double *c = mf->run_means + 3 * k;
            l = (double)luminance(rgb_make(1, 0, 0)) * c[0] + (double)luminance(rgb_make(0, 1, 0)) * c[1] +
                (double)luminance(rgb_make(0, 0, 1)) * c[2];
            s += l;
            s2 += l * l;
        }
        o->ref_mean_var = fmax(0, (s2 - s * s / n) / (n - 1)) / n;
    }
}

/* -1 with "PATH: pixel (x, y) is not finite" if img holds a NaN or Inf (a NaN run made
 * every result NaN), else 0. */
static int image_unfinite(const char *path, const image *img, rerror *e)
{
    size_t i, n = 3 * (size_t)img->width * (size_t)img->height;
    for (i = 0; i < n; ++i)
        if (!isfinite(img->px[i]))
            return rerror_set(e, "%s: pixel (%ld, %ld) is not finite", path, (long)(i / 3) % img->width,
                              (long)(i / 3) / img->width);
    return 0;
}

static int run(const bias_args *a, bias_result *r, double *nmse, rerror *e)
{
    image ref, mask, img;
    long bw, blocks, j;
    double *ref_b = NULL, *weight = NULL, *runs = NULL;
    int k, status = -1;
    bias_options o;
    moments_file mf;
    double *ref_var = NULL;
    memset(&mask, 0, sizeof mask);
    memset(&mf, 0, sizeof mf);
    bias_options_default(&o);
    o.level = a->level;
    o.resamples = a->resamples;
    if (a->ref_moments) {
        if (moments_read(a->ref_moments, &mf, e)) return -1;
        ref = mf.mean;
        memset(&mf.mean, 0, sizeof mf.mean);
    } else if (image_read(a->ref, &ref, NULL, e)) {
        return -1;
    }
    if (image_unfinite(a->ref ? a->ref : a->ref_moments, &ref, e)) goto done;
    if (a->mask && (image_read(a->mask, &mask, NULL, e) || image_unfinite(a->mask, &mask, e))) goto done;
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
        if (image_read(a->files[k], &img, NULL, e)) goto done;
        if (image_unfinite(a->files[k], &img, e)) {
            image_free(&img);
            goto done;
        }
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
    if (a->ref_moments) {
        if (!(ref_var = calloc((size_t)blocks, sizeof *ref_var))) {
            rerror_set(e, "out of memory");
            goto done;
        }
        reference_noise(&mf, a, a->mask ? &mask : NULL, bw, weight, ref_var, &o);
    }
    status = bias_measure(runs, ref_b, weight, a->file_count, blocks, &o, r, e);
done:
    free(ref_var);
    moments_file_free(&mf);
    free(ref_b);
    free(weight);
    free(runs);
    image_free(&ref);
    if (a->mask) image_free(&mask);
    return status;
}

static int write_json(const char *path, const bias_result *r, int block, double level, int ref_noise, double nm,
                      double nh, rerror *e)
{
    atomic_file f;
    if (atomic_file_open(&f, path, e)) return -1;
    fprintf(f.fp,
            "{\"runs\": %d, \"block\": %d, \"blocks\": %ld, \"level\": %.9g, \"reference_noise\": %s, "
            "\"rel_bias\": [%.9g, %.9g, %.9g], "
            "\"mean_abs_rel\": %.9g, \"mean_abs_rel_corrected\": [%.9g, %.9g, %.9g], \"noise_floor\": %.9g, "
            "\"nmse\": [%.9g, %.9g, %.9g]}\n",
            r->runs, block, r->blocks, level, ref_noise ? "true" : "false", r->rel_bias.value, r->rel_bias.lo, r->rel_bias.hi, r->mean_abs_rel.value,
            r->corrected, r->mean_abs_rel.lo, r->mean_abs_rel.hi, r->noise_floor, nm, nm - nh, nm + nh);
    return atomic_file_commit(&f, e);
}

/* Exit 0 only with finite numbers: no reference block in the mask range (a black
 * reference: the default range starts at 0.5) or a zero reference mean gave "rel_bias -nan"
 * and a JSON file with -nan tokens, exit 0. */
static int result_unfit(const bias_args *a, const bias_result *r, double nm, double nh, rerror *e)
{
    if (r->blocks == 0)
        return rerror_set(e, "restir compare --bias: no block to measure: none has a nonzero reference and a "
                             "luminance of %s in --mask-range %g,%g", a->mask ? a->mask : a->ref ? a->ref : a->ref_moments,
                          a->lo, a->hi);
    if (!isfinite(r->rel_bias.value) || !isfinite(r->rel_bias.lo) || !isfinite(r->rel_bias.hi) ||
        !isfinite(r->mean_abs_rel.value) || !isfinite(r->corrected) || !isfinite(r->noise_floor) || !isfinite(nm) ||
        !isfinite(nh))
        return rerror_set(e, "restir compare --bias: a result is not finite (rel_bias %g [%g, %g], nmse %g +- %g): the "
                             "reference's mean over the measured blocks is zero or the runs overflow",
                          r->rel_bias.value, r->rel_bias.lo, r->rel_bias.hi, nm, nh);
    return 0;
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
    if (!status) mean_t(nmse, a.file_count, a.level, &nm, &nh);
    if (!status && (status = result_unfit(&a, &r, nm, nh, &e)) != 0) status = -1;
    if (status || (a.json && write_json(a.json, &r, a.block, a.level, a.ref_moments != NULL, nm, nh, &e))) {
        fprintf(stderr, "%s\n", e.msg);
        free(a.files);
        free(nmse);
        return 2;
    }
    printf("level %g%s\n", a.level, a.ref_moments ? " (the reference's noise included)" : " (the reference taken as exact)");
    printf("runs %d\nblocks %ld\nrel_bias %.6g [%.6g, %.6g]\nmean_abs_rel %.6g\nmean_abs_rel_corrected %.6g [%.6g, %.6g]\n"
           "noise_floor %.6g\nnmse %.6g [%.6g, %.6g]\n",
           r.runs, r.blocks, r.rel_bias.value, r.rel_bias.lo, r.rel_bias.hi, r.mean_abs_rel.value, r.corrected,
           r.mean_abs_rel.lo, r.mean_abs_rel.hi, r.noise_floor, nm, nm - nh, nm + nh);
    free(a.files);
    free(nmse);
    return 0;
}
