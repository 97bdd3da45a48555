/* restir check: statistical verdict on whether two renderers estimate the same image
 * (docs/statistics.md, "check"). Exit status 0 consistent, 1 different (or not shown
 * equivalent with --require-equivalence), 2 usage or input error. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/atomic_file.h"
#include "restir/check.h"
#include "restir/image.h"
#include "restir/json_text.h"
#include "restir/moments.h"
#include "restir/output_set.h"

#define MAX_INPUTS 4096

static const char usage[] =
    "usage: restir check SIDE_A SIDE_B [options]\n"
    "  SIDE_A: --a RUN.pfm...          K >= 2 independent renders of A\n"
    "          --a-moments PREFIX      PREFIX.moments.json (+ .mean.pfm, .var.pfm)\n"
    "  SIDE_B: --b RUN.pfm... | --b-moments PREFIX\n"
    "          --ref REF.pfm           a reference taken as exact, or with\n"
    "            --ref-var VAR.pfm --ref-runs N   its single-run variance over N runs\n"
    "options:\n"
    "  --block N              block size in pixels (default 8; 1 = per pixel)\n"
    "  --alpha A              level of the 'different' verdict (default 0.01)\n"
    "  --correction sidak|bh  block family correction (default sidak)\n"
    "  --margin M             relative equivalence margin for the TOST (default 0.01)\n"
    "  --require-equivalence  also exit 1 unless equivalence within the margin is shown\n"
    "  --paired               run k of A and run k of B share their random numbers (same seeds):\n"
    "                         test the K per-run differences (needs --a and --b with the same K)\n"
    "  --json OUT.json        machine-readable results\n"
    "  --z-map OUT.pfm|.png   per-pixel normal-equivalent z (PFM: per channel; PNG: red A>B, blue A<B)\n"
    "  --block-z-map OUT.pfm|.png   the same per block (one pixel per block)\n"
    "  --quiet                print only the verdict line\n"
    "exit status: 0 consistent, 1 different, 2 usage or input error\n";

typedef struct {
    const char *runs[MAX_INPUTS];
    int run_count;
    const char *moments;
    const char *ref, *ref_var;
    long ref_runs;
} side_args;

typedef struct {
    side_args a, b;
    check_options opt;
    int require_equivalence, quiet, paired;
    const char *json, *z_map, *block_z_map;
} check_args;

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "restir check: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(restir check --help for usage)\n");
    return 2;
}

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(s, &end);
    return end == s || *end || errno == ERANGE || !isfinite(*out) ? -1 : 0;
}

static int parse_long(const char *s, long *out)
{
    char *end;
    errno = 0;
    *out = strtol(s, &end, 10);
    return end == s || *end || errno == ERANGE ? -1 : 0;
}

/* Collects the file names following --a / --b up to the next option. */
static int take_runs(side_args *s, int argc, char **argv, int *i)
{
    while (*i + 1 < argc && strncmp(argv[*i + 1], "--", 2) != 0) {
        if (s->run_count == MAX_INPUTS) return -1;
        s->runs[s->run_count++] = argv[++*i];
    }
    return 0;
}

