/* Private to src/cli. The path tracer's part of `restir render --method pt`: its option rows
 * and the call into the library (include/restir/render/pt.h), kept apart from cmd_render.c so
 * the render command only has to add the rows and call render_pt_image(). */
#ifndef RESTIR_CLI_RENDER_PT_H
#define RESTIR_CLI_RENDER_PT_H

#include "args.h"
#include "restir/render/pt.h"

typedef struct {
    pt_options o;    /* the rows write straight into the library's options */
    int progressive; /* --progressive N: rewrite the output image every N passes (CLI only) */
} render_pt_args;

void render_pt_args_default(render_pt_args *a);
/* Sets --ablate by name ("none" or one of pt_ablation_names); -1 if NAME is not one of
 * the path tracer's ablations. (--ablate is a row of the render command: it serves
 * every lighting method.) */
int render_pt_set_ablation(render_pt_args *a, const char *name);
/* Writes the PT option rows into rows[] (room for RENDER_PT_OPTION_ROWS); returns the count. */
#define RENDER_PT_OPTION_ROWS 13
int render_pt_options(cli_option *rows, render_pt_args *a);

/* Renders s with the path tracer (a->o with seed, threads, jitter, frame and quiet set by
 * the caller). SIGINT/SIGTERM (stop.h) stop it between passes: the checkpoint, if any, is
 * written and the image of the samples so far is returned. With a->progressive > 0 the mean
 * image is written to progressive_pfm every N passes. *img receives the mean image (caller
 * frees), *result (may be NULL) the counters (its state holds no sums). Prints a summary
 * line on stderr unless quiet. Returns 0, or 2 after printing the error. */
int render_pt_image(const render_pt_args *a, const scene *s, const char *progressive_pfm, image *img,
                    pt_result *result);

/* JSON fields (no braces) describing a PT render, for the render command's --stats. */
void render_pt_stats_json(FILE *out, const render_pt_args *a, const pt_result *r);

#endif
