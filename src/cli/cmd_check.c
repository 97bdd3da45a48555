/* restir check: statistical verdict on whether two renderers estimate the same image
 * (docs/statistics.md, "check"). Exit status 0 consistent, 1 different (or not shown
 * equivalent with --require-equivalence), 2 usage or input error. */
#include "cmd_check.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/image.h"
#include "restir/core/image_io.h"
#include "restir/core/json_text.h"
#include "restir/core/png.h"
#include "restir/core/progress.h"
#include "restir/core/upside_down.h"
#include "restir/metrics/check.h"
#include "restir/metrics/moments.h"
#include "restir/metrics/output_set.h"
#include "args.h"
#include "collide.h"
#include "outputs_ready.h"

#define MAX_INPUTS 4096

/* What the option table cannot say (printed after it by --help). */
static const char help_notes[] =
    "\nSIDE_A is --a RUN.pfm... (K >= 2 independent renders) or --a-moments PREFIX\n"
    "(PREFIX.moments.json + .mean.pfm + .var.pfm); SIDE_B is --b RUN.pfm..., --b-moments PREFIX\n"
    "or --ref REF.pfm (a reference taken as exact, or with --ref-var VAR.pfm --ref-runs N its\n"
    "single-run variance over N runs).\n"
    "exit status: 0 consistent, 1 different, 2 usage or input error, 3 inconclusive (a side's runs are\n"
    "heavy-tailed: the t-tests cannot be trusted at this K; docs/statistics.md)\n";

typedef struct {
    const char *run_names[MAX_INPUTS];
    cli_list runs; /* --a / --b RUN.pfm... */
    const char *moments;
    const char *ref, *ref_var;
    int ref_runs;
} side_args;

typedef struct {
    side_args a, b;
    check_options opt;
    int require_equivalence, quiet, paired, no_skew_correction, correction;
    int progress;          /* --progress (enum progress_mode) */
    double progress_every; /* --progress-every */
    const char *json, *z_map, *block_z_map;
    double scale_a; /* --scale-a (0: not given) */
} check_args;

static const char *const correction_names[] = {"sidak", "bh", NULL}; /* index = enum check_correction */

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "restir check: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(restir check --help for usage)\n");
    return 2;
}

