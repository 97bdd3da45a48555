/* Private to src/cli. Replaying one stage of a dump on its own inputs (docs/oracle.md §6):
 * `restir render ... --history-from-dump` and the one-pixel trace `restir inspect
 * --from-dump` installs around a render (cmd_replay.c). */
#ifndef RESTIR_CLI_RENDER_REPLAY_H
#define RESTIR_CLI_RENDER_REPLAY_H

#include "restir/frame/pixel_trace.h"
#include "render_args.h"

/* A pixel to trace (frame/pixel_trace.h) in the next render: fn(user, t) after each of its
 * temporal and spatial steps. */
typedef struct {
    long pixel;
    void (*fn)(void *user, const pixel_trace *t);
    /* the pixel's record of each complete stage output (after a mutation inside the stage) */
    void (*stage_output)(void *user, const char *stage, const reservoir *r);
    void *user;
} render_trace_request;

/* Set by cmd_replay.c for the duration of one cmd_render call (the CLI is single-threaded
 * outside the renderer), NULL otherwise. */
extern const render_trace_request *render_trace;

/* After the stage options: --history-from-dump (needs --from-dump DIR and --sequence A..B
 * with A >= 1: frame A-1's final reservoirs are DIR's frame A-1 file of the last stage of
 * its stage order, read as the previous frame's state) and the pending trace request.
 * Prints the error and returns 2, or 0. */
int apply_replay_options(render_args *a);

#endif
