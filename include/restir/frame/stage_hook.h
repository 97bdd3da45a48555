/* The hook through which the real-time frame reports its stages (GRIS §6.3 steps 1-4 and
 * the mutation stages of Mutations Algorithm 3) to whoever listens: the golden-oracle kit's
 * stage dumps and restart (oracle/stage_dump.h, stage_io_hook) implement it, the frame
 * never includes the oracle (test house_layers). Every member may be NULL.
 *
 * Order of calls per sequence: begin once; per frame: frame_begin, gbuffer, then per stage
 * `skips` (1: the stage is not computed this frame, its output comes from `reservoirs`),
 * `reservoirs` with the stage's complete output (the listener may dump it or replace it),
 * and frame_end once the frame is shaded. */
#ifndef RESTIR_FRAME_STAGE_HOOK_H
#define RESTIR_FRAME_STAGE_HOOK_H

#include <stdint.h>
#include "restir/core/error.h"
#include "restir/frame/pixel_trace.h"
#include "restir/render/gbuffer.h"
#include "restir/restir/reservoir.h"

typedef struct frame_stage_hook_s {
    void *user;
    int restarts; /* 1: `reservoirs` may replace stage outputs by read ones (a restart), so
                     the frame keeps primary-sample rows in its buffers (reservoir.h) */
    /* frames first..last; pss_rows: the frame's buffers have primary-sample rows */
    int (*begin)(void *user, int first, int last, int pss_rows, rerror *e);
    void (*frame_begin)(void *user, uint32_t frame);
    void (*gbuffer)(void *user, const gbuffer *g);
    int (*skips)(void *user, const char *stage);
    void (*reservoirs)(void *user, const char *stage, reservoir *rs, int width, int height);
    /* o: the frame's const restir_options (frame/options.h), for a manifest */
    int (*frame_end)(void *user, const void *o, rerror *e);
    /* non-NULL: pixel trace_pixel's temporal and spatial steps, each right after the step
       (pixel_trace.h; `restir inspect --from-dump`); called from a worker thread */
    void (*pixel)(void *user, const pixel_trace *t);
    long trace_pixel;
} frame_stage_hook;

#endif
