/* restir bench rays|restir|animation|realtime|stochastic|mutations|scaling|all: machine-readable benchmarks (JSON on
 * stdout). Timings are never asserted in tests; compare ratios measured in one run. */
#include "cmd_bench.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/bench/bench_rays.h"
#include "restir/bench/light_bench.h"
#include "restir/bench/pairing_sigma.h"
#include "restir/bench/pt_bench.h"
#include "restir/bench/restir_bench.h"
#include "restir/bench/scaling_bench.h"
#include "restir/bench/stochastic_bench.h"
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"
#include "restir/render/light_ris.h"
#include "restir/render/pt.h"
#include "restir/scene/animation.h"
#include "restir/scene/generate.h"
#include "restir/scene/generate_rooms.h"
#include "args.h"
#include "scene_args.h"
#include "stop.h"

#define SHARED_BUNNY "../shared/data/common-3d-test-models/stanford-bunny.obj"

typedef struct {
    bench_rays_options rays;
    int generated;   /* subdivision level of the displaced sphere, 0 = none */
    int rays_size[2];
    int has_rays_size;
    int pairing, no_pair_step, rc_criterion, shading; /* bench restir: Enhanced switches */
    int has_repeats;
    int light_ris, light_tiles;                       /* bench restir: light RIS (Enhanced 6.1) */
    int textures;                                     /* bench pairing-sigma: textures per pass count */
    int progress;                                     /* --progress (enum progress_mode) */
    double progress_every;                            /* --progress-every */
} bench_args;

/* Progress of a bench run: the total of `bench all` is not known before it runs (the
 * animated scenes are found on the way), so there is no bar and no ETA: a line as a
 * benchmark starts, with the time so far (every step on a terminal, in a log at most
 * one per --progress-every seconds).
 *
 * SIGINT / SIGTERM (stop.h) stop it within about a second: the stop flag is also the
 * thread pool's abort flag (threads_set_abort), so every parallel loop of the running step
 * (tiles, frames, timed repeats) hands out no more work and the step runs out quickly; its
 * timings are then wrong, so each step writes its JSON to a temporary file (bench_out) that
 * reaches stdout only when the step is complete. An interrupted or failed run ends the JSON
 * array with an entry {"bench": "incomplete", ...} after the complete steps' entries (never
 * a closed array that looks complete) and exits 128 + the signal (or 2). */
static progress bench_progress;
static int bench_steps, bench_committed; /* steps started; 1 once an entry reached stdout */
static FILE *bench_out;                   /* the running step's JSON */
static char bench_what[600];              /* the running step, for the interruption message */

/* Appends the finished step's JSON to stdout (0), or -1 if it cannot. */
static int step_commit(void)
{
    static char buf[65536];
    size_t n;
    int failed;
    if (!bench_out) return 0;
    rewind(bench_out);
    while ((n = fread(buf, 1, sizeof buf, bench_out)) > 0) {
        fwrite(buf, 1, n, stdout);
        bench_committed = 1;
    }
    failed = ferror(bench_out) || fflush(stdout) != 0;
    fclose(bench_out);
    bench_out = NULL;
    return failed ? -1 : 0;
}

static void step_discard(void)
{
    if (bench_out) fclose(bench_out);
    bench_out = NULL;
}

/* A step's error message; none once a stop signal came (the step was cut short on
 * purpose: what failed then is a consequence, bench_finish says what happened). */
static void step_error(const rerror *e)
{
    if (!stop_signal()) fprintf(stderr, "%s\n", e->msg);
}

/* A new step's temporary JSON file. */
static int step_open(void)
{
    if ((bench_out = tmpfile()) != NULL) return 0;
    fprintf(stderr, "restir bench: cannot create a temporary file for a benchmark's output\n");
    return -1;
}

/* 0 to run the next benchmark (after its progress line), 128 + the stop signal, or 2. The
 * step before this one is complete (its caller went on): its JSON goes to stdout. */
static int bench_step(const char *what, const char *name)
{
    if (stop_signal()) return 128 + stop_signal();
    if (step_commit() || step_open()) return 2;
    ++bench_steps;
    snprintf(bench_what, sizeof bench_what, "%s on %s", what, name);
    if (progress_line_due(&bench_progress))
        fprintf(stderr, "bench: step %d: %s on %s, %.1f s elapsed\n", bench_steps, what, name,
                now_seconds() - bench_progress.start_seconds);
    return 0;
}

