/* restir render SCENE [options]: render a scene with one of the methods and write
 * PFM + PNG preview (+ optional --stats JSON). This file reads as the command runs: parse
 * (the option table, render_table.c), validate (render_rules.c, and the techniques'
 * options, render_restir.c), run (one image, --runs in render_runs.c, or --sequence), write
 * (images here, --stats in render_stats.c). */
#include "cmd_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image_io.h"
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/offline.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"
#include "restir/oracle/stage_dump.h"
#include "restir/oracle/stage_dump_undo.h"
#include "restir/render/aov.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/render/motion.h"
#include "restir/restir/duplication.h"
#include "restir/scene/animation.h"
#include "args.h"
#include "collide.h"
#include "output.h"
#include "output_undo.h"
#include "render_args.h"
#include "render_rules.h"
#include "render_runs.h"
#include "render_sequence_runs.h"
#include "render_stats.h"
#include "render_table.h"
#include "stop.h"

static int render_aov_image(const render_args *a, const scene *s, image *img)
{
    rerror e;
    camera cam;
    gbuffer g;
    camera_init(&cam, scene_camera_at(s, a->frame), s->width, s->height);
    if (a->aov == AOV_MOTION ? gbuffer_build_with_motion(&g, s, a->frame, a->seed, a->jitter, a->threads, &e)
                             : gbuffer_build(&g, s, &cam, a->seed, (uint32_t)a->frame, a->jitter, a->threads, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    aov_render(&g, s, (enum aov_kind)a->aov, img);
    gbuffer_free(&g);
    return 0;
}

/* --aov duplicates without --sequence: the counts of the last frame's final reservoirs. */
static int duplicates_of(const restir_result *r, image *img)
{
    rerror e;
    size_t i, n = (size_t)r->mean.width * (size_t)r->mean.height;
    uint16_t *count = malloc(n * sizeof *count);
    if (!count || image_alloc(img, r->mean.width, r->mean.height, &e)) {
        fprintf(stderr, "out of memory\n");
        free(count);
        return 2;
    }
    duplication_counts(r->reservoirs, r->mean.width, r->mean.height, DUPLICATION_RADIUS, 1, count);
    for (i = 0; i < 3 * n; ++i) img->px[i] = (float)count[i / 3];
    free(count);
    return 0;
}

/* Guards that changed a ReSTIR estimate are never silent, even with --quiet (the path
 * tracer's NaN policy; docs/precision.md). */
static void restir_guard_warning(const restir_stats *st)
{
    uint64_t w = restir_stats_invalid_weights(st);
    if (w)
        fprintf(stderr, "restir: warning: %llu resampling weights were NaN, Inf or negative and were skipped "
                        "(--stats \"guards\")\n", (unsigned long long)w);
    if (st->nonfinite_pixels)
        fprintf(stderr, "restir: warning: %llu pixel estimates are NaN or Inf (kept in the image)\n",
                (unsigned long long)st->nonfinite_pixels);
}

/* ReSTIR PT (docs/restir-pt.md): with the run's seed. */
static int render_restir_image(const render_args *a, const scene *s, uint32_t seed, image *img, render_timings *t)
{
    restir_options o = a->restir;
    restir_result r;
    rerror e;
    o.seed = seed;
    o.keep_reservoirs |= o.output_aov == RESTIR_OUTPUT_DUPLICATES;
    if (restir_render(s, &o, &r, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (o.output_aov == RESTIR_OUTPUT_DUPLICATES) {
        if (duplicates_of(&r, img)) {
            restir_result_free(&r);
            return 2;
        }
    } else {
        *img = r.mean;
        r.mean.px = NULL;
    }
    t->restir = r.stats;
    t->restir_seconds = r.seconds;
    restir_guard_warning(&r.stats);
    restir_result_free(&r);
    return 0;
}

/* One image with the chosen method and seed. `progressive_pfm` is where the path
 * tracer rewrites its progressive output (NULL: nowhere). */
static int render_one(const render_args *a, const scene *s, uint32_t seed, const char *progressive_pfm, image *img,
                      render_timings *t)
{
    rerror e;
    if (a->method == METHOD_PT) {
        render_pt_args pt = a->pt;
        pt.o.seed = seed;
        return render_pt_image(&pt, s, progressive_pfm, img, &t->pt);
    }
    if (a->method == METHOD_RESTIR) return render_restir_image(a, s, seed, img, t);
    if (image_alloc(img, s->width, s->height, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    return render_aov_image(a, s, img);
}

/* --sequence: one image (+ PNG) per frame, PREFIX.0000.pfm ... (.exr when -o names an
 * .exr), each written atomically. */
typedef struct {
    const render_args *a;
    render_timings *t;
    char prefix[4096];
    const char *ext;
} sequence_sink;

static int write_image(const render_args *a, const image *img, const char *out, const char *png);

static int write_frame(void *user, int frame, const image *img, const restir_stats *st, rerror *e)
{
    sequence_sink *k = user;
    char pfm[4200], png[4200];
    restir_stats *grown = realloc(k->t->frame_stats, (size_t)(k->t->frame_count + 1) * sizeof *grown);
    int *numbers = grown ? realloc(k->t->frame_numbers, (size_t)(k->t->frame_count + 1) * sizeof *numbers) : NULL;
    if (grown) k->t->frame_stats = grown;
    if (!grown || !numbers) return rerror_set(e, "out of memory");
    k->t->frame_numbers = numbers;
    numbers[k->t->frame_count] = frame;
    grown[k->t->frame_count++] = *st;
    snprintf(pfm, sizeof pfm, "%s.%04d.%s", k->prefix, frame, k->ext);
    snprintf(png, sizeof png, "%s.%04d.png", k->prefix, frame);
    if (write_image(k->a, img, pfm, k->a->no_png ? "" : png)) {
        k->t->frame_count--; /* not written (nothing of it is left): not one to remove either */
        return rerror_set(e, "%s: not written", pfm);
    }
    return 0;
}

static int render_sequence(const render_args *a, const scene *s, const char *out, render_timings *t)
{
    sequence_sink k;
    rerror e;
    double t0 = now_seconds();
    k.a = a;
    k.t = t;
    output_prefix(k.prefix, sizeof k.prefix, out);
    k.ext = image_output_ext(out);
    if (restir_render_sequence(s, &a->restir, &a->seq, write_frame, &k, &t->restir, &e)) {
        /* Exit 2 leaves nothing: the frames and dump files this call wrote are removed (the
         * checkpoint of --resume FILE --checkpoint FILE stays: it was this call's input). */
        int frames = remove_sequence_frames(k.prefix, k.ext, t->frame_numbers, t->frame_count, !a->no_png);
        int dumped = stage_io_remove_written(&a->sio);
        if (a->seq.checkpoint && t->frame_count > 0 && !(a->seq.resume && !strcmp(a->seq.resume, a->seq.checkpoint)))
            remove(a->seq.checkpoint);
        fprintf(stderr, "%s\n", e.msg);
        if (frames || dumped)
            fprintf(stderr, "restir render: removed what this call wrote before the error: %d frame(s), %d dump file(s)\n",
                    frames, dumped);
        return 2;
    }
    t->restir_seconds = t->render = now_seconds() - t0;
    restir_guard_warning(&t->restir);
    if (!a->quiet && t->frame_count > 0)
        fprintf(stderr, "wrote frames %s.%04d.%s .. %s.%04d.%s\n", k.prefix, t->frame_numbers[0], k.ext, k.prefix,
                t->frame_numbers[t->frame_count - 1], k.ext);
    return 0;
}

/* The PFM and its PNG preview (aov depth: normalised by aov_preview; a duplicate-count
 * image: its heat map, output.h). */
static int write_image(const render_args *a, const image *img, const char *out, const char *png)
{
    image preview;
    rerror e;
    int status;
    if (a->method == METHOD_RESTIR && a->restir.output_aov == RESTIR_OUTPUT_DUPLICATES)
        return write_duplicates_outputs(img, out, png);
    if (a->method != METHOD_AOV || !png[0]) return write_outputs(img, out, png, a->exposure);
    if (aov_preview(img, (enum aov_kind)a->aov, &preview, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    status = write_outputs_preview(img, &preview, out, png, a->exposure);
    image_free(&preview);
    return status;
}

static int render_and_write(const render_args *a, scene *s, const char *out, const char *png, render_timings *t)
{
    image img;
    int status;
    double t0;
    if (a->sequence && a->runs > 0) return render_sequence_runs(a, s, out, t); /* per-frame moments */
    if (a->sequence) return render_sequence(a, s, out, t);
    t0 = now_seconds();
    if (a->runs > 0) {
        status = render_runs(a, s, out, &img, t, render_one);
        if (status) return status;
        t->render = now_seconds() - t0;
        if (png[0]) status = write_outputs(&img, NULL, png, a->exposure);
        if (!status && !a->quiet && !stop_signal())
        {
            char prefix[4096];
            output_prefix(prefix, sizeof prefix, out);
            const char *ext = image_output_ext(out);
            fprintf(stderr, "wrote %d runs as %s.mean.%s, %s.var.%s, %s.moments.json, %s.blocks.bin%s%s\n", a->runs,
                    prefix, ext, prefix, ext, prefix, prefix, png[0] ? " and " : "", png);
        }
        image_free(&img);
        return status;
    }
    status = render_one(a, s, a->seed, out, &img, t);
    if (status) return status;
    if (!stop_signal() && pt_time_limit_empty(a, t)) {
        image_free(&img);
        return 2;
    }
    if (stop_signal() && (a->method == METHOD_RESTIR ? t->restir.frames == 0 : a->method == METHOD_PT && t->pt.state.spp == 0)) {
        /* stopped at a tile boundary before anything was complete: no image to write */
        fprintf(stderr, "restir render: interrupted by %s before the first %s was complete: nothing written\n",
                stop_signal_name(), a->method == METHOD_RESTIR ? "frame" : "pass");
        image_free(&img);
        return 128 + stop_signal();
    }
    t->render = now_seconds() - t0;
    t0 = now_seconds();
    status = write_image(a, &img, out, png);
    t->write = now_seconds() - t0;
    if (!status && !a->quiet) fprintf(stderr, "wrote %s%s%s\n", out, png[0] ? " and " : "", png);
    image_free(&img);
    return status;
}

/* SIGINT / SIGTERM: what was kept, on stderr even with --quiet; exit 128 + signal. */
static int interrupted_status(const render_args *a, const render_timings *t, const char *out)
{
    int sig = stop_signal();
    char prefix[4096];
    if (!sig) return 0;
    output_prefix(prefix, sizeof prefix, out);
    if (a->sequence)
        fprintf(stderr, "restir render: interrupted by %s after %d frame(s); frames written so far are kept%s%s\n",
                stop_signal_name(), t->frame_count, a->seq.checkpoint ? ", checkpoint " : "",
                a->seq.checkpoint ? a->seq.checkpoint : "");
    else if (a->runs > 0)
        fprintf(stderr, "restir render: interrupted by %s: %s.mean.%s, .var.%s, .moments.json hold the runs finished so far (a run cut short is dropped)\n",
                stop_signal_name(), prefix, image_output_ext(out), image_output_ext(out));
    else if (a->method == METHOD_AOV) /* not stoppable: the signal came while it was written */
        fprintf(stderr, "restir render: %s arrived during the render: %s is complete\n", stop_signal_name(), out);
    else if (a->method == METHOD_PT)
        fprintf(stderr, "restir render: interrupted by %s: %s holds %u spp%s%s (resume with --resume)\n",
                stop_signal_name(), out, t->pt.state.spp, a->pt.o.checkpoint_path ? ", checkpoint " : "",
                a->pt.o.checkpoint_path ? a->pt.o.checkpoint_path : "");
    else
        fprintf(stderr, "restir render: interrupted by %s: %s holds the mean of %llu frame(s)\n", stop_signal_name(),
                out, (unsigned long long)t->restir.frames);
    return 128 + sig;
}

int cmd_render(int argc, char **argv)
{
    render_args a;
    render_timings t;
    cli_option options[RENDER_TABLE_ROWS];
    int given[RENDER_TABLE_ROWS];
    method_rows rows[3];
    const char *positional[1];
    char out[4096], png[4096];
    int count, status;
    scene s;
    rerror e;
    fill_aov_choices();
    memset(&a, 0, sizeof a);
    memset(&t, 0, sizeof t);
    render_pt_args_default(&a.pt);
    restir_options_default(&a.restir);
    a.threads = threads_default();
    a.seed = 1;
    a.method = METHOD_PT;
    render_table_build(options, &a, rows);
    cli_track_given(options, given);
    status = cli_parse("render", argc, argv, options, positional, 1, &count);
    if (status == 1) {
        cli_print_help(stdout, "render", "SCENE(.scene|.obj) [options]", options);
        return 0;
    }
    if (status) return status;
    if (count != 1) {
        fprintf(stderr, "restir render: expected one SCENE argument (see restir render --help)\n");
        return 2;
    }
    render_restir_apply(options, given, a.preset, &a.restir_flags, &a.restir);
    if (a.aov >= AOV_CHOICE_DUPLICATES) rows[2].method = METHOD_RESTIR; /* restir's two --aov images */
    status = check_method_options(&a, options, given, rows, 3);
    if (status) return status;
    a.overrides.quiet = a.quiet;
    progress_set_mode((enum progress_mode)a.progress, a.progress_every);
    apply_common_options(&a);
    status = apply_shared_options(&a, options, given);
    if (status) return status;
    if (a.method == METHOD_RESTIR && (status = render_restir_validate("render", &a.restir)) != 0) return status;
    a.sio.scene_path = positional[0];
    a.sio.argc = argc;
    a.sio.argv = argv;
    if (a.output) snprintf(out, sizeof out, "%s", a.output);
    else default_output_path(out, sizeof out, positional[0], "");
    if (a.no_png || a.sequence) png[0] = '\0';
    else if (a.png) snprintf(png, sizeof png, "%s", a.png);
    else preview_path(png, sizeof png, out);
    status = check_output_paths(&a, out, png);
    if (status) return status;
    status = load_scene_for_command("render", positional[0], &a.overrides, &s, &t.load, &t.prepare);
    if (status) return status;
    if (scene_is_animated(&s) && scene_pose_at(&s, a.frame, &e)) { /* objects at --frame (animation.h) */
        fprintf(stderr, "%s\n", e.msg);
        scene_free(&s);
        return 2;
    }
    if (a.method != METHOD_AOV && scene_emitter_count(&s) == 0 && !s.sky) {
        /* Every lighting method would return a black image: say so instead. */
        fprintf(stderr, "%s: scene has no emitters (no material with Ke > 0); --method aov renders it unlit\n",
                s.path);
        scene_free(&s);
        return 2;
    }
    stop_signals_install();
    status = render_and_write(&a, &s, out, png, &t);
    stop_signals_restore();
    if (!status && a.stats && (status = write_stats(a.stats, &a, &s, &t)) != 0 && !a.sequence && a.runs == 0) {
        remove(out); /* exit 2 leaves nothing: not the images of this call either */
        if (png[0]) remove(png);
    }
    if (!status) status = interrupted_status(&a, &t, out);
    free(t.frame_stats);
    free(t.frame_numbers);
    scene_free(&s);
    return status;
}

