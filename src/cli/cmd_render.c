/* restir render SCENE [options]: render a scene with one of the methods and write
 * PFM + PNG preview (+ optional --stats JSON). */
#include "cmd_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"
#include "restir/metrics/moments.h"
#include "restir/oracle/stage_dump.h"
#include "restir/render/aov.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/render/motion.h"
#include "restir/restir/duplication.h"
#include "restir/scene/animation.h"
#include "args.h"
#include "output.h"
#include "render_pt.h"
#include "render_restir.h"
#include "scene_args.h"
#include "stop.h"

enum render_method { METHOD_AOV, METHOD_PT, METHOD_RESTIR };
static const char *const method_names[] = {"aov", "pt", "restir", NULL};
/* --aov: the G-buffer channels of aov.h (--method aov), then two images only --method
 * restir has: "duplicates", each pixel's duplicate count (Enhanced §5; docs/correlation.md),
 * and "age", frames of temporal history per pixel (--sequence). */
enum { AOV_CHOICE_DUPLICATES = AOV_MOTION + 1, AOV_CHOICE_AGE, AOV_CHOICE_COUNT };
static const char *aov_choices[AOV_CHOICE_COUNT + 1];

static void fill_aov_choices(void)
{
    int i;
    for (i = 0; i < AOV_CHOICE_DUPLICATES; ++i) aov_choices[i] = aov_names[i];
    aov_choices[AOV_CHOICE_DUPLICATES] = "duplicates";
    aov_choices[AOV_CHOICE_AGE] = "age";
    aov_choices[AOV_CHOICE_COUNT] = NULL;
}

typedef struct {
    int method, aov;
    const char *output, *png, *stats;
    int no_png, quiet, jitter, threads, frame;
    int runs; /* --runs K: K independent renders -> mean, variance and count (restir check) */
    /* Options every lighting method has, parsed once and handed to the method by
     * apply_common_options (seed, jitter, threads, frame, quiet) and apply_shared_options: */
    const char *ablate; /* --ablate NAME, checked against the method's own list */
    int preset;         /* --preset: index, applied to the restir rows not given */
    restir_options restir;
    uint32_t seed;
    double exposure;
    scene_overrides overrides;
    render_pt_args pt; /* --method pt (render_pt.h) */
    /* the real-time pipeline (--method restir --sequence A..B) */
    const char *sequence, *mcap;
    int accumulate, no_temporal;
    restir_sequence seq;
    /* the golden-oracle kit (stage_dump.h): --dump-dir, --dump-stages, --from-dump, --from-stage */
    const char *dump_stages, *from_stage;
    stage_io sio;
    frame_stage_hook hook; /* sio as the frame's stage listener */
} render_args;

