/* `restir render --method pt`: options, progressive output. */
#include "render_pt.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image.h"
#include "restir/core/image_io.h"
#include "restir/core/pfm.h"
#include "restir/render/light_ris.h"
#include "restir/render/pt_state.h"
#include "stop.h"

/* --ablate for the path tracer: "none" or one of pt_ablation_names (one bit each). */
static const char *ablation_name(unsigned bits)
{
    int i;
    for (i = 0; pt_ablation_names[i]; ++i)
        if (bits & (1u << i)) return pt_ablation_names[i];
    return "none";
}

int render_pt_set_ablation(render_pt_args *a, const char *name)
{
    unsigned bit = pt_ablation_from_name(name);
    if (!bit && strcmp(name, "none")) return -1;
    a->o.ablations = bit;
    return 0;
}

void render_pt_args_default(render_pt_args *a)
{
    memset(a, 0, sizeof *a);
    pt_options_default(&a->o);
}

/* OPT_CHOICE writes an int: the enum must be one. */
typedef char pt_strategy_is_int_sized[sizeof(enum pt_strategy) == sizeof(int) ? 1 : -1];

int render_pt_options(cli_option *rows, render_pt_args *a)
{
    pt_options *o = &a->o;
    const cli_option r[RENDER_PT_OPTION_ROWS] = {
        {"--spp", OPT_UINT32, &o->spp, "pt: target samples per pixel (default 16; 0 with --time-limit: until time)", NULL, 0, 0, NULL},
        {"--time-limit", OPT_REAL, &o->time_limit, "pt: render whole 1-spp passes until SECONDS have passed", NULL, 0, 1e9, NULL},
        {"--max-depth", OPT_INT, &o->max_depth, "pt: maximum path length d in segments, 1..255 (default 10; 2 = direct light)", NULL, 1, PT_MAX_DEPTH_LIMIT, NULL},
        {"--min-depth", OPT_INT, &o->min_depth, "pt: shortest path length counted (default 1; 3 = indirect light only, like restir --paths indirect)", NULL, 1, PT_MAX_DEPTH_LIMIT, NULL},
        {"--pt-strategy", OPT_CHOICE, (int *)&o->strategy, "pt: MIS (GRIS Eq. 49), NEE only or BSDF sampling only", pt_strategy_names, 0, 0, NULL},
        {"--rr", OPT_FLAG, &o->russian_roulette, "pt: unbiased Russian roulette after the 3rd vertex (default off)", NULL, 0, 0, NULL},
        {"--sample-offset", OPT_UINT32, &o->sample_offset, "pt: first sample index (disjoint ranges merge: restir merge)", NULL, 0, 0, NULL},
        {"--checkpoint", OPT_STRING, &o->checkpoint_path, "pt: write the accumulation state here at the end and on SIGINT/SIGTERM", NULL, 0, 0, NULL},
        {"--checkpoint-every", OPT_REAL, &o->checkpoint_interval, "pt: also write the checkpoint every SECONDS", NULL, 0, 1e9, NULL},
        {"--resume", OPT_STRING, &o->resume_path, "pt: continue this checkpoint up to --spp", NULL, 0, 0, NULL},
        {"--progressive", OPT_INT, &a->progressive, "pt: rewrite the output PFM every N passes", NULL, 0, 1e9, NULL},
        {"--light-ris", OPT_INT, &o->light_ris.candidates, "pt, restir: NEE by light RIS, N candidates at x1 and max(1, N/B^2) at x_B (Enhanced 6.1; default 0 = off)", NULL, 0, LIGHT_RIS_MAX, NULL},
        {"--light-tiles", OPT_FLAG, &o->light_ris.tiles, "pt, restir: with --light-ris, candidates from 128 light tiles x 1024 samples, one tile per 8x8 pixels per sample", NULL, 0, 0, NULL},
    };
    memcpy(rows, r, sizeof r);
    return RENDER_PT_OPTION_ROWS;
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
    if (image_write(p->path, &img, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        p->failed = 1;
    }
    image_free(&img);
}

int render_pt_image(const render_pt_args *a, const scene *s, const char *progressive_pfm, image *img,
                    pt_result *result)
{
    pt_options o = a->o;
    pt_result r;
    progressive_ctx progressive;
    rerror e;
    int status;
    const int quiet = o.quiet;
    o.stop_flag = &stop_requested;
    progressive.path = progressive_pfm;
    progressive.failed = 0;
    if (a->progressive > 0 && progressive_pfm) {
        o.callback_every = a->progressive;
        o.on_passes = write_progressive;
        o.callback_ctx = &progressive;
    }
    status = pt_render(s, &o, &r, &e);
    if (status) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (!quiet && r.state.spp == 0) {
        fprintf(stderr, "pt: no pass complete in %.2f s%s\n", r.seconds, r.stopped ? ", stopped by a signal" : "");
    } else if (!quiet) {
        fprintf(stderr, "pt: %u spp (samples %u..%llu) in %.2f s, %.0f paths/s%s\n", r.state.spp,
                r.state.sample_offset, (unsigned long long)r.state.sample_offset + r.state.spp - 1, r.seconds,
                r.seconds > 0 ? (double)r.paths / r.seconds : 0.0, r.stopped ? ", stopped by a signal" : "");
        if (r.stopped && o.checkpoint_path) fprintf(stderr, "pt: resume with --resume %s\n", o.checkpoint_path);
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
            "\"ablate\": \"%s\", \"russian_roulette\": %d, \"light_ris\": %d, \"light_tiles\": %d, \"seconds\": %.6f, \"paths\": %llu, \"rays\": %llu, "
            "\"paths_per_second\": %.1f, \"nonfinite_samples\": %llu, \"stopped\": %d},\n",
            r->state.spp, r->state.sample_offset, a->o.max_depth, a->o.min_depth, pt_strategy_names[a->o.strategy],
            ablation_name(a->o.ablations), a->o.russian_roulette, a->o.light_ris.candidates, a->o.light_ris.tiles, r->seconds, (unsigned long long)r->paths, (unsigned long long)r->rays,
            r->seconds > 0 ? (double)r->paths / r->seconds : 0.0, (unsigned long long)r->state.nonfinite, r->stopped);
}