/* A benchmark over one prepared scene; `name` labels it in the JSON. */
typedef int (*scene_bench)(const scene *s, const char *name, const bench_args *a, int *first);

/* Separates the JSON objects of the output array. */
static void next_object(int *first)
{
    if (!*first) fprintf(bench_out, ",\n");
    *first = 0;
}

static int bench_rays_on(const scene *s, const char *name, const bench_args *a, int *first)
{
    rerror e;
    (void)name;
    next_object(first);
    if (bench_rays(s, &a->rays, bench_out, &e)) {
        step_error(&e);
        return 2;
    }
    return 0;
}

/* Path-tracing samples/s and rays/s, 1 thread and all threads. */
static int bench_pt_on(const scene *s, const char *name, const bench_args *a, int *first)
{
    rerror e;
    int t, counts[2];
    counts[0] = 1;
    counts[1] = a->rays.threads > 0 ? a->rays.threads : threads_default();
    for (t = 0; t < 2; ++t) {
        if (t == 1 && counts[1] == 1) break;
        next_object(first);
        if (bench_pt(bench_out, s, name, 4, counts[t], &e)) {
            step_error(&e);
            return 2;
        }
    }
    return 0;
}

/* The generator's progress steps (generate.h): none shown, but a stop signal ends the
 * building of a large sphere (1M triangles: about a second) at the next grid row. */
static int generate_stops(void *ctx, const char *phase, long done, long total)
{
    (void)ctx, (void)phase, (void)done, (void)total;
    return stop_signal();
}

static int generate_sphere(scene *s, int subdivisions, rerror *e)
{
    const generate_progress p = {generate_stops, NULL};
    return generate_displaced_sphere_progress(s, subdivisions, &p, e);
}

/* Runs fn on the generated displaced sphere with 12 n^2 triangles. */
static int on_generated(int subdivisions, scene_bench fn, const bench_args *a, int *first)
{
    scene s;
    rerror e;
    int status;
    memset(&s, 0, sizeof s);
    if ((status = bench_step(fn == bench_rays_on ? "rays" : "benchmark", "generated:displaced_sphere")) != 0) return status;
    /* the BVH build is the one part of a step no stop interrupts (1M triangles: about 1 s) */
    if (generate_sphere(&s, subdivisions, &e) || stop_signal() || scene_prepare(&s, &e)) {
        step_error(&e);
        scene_free(&s);
        return 2;
    }
    status = fn(&s, "generated:displaced_sphere", a, first);
    scene_free(&s);
    return status;
}

/* Runs fn on a scene file or OBJ. */
static int on_file(const char *path, scene_bench fn, const bench_args *a, int *first)
{
    scene s;
    scene_overrides none;
    int status;
    memset(&none, 0, sizeof none);
    if ((status = bench_step(fn == bench_rays_on ? "rays" : "benchmark", path)) != 0) return status;
    status = load_scene_for_command("bench", path, &none, &s, NULL, NULL);
    if (status) return status;
    status = fn(&s, path, a, first);
    scene_free(&s);
    return status;
}

/* ReSTIR PT at 64 x 64: one frame of the GRIS offline preset per (shift, MIS family), then
 * an equal-time comparison with the path tracer at 32 x 32 (3 seconds each). The image size
 * is changed on a shallow copy of the scene (the geometry is shared, not copied). */
static int bench_restir_on(const scene *s, const char *name, const bench_args *a, int *first)
{
    scene sized = *s;
    restir_options o;
    rerror e;
    int status;
    restir_options_default(&o);
    restir_options_preset_gris_offline(&o);
    o.threads = a->rays.threads > 0 ? a->rays.threads : threads_default();
    o.spatial.pairing = a->pairing;
    o.no_pair_step = a->no_pair_step;
    o.rc_criterion = a->rc_criterion;
    o.shading = a->shading;
    o.light_ris.candidates = a->light_ris;
    o.light_ris.tiles = a->light_tiles;
    sized.width = sized.height = 64;
    status = bench_restir(bench_out, &sized, name, &o, first, &e);
    if (!status && a->light_ris > 0) {
        next_object(first);
        status = bench_light_selection(bench_out, s, name, a->light_ris, a->light_tiles, &e);
    }
    if (!status) {
        sized.width = sized.height = 32;
        status = bench_restir_equal_time(bench_out, &sized, name, &o, 4096, 3, first, &e);
    }
    if (status) step_error(&e);
    return status ? 2 : 0;
}