typedef struct {
    double load, prepare, render, write;
    pt_result pt;        /* counters of a --method pt render */
    restir_stats restir; /* counters of a --method restir render (shift failures by reason, ...) */
    double restir_seconds;
    restir_stats *frame_stats; /* --sequence: per frame */
    int *frame_numbers;
    int frame_count;
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
    if (a->method == METHOD_AOV) fprintf(f.fp, "  \"aov\": \"%s\",\n", aov_names[a->aov]);
    if (a->method == METHOD_PT) render_pt_stats_json(f.fp, &a->pt, &t->pt);
    if (a->method == METHOD_RESTIR) {
        fprintf(f.fp, "  \"restir\": {\"seconds\": %.6f, \"config\": ", t->restir_seconds);
        restir_options_write_json(f.fp, &a->restir, "    ");
        fprintf(f.fp, ",\n    \"stats\":\n");
        restir_stats_write_json(f.fp, &t->restir, "    ");
        if (a->sequence) {
            int i;
            fprintf(f.fp, ",\n    \"sequence\": {\"first\": %d, \"last\": %d, \"accumulate\": %s},\n",
                    a->seq.first, a->seq.last, a->seq.accumulate ? "true" : "false");
            fprintf(f.fp, "    \"frames\": [");
            for (i = 0; i < t->frame_count; ++i) {
                fprintf(f.fp, "%s\n      {\"frame\": %d, \"stats\":\n", i ? "," : "", t->frame_numbers[i]);
                restir_stats_write_json(f.fp, &t->frame_stats[i], "      ");
                fprintf(f.fp, "}");
            }
            fprintf(f.fp, "]");
        }
        fprintf(f.fp, "\n  },\n");
    }
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

/* The sidecar's "renderer" object of a --runs file set (the options of the first run). */
static void write_runs_config(FILE *fp, const void *ctx, const char *indent)
{
    const render_args *a = ctx;
    if (a->method == METHOD_RESTIR) {
        restir_options_write_json(fp, &a->restir, indent);
    } else if (a->method == METHOD_PT) {
        fprintf(fp, "{\"spp\": %u, \"max_depth\": %d, \"jitter\": %s, \"seed\": %u}", a->pt.o.spp,
                a->pt.o.max_depth, a->jitter ? "true" : "false", a->seed);
    } else {
        fprintf(fp, "{\"aov\": \"%s\", \"jitter\": %s, \"seed\": %u}", aov_names[a->aov],
                a->jitter ? "true" : "false", a->seed);
    }
}

/* --runs K: K renders with seeds seed, seed+1, ..., seed+K-1 (independent, since every
 * random number's address contains the seed), reduced to per-pixel mean and sample
 * variance, plus the per-run image and block means that keep `restir check` exact when
 * the renderer correlates pixels (ReSTIR's spatial reuse; docs/statistics.md, "moments
 * files"). The mean goes to `img` for the preview. */
static int render_runs(const render_args *a, const scene *s, const char *out, image *img, render_timings *t)
{
    moments m;
    moments_meta meta;
    rerror e;
    char prefix[4096], name[64];
    int k, status = 0;
    e.msg[0] = '\0';
    output_prefix(prefix, sizeof prefix, out);
    if (moments_init(&m, s->width, s->height, &e) ||
        moments_set_block_sizes(&m, moments_default_block_sizes, 4, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        moments_free(&m);
        return 2;
    }
    meta.method = method_names[a->method];
    meta.write_config = write_runs_config;
    meta.ctx = a;
    /* Spatial reuse shares samples between pixels of one run; everything else keeps the
     * pixels of a run independent (their random numbers are addressed by pixel). */
    meta.correlation =
        a->method == METHOD_RESTIR && a->restir.spatial_passes > 0 ? MOMENTS_CORRELATED : MOMENTS_INDEPENDENT;
    for (k = 0; k < a->runs && !status && !stop_signal(); ++k) {
        image run;
        status = render_one(a, s, a->seed + (uint32_t)k, NULL, &run, t);
        if (status) break;
        /* A run cut short by SIGINT/SIGTERM has fewer samples than the others: adding it
         * would mix two estimators in one mean and variance, so it is dropped. */
        if (!stop_signal()) {
            snprintf(name, sizeof name, "seed %u", a->seed + (uint32_t)k);
            if (moments_add(&m, &run, name, &e)) status = 2;
        }
        image_free(&run);
    }
    if (!status && stop_signal() && m.runs < 2) {
        /* A variance needs two runs: nothing is written, and the status says so. */
        fprintf(stderr, "restir render: interrupted by %s after %ld finished run(s); fewer than 2, nothing written\n",
                stop_signal_name(), m.runs);
        moments_free(&m);
        return 128 + stop_signal();
    }
    if (!status && moments_write_meta(prefix, &m, &meta, &e)) status = 2;
    if (!status) {
        image var;
        if (moments_images(&m, img, &var, &e)) status = 2;
        else image_free(&var);
    }
    if (status == 2 && e.msg[0]) fprintf(stderr, "%s\n", e.msg);
    moments_free(&m);
    return status;
}

/* --sequence: one PFM (+ PNG) per frame, PREFIX.0000.pfm ..., each written atomically. */
typedef struct {
    const render_args *a;
    render_timings *t;
    char prefix[4096];
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
    snprintf(pfm, sizeof pfm, "%s.%04d.pfm", k->prefix, frame);
    snprintf(png, sizeof png, "%s.%04d.png", k->prefix, frame);
    if (write_image(k->a, img, pfm, k->a->no_png ? "" : png)) return rerror_set(e, "%s: not written", pfm);
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
    if (restir_render_sequence(s, &a->restir, &a->seq, write_frame, &k, &t->restir, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    t->restir_seconds = t->render = now_seconds() - t0;
    restir_guard_warning(&t->restir);
    if (!a->quiet && t->frame_count > 0)
        fprintf(stderr, "wrote frames %s.%04d.pfm .. %s.%04d.pfm\n", k.prefix, t->frame_numbers[0], k.prefix,
                t->frame_numbers[t->frame_count - 1]);
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
    if (a->sequence) return render_sequence(a, s, out, t);
    t0 = now_seconds();
    if (a->runs > 0) {
        status = render_runs(a, s, out, &img, t);
        if (status) return status;
        t->render = now_seconds() - t0;
        if (png[0]) status = write_outputs(&img, NULL, png, a->exposure);
        if (!status && !a->quiet && !stop_signal())
            fprintf(stderr, "wrote %d runs as %s mean/var/moments\n", a->runs, out);
        image_free(&img);
        return status;
    }
    status = render_one(a, s, a->seed, out, &img, t);
    if (status) return status;
    t->render = now_seconds() - t0;
    t0 = now_seconds();
    status = write_image(a, &img, out, png);
    t->write = now_seconds() - t0;
    if (!status && !a->quiet) fprintf(stderr, "wrote %s%s%s\n", out, png[0] ? " and " : "", png);
    image_free(&img);
    return status;
}

/* Appends the ReSTIR rows. --max-depth, --time-limit, --checkpoint and --resume exist for
 * more than one method: the path tracer's rows stay (with help for both), restir's copies
 * are dropped and apply_shared_options() hands the values over. */
static int add_restir_rows(cli_option *options, int n, render_args *a)
{
    cli_option rows[RENDER_RESTIR_OPTION_ROWS];
    int i, j, count = render_restir_options(rows, &a->restir);
    for (i = 0; i < n; ++i) {
        if (!strcmp(options[i].name, "--max-depth"))
            options[i].help = "maximum path length d in segments (2 = direct light; pt: 1..255, restir: 2..16; default 10)";
        if (!strcmp(options[i].name, "--checkpoint"))
            options[i].help = "pt: write the accumulation state here at the end and on SIGINT/SIGTERM; restir "
                              "--sequence: the previous-frame state after every frame";
        if (!strcmp(options[i].name, "--resume"))
            options[i].help = "pt: continue this checkpoint up to --spp; restir --sequence: continue after its frame";
        if (!strcmp(options[i].name, "--time-limit"))
            options[i].help = "pt: whole 1-spp passes, restir: whole frames until SECONDS have passed (restir: --frames ignored)";
    }
    for (j = 0; j < count; ++j) {
        int duplicate = 0;
        for (i = 0; i < n; ++i) duplicate |= !strcmp(options[i].name, rows[j].name);
        if (!duplicate) options[n++] = rows[j];
    }
    return n;
}

static int ablation_index(const char *const *names, const char *name)
{
    int i;
    for (i = 0; names[i]; ++i)
        if (!strcmp(names[i], name)) return i;
    return -1;
}

/* Hands the shared options to the chosen method. */
/* --dump-dir DIR [--dump-stages a,b], --from-dump DIR --from-stage S (docs/oracle.md). */
static int apply_stage_options(render_args *a)
{
    rerror e;
    int any = a->sio.dump_dir || a->dump_stages || a->sio.from_dir || a->from_stage;
    if (!any) return 0;
    if (!a->sequence) {
        fprintf(stderr, "restir render: --dump-dir, --dump-stages, --from-dump and --from-stage need --sequence A..B\n");
        return 2;
    }
    if (a->dump_stages && !a->sio.dump_dir) {
        fprintf(stderr, "restir render: --dump-stages needs --dump-dir DIR\n");
        return 2;
    }
    if (!a->sio.from_dir != !a->from_stage) {
        fprintf(stderr, "restir render: --from-dump DIR and --from-stage S go together\n");
        return 2;
    }
    if (a->dump_stages && stage_io_set_stages(&a->sio, a->dump_stages, &e)) {
        fprintf(stderr, "restir render: %s\n", e.msg);
        return 2;
    }
    if (a->from_stage) {
        if (strlen(a->from_stage) >= sizeof a->sio.from_stage) {
            fprintf(stderr, "restir render: --from-stage: '%s' is too long\n", a->from_stage);
            return 2;
        }
        strcpy(a->sio.from_stage, a->from_stage);
    }
    stage_io_hook(&a->sio, &a->hook);
    a->seq.stages = &a->hook;
    return 0;
}

/* --sequence A..B, --mcap C|inf, --accumulate, --no-temporal (restir only). */
static int apply_sequence_options(render_args *a)
{
    char *end;
    if (a->mcap) {
        double c = strcmp(a->mcap, "inf") ? strtod(a->mcap, &end) : INFINITY;
        if (strcmp(a->mcap, "inf") && (end == a->mcap || *end || !(c > 0) || isinf(c))) {
            fprintf(stderr, "restir render: --mcap: expected a number > 0 or inf, got '%s'\n", a->mcap);
            return 2;
        }
        a->restir.mcap = c;
    }
    if (a->no_temporal) a->restir.temporal = 0;
    if ((a->sequence || a->accumulate) && a->method != METHOD_RESTIR) {
        fprintf(stderr, "restir render: --sequence and --accumulate need --method restir\n");
        return 2;
    }
    if (a->restir.mutations > 0 && !a->sequence) { /* mutations live in the real-time pipeline */
        fprintf(stderr, "restir render: --mutations needs --method restir --sequence A..B\n");
        return 2;
    }
    if (a->accumulate && !a->sequence) {
        fprintf(stderr, "restir render: --accumulate needs --sequence A..B\n");
        return 2;
    }
    if (!a->sequence) return 0;
    if (a->runs > 0 || a->pt.o.time_limit > 0) {
        fprintf(stderr, "restir render: --sequence cannot be combined with --runs or --time-limit\n");
        return 2;
    }
    {
        long first = strtol(a->sequence, &end, 10), last;
        const char *rest = end;
        int ok = end != a->sequence && rest[0] == '.' && rest[1] == '.';
        if (ok) {
            last = strtol(rest + 2, &end, 10);
            ok = end != rest + 2 && !*end && first >= 0 && last >= first && last < 100000000;
        }
        if (!ok) {
            fprintf(stderr, "restir render: --sequence: expected A..B with 0 <= A <= B, got '%s'\n", a->sequence);
            return 2;
        }
        a->seq.first = (int)first;
        a->seq.last = (int)last;
    }
    a->seq.accumulate = a->accumulate;
    /* the path tracer's --checkpoint FILE / --resume FILE rows serve sequences too */
    a->seq.checkpoint = a->pt.o.checkpoint_path;
    a->seq.resume = a->pt.o.resume_path;
    return 0;
}

/* The options every method shares, parsed once into render_args, go to the method's
 * options here, once. */
static void apply_common_options(render_args *a)
{
    a->pt.o.seed = a->restir.seed = a->seed;
    a->pt.o.jitter = a->restir.jitter = a->jitter;
    a->pt.o.threads = a->restir.threads = a->threads;
    a->pt.o.quiet = a->restir.quiet = a->quiet;
    a->pt.o.frame = a->frame;
    a->restir.stop_flag = &stop_requested;
    /* The duplicate counters are reported by --stats only (--dedup and --aov duplicates
     * read the map themselves). */
    a->restir.no_duplicate_stats = !a->stats;
}

/* Rows [first, end) of options[] belong to one method (or, aov: need --method aov). */
typedef struct {
    int first, end, method;
} method_rows;

/* An option that does not apply to the chosen method is an error with a hint, not a
 * silent no-op. The shared rows (--max-depth, --time-limit, --checkpoint, --resume,
 * --ablate) are checked by name. */
static int check_method_options(const render_args *a, const cli_option *options, const int *given,
                                const method_rows *rows, int nrows)
{
    static const char *const hints[][2] = {
        {"--spp", "restir averages --frames N frames (or --time-limit) of --candidates N path trees"},
        {"--spatial-passes", "the path tracer has no reuse; --method restir"},
        {"--aov", "--method aov --aov CHANNEL"},
    };
    static const char *const pt_rows_restir_shares[] = {"--max-depth", "--time-limit", "--checkpoint", "--resume",
                                                        "--light-ris", "--light-tiles"};
    int r, i, h;
    for (r = 0; r < nrows; ++r) {
        if (rows[r].method == a->method) continue;
        for (i = rows[r].first; i < rows[r].end; ++i) {
            const char *hint = "see restir render --help";
            int shared = 0;
            if (!given[i]) continue;
            for (h = 0; h < (int)(sizeof pt_rows_restir_shares / sizeof *pt_rows_restir_shares) && rows[r].method == METHOD_PT; ++h)
                shared |= !strcmp(options[i].name, pt_rows_restir_shares[h]);
            if (shared) continue; /* restir takes them; aov: checked below */
            for (h = 0; h < (int)(sizeof hints / sizeof hints[0]); ++h)
                if (!strcmp(hints[h][0], options[i].name)) hint = hints[h][1];
            fprintf(stderr, "restir render: %s applies to --method %s, not --method %s (%s)\n", options[i].name,
                    method_names[rows[r].method], method_names[a->method], hint);
            return 2;
        }
    }
    if (a->method == METHOD_AOV) {
        static const char *const lighting[] = {"--max-depth", "--time-limit", "--checkpoint", "--resume", "--ablate",
                                               "--runs", "--light-ris", "--light-tiles"};
        for (h = 0; h < (int)(sizeof lighting / sizeof lighting[0]); ++h)
            if (cli_given(options, given, lighting[h])) {
                fprintf(stderr, "restir render: %s applies to --method pt and --method restir, not --method aov\n",
                        lighting[h]);
                return 2;
            }
    }
    if (a->method == METHOD_RESTIR && !a->sequence &&
        (cli_given(options, given, "--checkpoint") || cli_given(options, given, "--resume"))) {
        fprintf(stderr, "restir render: --checkpoint and --resume apply to --method pt and to --method restir with "
                        "--sequence A..B (offline restir frames are independent: --first-frame F continues a run)\n");
        return 2;
    }
    return 0;
}

/* Every file the command will write, checked before anything is rendered. */
static int check_output_paths(const render_args *a, const char *out, const char *png)
{
    const char *paths[4];
    rerror e;
    size_t n = strlen(out);
    int i, count = 0;
    if (n >= 4 && !strcmp(out + n - 4, ".png")) {
        fprintf(stderr, "restir render: -o %s: -o names the PFM (the data); the PNG preview is written next to it "
                        "(use -o %.*s.pfm, or --png FILE for the preview's name)\n", out, (int)(n - 4), out);
        return 2;
    }
    paths[count++] = out;
    if (png[0]) paths[count++] = png;
    if (a->stats) paths[count++] = a->stats;
    if (a->pt.o.checkpoint_path) paths[count++] = a->pt.o.checkpoint_path;
    for (i = 0; i < count; ++i) {
        if (output_path_check(paths[i], &e)) {
            fprintf(stderr, "restir render: %s\n", e.msg);
            return 2;
        }
    }
    if (png[0] && !strcmp(png, out)) {
        fprintf(stderr, "restir render: --png %s is the PFM's own path\n", png);
        return 2;
    }
    return 0;
}

/* SIGINT / SIGTERM: what was kept, on stderr even with --quiet; exit 128 + signal. */
static int interrupted_status(const render_args *a, const render_timings *t, const char *out)
{
    int sig = stop_signal();
    if (!sig) return 0;
    if (a->sequence)
        fprintf(stderr, "restir render: interrupted by %s after %d frame(s); frames written so far are kept%s%s\n",
                stop_signal_name(), t->frame_count, a->seq.checkpoint ? ", checkpoint " : "",
                a->seq.checkpoint ? a->seq.checkpoint : "");
    else if (a->runs > 0)
        fprintf(stderr, "restir render: interrupted by %s: %s mean/var/moments hold the runs finished so far (a run cut short is dropped)\n",
                stop_signal_name(), out);
    else if (a->method == METHOD_PT)
        fprintf(stderr, "restir render: interrupted by %s: %s holds %u spp%s%s (resume with --resume)\n",
                stop_signal_name(), out, t->pt.state.spp, a->pt.o.checkpoint_path ? ", checkpoint " : "",
                a->pt.o.checkpoint_path ? a->pt.o.checkpoint_path : "");
    else
        fprintf(stderr, "restir render: interrupted by %s: %s holds the mean of %llu frame(s)\n", stop_signal_name(),
                out, (unsigned long long)t->restir.frames);
    return 128 + sig;
}

/* --aov duplicates|age (issue 12): reservoirs exist only with --method restir (checked by
 * check_method_options), a temporal history only in sequences. */
static int apply_aov_options(render_args *a)
{
    if (a->method != METHOD_RESTIR || (a->aov != AOV_CHOICE_DUPLICATES && a->aov != AOV_CHOICE_AGE)) return 0;
    if (a->aov == AOV_CHOICE_AGE && !a->sequence) {
        fprintf(stderr, "restir render: --aov age needs --sequence A..B\n");
        return 2;
    }
    if (a->runs > 0) {
        fprintf(stderr, "restir render: --aov %s cannot be combined with --runs\n", aov_choices[a->aov]);
        return 2;
    }
    a->restir.output_aov = a->aov == AOV_CHOICE_AGE ? RESTIR_OUTPUT_AGE : RESTIR_OUTPUT_DUPLICATES;
    return 0;
}

static int apply_shared_options(render_args *a, const cli_option *options, const int *given)
{
    if (apply_sequence_options(a) || apply_stage_options(a) || apply_aov_options(a)) return 2;
    if (a->method == METHOD_RESTIR) a->restir.time_limit = a->pt.o.time_limit; /* --time-limit */
    if (a->method == METHOD_RESTIR) { /* --light-ris N, --light-tiles */
        a->restir.light_ris = a->pt.o.light_ris;
        a->restir.light_tiles = a->pt.o.light_tiles;
    }
    if (a->method == METHOD_RESTIR && cli_given(options, given, "--max-depth")) {
        if (a->pt.o.max_depth < 2 || a->pt.o.max_depth > PATH_MAX_LENGTH) {
            fprintf(stderr, "restir render: --max-depth: restir needs 2..%d, got %d\n", PATH_MAX_LENGTH,
                    a->pt.o.max_depth);
            return 2;
        }
        a->restir.max_depth = a->pt.o.max_depth;
    }
    if (!a->ablate) return 0;
    if (a->method == METHOD_PT && render_pt_set_ablation(&a->pt, a->ablate) == 0) return 0;
    if (a->method == METHOD_RESTIR && ablation_index(restir_ablation_names, a->ablate) >= 0) {
        a->restir.ablation = (enum restir_ablation)ablation_index(restir_ablation_names, a->ablate);
        return 0;
    }
    fprintf(stderr, "restir render: --ablate: '%s' is not an ablation of --method %s\n", a->ablate,
            method_names[a->method]);
    return 2;
}

int cmd_render(int argc, char **argv)
{
    render_args a;
    render_timings t;
    cli_option options[112];
    int given[112];
    method_rows rows[3];
    const char *positional[1];
    char out[4096], png[4096];
    int n = 0, count, status;
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
    {
        const cli_option rows[] = {
            {"-o", OPT_STRING, &a.output, "output PFM (default out/<scene>.pfm)", NULL, 0, 0, NULL},
            {"--png", OPT_STRING, &a.png, "PNG preview path (default: the PFM path with .png)", NULL, 0, 0, NULL},
            {"--no-png", OPT_FLAG, &a.no_png, "do not write the PNG preview", NULL, 0, 0, NULL},
            {"--exposure", OPT_REAL, &a.exposure, "preview exposure in stops (default 0)", NULL, -64, 64, NULL},
            {"--method", OPT_CHOICE, &a.method, "rendering method", method_names, 0, 0, NULL},
            {"--aov", OPT_CHOICE, &a.aov, "G-buffer channel for --method aov (encodings: docs/cli.md); --method restir: duplicates, per pixel the copies of its sample in its 17x17 window (PNG: heat map, black 0 .. red >= 20%), or age (--sequence): frames of temporal history per pixel (0: none)", aov_choices, 0, 0, NULL},
            {"--seed", OPT_UINT32, &a.seed, "run seed of the addressed RNG (default 1)", NULL, 0, 0, NULL},
            {"--threads", OPT_INT, &a.threads, "worker threads (default: online cores; 1 = no threads)", NULL, 1, 256,
             NULL},
            {"--frame", OPT_INT, &a.frame, "frame index (camera keyframes)", NULL, 0, 1e9, NULL},
            {"--jitter", OPT_FLAG, &a.jitter, "jittered sub-pixel primary rays (default: pixel centres)", NULL, 0, 0,
             NULL},
            {"--runs", OPT_INT, &a.runs, "K >= 2 independent runs (seeds seed..seed+K-1; a variance needs two): writes PREFIX.mean.pfm, PREFIX.var.pfm, PREFIX.moments.json for restir check", NULL, 2, 1e6, NULL},
            {"--sequence", OPT_STRING, &a.sequence, "A..B: the real-time pipeline (restir) over frames A..B inclusive, one -o NAME.pfm -> NAME.0000.pfm ... per frame", NULL, 0, 0, NULL},
            {"--accumulate", OPT_FLAG, &a.accumulate, "with --sequence: frame f's file holds the average of frames A..f (a still camera, GRIS 6.4)", NULL, 0, 0, NULL},
            {"--mcap", OPT_STRING, &a.mcap, "with --sequence: cap the previous frame's confidence at C x the current one's (C > 0 or inf; default 20, GRIS 6.2)", NULL, 0, 0, NULL},
            {"--no-temporal", OPT_FLAG, &a.no_temporal, "with --sequence: no temporal reuse (independent frames through the same pipeline)", NULL, 0, 0, NULL},
            {"--dump-dir", OPT_STRING, &a.sio.dump_dir, "with --sequence: write DIR/manifest.json and per frame the G-buffer and the reservoirs after each stage (docs/oracle.md)", NULL, 0, 0, NULL},
            {"--dump-stages", OPT_STRING, &a.dump_stages, "with --dump-dir: only these stages, e.g. initial,temporal,spatial1 (default: all)", NULL, 0, 0, NULL},
            {"--from-dump", OPT_STRING, &a.sio.from_dir, "with --sequence: restart from this stage dump (needs --from-stage)", NULL, 0, 0, NULL},
            {"--from-stage", OPT_STRING, &a.from_stage, "with --from-dump: replace stage S's output of every frame by the dumped one; later stages run on it", NULL, 0, 0, NULL},
            {"--stats", OPT_STRING, &a.stats, "write timings and counters as JSON", NULL, 0, 0, NULL},
            {"--quiet", OPT_FLAG, &a.quiet, "no progress or messages on stderr", NULL, 0, 0, NULL},
            {"--ablate", OPT_STRING, &a.ablate, "a deliberately broken estimator: pt: light-pdf|mis-sum|mis-lobe|light-ris-pdf, restir: jacobian|light-pdf|...", NULL, 0, 0, NULL},
        };
        for (n = 0; n < (int)(sizeof rows / sizeof rows[0]); ++n) options[n] = rows[n];
    }
    n += scene_override_options(options + n, &a.overrides);
    rows[0].first = n;
    rows[0].method = METHOD_PT;
    n += render_pt_options(options + n, &a.pt);
    rows[0].end = n;
    options[n++] = render_restir_preset_row(&a.preset);
    rows[1].first = n - 1;
    rows[1].method = METHOD_RESTIR;
    n = add_restir_rows(options, n, &a);
    rows[1].end = n;
    memset(&options[n], 0, sizeof options[n]);
    cli_track_given(options, given);
    for (count = 0; count < n; ++count)
        if (!strcmp(options[count].name, "--aov")) rows[2].first = count, rows[2].end = count + 1;
    rows[2].method = METHOD_AOV;
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
    render_restir_apply_preset(options, given, a.preset, &a.restir);
    if (a.aov >= AOV_CHOICE_DUPLICATES) rows[2].method = METHOD_RESTIR; /* restir's two --aov images */
    status = check_method_options(&a, options, given, rows, 3);
    if (status) return status;
    a.overrides.quiet = a.quiet;
    apply_common_options(&a);
    status = apply_shared_options(&a, options, given);
    if (status) return status;
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