/* Returns 0, or the exit status to return (2 on a usage error, 0 after --help). */
static int parse_args(int argc, char **argv, check_args *a, int *done)
{
    int i;
    *done = 0;
    memset(a, 0, sizeof *a);
    check_options_default(&a->opt);
    for (i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        int needs_value = strcmp(opt, "--a") && strcmp(opt, "--b") && strcmp(opt, "--require-equivalence") &&
                          strcmp(opt, "--paired") && strcmp(opt, "--quiet") && strcmp(opt, "--help") && strcmp(opt, "-h");
        if (needs_value && !val) return usage_error("%s needs a value", opt);
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            fputs(usage, stdout);
            *done = 1;
            return 0;
        } else if (!strcmp(opt, "--a") || !strcmp(opt, "--b")) {
            side_args *s = opt[2] == 'a' ? &a->a : &a->b;
            if (take_runs(s, argc, argv, &i)) return usage_error("too many files after %s", opt);
            continue;
        } else if (!strcmp(opt, "--a-moments")) {
            a->a.moments = val;
        } else if (!strcmp(opt, "--b-moments")) {
            a->b.moments = val;
        } else if (!strcmp(opt, "--ref")) {
            a->b.ref = val;
        } else if (!strcmp(opt, "--ref-var")) {
            a->b.ref_var = val;
        } else if (!strcmp(opt, "--ref-runs")) {
            if (parse_long(val, &a->b.ref_runs) || a->b.ref_runs < 2)
                return usage_error("--ref-runs must be an integer >= 2, not '%s'", val);
        } else if (!strcmp(opt, "--block")) {
            long b;
            if (parse_long(val, &b) || b < 1 || b > 4096) return usage_error("--block must be 1..4096, not '%s'", val);
            a->opt.block_size = (int)b;
        } else if (!strcmp(opt, "--alpha")) {
            if (parse_double(val, &a->opt.alpha) || !(a->opt.alpha > 0 && a->opt.alpha < 1))
                return usage_error("--alpha must be in (0, 1), not '%s'", val);
        } else if (!strcmp(opt, "--margin")) {
            if (parse_double(val, &a->opt.margin) || !(a->opt.margin > 0 && a->opt.margin < 1))
                return usage_error("--margin must be in (0, 1), not '%s'", val);
        } else if (!strcmp(opt, "--correction")) {
            if (!strcmp(val, "sidak"))
                a->opt.correction = CHECK_SIDAK;
            else if (!strcmp(val, "bh"))
                a->opt.correction = CHECK_BH;
            else
                return usage_error("--correction must be sidak or bh, not '%s'", val);
        } else if (!strcmp(opt, "--require-equivalence")) {
            a->require_equivalence = 1;
            continue;
        } else if (!strcmp(opt, "--quiet")) {
            a->quiet = 1;
            continue;
        } else if (!strcmp(opt, "--paired")) {
            a->paired = 1;
            continue;
        } else if (!strcmp(opt, "--json")) {
            a->json = val;
        } else if (!strcmp(opt, "--z-map")) {
            a->z_map = val;
        } else if (!strcmp(opt, "--block-z-map")) {
            a->block_z_map = val;
        } else {
            return usage_error("unknown option '%s'", opt);
        }
        ++i; /* the value */
    }
    if ((a->a.run_count > 0) + (a->a.moments != NULL) != 1 || a->a.ref)
        return usage_error("%s", "give side A as exactly one of --a RUN... or --a-moments PREFIX");
    if ((a->b.run_count > 0) + (a->b.moments != NULL) + (a->b.ref != NULL) != 1)
        return usage_error("%s", "give side B as exactly one of --b RUN..., --b-moments PREFIX or --ref REF.pfm");
    if ((a->b.ref_var != NULL) != (a->b.ref_runs > 0) || (a->b.ref_var && !a->b.ref))
        return usage_error("%s", "--ref-var and --ref-runs go together, with --ref");
    if (a->paired && (a->a.run_count == 0 || a->b.run_count == 0 || a->a.run_count != a->b.run_count))
        return usage_error("%s", "--paired needs --a RUN... and --b RUN... with the same number of runs");
    return 0;
}

/* ---- loading a side ---- */

static int load_runs(check_side *side, const side_args *s, int block, rerror *e)
{
    int i;
    for (i = 0; i < s->run_count; ++i) {
        image img;
        int status;
        if (pfm_read(s->runs[i], &img, NULL, e)) return -1;
        if (i == 0 && check_side_begin_runs(side, img.width, img.height, block, e)) {
            image_free(&img);
            return -1;
        }
        status = check_side_add_run(side, &img, s->runs[i], e);
        image_free(&img);
        if (status) return -1;
    }
    if (s->run_count < 2)
        return rerror_at(e, s->runs[0], 0, "only one run given: at least 2 independent runs are needed");
    return check_side_end_runs(side, e);
}