/* Object animation cost (issue 10): scene_pose_at per frame over the scene's keyframe range
 * (vertices posed from the rest pose, bounds, BVH rebuilt from scratch), the median and the
 * mean ms per frame, and how much of it is the BVH build alone (scene_prepare). */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int bench_animation_on(const scene *src, const char *name, const bench_args *a, int *first)
{
    scene s;
    rerror e;
    double ms[64], build[64], sum = 0;
    /* 17 frames, or 3 for the 1M-triangle case (2 s per frame). */
    int f0 = 0, f1 = 0, n = 0, f, step, frames = src->triangle_count > 200000 ? 3 : 17;
    (void)a;
    if (scene_clone(&s, src, &e)) {
        step_error(&e);
        return 2;
    }
    if (scene_frame_range(&s, &f0, &f1)) f0 = f1 = 0;
    step = (f1 - f0) / (frames - 1) > 0 ? (f1 - f0) / (frames - 1) : 1;
    for (f = f0; f <= f1 && n < frames; f += step) {
        double t0 = now_seconds(), t1;
        if (threads_cancelled()) { /* stopped (SIGINT): the step is discarded, end it now */
            scene_free(&s);
            return 0;
        }
        if (scene_pose_at(&s, f, &e)) break;
        t1 = now_seconds();
        if (threads_cancelled() || scene_prepare(&s, &e)) break;
        ms[n] = 1e3 * (t1 - t0);
        build[n] = 1e3 * (now_seconds() - t1);
        sum += ms[n++];
    }
    if (f <= f1 && n < frames) {
        step_error(&e);
        scene_free(&s);
        return 2;
    }
    next_object(first);
    fprintf(bench_out, "{\"bench\": \"animation\", \"scene\": \"%s\", \"triangles\": %zu, \"animated_objects\": %zu, "
           "\"frames\": %d, \"pose_ms_mean\": %.3f, ",
           name, s.triangle_count, scene_animated_object_count(&s), n, n ? sum / n : 0.0);
    qsort(ms, (size_t)n, sizeof *ms, cmp_double);
    qsort(build, (size_t)n, sizeof *build, cmp_double);
    fprintf(bench_out, "\"pose_ms_median\": %.3f, \"bvh_build_ms_median\": %.3f}", n ? ms[n / 2] : 0.0, n ? build[n / 2] : 0.0);
    scene_free(&s);
    return 0;
}

/* The displaced sphere with 12 n^2 triangles (n = 289: 1M) turning once about y over
 * frames 0..16 while the light stays. */
static int bench_animation_generated(int subdivisions, const bench_args *a, int *first)
{
    scene s;
    rerror e;
    object_keyframe k[2];
    int status;
    memset(&s, 0, sizeof s);
    memset(k, 0, sizeof k);
    k[0].axis = k[1].axis = v3(0, 1, 0);
    k[1].frame = 16;
    k[1].angle_degrees = 180;
    k[1].translate = v3((real)0.2, 0, 0);
    if ((status = bench_step("animation", "generated:displaced_sphere(animated)")) != 0) return status;
    if (generate_sphere(&s, subdivisions, &e) || scene_add_object_animation(&s, 0, v3(0, 0, 0), k, 2, &e) ||
        stop_signal() || scene_prepare(&s, &e)) {
        step_error(&e);
        scene_free(&s);
        return 2;
    }
    status = bench_animation_on(&s, "generated:displaced_sphere(animated)", a, first);
    scene_free(&s);
    return status;
}

/* `bench animation`: the shipped animated scenes, then the 1M-triangle case. */
static int bench_animation_all(const bench_args *a, int *first)
{
    static const char *const files[] = {"scenes/pillars.scene", "scenes/shadow.scene", "scenes/ajar-swing.scene",
                                        "scenes/ajar-swing-still.scene"};
    size_t i;
    int status = 0;
    for (i = 0; !status && i < sizeof files / sizeof *files; ++i) status = on_file(files[i], bench_animation_on, a, first);
    if (!status) status = bench_animation_generated(a->generated ? a->generated : 289, a, first);
    return status;
}

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f) fclose(f);
    return f != NULL;
}

/* The real-time pipeline at 256 x 256 with the gris-realtime preset over the scene's frame
 * range (at most 16 frames; frames 0..7 of a scene without keyframes). */
