/* `restir render --sequence A..B --runs K` (render_sequence_runs.h): per-frame statistical
 * verdicts for sequences (issue 31; docs/oracle.md §8). */
#include "render_sequence_runs.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/image_io.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"
#include "restir/metrics/moments.h"
#include "output.h"
#include "stop.h"

typedef struct {
    moments *m; /* one per frame first..last */
    int first;
    uint32_t seed;
    int failed;
} runs_sink;

static int add_frame(void *user, int frame, const image *img, const restir_stats *st, rerror *e)
{
    runs_sink *k = user;
    char name[64];
    (void)st;
    snprintf(name, sizeof name, "seed %u", k->seed);
    if (moments_add(&k->m[frame - k->first], img, name, e)) return -1;
    return 0;
}

static void write_config(FILE *fp, const void *ctx, const char *indent)
{
    const render_args *a = ctx;
    restir_options_write_json(fp, &a->restir, indent);
}

/* The dump of run k: DIR/run_KK (a fresh stage_io with the command's configuration). */
static void run_dump(const render_args *a, int k, stage_io *io, frame_stage_hook *hook, char *dir, size_t size)
{
    *io = a->sio;
    io->order[0][0] = '\0';
    io->n_order = io->frames_done = io->restarted = io->failed = io->created_dir = 0;
    io->rc_missing = io->rc_nonempty = 0;
    snprintf(dir, size, "%s/run_%02d", a->sio.dump_dir, k);
    io->dump_dir = dir;
    stage_io_hook(io, hook);
    hook->pixel = a->hook.pixel;
    hook->trace_pixel = a->hook.trace_pixel;
}

int render_sequence_runs(const render_args *a, const scene *s, const char *out, render_timings *t)
{
    int frames = a->seq.last - a->seq.first + 1, f, k, status = 0;
    runs_sink sink;
    moments_meta meta;
    char prefix[4096], fprefix[4200], dump[4300];
    rerror e;
    e.msg[0] = '\0';
    output_prefix(prefix, sizeof prefix, out);
    sink.m = calloc((size_t)frames, sizeof *sink.m);
    sink.first = a->seq.first;
    if (!sink.m) {
        fprintf(stderr, "restir render: out of memory\n");
        return 2;
    }
    for (f = 0; f < frames && !status; ++f)
        if (moments_init(&sink.m[f], s->width, s->height, &e) ||
            moments_set_block_sizes(&sink.m[f], moments_default_block_sizes, 4, &e))
            status = 2;
    if (!status && a->sio.dump_dir && mkdir(a->sio.dump_dir, 0777) != 0 && errno != EEXIST) {
        snprintf(e.msg, sizeof e.msg, "%s: cannot create the directory", a->sio.dump_dir);
        status = 2;
    }
    for (k = 0; k < a->runs && !status && !stop_signal(); ++k) {
        restir_options o = a->restir;
        restir_sequence q = a->seq;
        restir_stats total;
        stage_io io;
        frame_stage_hook hook;
        memset(&total, 0, sizeof total);
        o.seed = a->seed + (uint32_t)k; /* run k: every random number's address has its seed */
        sink.seed = o.seed;
        if (a->sio.dump_dir) {
            run_dump(a, k, &io, &hook, dump, sizeof dump);
            q.stages = &hook;
        }
        if (restir_render_sequence(s, &o, &q, add_frame, &sink, &total, &e)) status = 2;
        else restir_stats_add(&t->restir, &total);
    }
    if (!status && stop_signal()) {
        fprintf(stderr, "restir render: interrupted by %s: no per-frame moments written\n", stop_signal_name());
        status = 128 + stop_signal();
    }
    meta.method = "restir";
    meta.write_config = write_config;
    meta.ctx = a;
    meta.image_ext = image_output_ext(out);
    meta.correlation = a->restir.spatial_passes > 0 ? MOMENTS_CORRELATED : MOMENTS_INDEPENDENT;
    for (f = 0; f < frames && status == 0; ++f) {
        snprintf(fprefix, sizeof fprefix, "%s.%04d", prefix, a->seq.first + f);
        if (moments_write_meta(fprefix, &sink.m[f], &meta, &e)) status = 2;
    }
    if (status == 2 && e.msg[0]) fprintf(stderr, "%s\n", e.msg);
    if (!status && !a->quiet)
        fprintf(stderr, "wrote %d runs per frame as %s.%04d.mean.%s .. %s.%04d.mean.%s (+ .var.%s, .moments.json, "
                        ".blocks.bin)\n", a->runs, prefix, a->seq.first, meta.image_ext, prefix, a->seq.last,
                meta.image_ext, meta.image_ext);
    for (f = 0; f < frames; ++f) moments_free(&sink.m[f]);
    free(sink.m);
    return status;
}
