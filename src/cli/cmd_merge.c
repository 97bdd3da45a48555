/* restir merge -o OUT.pfm INPUT... : combine independent path-tracer runs.
 * Inputs are either checkpoints (--checkpoint files of runs over adjacent sample ranges of
 * one seed: their double sums are added, the result equals one run over the union up to
 * rounding) or mean images with --counts (the sample-count-weighted mean). */
#include "cmd_merge.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/image_io.h"
#include "restir/core/pfm.h"
#include "restir/core/progress.h"
#include "restir/render/pt.h"
#include "restir/render/pt_checkpoint.h"
#include "restir/render/pt_state.h"
#include "args.h"
#include "collide.h"
#include "outputs_ready.h"
#include "output.h"

#define MERGE_MAX_INPUTS 4096

typedef struct {
    const char *output, *png, *counts, *checkpoint_out;
    int no_png, quiet;
    double exposure;
    int progress;          /* --progress (enum progress_mode) */
    double progress_every; /* --progress-every */
} merge_args;

static int is_checkpoint(const char *path)
{
    char magic[8];
    FILE *f = fopen(path, "rb");
    size_t n;
    if (!f) return 0;
    n = fread(magic, 1, sizeof magic, f);
    fclose(f);
    return n == sizeof magic && !memcmp(magic, "RESTIRPT", 8);
}

/* "512,512,1024" -> counts[]; returns the number parsed or -1. */
static int parse_counts(const char *text, double *counts, int max)
{
    int n = 0;
    const char *p = text;
    while (*p && n < max) {
        char *end;
        double v = strtod(p, &end);
        if (end == p || !(v >= 0) || !isfinite(v)) return -1;
        counts[n++] = v;
        if (*end == ',') end++;
        else if (*end) return -1;
        p = end;
    }
    return *p ? -1 : n;
}

static int cmp_offset(const void *a, const void *b)
{
    const pt_state *x = a, *y = b;
    return x->sample_offset < y->sample_offset ? -1 : x->sample_offset > y->sample_offset;
}

/* Reading the inputs is what takes long (many 1080p checkpoints): progress counts them. */
static progress read_progress;

static int merge_checkpoints(const merge_args *a, const char **inputs, int n, image *out)
{
    pt_state *st = calloc((size_t)n, sizeof *st);
    rerror e;
    int i, status = 0;
    if (!st) return 2;
    for (i = 0; i < n && !status; ++i) {
        progress_update(&read_progress, i, n);
        if (pt_checkpoint_read(inputs[i], &st[i], &e)) status = 2;
    }
    if (!status) {
        qsort(st, (size_t)n, sizeof *st, cmp_offset);
        for (i = 1; i < n && !status; ++i)
            if (pt_state_merge(&st[0], &st[i], &e)) status = 2;
    }
    if (!status && pt_state_mean(&st[0], out, &e)) status = 2;
    if (!status && a->checkpoint_out && pt_checkpoint_write(a->checkpoint_out, &st[0], &e)) {
        image_free(out); /* the caller frees the image only on success */
        status = 2;
    }
    if (status) fprintf(stderr, "%s\n", e.msg);
    else if (!a->quiet)
        fprintf(stderr, "merged %d checkpoints: %u spp (samples %u..%llu)%s\n", n, st[0].spp, st[0].sample_offset,
                (unsigned long long)st[0].sample_offset + st[0].spp - 1, st[0].nonfinite ? ", with NaN/Inf samples" : "");
    for (i = 0; i < n; ++i) pt_state_free(&st[i]);
    free(st);
    return status;
}

/* A mean image with a NaN or Inf pixel has no sample-count-weighted mean: refused. */
static int image_check_finite(const char *path, const image *img, rerror *e)
{
    size_t i, n = 3 * (size_t)img->width * (size_t)img->height;
    for (i = 0; i < n; ++i)
        if (!isfinite(img->px[i])) {
            size_t p = i / 3;
            return rerror_set(e, "%s: pixel (%zu, %zu) channel %c is %s; a mean image must be finite", path,
                              p % (size_t)img->width, p / (size_t)img->width, "RGB"[i % 3],
                              isnan(img->px[i]) ? "NaN" : "Inf");
        }
    return 0;
}

