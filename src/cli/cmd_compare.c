/* restir compare TEST.pfm REF.pfm: every metric of metrics.h and flip.h, a table on
 * stdout, optionally JSON and a false-colour error map (docs/metrics.md). */
#include "cmd_compare.h"
#include "cmd_bias.h"
#include "cmd_covariance.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/image.h"
#include "restir/core/image_io.h"
#include "restir/core/json_text.h"
#include "restir/core/pfm.h"
#include "restir/core/png.h"
#include "restir/core/upside_down.h"
#include "restir/metrics/error_map.h"
#include "restir/metrics/flip.h"
#include "restir/metrics/metrics.h"
#include "args.h"
#include "outputs_ready.h"

/* What the option table cannot say (printed after it by --help). */
static const char help_notes[] =
    "\nCompares TEST against the reference REF (same size, finite values) and prints\n"
    "mse, rmse, relmse, mape, smape, marb, rel_bias, flip_ldr and flip_hdr (formulas:\n"
    "docs/metrics.md). `restir compare --covariance RUN.pfm...` and `restir compare --bias\n"
    "RUN.pfm... --ref REF.pfm` are different measurements (restir compare --covariance --help,\n"
    "restir compare --bias --help).\n"
    "exit status: 0 done, 2 bad usage or bad input.\n";

typedef struct {
    const char *test_path, *ref_path, *json_path, *map_path;
    int metric;
    int has_crop;
    image_rect crop;
    flip_params flip;
} compare_options;

typedef struct {
    image_metrics m;
    double flip_start, flip_stop;
    int flip_count;
    float *flip_ldr_map, *flip_hdr_map; /* crop-sized */
} compare_results;

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "restir compare: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(restir compare --help for usage)\n");
    return 2;
}

/* Strict "x,y,w,h": four integers, nothing else. */
static int parse_crop(const char *s, image_rect *r)
{
    long v[4];
    char *end;
    int i;
    for (i = 0; i < 4; ++i) {
        errno = 0;
        v[i] = strtol(s, &end, 10);
        if (end == s || errno || v[i] < -1000000000L || v[i] > 1000000000L) return -1;
        if (i < 3 && *end != ',') return -1;
        s = end + 1;
    }
    if (*end != '\0') return -1;
    r->x = (int)v[0];
    r->y = (int)v[1];
    r->w = (int)v[2];
    r->h = (int)v[3];
    return 0;
}