static int bench_realtime_on(const scene *s, const char *name, const bench_args *a, int *first)
{
    scene sized = *s;
    restir_options o;
    rerror e;
    int f0 = 0, f1 = 7, status;
    restir_options_default(&o);
    restir_options_preset_gris_realtime(&o);
    o.threads = a->rays.threads > 0 ? a->rays.threads : threads_default();
    sized.width = sized.height = 256;
    if (scene_frame_range(s, &f0, &f1) == 0 && f1 > f0 + 15) f1 = f0 + 15;
    status = bench_realtime(bench_out, &sized, name, &o, f0, f1, first, &e);
    if (status) step_error(&e);
    return status ? 2 : 0;
}

/* Thread scaling (scaling_bench.h): the real-time preset, 4 frames at --size (default
 * 512 x 512), 1 vs --threads (default 2) threads, --repeats rounds (default 3). */
/* Enhanced Eq. 3's readings measured (docs/enhanced.md §2): 254 x 254 textures, seed 1. */
static int bench_pairing_sigma_run(const bench_args *a, int *first)
{
    rerror e;
    int status = bench_step("pairing-sigma", "reuse textures");
    if (status) return status;
    status = bench_pairing_sigma(bench_out, a->textures > 0 ? a->textures : 16, 254, 1, first, &e);
    if (status) step_error(&e);
    return status ? 2 : 0;
}

static int bench_scaling_on(const scene *s, const char *name, const bench_args *a, int *first)
{
    scene sized = *s;
    restir_options o;
    rerror e;
    int status;
    restir_options_default(&o);
    restir_options_preset_gris_realtime(&o);
    sized.width = a->has_rays_size ? a->rays_size[0] : 512;
    sized.height = a->has_rays_size ? a->rays_size[1] : 512;
    status = bench_scaling(bench_out, &sized, name, &o, 4, a->rays.threads > 1 ? a->rays.threads : 2,
                           a->has_repeats ? a->rays.repeats : 3, first, &e);
    if (status) step_error(&e);
    return status ? 2 : 0;
}

/* Stochastic pairwise MIS and reuse cells at 256 x 256 (stochastic_bench.h). */
static int bench_stochastic_on(const scene *s, const char *name, const bench_args *a, int *first)
{
    scene sized = *s;
    rerror e;
    int status;
    sized.width = sized.height = 256;
    status = bench_stochastic(bench_out, &sized, name, a->rays.threads > 0 ? a->rays.threads : threads_default(), first, &e);
    if (status) step_error(&e);
    return status ? 2 : 0;
}

/* MCMC mutations at 256 x 256, gris-realtime preset, frames 0..3, 1 mutation per pixel. */
static int bench_mutations_on(const scene *s, const char *name, const bench_args *a, int *first)
{
    scene sized = *s;
    restir_options o;
    rerror e;
    int status;
    restir_options_default(&o);
    restir_options_preset_gris_realtime(&o);
    o.threads = a->rays.threads > 0 ? a->rays.threads : threads_default();
    o.mutation.count = 1;
    sized.width = sized.height = 256;
    status = bench_mutations(bench_out, &sized, name, &o, 0, 3, first, &e);
    if (status) step_error(&e);
    return status ? 2 : 0;
}