static int merge_images(const merge_args *a, const char **inputs, int n, image *out)
{
    image *imgs = calloc((size_t)n, sizeof *imgs);
    double *counts = calloc((size_t)n, sizeof *counts);
    rerror e;
    int i, loaded = 0, status = 0;
    if (!imgs || !counts) status = 2;
    if (!status && (!a->counts || parse_counts(a->counts, counts, n) != n)) {
        if (a->counts)
            fprintf(stderr, "restir merge: --counts %s: expected %d finite sample counts >= 0, one per input (e.g. "
                            "--counts 512,512)\n", a->counts, n);
        else
            fprintf(stderr, "restir merge: images need --counts with one sample count per input (e.g. --counts 512,512)\n");
        status = 2;
    }
    for (i = 0; i < n && !status; ++i, ++loaded)
        if ((progress_update(&read_progress, i, n), image_read(inputs[i], &imgs[i], NULL, &e)) || image_check_finite(inputs[i], &imgs[i], &e)) {
            fprintf(stderr, "%s\n", e.msg);
            status = 2;
        }
    if (!status && pt_merge_means(imgs, counts, n, out, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        status = 2;
    }
    for (i = 0; i < loaded; ++i) image_free(&imgs[i]);
    free(imgs);
    free(counts);
    return status;
}

/* Before reading anything: every output writable, none overwriting another or an input
 * (`merge -o a.ckpt a.ckpt b.ckpt` would replace an input by a PFM), no input twice. */
static int check_merge_outputs(const merge_args *a, const char **inputs, int count)
{
    named_file outs[3], *ins = calloc((size_t)count + 1, sizeof *ins);
    char png[4096], label[MERGE_MAX_INPUTS][24];
    rerror e;
    int i, status = 0;
    if (!ins) return 2;
    if (a->no_png) png[0] = '\0';
    else if (a->png) snprintf(png, sizeof png, "%s", a->png);
    else preview_path(png, sizeof png, a->output);
    outs[0].path = a->output, outs[0].role = "-o";
    outs[1].path = png, outs[1].role = "the PNG preview";
    outs[2].path = a->checkpoint_out, outs[2].role = "--checkpoint-out";
    if (image_output_check(a->output, &e)) { /* .exr or PFM; .png is the preview, .jpg ... not written */
        fprintf(stderr, "restir merge: %s\n", e.msg);
        status = 2;
    }
    for (i = 0; i < count; ++i) {
        snprintf(label[i], sizeof label[i], "input %d", i + 1);
        ins[i].path = inputs[i], ins[i].role = label[i];
    }
    /* one run twice would count its samples twice (checkpoints would say "not adjacent") */
    if (!status) status = inputs_distinct("merge", ins, count);
    if (!status) status = outputs_ready("merge", outs, 3, ins, count);
    free(ins);
    return status;
}

int cmd_merge(int argc, char **argv)
{
    merge_args a;
    const char **inputs = calloc(MERGE_MAX_INPUTS, sizeof *inputs);
    image out;
    char png[4096];
    int count = 0, status, checkpoints = 0, i;
    file_before ckpt_before;
    memset(&a, 0, sizeof a);
    if (!inputs) return 2;
    {
        const cli_option options[] = {
            {"-o", OPT_STRING, &a.output, "output image, PFM or .exr (required)", NULL, 0, 0, NULL},
            {"--counts", OPT_STRING, &a.counts, "sample counts of image inputs, comma-separated (N,N,...)", NULL, 0, 0, NULL},
            {"--checkpoint-out", OPT_STRING, &a.checkpoint_out, "also write the merged checkpoint (checkpoint inputs)", NULL, 0, 0, NULL},
            {"--png", OPT_STRING, &a.png, "PNG preview path (default: the PFM path with .png)", NULL, 0, 0, NULL},
            {"--no-png", OPT_FLAG, &a.no_png, "do not write the PNG preview", NULL, 0, 0, NULL},
            {"--exposure", OPT_REAL, &a.exposure, "preview exposure in stops (default 0)", NULL, -64, 64, NULL},
            {"--quiet", OPT_FLAG, &a.quiet, "no messages on stderr", NULL, 0, 0, NULL},
            CLI_PROGRESS_ROWS(&a.progress, &a.progress_every),
            {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
        };
        status = cli_parse("merge", argc, argv, options, inputs, MERGE_MAX_INPUTS, &count);
        if (status == 1) {
            cli_print_help(stdout, "merge", "-o OUT.pfm RUN.ckpt... | -o OUT.pfm IMG.pfm... --counts N,N,...", options);
            free(inputs);
            return 0;
        }
    }
    if (!status && (count < 1 || !a.output)) {
        fprintf(stderr, "restir merge: expected -o OUT.pfm and at least one input (see restir merge --help)\n");
        status = 2;
    }
    if (!status) status = check_merge_outputs(&a, inputs, count);
    for (i = 0; i < count; ++i) checkpoints += is_checkpoint(inputs[i]);
    for (i = 0; i < count && !status; ++i) {
        struct stat st;
        if (stat(inputs[i], &st) == 0 && S_ISREG(st.st_mode) && st.st_size == 0) {
            fprintf(stderr, "restir merge: %s: empty file (neither a checkpoint nor an image)\n", inputs[i]);
            status = 2;
        }
    }
    if (!status && checkpoints != 0 && checkpoints != count) {
        fprintf(stderr, "restir merge: inputs must be all checkpoints or all images\n");
        status = 2;
    }
    /* each was ignored (exit 0): a checkpoint knows its sample count, an image has no state */
    if (!status && checkpoints && a.counts) {
        fprintf(stderr, "restir merge: --counts is for image inputs; a checkpoint holds its own sample count\n");
        status = 2;
    }
    if (!status && !checkpoints && a.checkpoint_out) {
        fprintf(stderr, "restir merge: --checkpoint-out needs checkpoint inputs (images hold no path-tracer state)\n");
        status = 2;
    }
    if (a.checkpoint_out) file_before_note(&ckpt_before, a.checkpoint_out);
    progress_set_mode((enum progress_mode)a.progress, a.progress_every);
    progress_begin(&read_progress, "merge: reading inputs", a.quiet);
    progress_expect(&read_progress, count);
    if (!status) status = checkpoints ? merge_checkpoints(&a, inputs, count, &out) : merge_images(&a, inputs, count, &out);
    if (!status) progress_update(&read_progress, count, count);
    progress_end(&read_progress);
    if (!status) {
        if (a.no_png) png[0] = '\0';
        else if (a.png) snprintf(png, sizeof png, "%s", a.png);
        else preview_path(png, sizeof png, a.output);
        status = write_outputs(&out, a.output, png, a.exposure);
        image_free(&out);
        /* exit 2 leaves nothing: not the merged checkpoint written before the image failed */
        if (status && a.checkpoint_out && file_remove_if_written(&ckpt_before, a.checkpoint_out))
            fprintf(stderr, "restir merge: %s: removed (the merged image could not be written)\n", a.checkpoint_out);
    }
    free(inputs);
    return status;
}
