/* The real-time ReSTIR PT pipeline (src/frame/pipeline.c; GRIS §6.3 steps 1-4, Mutations
 * Algorithm 2): a sequence of frames with temporal reuse. */
#ifndef RESTIR_FRAME_PIPELINE_H
#define RESTIR_FRAME_PIPELINE_H

#include "restir/core/image.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"

/* Called once per rendered frame, in order: img is frame `frame`'s image (with
 * accumulate: the running average of frames first..frame), st its own counters and
 * timings. Returns 0 to go on, nonzero (with *e set) to stop the sequence. */
typedef int (*restir_frame_sink)(void *user, int frame, const image *img, const restir_stats *st, rerror *e);

typedef struct {
    int first, last;        /* frames first..last inclusive (camera keyframe indices) */
    int accumulate;         /* hand the sink the running average (a still camera, GRIS §6.4 footnote) */
    const char *checkpoint; /* non-NULL: the previous-frame state (the final reservoirs of
                               the frame just rendered: a reservoir dump, tag "sequence") is
                               written here atomically after each frame */
    const char *resume;     /* non-NULL: continue after the frame k stored in this checkpoint
                               (first-1 <= k < last): frames k+1..last come out
                               byte-identical to an uninterrupted run (not with accumulate) */
    int resume_foreign;     /* 1: `resume` is another build's final reservoirs of frame first-1
                               (a stage dump file of any tag: `--history-from-dump`,
                               docs/oracle.md §6), not this program's checkpoint */
    const struct frame_stage_hook_s *stages; /* non-NULL: the stage listener (stage_hook.h),
                                  e.g. per-stage dumps and/or restart (docs/oracle.md) */
} restir_sequence;

/* Renders frames seq->first..last of s with the real-time pipeline: per frame the scene's
 * camera at that frame, G-buffer, initial resampling, temporal reuse against the previous
 * frame's final reservoirs (if o->temporal), o->spatial_passes spatial passes, shading;
 * the spatial output is the next frame's temporal input. Frame f draws the addresses of
 * an offline frame f (docs/restir-pt.md "Random numbers"), plus RNG_VERTEX_TEMPORAL_RIS for
 * the temporal selection. Byte-identical for any thread count. *total sums the frames. */
int restir_render_sequence(const scene *s, const restir_options *o, const restir_sequence *seq,
                           restir_frame_sink sink, void *user, restir_stats *total, rerror *e);

#endif