/* The scenes of issue 13: cornell, cornell-glossy, glass, ajar. */
static int bench_mutations_all(const bench_args *a, int *first)
{
    static const char *const files[] = {"scenes/cornell.scene", "scenes/cornell-glossy.scene", "scenes/glass.scene",
                                        "scenes/ajar.scene"};
    size_t i;
    int status = 0;
    for (i = 0; i < sizeof files / sizeof files[0] && !status; ++i) status = on_file(files[i], bench_mutations_on, a, first);
    return status;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* 1 if the scene file has animated objects or camera keyframes. */
static int is_animated_file(const char *path)
{
    scene s;
    rerror e;
    int f0, f1, animated;
    if (scene_load(&s, path, &e)) return 0;
    animated = scene_frame_range(&s, &f0, &f1) == 0;
    scene_free(&s);
    return animated;
}

/* Every animated scenes/NAME.scene (object or camera keyframes), in name order; the
 * still Cornell box if there is none. */
static int bench_realtime_animated(const bench_args *a, int *first)
{
    char *names[256], path[1024];
    int n = 0, i, status = 0, any = 0;
    DIR *d = opendir("scenes");
    struct dirent *ent;
    while (d && (ent = readdir(d)) != NULL && n < 256) {
        size_t len = strlen(ent->d_name);
        if (len > 6 && !strcmp(ent->d_name + len - 6, ".scene") && (names[n] = malloc(len + 1)) != NULL)
            memcpy(names[n++], ent->d_name, len + 1);
    }
    if (d) closedir(d);
    qsort(names, (size_t)n, sizeof names[0], compare_names);
    for (i = 0; i < n; ++i) {
        snprintf(path, sizeof path, "scenes/%s", names[i]);
        if (!status && is_animated_file(path)) {
            any = 1;
            status = on_file(path, bench_realtime_on, a, first);
        }
        free(names[i]);
    }
    if (!any && !status) status = on_file("scenes/cornell.scene", bench_realtime_on, a, first);
    return status;
}

/* `bench all`: rays on the shipped Cornell box, the >= 100k-triangle generated sphere and
 * the Stanford bunny when ../shared/data is present (the Embree yardstick's scene); then
 * path-tracing throughput on the Cornell box and the generated sphere; then ReSTIR PT. */
static int bench_all(const bench_args *a, int *first)
{
    int status = on_file("scenes/cornell.scene", bench_rays_on, a, first);
    if (!status) status = on_generated(92, bench_rays_on, a, first);
    if (!status && file_exists(SHARED_BUNNY)) status = on_file(SHARED_BUNNY, bench_rays_on, a, first);
    if (!status) status = on_file("scenes/cornell.scene", bench_pt_on, a, first);
    if (!status) status = on_generated(92, bench_pt_on, a, first);
    if (!status) status = on_file("scenes/cornell.scene", bench_restir_on, a, first);
    if (!status) status = bench_animation_all(a, first);
    if (!status) status = bench_realtime_animated(a, first);
    if (!status) status = bench_mutations_all(a, first);
    return status;
}

/* Closes the JSON array. A run that did not complete ends it with an "incomplete" entry
 * (why, and how many steps before the one cut short are on stdout) and says on stderr, in
 * one line, what was interrupted. */
static void bench_finish(int status)
{
    int kept = bench_steps > 0 ? bench_steps - 1 : 0;
    if (status == 0) {
        printf("\n]\n");
        fflush(stdout);
        return;
    }
    printf("%s{\"bench\": \"incomplete\", \"complete\": false, \"reason\": \"%s\", \"complete_steps\": %d}\n]\n",
           bench_committed ? ",\n" : "", status > 128 && stop_signal() ? stop_signal_name() : "error", kept);
    fflush(stdout);
    if (status > 128 && stop_signal())
        fprintf(stderr, "restir bench: interrupted by %s during step %d (%s) after %.1f s: stdout holds the %d complete "
                        "step(s) and an \"incomplete\" entry\n",
                stop_signal_name(), bench_steps, bench_steps ? bench_what : "start", now_seconds() - bench_progress.start_seconds,
                kept);
}

int cmd_bench(int argc, char **argv)
{
    bench_args a;
    const char *positional[2];
    int count, status, first = 1;
    memset(&a, 0, sizeof a);
    bench_rays_default_options(&a.rays);
    {
        const cli_option options[] = {
            {"--generated", OPT_INT, &a.generated, "bench rays on the generated displaced sphere of this subdivision (92: 100k tris)", NULL, 1, 2000, NULL},
            {"--threads", OPT_INT, &a.rays.threads, "thread count measured besides 1 (default: online cores)", NULL, 1, 256, NULL},
            {"--repeats", OPT_INT, &a.rays.repeats, "timed repetitions; the median is reported", NULL, 1, 1000, &a.has_repeats},
            {"--textures", OPT_INT, &a.textures, "bench pairing-sigma: independent reuse textures per pass count (default 16)", NULL, 2, 4096, NULL},
            {"--size", OPT_SIZE, a.rays_size, "primary ray grid (default 512x512)", NULL, 0, 0, &a.has_rays_size},
            {"--seed", OPT_UINT32, &a.rays.seed, "seed of the jitter and bounce directions", NULL, 0, 0, NULL},
            {"--pairing", OPT_CHOICE, &a.pairing, "bench restir: spatial neighbours disk (default) or paired (Enhanced 3)",
             restir_pairing_names, 0, 0, NULL},
            {"--no-pair-step", OPT_FLAG, &a.no_pair_step, "bench restir, --pairing paired: per-pixel GRIS steps", NULL, 0,
             0, NULL},
            {"--rc-criterion", OPT_CHOICE, &a.rc_criterion, "bench restir: reconnection criterion gris or footprint",
             rc_mode_names, 0, 0, NULL},
            {"--shading", OPT_CHOICE, &a.shading, "bench restir: pixel estimate scalar or vector (Enhanced 6.3)",
             restir_shading_names, 0, 0, NULL},
            {"--light-ris", OPT_INT, &a.light_ris, "bench restir: NEE by light RIS with N candidates at x1 (Enhanced 6.1); also times the light selection", NULL, 0, LIGHT_RIS_MAX, NULL},
            {"--light-tiles", OPT_FLAG, &a.light_tiles, "bench restir, with --light-ris: candidates from light tiles", NULL, 0, 0, NULL},
            CLI_PROGRESS_ROWS(&a.progress, &a.progress_every),
            {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
        };
        status = cli_parse("bench", argc, argv, options, positional, 2, &count);
        if (status == 1) {
            cli_print_help(stdout, "bench",
                           "rays SCENE | rays --generated N | restir [SCENE] | animation [SCENE] | realtime [SCENE] | stochastic [SCENE] | mutations [SCENE] | scaling [SCENE] | pairing-sigma | all [options]",
                           options);
            return 0;
        }
    }
    if (status) return status;
    if (a.has_rays_size) {
        a.rays.width = a.rays_size[0];
        a.rays.height = a.rays_size[1];
    }
    if (count < 1 ||
        (strcmp(positional[0], "rays") && strcmp(positional[0], "all") && strcmp(positional[0], "restir") &&
         strcmp(positional[0], "animation") && strcmp(positional[0], "realtime") && strcmp(positional[0], "stochastic") &&
         strcmp(positional[0], "mutations") && strcmp(positional[0], "scaling") && strcmp(positional[0], "pairing-sigma")) ||
        (!strcmp(positional[0], "rays") && count != 2 && !a.generated)) {
        fprintf(stderr, "restir bench: expected `rays SCENE`, `rays --generated N`, `restir [SCENE]`, `animation [SCENE]`, "
                        "`realtime [SCENE]`, `stochastic [SCENE]`, `mutations [SCENE]`, `scaling [SCENE]`, `pairing-sigma` or `all`\n");
        return 2;
    }
    progress_set_mode((enum progress_mode)a.progress, a.progress_every);
    progress_begin(&bench_progress, "bench", 0);
    stop_signals_install();
    threads_set_abort(&stop_requested);
    printf("[\n");
    fflush(stdout);
    if (step_open()) return 2;
    if (!strcmp(positional[0], "all")) status = bench_all(&a, &first);
    else if (!strcmp(positional[0], "restir"))
        status = on_file(count > 1 ? positional[1] : "scenes/cornell.scene", bench_restir_on, &a, &first);
    else if (!strcmp(positional[0], "animation"))
        status = count > 1 ? on_file(positional[1], bench_animation_on, &a, &first) : bench_animation_all(&a, &first);
    else if (!strcmp(positional[0], "stochastic"))
        status = on_file(count > 1 ? positional[1] : "scenes/cornell.scene", bench_stochastic_on, &a, &first);
    else if (!strcmp(positional[0], "mutations"))
        status = count > 1 ? on_file(positional[1], bench_mutations_on, &a, &first) : bench_mutations_all(&a, &first);
    else if (!strcmp(positional[0], "scaling"))
        status = on_file(count > 1 ? positional[1] : "scenes/cornell.scene", bench_scaling_on, &a, &first);
    else if (!strcmp(positional[0], "pairing-sigma"))
        status = bench_pairing_sigma_run(&a, &first);
    else if (!strcmp(positional[0], "realtime"))
        status = count > 1 ? on_file(positional[1], bench_realtime_on, &a, &first) : bench_realtime_animated(&a, &first);
    else if (a.generated) status = on_generated(a.generated, bench_rays_on, &a, &first);
    else status = on_file(positional[1], bench_rays_on, &a, &first);
    if (stop_signal()) status = 128 + stop_signal(); /* a step was cut short (its errors are the stop's) */
    if (status == 0 && step_commit()) status = 2;
    step_discard();
    bench_finish(status);
    threads_set_abort(NULL);
    stop_signals_restore();
    progress_end(&bench_progress);
    return status;
}
