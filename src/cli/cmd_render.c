/* restir render SCENE [options]: render a scene with one of the methods and write
 * PFM + PNG preview (+ optional --stats JSON). */
#include <stdio.h>
#include <string.h>
#include "args.h"
#include "output.h"
#include "restir/aov.h"
#include "restir/atomic_file.h"
#include "restir/camera.h"
#include "restir/gbuffer.h"
#include "restir/progress.h"
#include "restir/threads.h"
#include "render_pt.h"
#include "scene_args.h"

enum render_method { METHOD_AOV, METHOD_PT };
static const char *const method_names[] = {"aov", "pt", NULL};
static const char *const aov_choices[] = {"normal", "albedo", "depth", "object", NULL};

typedef struct {
    int method, aov;
    const char *output, *png, *stats;
    int no_png, quiet, jitter, threads, frame;
    uint32_t seed;
    double exposure;
    scene_overrides overrides;
    render_pt_args pt; /* --method pt (render_pt.h) */
} render_args;

typedef struct {
    double load, prepare, render, write;
    pt_result pt; /* counters of a --method pt render */
} render_timings;

static int write_stats(const char *path, const render_args *a, const scene *s, const render_timings *t)
{
    rerror e;
    atomic_file f;
    if (atomic_file_open(&f, path, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    fprintf(f.fp, "{\n  \"command\": \"render\",\n  \"scene\": \"%s\",\n  \"method\": \"%s\",\n", s->path,
            method_names[a->method]);
    fprintf(f.fp, "  \"width\": %d,\n  \"height\": %d,\n  \"threads\": %d,\n  \"seed\": %u,\n  \"frame\": %d,\n",
            s->width, s->height, a->threads, a->seed, a->frame);
    if (a->method == METHOD_AOV) fprintf(f.fp, "  \"aov\": \"%s\",\n", aov_choices[a->aov]);
    if (a->method == METHOD_PT) render_pt_stats_json(f.fp, &a->pt, &t->pt);
    fprintf(f.fp, "  \"triangles\": %zu,\n", s->triangle_count);
    fprintf(f.fp, "  \"seconds\": {\"load\": %.6f, \"bvh\": %.6f, \"render\": %.6f, \"write\": %.6f}\n}\n", t->load,
            t->prepare, t->render, t->write);
    if (atomic_file_commit(&f, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    return 0;
}

static int render_aov_image(const render_args *a, const scene *s, image *img)
{
    rerror e;
    camera cam;
    gbuffer g;
    camera_init(&cam, scene_camera_at(s, a->frame), s->width, s->height);
    if (gbuffer_build(&g, s, &cam, a->seed, (uint32_t)a->frame, a->jitter, a->threads, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    aov_render(&g, s, (enum aov_kind)a->aov, img);
    gbuffer_free(&g);
    return 0;
}

static int render_and_write(const render_args *a, scene *s, render_timings *t)
{
    image img;
    rerror e;
    char out[4096], png[4096];
    int status;
    double t0;
    if (a->output) snprintf(out, sizeof out, "%s", a->output);
    else default_output_path(out, sizeof out, s->path, "");
    t0 = now_seconds();
    if (a->method == METHOD_PT) {
        status = render_pt_image(&a->pt, s, a->seed, a->threads, a->jitter, a->frame, a->quiet, out, &img, &t->pt);
        if (status) return status;
    } else {
        if (image_alloc(&img, s->width, s->height, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            return 2;
        }
        status = render_aov_image(a, s, &img);
    }
    t->render = now_seconds() - t0;
    if (a->no_png) png[0] = '\0';
    else if (a->png) snprintf(png, sizeof png, "%s", a->png);
    else preview_path(png, sizeof png, out);
    t0 = now_seconds();
    if (!status) status = write_outputs(&img, out, png, a->exposure);
    t->write = now_seconds() - t0;
    if (!status && !a->quiet) fprintf(stderr, "wrote %s%s%s\n", out, png[0] ? " and " : "", png);
    image_free(&img);
    return status;
}

int cmd_render(int argc, char **argv)
{
    render_args a;
    render_timings t;
    cli_option options[40];
    const char *positional[1];
    int n = 0, count, status;
    scene s;
    memset(&a, 0, sizeof a);
    memset(&t, 0, sizeof t);
    render_pt_args_default(&a.pt);
    a.threads = threads_default();
    a.seed = 1;
    a.method = METHOD_AOV;
    {
        const cli_option rows[] = {
            {"-o", OPT_STRING, &a.output, "output PFM (default out/<scene>.pfm)", NULL, 0, 0, NULL},
            {"--png", OPT_STRING, &a.png, "PNG preview path (default: the PFM path with .png)", NULL, 0, 0, NULL},
            {"--no-png", OPT_FLAG, &a.no_png, "do not write the PNG preview", NULL, 0, 0, NULL},
            {"--exposure", OPT_REAL, &a.exposure, "preview exposure in stops (default 0)", NULL, -64, 64, NULL},
            {"--method", OPT_CHOICE, &a.method, "rendering method", method_names, 0, 0, NULL},
            {"--aov", OPT_CHOICE, &a.aov, "G-buffer channel for --method aov", aov_choices, 0, 0, NULL},
            {"--seed", OPT_UINT32, &a.seed, "run seed of the addressed RNG (default 1)", NULL, 0, 0, NULL},
            {"--threads", OPT_INT, &a.threads, "worker threads (default: online cores; 1 = no threads)", NULL, 1, 256,
             NULL},
            {"--frame", OPT_INT, &a.frame, "frame index (camera keyframes)", NULL, 0, 1e9, NULL},
            {"--jitter", OPT_FLAG, &a.jitter, "jittered sub-pixel primary rays (default: pixel centres)", NULL, 0, 0,
             NULL},
            {"--stats", OPT_STRING, &a.stats, "write timings and counters as JSON", NULL, 0, 0, NULL},
            {"--quiet", OPT_FLAG, &a.quiet, "no progress or messages on stderr", NULL, 0, 0, NULL},
        };
        for (n = 0; n < (int)(sizeof rows / sizeof rows[0]); ++n) options[n] = rows[n];
    }
    n += scene_override_options(options + n, &a.overrides);
    n += render_pt_options(options + n, &a.pt);
    memset(&options[n], 0, sizeof options[n]);
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
    a.overrides.quiet = a.quiet;
    status = load_scene_for_command("render", positional[0], &a.overrides, &s, &t.load, &t.prepare);
    if (status) return status;
    status = render_and_write(&a, &s, &t);
    if (!status && a.stats) status = write_stats(a.stats, &a, &s, &t);
    scene_free(&s);
    return status;
}
