/* `restir render --method pt`: options, signal handling, progressive output. */
#include "render_pt.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/image.h"

static const char *const ablate_choices[] = {"none", "light-pdf", "mis-sum", "mis-lobe", NULL};

int render_pt_set_ablation(render_pt_args *a, const char *name)
{
    int i;
    for (i = 0; ablate_choices[i]; ++i) {
        if (!strcmp(ablate_choices[i], name)) {
            a->ablate = i;
            return 0;
        }
    }
    return -1;
}

void render_pt_args_default(render_pt_args *a)
{
    pt_options o;
    pt_options_default(&o);
    memset(a, 0, sizeof *a);
    a->spp = o.spp;
    a->max_depth = o.max_depth;
    a->min_depth = o.min_depth;
    a->strategy = (int)o.strategy;
}

int render_pt_options(cli_option *rows, render_pt_args *a)
{
    const cli_option r[RENDER_PT_OPTION_ROWS] = {
        {"--spp", OPT_UINT32, &a->spp, "pt: target samples per pixel (default 16; 0 with --time-limit: until time)", NULL, 0, 0, NULL},
        {"--time-limit", OPT_REAL, &a->time_limit, "pt: render whole 1-spp passes until SECONDS have passed", NULL, 0, 1e9, NULL},
        {"--max-depth", OPT_INT, &a->max_depth, "pt: maximum path length d in segments, 1..255 (default 10; 2 = direct light)", NULL, 1, PT_MAX_DEPTH_LIMIT, NULL},
        {"--min-depth", OPT_INT, &a->min_depth, "pt: shortest path length counted (default 1; 3 = indirect light only, like restir --paths indirect)", NULL, 1, PT_MAX_DEPTH_LIMIT, NULL},
        {"--pt-strategy", OPT_CHOICE, &a->strategy, "pt: MIS (GRIS Eq. 49), NEE only or BSDF sampling only", pt_strategy_names, 0, 0, NULL},
        {"--ablate", OPT_CHOICE, &a->ablate, "pt: a deliberately broken estimator (docs/path-tracer.md)", ablate_choices, 0, 0, NULL},
        {"--rr", OPT_FLAG, &a->rr, "pt: unbiased Russian roulette after the 3rd vertex (default off)", NULL, 0, 0, NULL},
        {"--sample-offset", OPT_UINT32, &a->sample_offset, "pt: first sample index (disjoint ranges merge: restir merge)", NULL, 0, 0, NULL},
        {"--checkpoint", OPT_STRING, &a->checkpoint, "pt: write the accumulation state here at the end and on SIGINT/SIGTERM", NULL, 0, 0, NULL},
        {"--checkpoint-every", OPT_REAL, &a->checkpoint_every, "pt: also write the checkpoint every SECONDS", NULL, 0, 1e9, NULL},
        {"--resume", OPT_STRING, &a->resume, "pt: continue this checkpoint up to --spp", NULL, 0, 0, NULL},
        {"--progressive", OPT_INT, &a->progressive, "pt: rewrite the output PFM every N passes", NULL, 0, 1e9, NULL},
    };
    memcpy(rows, r, sizeof r);
    return RENDER_PT_OPTION_ROWS;
}

/* ---- stopping on SIGINT / SIGTERM ---- */

static volatile sig_atomic_t stop_requested;

static void on_stop_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

typedef struct {
    struct sigaction old_int, old_term;
} saved_handlers;

static void install_stop_handlers(saved_handlers *saved)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    stop_requested = 0;
    sigaction(SIGINT, &sa, &saved->old_int);
    sigaction(SIGTERM, &sa, &saved->old_term);
}

static void restore_handlers(const saved_handlers *saved)
{
    sigaction(SIGINT, &saved->old_int, NULL);
    sigaction(SIGTERM, &saved->old_term, NULL);
}

/* ---- progressive output ---- */

typedef struct {
    const char *path;
    int failed;
} progressive_ctx;

