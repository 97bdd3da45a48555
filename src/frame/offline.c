/* The offline ReSTIR PT renderer (GRIS §6.5): initial resampling, K spatial passes
 * (GRIS §6.3 step 3), shading, frames averaged with GRIS Eq. 47 (include/restir/frame/offline.h). */
#include "restir/frame/offline.h"

#include <stdlib.h>
#include <string.h>
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "stages.h"

/* One independent offline frame: G-buffer, initial resampling, K spatial passes, shading
 * (GRIS §6.3 steps 1, 3, 4; no temporal reuse: GRIS §6.5). Returns 0, -1 on failure, or 1
 * if SIGINT/SIGTERM cancelled it at a tile boundary (threads_set_cancel): then nothing of
 * the frame reached the sum. */
static int render_frame(frame_job *j, const camera *cam, restir_stats *times, rerror *e)
{
    double t = now_seconds();
    reservoir *final;
    if (frame_stage_gbuffer(j, cam, times, &t, e)) return -1;
    if (!threads_cancelled()) frame_stage_initial(j, times, &t);
    final = threads_cancelled() ? NULL : frame_stage_spatial(j, j->initial, j->pong, times, &t);
    if (final) frame_stage_shade(j, final, times, &t); /* it checks the cancel flag itself */
    gbuffer_free(&j->g);
    return j->shade_cancelled || !final ? 1 : 0;
}

void restir_result_free(restir_result *r)
{
    image_free(&r->mean);
    free(r->reservoirs);
    memset(r, 0, sizeof *r);
}

/* Frames f = first_frame, first_frame + 1, ...: `frames` of them, or (time_limit > 0)
 * until the time is up; a set stop_flag cancels the frame in progress at a tile boundary
 * (threads_set_cancel) and ends the render with the frames complete so far (maybe none).
 * Returns the number rendered, -1 on failure. */
static long render_frames(frame_job *j, restir_stats *times, double t0, rerror *e)
{
    const restir_options *o = j->o;
    camera cam;
    progress bar;
    long f;
    uint64_t max_frames = (uint64_t)UINT32_MAX / (uint64_t)o->candidates - (uint64_t)o->first_frame;
    volatile sig_atomic_t *old_cancel;
    int status = 0;
    camera_init(&cam, scene_camera_at(j->s, 0), j->s->width, j->s->height);
    old_cancel = threads_set_cancel(o->stop_flag);
    progress_begin(&bar, "restir", o->quiet || o->time_limit > 0);
    progress_expect(&bar, o->frames);
    for (f = 0;; ++f) {
        if (o->time_limit > 0 ? (f > 0 && now_seconds() - t0 >= o->time_limit) : f >= o->frames) break;
        if ((uint64_t)f >= max_frames || (o->stop_flag && *o->stop_flag)) break;
        j->frame = (uint32_t)(o->first_frame + f);
        status = render_frame(j, &cam, times, e);
        if (status) break; /* -1: failed; 1: cancelled, the frame is not counted */
        if (o->time_limit <= 0) progress_update(&bar, (int)f + 1, o->frames);
    }
    progress_end(&bar);
    threads_set_cancel(old_cancel);
    return status < 0 ? -1 : f;
}

static int run_frames(frame_job *j, restir_result *out, double t0, rerror *e)
{
    const restir_options *o = j->o;
    size_t pixels = (size_t)j->s->width * (size_t)j->s->height, i;
    long frames = render_frames(j, &out->stats, t0, e);
    if (frames < 0) return -1;
    out->stats.frames = (uint64_t)frames;
    if (image_alloc(&out->mean, j->s->width, j->s->height, e)) return -1;
    /* GRIS Eq. 47; no frame (stopped during the first): a black image with frames = 0,
     * which the caller must not present as a result */
    for (i = 0; i < 3 * pixels; ++i) out->mean.px[i] = frames ? (float)(j->sum[i] / (double)frames) : 0.0f;
    out->stats.nonfinite_pixels = image_nonfinite_pixels(&out->mean); /* kept, counted (docs/precision.md) */
    if (o->keep_reservoirs) {
        out->reservoirs = rmalloc(pixels, sizeof *out->reservoirs, e);
        if (!out->reservoirs) return -1;
        memcpy(out->reservoirs, j->final, pixels * sizeof *out->reservoirs);
    }
    return 0;
}

int restir_render(const scene *s, const restir_options *o, restir_result *out, rerror *e)
{
    reuse_texture textures[PAIRING_MAX_TEXTURES];
    frame_job j;
    light_set lights;
    size_t pixels;
    double t0 = now_seconds();
    int status = 0;
    memset(out, 0, sizeof *out);
    if (restir_options_validate(o, e)) return -1;
    if (s->width < 1 || s->height < 1) return rerror_set(e, "%s: image size %dx%d", s->path, s->width, s->height);
    if (lights_build(&lights, s, e)) return -1;
    memset(&j, 0, sizeof j);
    j.s = s;
    j.o = o;
    restir_context_for(&j.ctx, s, &lights, o);
    restir_initial_options_for(&j.io, o);
    spatial_neighbor_options(&j.no, &o->spatial);
    if (restir_pairing_build(&j.no, o, textures, e)) {
        lights_free(&lights);
        return -1;
    }
    j.max_domains = neighbor_candidate_count(&j.no) + 1;
    pixels = (size_t)s->width * (size_t)s->height;
    j.initial = rmalloc(pixels, sizeof *j.initial, e);
    j.pong = o->spatial_passes > 0 ? rmalloc(pixels, sizeof *j.pong, e) : NULL;
    j.sum = rcalloc(3 * pixels, sizeof *j.sum, e);
    if (o->shading == RESTIR_SHADING_VECTOR && o->spatial_passes > 0 &&
        !(j.vector_shade = rcalloc(pixels, sizeof *j.vector_shade, e)))
        status = -1;
    if (!j.initial || (o->spatial_passes > 0 && !j.pong) || !j.sum || frame_workers_alloc(&j, e)) status = -1;
    if (!status) status = run_frames(&j, out, t0, e);
    if (!status) {
        frame_sum_stats(&j, &out->stats);
        out->stats.passes = o->spatial_passes;
        restir_memory_per_pixel(o, 0, &out->stats.memory);
        out->seconds = now_seconds() - t0;
    }
    free(j.initial);
    free(j.pong);
    free(j.sum);
    free(j.vector_shade);
    frame_workers_free(&j);
    restir_pairing_free(&j.no);
    lights_free(&lights);
    if (status) restir_result_free(out);
    return status;
}