static int load_reference(check_side *side, const side_args *s, rerror *e)
{
    image ref;
    moments_file f;
    size_t i, n;
    if (pfm_read(s->ref, &ref, NULL, e)) return -1;
    n = (size_t)ref.width * (size_t)ref.height * 3;
    for (i = 0; i < n; ++i)
        if (!isfinite(ref.px[i])) {
            image_free(&ref);
            return rerror_at(e, s->ref, 0, "pixel (%ld, %ld) is not finite", (long)(i / 3) % ref.width,
                             (long)(i / 3) / ref.width);
        }
    if (!s->ref_var) return check_side_exact(side, &ref, e);
    memset(&f, 0, sizeof f);
    f.mean = ref;
    f.runs = s->ref_runs;
    if (pfm_read(s->ref_var, &f.var, NULL, e)) {
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
    if (s->run_count > 0) return load_runs(side, s, block, e);
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

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && !strcmp(s + n - k, suffix);
}

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

static int write_z_map(const char *path, const image *z, rerror *e)
{
    return has_suffix(path, ".png") || has_suffix(path, ".PNG") ? write_z_png(path, z, e) : pfm_write(path, z, e);
}

static const char *side_kind_name(const check_side *s)
{
    return s->kind == CHECK_SIDE_RUNS ? "images" : s->kind == CHECK_SIDE_MOMENTS ? "moments" : "exact";
}

static const char channel_names[3] = {'r', 'g', 'b'};

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

static int write_json(const char *path, const check_args *args, const check_side *a, const check_side *b,
                      const check_result *r, int status, rerror *e)
{
    atomic_file f;
    FILE *fp;
    if (atomic_file_open(&f, path, e)) return -1;
    fp = f.fp;
    fprintf(fp, "{\n  \"verdict\": \"%s\",\n  \"exit_status\": %d,\n", r->different ? "different" : "consistent",
            status);
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
    fprintf(fp, "  \"pixels\": {\"tests\": %ld, \"p_below_alpha\": %ld, \"expected_if_consistent\": ", r->pixel_tests,
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
    fprintf(fp, ", \"equivalent\": %s}\n}\n", r->tost.equivalent ? "true" : "false");
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
    if (args->z_map && (!(staged = output_set_stage(&out, args->z_map, e)) || write_z_map(staged, &r->pixel_z, e)))
        goto fail;
    if (args->block_z_map &&
        (!(staged = output_set_stage(&out, args->block_z_map, e)) || write_z_map(staged, &r->block_z, e)))
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
    printf("  most extreme: block (%d, %d) channel %c, diff %.4g, t = %.4g, dof = %.4g, p = %.3g, z = %.3g\n",
           r->worst.x, r->worst.y, channel_names[r->worst.channel], r->worst.test.diff, r->worst.test.t,
           r->worst.test.dof, r->worst.test.p, r->worst.z);
    printf("pixels: %ld of %ld uncorrected per-pixel tests have p < %g (about %.0f expected if consistent)\n",
           r->pixels_p_below_alpha, r->pixel_tests, o->alpha, o->alpha * (double)r->pixel_tests);
    if (r->bias_ci_bounded)
        printf("relative bias A/B - 1: %+.4f%% [%g%% CI %+.4f%%, %+.4f%%]\n", 100.0 * r->bias, 100.0 * (1.0 - o->alpha),
               100.0 * r->bias_lo, 100.0 * r->bias_hi);
    else
        printf("relative bias A/B - 1: %+.4f%% (interval unbounded: B's mean is not significantly nonzero)\n",
               100.0 * r->bias);
    printf("equivalence (TOST, margin %g%%, level %g): %s (p = %.3g)\n", 100.0 * r->tost.margin, o->alpha,
           r->tost.equivalent ? "equivalent" : "not shown equivalent", r->tost.p);
}

/* The file that names a side in messages. */
static const char *side_file(const side_args *s)
{
    return s->run_count > 0 ? s->runs[0] : s->moments ? s->moments : s->ref;
}

int cmd_check(int argc, char **argv)
{
    check_args args;
    check_side a, b;
    check_result r;
    rerror e;
    int done, status;
    if ((status = parse_args(argc, argv, &args, &done)) != 0 || done) return status;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    if (load_side(&a, &args.a, args.opt.block_size, &e) || load_side(&b, &args.b, args.opt.block_size, &e) ||
        ((a.width != b.width || a.height != b.height) &&
         rerror_at(&e, side_file(&args.b), 0, "image is %d x %d but side A (%s) is %d x %d", b.width, b.height,
                   side_file(&args.a), a.width, a.height)) ||
        (args.paired ? check_compare_paired(&a, &b, &args.opt, &r, &e) : check_compare(&a, &b, &args.opt, &r, &e))) {
        fprintf(stderr, "%s\n", e.msg);
        check_side_free(&a);
        check_side_free(&b);
        return 2;
    }
    status = r.different || (args.require_equivalence && !r.tost.equivalent) ? 1 : 0;
    if (write_outputs(&args, &a, &b, &r, status, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        status = 2;
    } else {
        if (!args.quiet) print_summary(&args, &a, &b, &r);
        printf("verdict: %s%s\n", r.different ? "different" : "consistent",
               args.require_equivalence && !r.different && !r.tost.equivalent ? " (but not shown equivalent)" : "");
    }
    check_result_free(&r);
    check_side_free(&a);
    check_side_free(&b);
    return status;
}
