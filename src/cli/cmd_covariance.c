/* restir compare --covariance RUN.pfm... : the average box covariance between pixels
 * of K independent renders (Mutations Eq. 21; docs/statistics.md, "covariance").
 * `restir compare` hands its whole argument list here when --covariance is present. */
#include "cmd_covariance.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/image.h"
#include "restir/core/image_io.h"
#include "restir/core/json_text.h"
#include "restir/core/progress.h"
#include "restir/metrics/covariance.h"
#include "restir/metrics/output_set.h"
#include "args.h"
#include "outputs_ready.h"

/* What the option table cannot say (printed after it by --help). */
static const char help_notes[] =
    "\nK >= 2 independent renders of the same image (Mutations Eq. 21: covariance of each\n"
    "pixel with the pixels of the box of radius R around it, averaged over the box, then\n"
    "over the image; on luminance).\n";

typedef struct {
    const char **files;
    int file_count;
    int radius, exclude_center, covariance;
    const char *curve, *map, *json;
    int progress;          /* --progress (enum progress_mode) */
    double progress_every; /* --progress-every */
} covariance_args;

static int usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "restir compare --covariance: %s%s\n(restir compare --covariance --help for usage)\n", what, arg);
    return 2;
}

/* Before reading any image: the runs are distinct files (one file twice is not two
 * independent renders) and the outputs are writable, distinct and not a run. */
static int check_files(const covariance_args *a)
{
    named_file outs[3], *ins = calloc((size_t)a->file_count, sizeof *ins);
    int i, status;
    if (!ins) return usage_error("out of memory", "");
    for (i = 0; i < a->file_count; ++i) ins[i].path = a->files[i], ins[i].role = "a run";
    outs[0].path = a->curve, outs[0].role = "--curve";
    outs[1].path = a->map, outs[1].role = "--map";
    outs[2].path = a->json, outs[2].role = "--json";
    status = inputs_distinct("compare --covariance", ins, a->file_count);
    if (!status) status = outputs_ready("compare --covariance", outs, 3, ins, a->file_count);
    free(ins);
    return status;
}

