/* Real-time sequences in tests: K runs of restir_render_sequence to a frame sink, or one
 * run with a copy of every frame's image. */
#ifndef RESTIR_TESTS_SEQUENCE_UTIL_H
#define RESTIR_TESTS_SEQUENCE_UTIL_H

#include "restir/core/image.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"
#include "restir/scene/scene.h"

/* K sequences first..last of the real-time pipeline (restir_render_sequence), run k with the
 * seed o->seed + 7919 k, every frame to sink(user, ...); *run0 (may be NULL) receives run 0's
 * totals. 0 on success (a test failure is recorded otherwise). */
int rt_sequence_runs(const scene *s, const restir_options *o, int first, int last, int runs, restir_frame_sink sink,
                     void *user, restir_stats *run0);

/* One sequence first..last of the real-time pipeline (restir_render_sequence with o) and a
 * copy of every frame's image: frame f into img[f - first] (last - first + 1 entries;
 * image_free each). 0 on success (a test failure is recorded otherwise, and nothing is
 * left allocated). */
int rt_sequence_images(const scene *s, const restir_options *o, int first, int last, image *img);

#endif