/* Returns 0, or the exit status to return (2 on a usage error, 0 after --help). */
static int parse_args(int argc, char **argv, check_args *a, int *done)
{
    const char *positional[1];
    int count, status;
    *done = 0;
    memset(a, 0, sizeof *a);
    check_options_default(&a->opt);
    a->a.runs.items = a->a.run_names;
    a->b.runs.items = a->b.run_names;
    a->a.runs.max = a->b.runs.max = MAX_INPUTS;
    a->correction = (int)a->opt.correction;
    {
        const cli_option options[] = {
            {"--a", OPT_LIST, &a->a.runs, "side A: K >= 2 independent renders", NULL, 0, 0, NULL},
            {"--a-moments", OPT_STRING, &a->a.moments, "side A: PREFIX.moments.json (+ the .mean and .var images it names, PFM or EXR)", NULL, 0, 0, NULL},
            {"--b", OPT_LIST, &a->b.runs, "side B: K >= 2 independent renders", NULL, 0, 0, NULL},
            {"--b-moments", OPT_STRING, &a->b.moments, "side B: a moments file set", NULL, 0, 0, NULL},
            {"--ref", OPT_STRING, &a->b.ref, "side B: a reference REF.pfm (or .exr, .png) taken as exact (or with --ref-var, --ref-runs)", NULL, 0, 0, NULL},
            {"--ref-var", OPT_STRING, &a->b.ref_var, "the reference's single-run variance VAR.pfm (or .exr)", NULL, 0, 0, NULL},
            {"--ref-runs", OPT_INT, &a->b.ref_runs, "the number of runs N behind --ref-var", NULL, 2, 2147483647.0, NULL},
            {"--block", OPT_INT, &a->opt.block_size, "block size in pixels (default 8; 1 = per pixel)", NULL, 1, 4096, NULL},
            {"--alpha", OPT_REAL, &a->opt.alpha, "level of the 'different' verdict, in (0, 1) (default 0.01)", NULL, 0, 0, NULL},
            {"--correction", OPT_CHOICE, &a->correction, "block family correction (default sidak)", correction_names, 0, 0, NULL},
            {"--margin", OPT_REAL, &a->opt.margin, "relative equivalence margin for the TOST, in (0, 1) (default 0.01)", NULL, 0, 0, NULL},
            {"--require-equivalence", OPT_FLAG, &a->require_equivalence, "also exit 1 unless equivalence within the margin is shown", NULL, 0, 0, NULL},
            {"--paired", OPT_FLAG, &a->paired, "run k of A and run k of B share their random numbers (same seeds): test the K per-run differences (needs --a and --b with the same K)", NULL, 0, 0, NULL},
            {"--json", OPT_STRING, &a->json, "machine-readable results OUT.json", NULL, 0, 0, NULL},
            {"--z-map", OPT_STRING, &a->z_map, "per-pixel normal-equivalent z, OUT.pfm or OUT.exr (per channel) or OUT.png (red A>B, blue A<B)", NULL, 0, 0, NULL},
            {"--block-z-map", OPT_STRING, &a->block_z_map, "the same per block (one pixel per block)", NULL, 0, 0, NULL},
            {"--no-skew-correction", OPT_FLAG, &a->no_skew_correction, "plain Welch block tests (default: discount the tail opposite the pooled skewness of the per-run block means, Hall 1992)", NULL, 0, 0, NULL},
            {"--scale-a", OPT_REAL, &a->scale_a, "multiply side A by S (a planted relative bias S - 1, to measure power)", NULL, 1e-300, 1e6, NULL},
            {"--quiet", OPT_FLAG, &a->quiet, "print only the verdict line (and no progress)", NULL, 0, 0, NULL},
            CLI_PROGRESS_ROWS(&a->progress, &a->progress_every),
            {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
        };
        status = cli_parse("check", argc, argv, options, positional, 0, &count);
        if (status == 1) {
            cli_print_help(stdout, "check", "SIDE_A SIDE_B [options]", options);
            fputs(help_notes, stdout);
            *done = 1;
            return 0;
        }
        if (status) return status;
    }
    a->opt.correction = (enum check_correction)a->correction;
    if (a->no_skew_correction) a->opt.skew_correction = 0;
    if (!(a->opt.alpha > 0 && a->opt.alpha < 1)) return usage_error("%s", "--alpha: expected a number in (0, 1)");
    if (!(a->opt.margin > 0 && a->opt.margin < 1)) return usage_error("%s", "--margin: expected a number in (0, 1)");
    if ((a->a.runs.count > 0) + (a->a.moments != NULL) != 1 || a->a.ref)
        return usage_error("%s", "give side A as exactly one of --a RUN... or --a-moments PREFIX");
    if ((a->b.runs.count > 0) + (a->b.moments != NULL) + (a->b.ref != NULL) != 1)
        return usage_error("%s", "give side B as exactly one of --b RUN..., --b-moments PREFIX or --ref REF.pfm");
    if ((a->b.ref_var != NULL) != (a->b.ref_runs > 0) || (a->b.ref_var && !a->b.ref))
        return usage_error("%s", "--ref-var and --ref-runs go together, with --ref");
    if (a->paired && (a->a.runs.count == 0 || a->b.runs.count == 0 || a->a.runs.count != a->b.runs.count))
        return usage_error("%s", "--paired needs --a RUN... and --b RUN... with the same number of runs");
    return 0;
}

/* ---- loading a side ---- */

/* Reading the runs is what takes long (K images of 1080p: 24 MB each): progress counts
 * them over both sides. */
static progress load_progress;
static long runs_read, runs_total;

static int load_runs(check_side *side, const side_args *s, int block, rerror *e)
{
    int i;
    for (i = 0; i < s->runs.count; ++i) {
        image img;
        int status;
        progress_update(&load_progress, runs_read, runs_total);
        if (image_read(s->runs.items[i], &img, NULL, e)) return -1;
        ++runs_read;
        if (i == 0 && check_side_begin_runs(side, img.width, img.height, block, e)) {
            image_free(&img);
            return -1;
        }
        status = check_side_add_run(side, &img, s->runs.items[i], e);
        image_free(&img);
        if (status) return -1;
    }
    if (s->runs.count < 2)
        return rerror_at(e, s->runs.items[0], 0, "only one run given: at least 2 independent runs are needed");
    return check_side_end_runs(side, e);
}

static int load_reference(check_side *side, const side_args *s, rerror *e)
{
    image ref;
    moments_file f;
    size_t i, n;
    if (image_read(s->ref, &ref, NULL, e)) return -1;
    n = (size_t)ref.width * (size_t)ref.height * 3;
    for (i = 0; i < n; ++i)
        if (!isfinite(ref.px[i])) {
            /* the message first: image_free zeroes the width (it divided by zero: SIGFPE) */
            rerror_at(e, s->ref, 0, "pixel (%ld, %ld) is not finite", (long)(i / 3) % ref.width,
                      (long)(i / 3) / ref.width);
            image_free(&ref);
            return -1;
        }
    if (!s->ref_var) return check_side_exact(side, &ref, e);
    memset(&f, 0, sizeof f);
    f.mean = ref;
    f.runs = s->ref_runs;
    if (image_read(s->ref_var, &f.var, NULL, e)) {
        image_free(&ref);
        return -1;
    }
    if (f.var.width != ref.width || f.var.height != ref.height) {
        rerror_at(e, s->ref_var, 0, "variance image is %d x %d, the reference is %d x %d", f.var.width,
                  f.var.height, ref.width, ref.height);
        moments_file_free(&f);
        return -1;
    }
    for (i = 0; i < n; ++i)
        if (!isfinite(f.var.px[i]) || f.var.px[i] < 0.0f) {
            rerror_at(e, s->ref_var, 0, "pixel (%ld, %ld) is not a finite non-negative variance",
                      (long)(i / 3) % ref.width, (long)(i / 3) / ref.width);
            moments_file_free(&f);
            return -1;
        }
    if (check_side_from_moments(side, &f, s->ref_var, e)) {
        moments_file_free(&f);
        return -1;
    }
    return 0;
}

static int load_side(check_side *side, const side_args *s, int block, rerror *e)
{
    memset(side, 0, sizeof *side);
    if (s->runs.count > 0) return load_runs(side, s, block, e);
    if (s->moments) {
        moments_file f;
        if (moments_read(s->moments, &f, e)) return -1;
        if (check_side_from_moments(side, &f, s->moments, e)) {
            moments_file_free(&f);
            return -1;
        }
        return 0;
    }
    return load_reference(side, s, e);
}

/* ---- outputs ---- */

/* PNG view of a z map: the channel with the largest |z| decides; red where A is
 * brighter, blue where darker, full intensity at |z| >= 6. */
static int write_z_png(const char *path, const image *z, rerror *e)
{
    size_t i, n = (size_t)z->width * (size_t)z->height;
    unsigned char *rgb = rmalloc(n, 3, e);
    int status;
    if (!rgb) return -1;
    for (i = 0; i < n; ++i) {
        const float *p = z->px + 3 * i;
        float v = p[0];
        double level;
        if (fabsf(p[1]) > fabsf(v)) v = p[1];
        if (fabsf(p[2]) > fabsf(v)) v = p[2];
        level = fabs(v) / 6.0;
        if (level > 1.0) level = 1.0;
        rgb[3 * i] = v > 0 ? (unsigned char)(255.0 * level + 0.5) : 0;
        rgb[3 * i + 1] = 0;
        rgb[3 * i + 2] = v < 0 ? (unsigned char)(255.0 * level + 0.5) : 0;
    }
    status = png_write_rgb8(path, z->width, z->height, rgb, e);
    free(rgb);
    return status;
}

/* The format follows the name the user gave (final), not the temporary file's (staged):
 * .png the colour picture, .exr OpenEXR, else PFM. */
static int write_z_map(const char *staged, const char *final, const image *z, rerror *e)
{
    return image_path_is(final, "png") ? write_z_png(staged, z, e) : image_write_as(staged, final, z, e);
}

static const char *side_kind_name(const check_side *s)
{
    return s->kind == CHECK_SIDE_RUNS ? "images" : s->kind == CHECK_SIDE_MOMENTS ? "moments" : "exact";
}

static const char channel_names[3] = {'r', 'g', 'b'};

/* Where a side's block variances come from. */
static const char *block_source(const check_side *s, int from_runs)
{
    return s->kind == CHECK_SIDE_EXACT ? "exact" : from_runs ? "per-run block means" : "independent-pixel formula";
}

/* The file that names a side in messages. */
static const char *side_file(const side_args *s)
{
    return s->runs.count > 0 ? s->runs.items[0] : s->moments ? s->moments : s->ref;
}

static void put_key_number(FILE *fp, const char *indent, const char *key, double v, int last)
{
    fprintf(fp, "%s\"%s\": ", indent, key);
    json_put_number(fp, v);
    fputs(last ? "\n" : ",\n", fp);
}

static void put_estimate(FILE *fp, const char *key, stats_estimate est, const check_side *s, int from_runs)
{
    fprintf(fp, "    \"%s\": {\"source\": \"%s\", \"runs\": %ld, \"mean\": ", key, side_kind_name(s), s->runs);
    json_put_number(fp, est.mean);
    fputs(", \"se\": ", fp);
    json_put_number(fp, sqrt(est.var_of_mean));
    fputs(", \"dof\": ", fp);
    json_put_number(fp, s->kind == CHECK_SIDE_EXACT ? NAN : est.dof);
    fprintf(fp, ", \"variance_from\": \"%s\"},\n",
            s->kind == CHECK_SIDE_EXACT ? "exact" : from_runs ? "per-run image means" : "independent-pixel bound");
}

/* The warning for a moments side from a renderer that correlates pixels but without the
 * per-run statistics a part of the verdict needs (docs/statistics.md, "Correlated
 * renderers"); returns 0 (no warning) or 1 with the text in msg. */
static int correlated_warning(char *msg, size_t size, int side_b, const char *prefix, const check_result *r,
                              int block_size)
{
    int warn = side_b ? r->correlated_warning_b : r->correlated_warning_a;
    int blocks = side_b ? r->blocks_b_from_runs : r->blocks_a_from_runs;
    int lum = side_b ? r->lum_b_exact_runs : r->lum_a_exact_runs;
    char missing[96];
    if (!warn) return 0;
    if (!blocks && !lum)
        snprintf(missing, sizeof missing, "image means nor block means at block size %d", block_size);
    else if (!blocks)
        snprintf(missing, sizeof missing, "block means at block size %d", block_size);
    else
        snprintf(missing, sizeof missing, "image means");
    snprintf(msg, size,
             "side %c (%s) comes from a renderer that correlates pixels (\"correlated_pixels\": true) but has no "
             "per-run %s: %s independent pixels and can call a correct renderer different; re-render with "
             "`restir render --runs K` (keeps per-run block means at block sizes 4, 8, 16, 32) or give the raw runs",
             side_b ? 'B' : 'A', prefix, missing,
             blocks ? "the image-mean test assumes" : lum ? "its block tests assume" : "both of its tests assume");
    return 1;
}

/* Fewer runs than this from a renderer that correlates pixels: the block tests' false-alarm
 * rate was measured above nominal (docs/statistics.md, "False alarms on correct ReSTIR"). */
#define CHECK_CORRELATED_MIN_RUNS 16

/* The warning for a side from a correlated renderer with per-run block means from too few
 * runs; returns 0 (no warning) or 1 with the text in msg. */
static int few_runs_warning(char *msg, size_t size, int side_b, const char *prefix, const check_side *s,
                            const check_result *r)
{
    int blocks = side_b ? r->blocks_b_from_runs : r->blocks_a_from_runs;
    if (s->kind != CHECK_SIDE_MOMENTS || s->correlation != MOMENTS_CORRELATED || !blocks ||
        s->runs >= CHECK_CORRELATED_MIN_RUNS)
        return 0;
    snprintf(msg, size,
             "side %c (%s) comes from a renderer that correlates pixels and has K = %ld runs: its per-run block "
             "means are skewed, and with K < %d the block tests were measured to reject a correct ReSTIR more often "
             "than alpha (docs/statistics.md, \"False alarms on correct ReSTIR\"); use K >= %d",
             side_b ? 'B' : 'A', prefix, s->runs, CHECK_CORRELATED_MIN_RUNS, CHECK_CORRELATED_MIN_RUNS);
    return 1;
}

/* Every warning about side `side_b` (0 = A, 1 = B), one at a time: index 0, 1, ... */
static int side_warning(char *msg, size_t size, int side_b, int index, const check_args *args, const check_side *s,
                        const check_result *r)
{
    const char *prefix = side_b ? side_file(&args->b) : side_file(&args->a);
    int have = 0;
    if (correlated_warning(msg, size, side_b, prefix, r, args->opt.block_size) && have++ == index) return 1;
    if (few_runs_warning(msg, size, side_b, prefix, s, r) && have++ == index) return 1;
    return 0;
}

/* The verdict word: inconclusive overrides both (the tests ran, but cannot be trusted). */
static const char *verdict_word(const check_result *r)
{
    return r->inconclusive ? "inconclusive" : r->different ? "different" : "consistent";
}

/* "heavy-tailed runs (A: tail index 1.3 < 2, skewness 3.1), need K >= 240 per side" */
static void inconclusive_reason(char *buf, size_t size, const check_result *r)
{
    const check_tail *t = r->tail_a.heavy ? &r->tail_a : &r->tail_b;
    double g = fabs(t->skew_image) > fabs(t->skew_blocks) ? t->skew_image : t->skew_blocks;
    snprintf(buf, size,
             "heavy-tailed runs (side %c: tail index %.2g < %g, skewness %.2g%s), need K >= %ld per side%s",
             r->tail_a.heavy ? 'A' : 'B', t->tail_index, CHECK_TAIL_ALPHA_MIN, g,
             r->tail_a.heavy && r->tail_b.heavy ? "; side B too" : "", r->runs_needed,
             t->tail_index <= 2 ? " and a finite variance (a tail index <= 2 means none: more runs may not help)" : "");
}

static void put_tail(FILE *fp, const char *name, const check_tail *t, int last)
{
    fprintf(fp, "    \"%s\": {\"measured\": %s, \"skewness_image_mean\": ", name, t->measured ? "true" : "false");
    json_put_number(fp, t->skew_image);
    fputs(", \"skewness_blocks\": ", fp);
    json_put_number(fp, t->skew_blocks);
    fputs(", \"tail_index\": ", fp);
    json_put_number(fp, isfinite(t->tail_index) ? t->tail_index : NAN);
    fputs(", \"tail_index_upper\": ", fp);
    json_put_number(fp, isfinite(t->tail_upper) ? t->tail_upper : NAN);
    fprintf(fp, ", \"exceedances\": %ld, \"tail_count\": %ld, \"heavy\": %s}%s\n", t->exceedances, t->tail_count,
            t->heavy ? "true" : "false", last ? "" : ",");
}

static int write_json(const char *path, const check_args *args, const check_side *a, const check_side *b,
                      const check_result *r, int status, rerror *e)
{
    atomic_file f;
    FILE *fp;
    int side, count;
    if (atomic_file_open(&f, path, e)) return -1;
    fp = f.fp;
    fprintf(fp, "{\n  \"verdict\": \"%s\",\n  \"exit_status\": %d,\n", verdict_word(r), status);
    fprintf(fp, "  \"tests_say\": \"%s\",\n", r->different ? "different" : "consistent");
    if (r->inconclusive) {
        char reason[512];
        inconclusive_reason(reason, sizeof reason, r);
        fputs("  \"inconclusive_reason\": ", fp);
        json_put_string(fp, reason);
        fprintf(fp, ",\n  \"runs_needed\": %ld,\n", r->runs_needed);
    }
    fprintf(fp, "  \"tails\": {\n");
    put_key_number(fp, "    ", "tail_index_min", CHECK_TAIL_ALPHA_MIN, 0);
    put_tail(fp, "a", &r->tail_a, 0);
    put_tail(fp, "b", &r->tail_b, 1);
    fprintf(fp, "  },\n");
    fprintf(fp, "  \"width\": %d,\n  \"height\": %d,\n", a->width, a->height);
    put_key_number(fp, "  ", "alpha", args->opt.alpha, 0);
    fprintf(fp, "  \"paired\": %s,\n", r->paired ? "true" : "false");
    fprintf(fp, "  \"image_mean\": {\n    \"channel\": \"luminance\",\n");
    put_estimate(fp, "a", r->lum_a, a, r->lum_a_exact_runs);
    put_estimate(fp, "b", r->lum_b, b, r->lum_b_exact_runs);
    put_key_number(fp, "    ", "diff", r->global.diff, 0);
    put_key_number(fp, "    ", "t", r->global.t, 0);
    put_key_number(fp, "    ", "dof", r->global.dof, 0);
    put_key_number(fp, "    ", "p", r->global.p, 0);
    put_key_number(fp, "    ", "level", 0.5 * args->opt.alpha, 0);
    fprintf(fp, "    \"reject\": %s\n  },\n", r->global_reject ? "true" : "false");
    fprintf(fp, "  \"blocks\": {\n    \"block_size\": %d,\n    \"blocks_x\": %d,\n    \"blocks_y\": %d,\n",
            args->opt.block_size, r->blocks_x, r->blocks_y);
    fprintf(fp, "    \"correction\": \"%s\",\n    \"tests\": %ld,\n", args->opt.correction == CHECK_BH ? "bh" : "sidak",
            r->tests);
    put_key_number(fp, "    ", "family_level", 0.5 * args->opt.alpha, 0);
    put_key_number(fp, "    ", "p_threshold", r->block_threshold, 0);
    fprintf(fp, "    \"rejected\": %ld,\n", r->rejected);
    fprintf(fp, "    \"skew_correction\": %s,\n", args->opt.skew_correction ? "true" : "false");
    put_key_number(fp, "    ", "skewness_a", r->skew_a, 0);
    put_key_number(fp, "    ", "skewness_b", r->skew_b, 0);
    fprintf(fp, "    \"variance_from_a\": \"%s\",\n    \"variance_from_b\": \"%s\",\n", block_source(a, r->blocks_a_from_runs),
            block_source(b, r->blocks_b_from_runs));
    fprintf(fp, "    \"most_extreme\": {\"x\": %d, \"y\": %d, \"channel\": \"%c\", \"diff\": ", r->worst.x, r->worst.y,
            channel_names[r->worst.channel]);
    json_put_number(fp, r->worst.test.diff);
    fputs(", \"t\": ", fp);
    json_put_number(fp, r->worst.test.t);
    fputs(", \"dof\": ", fp);
    json_put_number(fp, r->worst.test.dof);
    fputs(", \"p\": ", fp);
    json_put_number(fp, r->worst.test.p);
    fputs(", \"z\": ", fp);
    json_put_number(fp, r->worst.z);
    fputs("}\n  },\n", fp);
    fprintf(fp, "  \"pixels\": {\"diagnostic\": \"uncorrected per-pixel tests, not part of the verdict\", "
                "\"tests\": %ld, \"p_below_alpha\": %ld, \"expected_if_consistent\": ", r->pixel_tests,
            r->pixels_p_below_alpha);
    json_put_number(fp, args->opt.alpha * (double)r->pixel_tests);
    fputs("},\n  \"relative_bias\": {\"estimate\": ", fp);
    json_put_number(fp, r->bias);
    fputs(", \"ci_low\": ", fp);
    json_put_number(fp, r->bias_ci_bounded ? r->bias_lo : NAN);
    fputs(", \"ci_high\": ", fp);
    json_put_number(fp, r->bias_ci_bounded ? r->bias_hi : NAN);
    fputs(", \"ci_level\": ", fp);
    json_put_number(fp, 1.0 - args->opt.alpha);
    fputs("},\n  \"equivalence\": {\"margin\": ", fp);
    json_put_number(fp, r->tost.margin);
    fputs(", \"p_lower\": ", fp);
    json_put_number(fp, r->tost.p_lower);
    fputs(", \"p_upper\": ", fp);
    json_put_number(fp, r->tost.p_upper);
    fputs(", \"p\": ", fp);
    json_put_number(fp, r->tost.p);
    fprintf(fp, ", \"equivalent\": %s},\n  \"warnings\": [", r->tost.equivalent ? "true" : "false");
    for (side = 0, count = 0; side < 2; ++side) {
        char msg[1024];
        int index;
        for (index = 0; side_warning(msg, sizeof msg, side, index, args, side ? b : a, r); ++index) {
            fputs(count++ ? ",\n    " : "\n    ", fp);
            json_put_string(fp, msg);
        }
    }
    fprintf(fp, "%s]\n}\n", count ? "\n  " : "");
    return atomic_file_commit(&f, e);
}

static int write_outputs(const check_args *args, const check_side *a, const check_side *b, const check_result *r,
                         int status, rerror *e)
{
    output_set out;
    const char *staged;
    output_set_init(&out);
    if (args->json &&
        (!(staged = output_set_stage(&out, args->json, e)) || write_json(staged, args, a, b, r, status, e)))
        goto fail;
    if (args->z_map && (!(staged = output_set_stage(&out, args->z_map, e)) || write_z_map(staged, args->z_map, &r->pixel_z, e)))
        goto fail;
    if (args->block_z_map &&
        (!(staged = output_set_stage(&out, args->block_z_map, e)) || write_z_map(staged, args->block_z_map, &r->block_z, e)))
        goto fail;
    return output_set_commit(&out, e);
fail:
    output_set_abort(&out);
    return -1;
}

/* ---- summary ---- */

static void describe_side(const char *label, const check_side *s)
{
    if (s->kind == CHECK_SIDE_EXACT)
        printf("%s: exact reference\n", label);
    else
        printf("%s: %ld runs (%s)\n", label, s->runs, side_kind_name(s));
}

static void print_tail(const char *side, const check_tail *t)
{
    if (!t->measured) {
        printf("  %s: not measured (needs >= %d runs with per-run block means and >= %d positive deviations of "
               "them; %ld here)\n",
               side, CHECK_TAIL_MIN_RUNS, CHECK_TAIL_MIN_EXCEEDANCES, t->exceedances);
        return;
    }
    printf("  %s: skewness of the per-run image means %.3g, of the block means %.3g; tail index %.3g, + 1 sd %.3g "
           "(Hill, %ld of %ld standardised deviations)%s\n",
           side, t->skew_image, t->skew_blocks, t->tail_index, t->tail_upper, t->tail_count, t->exceedances,
           t->heavy ? ": HEAVY" : "");
}

static void print_tails(const check_result *r)
{
    printf("tails of the per-run statistics (a tail index + 1 sd < %g: the t-tests cannot be trusted):\n",
           CHECK_TAIL_ALPHA_MIN);
    print_tail("A", &r->tail_a);
    print_tail("B", &r->tail_b);
}

static void print_summary(const check_args *args, const check_side *a, const check_side *b, const check_result *r)
{
    const check_options *o = &args->opt;
    printf("restir check: %d x %d pixels\n", a->width, a->height);
    describe_side("  A", a);
    describe_side("  B", b);
    printf("image mean (luminance): A %.9g (se %.3g), B %.9g (se %.3g)\n", r->lum_a.mean, sqrt(r->lum_a.var_of_mean),
           r->lum_b.mean, sqrt(r->lum_b.var_of_mean));
    if (!r->lum_a_exact_runs && a->kind != CHECK_SIDE_EXACT)
        printf("  note: A has no per-run means; its se assumes independent pixels\n");
    if (!r->lum_b_exact_runs && b->kind != CHECK_SIDE_EXACT)
        printf("  note: B has no per-run means; its se assumes independent pixels\n");
    if (r->paired) printf("paired: run k of A with run k of B; the tests below are on the %ld per-run differences\n", a->runs);
    printf("  %s t = %.4g, dof = %.4g, p = %.3g (level %g): %s\n", r->paired ? "paired" : "Welch", r->global.t, r->global.dof, r->global.p,
           0.5 * o->alpha, r->global_reject ? "REJECT" : "no evidence of a difference");
    printf("blocks %dx%d: %ld tests (%d x %d blocks x 3 channels), %s, family level %g, p threshold %.3g: %ld rejected\n",
           o->block_size, o->block_size, r->tests, r->blocks_x, r->blocks_y,
           o->correction == CHECK_BH ? "Benjamini-Hochberg" : "Sidak", 0.5 * o->alpha, r->block_threshold,
           r->rejected);
    printf("  block variances: A %s, B %s; skewness of per-run block means A %.3g, B %.3g (%s)\n",
           block_source(a, r->blocks_a_from_runs), block_source(b, r->blocks_b_from_runs), r->skew_a, r->skew_b,
           o->skew_correction ? "skew-corrected tail" : "no skew correction");
    printf("  most extreme: block (%d, %d) channel %c, diff %.4g, t = %.4g, dof = %.4g, p = %.3g, z = %.3g\n",
           r->worst.x, r->worst.y, channel_names[r->worst.channel], r->worst.test.diff, r->worst.test.t,
           r->worst.test.dof, r->worst.test.p, r->worst.z);
    printf("diagnostic, not the verdict: %ld of %ld uncorrected per-pixel tests have p < %g (about %.0f expected if "
           "consistent; pixels of one run are not independent under reuse, so an excess here alone proves nothing)\n",
           r->pixels_p_below_alpha, r->pixel_tests, o->alpha, o->alpha * (double)r->pixel_tests);
    print_tails(r);
    if (r->bias_ci_bounded)
        printf("relative bias A/B - 1: %+.4f%% [%g%% CI %+.4f%%, %+.4f%%]\n", 100.0 * r->bias, 100.0 * (1.0 - o->alpha),
               100.0 * r->bias_lo, 100.0 * r->bias_hi);
    else
        printf("relative bias A/B - 1: %+.4f%% (interval unbounded: B's mean is not significantly nonzero)\n",
               100.0 * r->bias);
    printf("equivalence (TOST, margin %g%%, level %g): %s (p = %.3g)\n", 100.0 * r->tost.margin, o->alpha,
           r->tost.equivalent ? "equivalent" : "not shown equivalent", r->tost.p);
}

/* --scale-a: the planted bias (never fails; an int for the chain of steps in cmd_check). */
static int scale_side(check_side *a, double scale)
{
    if (scale > 0) check_side_scale(a, scale);
    return 0;
}

/* --z-map and --block-z-map: .png (the picture), .exr, else PFM; a name of a format
 * that is not written is refused before any work. */
static int check_map_names(const check_args *args)
{
    const char *maps[2];
    rerror e;
    int i;
    maps[0] = args->z_map, maps[1] = args->block_z_map;
    for (i = 0; i < 2; ++i)
        if (maps[i] && !image_path_is(maps[i], "png") && image_output_check(maps[i], &e)) {
            fprintf(stderr, "restir check: %s %s\n", i ? "--block-z-map" : "--z-map", e.msg);
            return 2;
        }
    return 0;
}

/* --json, --z-map and --block-z-map can be written and must not overwrite each other or an
 * input image; no input is given twice. */
static int check_collisions(const check_args *args)
{
    static const char *const moments_files[] = {".mean.pfm", ".var.pfm", ".mean.exr", ".var.exr", ".moments.json",
                                                ".blocks.bin"};
    named_file outs[3], ins[2 * MAX_INPUTS + 16];
    char names[12][4200];
    int n = 0, side, i, m = 0, runs;
    outs[0].path = args->json, outs[0].role = "--json";
    outs[1].path = args->z_map, outs[1].role = "--z-map";
    outs[2].path = args->block_z_map, outs[2].role = "--block-z-map";
    for (side = 0; side < 2; ++side) { /* the runs first: they must be distinct files */
        const side_args *s = side ? &args->b : &args->a;
        for (i = 0; i < s->runs.count; ++i) ins[n].path = s->runs.items[i], ins[n++].role = side ? "--b" : "--a";
    }
    runs = n;
    for (side = 0; side < 2; ++side) {
        const side_args *s = side ? &args->b : &args->a;
        ins[n].path = s->ref, ins[n++].role = "--ref";
        ins[n].path = s->ref_var, ins[n++].role = "--ref-var";
        for (i = 0; s->moments && i < 6; ++i, ++m) { /* PREFIX or PREFIX.moments.json */
            size_t len = strlen(s->moments), suffix = strlen(".moments.json");
            int stem = (int)(len > suffix && !strcmp(s->moments + len - suffix, ".moments.json") ? len - suffix : len);
            snprintf(names[m], sizeof names[m], "%.*s%s", stem, s->moments, moments_files[i]);
            ins[n].path = names[m], ins[n++].role = side ? "a file of --b-moments" : "a file of --a-moments";
        }
    }
    /* the runs of both sides are distinct files: one file twice is not two independent runs */
    if (inputs_distinct("check", ins, runs)) return 2;
    return outputs_ready("check", outs, 3, ins, n);
}

int cmd_check(int argc, char **argv)
{
    check_args args;
    check_side a, b;
    check_result r;
    rerror e;
    int done, status;
    if ((status = parse_args(argc, argv, &args, &done)) != 0 || done) return status;
    if (check_map_names(&args) || check_collisions(&args)) return 2;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    progress_set_mode((enum progress_mode)args.progress, args.progress_every);
    progress_begin(&load_progress, "check: reading runs", args.quiet);
    runs_total = args.a.runs.count + args.b.runs.count;
    progress_expect(&load_progress, runs_total);
    status = load_side(&a, &args.a, args.opt.block_size, &e) || load_side(&b, &args.b, args.opt.block_size, &e);
    if (!status) progress_update(&load_progress, runs_total, runs_total);
    progress_end(&load_progress);
    if (status ||
        ((a.width != b.width || a.height != b.height) &&
         rerror_at(&e, side_file(&args.b), 0, "image is %d x %d but side A (%s) is %d x %d", b.width, b.height,
                   side_file(&args.a), a.width, a.height)) ||
        scale_side(&a, args.scale_a) ||
        (args.paired ? check_compare_paired(&a, &b, &args.opt, &r, &e) : check_compare(&a, &b, &args.opt, &r, &e))) {
        fprintf(stderr, "%s\n", e.msg);
        check_side_free(&a);
        check_side_free(&b);
        return 2;
    }
    image_warn_upside_down(&a.mean, side_file(&args.a), &b.mean, side_file(&args.b));
    status = r.different || (args.require_equivalence && !r.tost.equivalent) ? 1 : 0;
    if (r.inconclusive) status = 3;
    {
        char msg[1024];
        int side, index;
        for (side = 0; side < 2; ++side)
            for (index = 0; side_warning(msg, sizeof msg, side, index, &args, side ? &b : &a, &r); ++index)
                fprintf(stderr, "restir check: warning: %s\n", msg);
    }
    if (write_outputs(&args, &a, &b, &r, status, &e)) {
        message_unstaged(e.msg);
        fprintf(stderr, "%s\n", e.msg);
        status = 2;
    } else {
        if (!args.quiet) print_summary(&args, &a, &b, &r);
        if (r.inconclusive) {
            char reason[512];
            inconclusive_reason(reason, sizeof reason, &r);
            printf("verdict: inconclusive: %s (the tests alone say %s)\n", reason,
                   r.different ? "different" : "consistent");
        } else {
            printf("verdict: %s%s\n", r.different ? "different" : "consistent",
                   args.require_equivalence && !r.different && !r.tost.equivalent ? " (but not shown equivalent)" : "");
        }
    }
    check_result_free(&r);
    check_side_free(&a);
    check_side_free(&b);
    return status;
}