static int parse_args(int argc, char **argv, covariance_args *a, int *done)
{
    int status;
    *done = 0;
    memset(a, 0, sizeof *a);
    a->radius = 8;
    a->files = calloc((size_t)argc, sizeof *a->files);
    if (!a->files) return usage_error("out of memory", "");
    {
        const cli_option options[] = {
            {"--covariance", OPT_FLAG, &a->covariance, "this measurement (instead of compare's metrics)", NULL, 0, 0, NULL},
            {"--radius", OPT_INT, &a->radius, "box radius R (default 8, as in Mutations Table 1)", NULL, 0, 4096, NULL},
            {"--exclude-center", OPT_FLAG, &a->exclude_center, "leave the pixel itself (its variance) out of each box", NULL, 0, 0, NULL},
            {"--curve", OPT_STRING, &a->curve, "OUT.csv: the value for every radius 0..R (CSV radius,covariance; plot with restir plot)", NULL, 0, 0, NULL},
            {"--map", OPT_STRING, &a->map, "OUT.pfm or OUT.exr: per-pixel box covariance at radius R", NULL, 0, 0, NULL},
            {"--json", OPT_STRING, &a->json, "OUT.json: machine-readable result", NULL, 0, 0, NULL},
            CLI_PROGRESS_ROWS(&a->progress, &a->progress_every),
            {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
        };
        status = cli_parse("compare --covariance", argc, argv, options, a->files, argc, &a->file_count);
        if (status == 1) {
            cli_print_help(stdout, "compare --covariance", "RUN.pfm... [options]", options);
            fputs(help_notes, stdout);
            *done = 1;
            return 0;
        }
        if (status) return status;
    }
    if (a->file_count < 2) return usage_error("needs at least 2 images (independent renders)", "");
    if (a->exclude_center && a->radius < 1) return usage_error("--exclude-center needs --radius >= 1", "");
    if (a->map) { /* the format follows the name (.exr or PFM): refused before any work */
        rerror e;
        if (image_output_check(a->map, &e)) return usage_error("--map ", e.msg);
    }
    return check_files(a);
}

/* Each image is read and its box products added (K images of 1080p at radius 8: seconds
 * each): progress counts the images. */
static int accumulate(const covariance_args *a, covariance_accum *c, rerror *e)
{
    progress p;
    int i;
    progress_set_mode((enum progress_mode)a->progress, a->progress_every);
    progress_begin(&p, "compare --covariance", 0);
    progress_expect(&p, a->file_count);
    for (i = 0; i < a->file_count; ++i) {
        image img;
        int status;
        progress_update(&p, i, a->file_count);
        if (image_read(a->files[i], &img, NULL, e)) {
            progress_end(&p);
            return -1;
        }
        if (i == 0 && covariance_init(c, img.width, img.height, a->radius, a->exclude_center, e)) {
            image_free(&img);
            progress_end(&p);
            return -1;
        }
        status = covariance_add(c, &img, a->files[i], e);
        image_free(&img);
        if (status) {
            progress_end(&p);
            return -1;
        }
    }
    progress_update(&p, a->file_count, a->file_count);
    progress_end(&p);
    return 0;
}

static int write_curve(const char *path, const double *v, int radius, int exclude, rerror *e)
{
    atomic_file f;
    int r;
    if (atomic_file_open(&f, path, e)) return -1;
    fprintf(f.fp, "radius,covariance\n");
    for (r = exclude ? 1 : 0; r <= radius; ++r) fprintf(f.fp, "%d,%.9g\n", r, v[r]);
    return atomic_file_commit(&f, e);
}

static int write_json(const char *path, const covariance_args *a, const covariance_accum *c, const double *v,
                      rerror *e)
{
    atomic_file f;
    int r;
    if (atomic_file_open(&f, path, e)) return -1;
    fprintf(f.fp, "{\n  \"metric\": \"covariance\",\n  \"reference\": \"Mutations Eq. 21, box average then image average\",\n");
    fprintf(f.fp, "  \"channel\": \"luminance\",\n  \"images\": %ld,\n  \"width\": %d,\n  \"height\": %d,\n", c->images,
            c->width, c->height);
    fprintf(f.fp, "  \"radius\": %d,\n  \"exclude_center\": %s,\n  \"covariance\": ", a->radius,
            a->exclude_center ? "true" : "false");
    json_put_number(f.fp, v[a->radius]);
    fprintf(f.fp, ",\n  \"per_radius\": [");
    for (r = 0; r <= a->radius; ++r) {
        if (r) fputs(", ", f.fp);
        json_put_number(f.fp, v[r]);
    }
    fprintf(f.fp, "]\n}\n");
    return atomic_file_commit(&f, e);
}

static int write_outputs(const covariance_args *a, const covariance_accum *c, const double *v, const image *map,
                         rerror *e)
{
    output_set out;
    const char *staged;
    output_set_init(&out);
    if (a->curve && (!(staged = output_set_stage(&out, a->curve, e)) ||
                     write_curve(staged, v, a->radius, a->exclude_center, e)))
        goto fail;
    if (a->map && (!(staged = output_set_stage(&out, a->map, e)) || image_write_as(staged, a->map, map, e))) goto fail;
    if (a->json && (!(staged = output_set_stage(&out, a->json, e)) || write_json(staged, a, c, v, e))) goto fail;
    return output_set_commit(&out, e);
fail:
    output_set_abort(&out);
    return -1;
}

int cmd_compare_covariance(int argc, char **argv)
{
    covariance_args args;
    covariance_accum c;
    image map;
    double *v = NULL;
    rerror e;
    int done, status = 0;
    memset(&c, 0, sizeof c);
    memset(&map, 0, sizeof map);
    if ((status = parse_args(argc, argv, &args, &done)) != 0 || done) {
        free(args.files);
        return status;
    }
    v = calloc((size_t)args.radius + 1, sizeof *v);
    if (!v) {
        rerror_set(&e, "out of memory");
        status = 2;
    } else if (accumulate(&args, &c, &e) || covariance_result(&c, v, args.map ? &map : NULL, &e) ||
               write_outputs(&args, &c, v, &map, &e)) {
        status = 2;
    }
    if (status) {
        message_unstaged(e.msg);
        fprintf(stderr, "%s\n", e.msg);
    }
    else
        printf("covariance (Mutations Eq. 21, luminance, %s centre): %ld images, %d x %d, radius %d: %.6g\n",
               args.exclude_center ? "without" : "with", c.images, c.width, c.height, args.radius, v[args.radius]);
    free(v);
    free(args.files);
    image_free(&map);
    covariance_free(&c);
    return status;
}