static void write_progressive(void *ctx, const pt_state *st)
{
    progressive_ctx *p = ctx;
    image img;
    rerror e;
    if (p->failed || pt_state_mean(st, &img, &e)) return;
    if (pfm_write(p->path, &img, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        p->failed = 1;
    }
    image_free(&img);
}

static void options_from_args(const render_pt_args *a, uint32_t seed, int threads, int jitter, int frame, int quiet,
                              pt_options *o)
{
    pt_options_default(o);
    o->spp = a->spp;
    o->time_limit = a->time_limit;
    o->seed = seed;
    o->sample_offset = a->sample_offset;
    o->max_depth = a->max_depth;
    o->min_depth = a->min_depth;
    o->strategy = (enum pt_strategy)a->strategy;
    o->russian_roulette = a->rr;
    o->jitter = jitter;
    o->ablations = a->ablate > 0 ? pt_ablation_from_name(ablate_choices[a->ablate]) : 0;
    o->frame = frame;
    o->threads = threads;
    o->quiet = quiet;
    o->checkpoint_path = a->checkpoint;
    o->checkpoint_interval = a->checkpoint_every;
    o->resume_path = a->resume;
    o->stop_flag = &stop_requested;
}

int render_pt_image(const render_pt_args *a, const scene *s, uint32_t seed, int threads, int jitter, int frame,
                    int quiet, const char *progressive_pfm, image *img, pt_result *result)
{
    pt_options o;
    pt_result r;
    progressive_ctx progressive;
    saved_handlers saved;
    rerror e;
    int status;
    options_from_args(a, seed, threads, jitter, frame, quiet, &o);
    progressive.path = progressive_pfm;
    progressive.failed = 0;
    if (a->progressive > 0 && progressive_pfm) {
        o.callback_every = a->progressive;
        o.on_passes = write_progressive;
        o.callback_ctx = &progressive;
    }
    install_stop_handlers(&saved);
    status = pt_render(s, &o, &r, &e);
    restore_handlers(&saved);
    if (status) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (!quiet) {
        fprintf(stderr, "pt: %u spp (samples %u..%llu) in %.2f s, %.0f paths/s%s\n", r.state.spp,
                r.state.sample_offset, (unsigned long long)r.state.sample_offset + r.state.spp - 1, r.seconds,
                r.seconds > 0 ? (double)r.paths / r.seconds : 0.0, r.stopped ? ", stopped by a signal" : "");
        if (r.stopped && a->checkpoint) fprintf(stderr, "pt: resume with --resume %s\n", a->checkpoint);
    }
    /* The NaN policy (docs/path-tracer.md): never silent, even with --quiet. */
    if (r.state.nonfinite)
        fprintf(stderr, "pt: warning: %llu samples had NaN/Inf radiance and were accumulated as 0 "
                        "(first: sample %u of pixel %u)\n",
                (unsigned long long)r.state.nonfinite, r.state.first_nonfinite_sample, r.state.first_nonfinite_pixel);
    *img = r.mean;
    memset(&r.mean, 0, sizeof r.mean);
    /* Keep the counters of the state for --stats; its per-pixel sums are not needed. */
    free(r.state.sum);
    free(r.state.sum_sq);
    r.state.sum = r.state.sum_sq = NULL;
    if (result) *result = r;
    return 0;
}

void render_pt_stats_json(FILE *out, const render_pt_args *a, const pt_result *r)
{
    fprintf(out,
            "  \"pt\": {\"spp\": %u, \"sample_offset\": %u, \"max_depth\": %d, \"min_depth\": %d, \"strategy\": \"%s\", "
            "\"ablate\": \"%s\", \"russian_roulette\": %d, \"seconds\": %.6f, \"paths\": %llu, \"rays\": %llu, "
            "\"paths_per_second\": %.1f, \"nonfinite_samples\": %llu, \"stopped\": %d},\n",
            r->state.spp, r->state.sample_offset, a->max_depth, a->min_depth, pt_strategy_names[a->strategy],
            ablate_choices[a->ablate], a->rr, r->seconds, (unsigned long long)r->paths, (unsigned long long)r->rays,
            r->seconds > 0 ? (double)r->paths / r->seconds : 0.0, (unsigned long long)r->state.nonfinite, r->stopped);
}