/* Returns 0 to proceed, 1 after --help, 2 on a usage error (already reported). */
static int parse_args(int argc, char **argv, compare_options *o)
{
    const char *positional[2], *metric = NULL, *crop = NULL;
    int count, status;
    memset(o, 0, sizeof *o);
    o->metric = METRIC_FLIP_HDR;
    flip_default_params(&o->flip);
    {
        const cli_option options[] = {
            {"--json", OPT_STRING, &o->json_path, "also write all values as JSON OUT.json (atomically)", NULL, 0, 0, NULL},
            {"--metric", OPT_STRING, &metric, "metric of the error map (default flip_hdr; \"flip\" = flip_hdr)", NULL, 0, 0, NULL},
            {"--error-map", OPT_STRING, &o->map_path, "false-colour map OUT.png of that metric with a colour bar (FLIP: magma, fixed scale 0..1; others: viridis from the map's min to max)", NULL, 0, 0, NULL},
            {"--crop", OPT_STRING, &crop, "x,y,w,h: evaluate only this rectangle (FLIP sees only the crop)", NULL, 0, 0, NULL},
            {"--ppd", OPT_REAL, &o->flip.ppd, "FLIP pixels per degree, > 0 (default 67.02: 0.7 m from a 0.7 m wide 4K monitor)", NULL, 0, 0, NULL},
            {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
        };
        status = cli_parse("compare", argc, argv, options, positional, 2, &count);
        if (status == 1) {
            cli_print_help(stdout, "compare", "TEST.pfm REF.pfm [options]", options);
            fputs(help_notes, stdout);
            return 1;
        }
        if (status) return 2;
    }
    if (count < 2) return usage_error("%s", "needs TEST.pfm and REF.pfm");
    o->test_path = positional[0];
    o->ref_path = positional[1];
    if (metric && (o->metric = metric_from_name(metric)) < 0) return usage_error("unknown metric '%s'", metric);
    if (metric && !o->map_path) /* it chooses the map only: alone it was ignored (every metric is printed) */
        return usage_error("--metric %s chooses the --error-map's metric; without --error-map every metric is printed",
                           metric);
    if (crop) {
        if (parse_crop(crop, &o->crop)) return usage_error("--crop '%s' is not x,y,w,h", crop);
        o->has_crop = 1;
    }
    if (!(o->flip.ppd > 0)) return usage_error("%s", "--ppd: expected a positive number");
    if (o->map_path && o->metric == METRIC_REL_BIAS)
        return usage_error("%s", "rel_bias is one number per image: it has no error map");
    {
        /* before any work: writable, not each other, not an input (outputs_ready.h) */
        const named_file outs[] = {{o->json_path, "--json"}, {o->map_path, "--error-map"}};
        const named_file ins[] = {{o->test_path, "TEST"}, {o->ref_path, "REF"}};
        return outputs_ready("compare", outs, 2, ins, 2);
    }
}

/* Copies the rectangle r of src into a new image. */
static int crop_image(const image *src, const image_rect *r, image *out, rerror *e)
{
    int y;
    if (image_alloc(out, r->w, r->h, e)) return -1;
    for (y = 0; y < r->h; ++y)
        memcpy(image_pixel(out, 0, y), image_pixel(src, r->x, r->y + y), sizeof(float) * 3 * (size_t)r->w);
    return 0;
}

static int compute_all(const compare_options *o, const image *test, const image *ref, compare_results *res,
                       rerror *e)
{
    image ct, cr;
    size_t n = (size_t)o->crop.w * o->crop.h;
    int status = -1;
    if (metrics_compute(test, ref, &o->crop, &res->m, e)) return -1;
    if (crop_image(test, &o->crop, &ct, e)) return -1;
    if (crop_image(ref, &o->crop, &cr, e)) {
        image_free(&ct);
        return -1;
    }
    res->flip_ldr_map = rmalloc(n, sizeof(float), e);
    res->flip_hdr_map = res->flip_ldr_map ? rmalloc(n, sizeof(float), e) : NULL;
    if (res->flip_hdr_map &&
        !flip_ldr(&ct, &cr, &o->flip, res->flip_ldr_map, &res->m.value[METRIC_FLIP_LDR], e) &&
        !flip_hdr(&ct, &cr, &o->flip, res->flip_hdr_map, &res->m.value[METRIC_FLIP_HDR], &res->flip_start,
                  &res->flip_stop, &res->flip_count, e))
        status = 0;
    image_free(&ct);
    image_free(&cr);
    return status;
}

static void print_table(const compare_options *o, const image *ref, const compare_results *res)
{
    int i;
    printf("test      %s\nreference %s\n", o->test_path, o->ref_path);
    printf("size      %d x %d, crop %d,%d,%d,%d (%ld pixels), eps = %.6g\n", ref->width, ref->height, o->crop.x,
           o->crop.y, o->crop.w, o->crop.h, res->m.pixels, res->m.eps);
    printf("FLIP      %.4g ppd, HDR exposures %.4f .. %.4f in %d steps\n", o->flip.ppd, res->flip_start,
           res->flip_stop, res->flip_count);
    printf("%-10s %s\n", "metric", "value");
    for (i = 0; i < METRIC_COUNT; ++i)
        printf("%-10s %.9g%s\n", metric_name(i), res->m.value[i], i == o->metric && o->map_path ? "   (error map)" : "");
}

/* ---- JSON ---- */

static int write_json(const compare_options *o, const image *ref, const compare_results *res, rerror *e)
{
    atomic_file af;
    FILE *f;
    int i;
    if (atomic_file_open(&af, o->json_path, e)) return -1;
    f = af.fp;
    fputs("{\n  \"test\": ", f);
    json_put_string(f, o->test_path);
    fputs(",\n  \"reference\": ", f);
    json_put_string(f, o->ref_path);
    fprintf(f, ",\n  \"width\": %d,\n  \"height\": %d,\n", ref->width, ref->height);
    fprintf(f, "  \"crop\": [%d, %d, %d, %d],\n  \"pixels\": %ld,\n  \"eps\": ", o->crop.x, o->crop.y, o->crop.w,
            o->crop.h, res->m.pixels);
    json_put_number(f, res->m.eps);
    fputs(",\n  \"metrics\": {\n", f);
    for (i = 0; i < METRIC_COUNT; ++i) {
        fprintf(f, "    \"%s\": ", metric_name(i));
        json_put_number(f, res->m.value[i]);
        fputs(i + 1 < METRIC_COUNT ? ",\n" : "\n", f);
    }
    fprintf(f, "  },\n  \"flip\": {\"ppd\": %.17g, \"start_exposure\": ", o->flip.ppd);
    json_put_number(f, res->flip_start);
    fputs(", \"stop_exposure\": ", f);
    json_put_number(f, res->flip_stop);
    fprintf(f, ", \"exposures\": %d}\n}\n", res->flip_count);
    return atomic_file_commit(&af, e);
}

/* ---- error map ---- */

static int write_error_map(const compare_options *o, const image *test, const image *ref, const compare_results *res,
                           rerror *e)
{
    size_t n = (size_t)o->crop.w * o->crop.h, i;
    float *map = NULL;
    const float *values;
    double lo = 0, hi = 1;
    error_palette palette = PALETTE_MAGMA;
    rgb8_image img;
    int status;
    if (o->metric == METRIC_FLIP_LDR || o->metric == METRIC_FLIP_HDR) {
        values = o->metric == METRIC_FLIP_LDR ? res->flip_ldr_map : res->flip_hdr_map;
    } else {
        if (!(map = rmalloc(n, sizeof(float), e))) return -1;
        if (metrics_error_map(o->metric, test, ref, &o->crop, map, e)) {
            free(map);
            return -1;
        }
        values = map;
        palette = PALETTE_VIRIDIS;
        lo = HUGE_VAL;
        hi = -HUGE_VAL;
        for (i = 0; i < n; ++i) {
            if (values[i] < lo) lo = values[i];
            if (values[i] > hi) hi = values[i];
        }
    }
    status = error_map_render(values, o->crop.w, o->crop.h, lo, hi, palette, &img, e);
    free(map);
    if (status) return -1;
    status = png_write_rgb8(o->map_path, img.width, img.height, img.rgb, e);
    rgb8_image_free(&img);
    return status;
}

static int fail(const rerror *e)
{
    fprintf(stderr, "%s\n", e->msg);
    return 2;
}

/* `compare --covariance FILES...` (Mutations Eq. 21 over K images) and `compare --bias
 * RUNS... --ref REF` (issue 12) are different measurements with their own options: the
 * whole command line goes to them. */
static int has_flag(int argc, char **argv, const char *flag)
{
    int i;
    for (i = 1; i < argc; ++i)
        if (!strcmp(argv[i], flag)) return 1;
    return 0;
}

int cmd_compare(int argc, char **argv)
{
    compare_options o;
    compare_results res;
    image test, ref;
    rerror e;
    int status = 2, parsed;
    if (has_flag(argc, argv, "--covariance")) return cmd_compare_covariance(argc, argv);
    if (has_flag(argc, argv, "--bias")) return cmd_compare_bias(argc, argv);
    parsed = parse_args(argc, argv, &o);
    if (parsed) return parsed == 1 ? 0 : 2;
    memset(&res, 0, sizeof res);
    if (image_read(o.ref_path, &ref, NULL, &e)) return fail(&e);
    if (image_read(o.test_path, &test, NULL, &e)) {
        image_free(&ref);
        return fail(&e);
    }
    if (!o.has_crop) o.crop = image_full_rect(&ref);
    if (metrics_check_inputs(&test, o.test_path, &ref, o.ref_path, &o.crop, &e) ||
        compute_all(&o, &test, &ref, &res, &e)) {
        fail(&e);
    } else if (o.map_path && write_error_map(&o, &test, &ref, &res, &e)) {
        fail(&e);
    } else if (o.json_path && write_json(&o, &ref, &res, &e)) {
        if (o.map_path) remove(o.map_path); /* both outputs or neither */
        fail(&e);
    } else {
        print_table(&o, &ref, &res);
        image_warn_upside_down(&test, o.test_path, &ref, o.ref_path);
        status = 0;
    }
    free(res.flip_ldr_map);
    free(res.flip_hdr_map);
    image_free(&test);
    image_free(&ref);
    return status;
}
