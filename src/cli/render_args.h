/* Private to src/cli. What `restir render` parses (render_args) and measures (render_timings),
 * shared by cmd_render.c (parse, validate, run, write) and the files it is split into:
 * render_table.c (the option table), render_rules.c (which options go together and where
 * they go), render_runs.c (--runs), render_stats.c (--stats). */
#ifndef RESTIR_CLI_RENDER_ARGS_H
#define RESTIR_CLI_RENDER_ARGS_H

#include "restir/frame/offline.h"
#include "restir/frame/pipeline.h"
#include "restir/oracle/stage_dump.h"
#include "restir/render/aov.h"
#include "args.h"
#include "render_pt.h"
#include "render_restir.h"
#include "scene_args.h"

enum render_method { METHOD_AOV, METHOD_PT, METHOD_RESTIR };
extern const char *const method_names[]; /* "aov", "pt", "restir" */
/* --aov: the G-buffer channels of aov.h (--method aov), then two images only --method
 * restir has: "duplicates", each pixel's duplicate count (Enhanced §5; docs/correlation.md),
 * and "age", frames of temporal history per pixel (--sequence). */
enum { AOV_CHOICE_DUPLICATES = AOV_MOTION + 1, AOV_CHOICE_AGE, AOV_CHOICE_COUNT };
extern const char *aov_choices[AOV_CHOICE_COUNT + 1];
/* Fills aov_choices (aov.h's names, then "duplicates", "age"). */
void fill_aov_choices(void);

typedef struct {
    int method, aov;
    const char *output, *png, *stats;
    int no_png, quiet, jitter, threads, frame;
    int progress;          /* --progress: enum progress_mode */
    double progress_every; /* --progress-every SECONDS (0: the default) */
    int runs; /* --runs K: K independent renders -> mean, variance and count (restir check) */
    /* Options every lighting method has, parsed once and handed to the method by
     * apply_common_options (seed, jitter, threads, frame, quiet) and apply_shared_options: */
    const char *ablate; /* --ablate NAME, checked against the method's own list */
    int preset;         /* --preset: index, applied to the restir rows not given */
    restir_options restir;
    render_restir_flags restir_flags; /* --mis, --no-confidence-scaling (render_restir.h) */
    uint32_t seed;
    double exposure;
    scene_overrides overrides;
    render_pt_args pt; /* --method pt (render_pt.h) */
    /* the real-time pipeline (--method restir --sequence A..B) */
    const char *sequence, *mcap;
    int accumulate, no_temporal;
    restir_sequence seq;
    /* the golden-oracle kit (stage_dump.h): --dump-dir, --dump-stages, --from-dump, --from-stage */
    const char *dump_stages, *from_stage, *dump_region;
    int dump_halo; /* --dump-halo N (pixels around --dump-region) */
    stage_io sio;
    frame_stage_hook hook; /* sio as the frame's stage listener */
    int history_from_dump; /* --history-from-dump: frame A-1's final state from --from-dump (render_replay.h) */
    char history_path[4200];
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

/* Rows [first, end) of options[] belong to one method (or, aov: need --method aov). */
typedef struct {
    int first, end, method;
} method_rows;

#endif
