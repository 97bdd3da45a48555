/* The real-time ReSTIR PT pipeline (GRIS §6.3 steps 1-4; Mutations §2.4 Algorithm 2;
 * include/restir/frame/pipeline.h, restir_render_sequence; docs/restir-pt.md "Temporal reuse").
 *
 *   per frame t:  pose the scene (animated: one of two copies, BVH rebuilt) + camera at t
 *                 G-buffer (primary hits)                         GRIS §6.3 step 1
 *                 motion vectors + disocclusion against t-1 (gbuffer_motion)
 *                 initial resampling -> A                          step 1
 *                 temporal reuse (A, previous final P) -> B        step 2 (temporal.h; in
 *                                                                  animated scenes samples
 *                                                                  crossing frames are re-traced;
 *                                                                  cap lowered by P's duplication
 *                                                                  map with --dedup, Enhanced §5;
 *                                                                  dual MVs, Enhanced §6.4)
 *                 boiling filter on B (--boiling-filter: RTXDI, biased)
 *                 [N MCMC mutations of A, --mutate-after initial]  Mutations §3 (mutate.h)
 *                 [N MCMC mutations of B, default stage]           Mutations Algorithm 3
 *                 K spatial passes B -> A -> B ...                 step 3 (spatial.h)
 *                 [N MCMC mutations of the last output, --mutate-after spatial]
 *                 shading of the last output                       step 4
 *                 duplication map of the last output (Enhanced §5 step 1; docs/correlation.md)
 *                 the last output becomes P, the G-buffer, camera and scene of t are kept
 *
 * The previous frame's state (reservoirs P, G-buffer, camera, restir_context of its posed
 * scene) lives exactly one frame: it is replaced at the end of the next frame. */
#include "restir/frame/pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"
#include "restir/render/motion.h"
#include "restir/restir/boiling_filter.h"
#include "restir/restir/duplication.h"
#include "restir/restir/reservoir_dump.h"
#include "restir/scene/animation.h"
#include "stages.h"

typedef struct {
    frame_job j;            /* the current frame's stages (stages.h) */
    light_set lights;
    reservoir *prev;        /* P: frame t-1's final reservoirs */
    gbuffer prev_g;         /* frame t-1's G-buffer */
    camera cam, prev_cam;
    restir_context prev_ctx; /* frame t-1's scene (posed at t-1) */
    int has_prev, prev_frame;
    scene posed[2];          /* animated scenes: two posed copies, frames t and t-1 alternate */
    int animated, cur_copy;  /* cur_copy: the copy posed at frame t (the other one holds t-1) */
    const reservoir *cur;   /* temporal stage input: the initial reservoirs */
    reservoir *out;         /* temporal stage output; mutation stage in/out */
    uint16_t *dup;          /* duplicate counts of P (Enhanced §5 step 1; duplication.h) */
    uint16_t *age, *prev_age; /* temporal history age of frame t and of P (--aov age) */
    int mutate_stage;       /* enum mutate_stage of the running mutation stage */
} pipeline;

/* ---- reprojection ---------------------------------------------------------------------- */

/* The pixel of frame t-1 where pixel p's x1 was (gbuffer_motion: camera and object motion,
 * disocclusion by the previous G-buffer's object, depth and normal), or -1. Which pixel
 * is chosen depends on G-buffers only, never on reservoirs, so any choice keeps the GRIS
 * step unbiased (it only changes how much the history helps). */
static long reproject(const pipeline *pl, long p, long *standard)
{
    const gbuffer_texel *t = &pl->j.g.texels[p];
    int x, y, w = pl->j.g.width, h = pl->j.g.height;
    int ok = gbuffer_previous_pixel(t, &x, &y);
    *standard = x >= 0 && y >= 0 && x < w && y < h ? (long)y * w + x : -1; /* even if disoccluded */
    if (ok && *standard >= 0) return pl->prev_g.texels[*standard].valid ? *standard : -1;
    /* --motion-vectors dual (Enhanced §6.4): a disoccluded pixel follows its occluder */
    if (pl->j.o->temporal.motion_vectors != RESTIR_MV_DUAL ||
        !gbuffer_dual_previous_pixel(t, pl->j.s, (int)pl->j.frame, &pl->cam, pl->prev_frame, &pl->prev_g, &x, &y))
        return -1;
    return (long)y * w + x;
}

/* The temporal cap at the source pixel q: --mcap, or with --dedup Enhanced §5 step 3,
 * lerp(mcap, c_cap_min, D(q)^alpha) with q's duplication score in frame t-1 (BIASED). */
static real temporal_cap(const pipeline *pl, long q, temporal_stats *st)
{
    const restir_options *o = pl->j.o;
    double cap;
    if (!o->correlation.dedup || q < 0) return (real)o->temporal.mcap;
    cap = duplication_cap(o->temporal.mcap, o->correlation.dedup_min, duplication_score(pl->dup[q], DUPLICATION_RADIUS), o->correlation.dedup_alpha);
    if (cap < o->temporal.mcap) st->dedup_lowered++;
    return (real)cap;
}

/* ---- temporal stage -------------------------------------------------------------------- */

/* `restir inspect --from-dump`: the traced pixel's temporal step (frame/pixel_trace.h); q
 * is the source pixel in the previous frame (-1: none, the step had one domain). */
static void trace_temporal(const pipeline *pl, const worker_state *w, long p, long q, rng_key key, const real *u)
{
    const frame_job *j = &pl->j;
    pixel_trace t;
    long pixels[2];
    const reservoir *in[2];
    temporal_stats unused;
    memset(&unused, 0, sizeof unused);
    pixels[0] = p;
    pixels[1] = q;
    in[0] = &pl->cur[p];
    in[1] = q >= 0 ? &pl->prev[q] : NULL;
    pixel_trace_gris(&t, PIXEL_TRACE_TEMPORAL, "temporal", j->frame, p, -1, key, RNG_VERTEX_TEMPORAL_RIS,
                     (int)restir_step_mis(j->o, j->o->temporal.mis), q >= 0 ? 2 : 1, pixels, in, u, q >= 0 ? &w->ws : NULL,
                     &pl->out[p]);
    t.mcap = temporal_cap(pl, q, &unused);
    j->hook->pixel(j->hook->user, &t);
}

static void temporal_pixel(pipeline *pl, worker_state *w, long p)
{
    frame_job *j = &pl->j;
    const restir_options *o = j->o;
    const restir_context *back = &pl->prev_ctx;
    temporal_frames tf;
    rng_key key = initial_pixel_key(&j->io, o->seed, j->frame, (uint32_t)p);
    path_vertex *v = w->verts;
    long q = -1, standard = -1;
    int dual;
    real u[2];
    pl->age[p] = 0;
    if (!gbuffer_primary_vertex(j->s, &j->g, p, &v[0])) {
        reservoir_init(&pl->out[p]);
        return;
    }
    if (pl->has_prev) q = reproject(pl, p, &standard);
    dual = q >= 0 && q != standard;
    w->st.temporal.dual += (uint64_t)dual;
    pl->age[p] = (uint16_t)(q < 0 ? 0 : pl->prev_age[q] < UINT16_MAX ? pl->prev_age[q] + 1 : UINT16_MAX);
    if (q >= 0 && o->ablation == RESTIR_ABLATE_TEMPORAL_TARGET) {
        /* ablation: the previous pixel's x1 seen with the CURRENT camera in the current scene */
        back = &j->ctx;
        if (!gbuffer_primary_vertex(j->s, &j->g, q, &v[1])) q = -1;
    } else if (dual && o->ablation == RESTIR_ABLATE_DUAL_MV_VERTEX) {
        /* ablation: the dual source's reservoir with the occluder pixel's x1 */
        if (!gbuffer_primary_vertex(pl->prev_ctx.path.scene, &pl->prev_g, standard, &v[1])) q = -1;
    } else if (q >= 0)
        gbuffer_primary_vertex(pl->prev_ctx.path.scene, &pl->prev_g, q, &v[1]); /* valid: reproject checked */
    u[0] = rng_u(key, RNG_RIS, RNG_VERTEX_TEMPORAL_RIS, 0u);
    u[1] = rng_u(key, RNG_RIS, RNG_VERTEX_TEMPORAL_RIS, 1u);
    tf.ctx[0] = &j->ctx;
    tf.ctx[1] = back;
    tf.frame[0] = (int)j->frame;
    tf.frame[1] = back == &j->ctx ? (int)j->frame : pl->prev_frame;
    temporal_resample_mode(&j->ctx, back, pl->animated && o->ablation != RESTIR_ABLATE_TEMPORAL_SUFFIX ? &tf : NULL,
                           restir_step_mis(o, o->temporal.mis), &v[0], q >= 0 ? &v[1] : NULL, &pl->cur[p],
                           q >= 0 ? &pl->prev[q] : NULL, temporal_cap(pl, q, &w->st.temporal), o->temporal.mcap_mode,
                           u, &pl->out[p], &w->ws, &w->st.temporal);
    if (j->hook && j->hook->pixel && j->hook->trace_pixel == p) trace_temporal(pl, w, p, q, key, u);
}

static void temporal_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    pipeline *pl = ctx;
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) temporal_pixel(pl, &pl->j.workers[worker], (long)y * pl->j.s->width + x);
}

/* GRIS §6.3 step 2: cur (this frame's initial reservoirs) and P -> out. */
static void stage_temporal(pipeline *pl, const reservoir *cur, reservoir *out, restir_stats *times, double *t)
{
    pl->cur = cur;
    pl->out = out;
    parallel_tiles(pl->j.s->width, pl->j.s->height, 16, pl->j.o->threads, temporal_tile, pl, NULL, NULL);
    times->ms_temporal += frame_lap_ms(t);
}

/* ---- correlation stages (docs/correlation.md) ------------------------------------------ */

/* --boiling-filter S (RTXDI, Enhanced §7.4 Fig. 9; biased): on the temporal output. */
static void stage_boiling(pipeline *pl, reservoir *rs, restir_stats *times, double *t)
{
    frame_job *j = &pl->j;
    if (!(j->o->correlation.boiling_filter > 0)) return;
    times->boiling_cleared += boiling_filter(rs, j->s->width, j->s->height, BOILING_GROUP, j->o->correlation.boiling_filter);
    pipeline_stage_done(j, "boiling", rs);
    times->ms_correlation += frame_lap_ms(t);
}

/* Enhanced §5 step 1: the duplication map of the frame's final reservoirs (read by the
 * next frame's temporal cap with --dedup) and its summary (--stats "correlation"). */
static void stage_duplication(pipeline *pl, const reservoir *final, restir_stats *times, double *t)
{
    duplication_summary sum;
    long n = (long)pl->j.s->width * pl->j.s->height;
    duplication_counts(final, pl->j.s->width, pl->j.s->height, DUPLICATION_RADIUS, pl->j.o->threads, pl->dup);
    duplication_summarize(pl->dup, n, &sum);
    duplication_summary_add(&times->correlation, &sum);
    times->ms_correlation += frame_lap_ms(t);
}

/* ---- MCMC mutations (Mutations §3 Algorithm 3; mutate.h) ------------------------------- */

/* `restir inspect --from-dump`: the traced pixel's chain, the same numbers as
 * mutate_reservoir's (mutate_reservoir_traced), handed to the listener. */
static void trace_mutation(pipeline *pl, worker_state *w, long p, rng_key key, const path_vertex *v)
{
    frame_job *j = &pl->j;
    pixel_trace t;
    memset(&t, 0, sizeof t);
    mutate_reservoir_traced(&j->ctx, v, key, pl->mutate_stage, &j->o->mutation,
                            &pl->out[p], reservoir_buffer_pss_row(pl->out, (size_t)j->s->width * (size_t)j->s->height,
                                                                  (size_t)p),
                            &w->st.mutate, &t.mutation);
    t.step = PIXEL_TRACE_MUTATION;
    /* the stage the chain's output is dumped as (stage_mutate) */
    snprintf(t.stage, sizeof t.stage, "%s", pl->mutate_stage == MUTATE_AFTER_INITIAL    ? "mutate-initial"
                                            : pl->mutate_stage == MUTATE_AFTER_TEMPORAL ? "mutate-temporal"
                                                                                         : "mutate-spatial");
    t.frame = j->frame;
    t.pixel = p;
    t.pass = -1;
    t.key = key;
    t.mutate_stage = pl->mutate_stage;
    t.selected = -1;
    t.out = pl->out[p];
    j->hook->pixel(j->hook->user, &t);
}

static void mutate_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    pipeline *pl = ctx;
    frame_job *j = &pl->j;
    worker_state *w = &j->workers[worker];
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            long p = (long)y * j->s->width + x;
            rng_key key = initial_pixel_key(&j->io, j->o->seed, j->frame, (uint32_t)p);
            path_vertex v;
            if (!gbuffer_primary_vertex(j->s, &j->g, p, &v)) continue;
            if (j->hook && j->hook->pixel && j->hook->trace_pixel == p) {
                trace_mutation(pl, w, p, key, &v);
                continue;
            }
            mutate_reservoir_opts(&j->ctx, &v, key, pl->mutate_stage, &j->o->mutation, &pl->out[p],
                                  reservoir_buffer_pss_row(pl->out, (size_t)j->s->width * (size_t)j->s->height, (size_t)p),
                                  &w->st.mutate);
        }
}

/* The mutation pass itself (stage_mutate). */
static void mutate_pass(pipeline *pl, reservoir *r, int stage, restir_stats *times, double *t)
{
    pl->out = r;
    pl->mutate_stage = stage;
    parallel_tiles(pl->j.s->width, pl->j.s->height, 16, pl->j.o->threads, mutate_tile, pl, NULL, NULL);
    times->ms_mutate += frame_lap_ms(t);
}

/* N mutations of every pixel's reservoir in r (in place) if the options ask for `stage`:
 * a stage of its own for dumps, restart and diff-dump ("mutate-initial", "mutate-temporal",
 * "mutate-spatial"), reported after the stage it mutates. Returns 1 if the frame was
 * cancelled (the incomplete stage is neither dumped nor used). Without mutations nothing
 * is reported: the stage order and every output stay those of a run without them. */
static int stage_mutate(pipeline *pl, reservoir *r, int stage, restir_stats *times, double *t)
{
    const char *name = stage == MUTATE_AFTER_INITIAL    ? "mutate-initial"
                       : stage == MUTATE_AFTER_TEMPORAL ? "mutate-temporal"
                                                        : "mutate-spatial";
    if (pl->j.o->mutation.count <= 0 || !(pl->j.o->mutation.stages & stage)) return 0;
    if (!pipeline_stage_skipped(&pl->j, name)) mutate_pass(pl, r, stage, times, t);
    if (threads_cancelled()) return 1;
    pipeline_stage_done(&pl->j, name, r);
    return 0;
}

/* ---- the frame ------------------------------------------------------------------------- */

static void swap_reservoirs(reservoir **a, reservoir **b)
{
    reservoir *t = *a;
    *a = *b;
    *b = t;
}

/* The previous-frame state becomes this frame's: final reservoirs, G-buffer, camera, scene. */
static void keep_as_previous(pipeline *pl, const reservoir *final)
{
    frame_job *j = &pl->j;
    if (final == j->initial) swap_reservoirs(&j->initial, &pl->prev);
    else swap_reservoirs(&j->pong, &pl->prev);
    {
        uint16_t *t = pl->age; /* this frame's ages become P's */
        pl->age = pl->prev_age;
        pl->prev_age = t;
    }
    if (!j->o->temporal.enabled) memset(pl->prev_age, 0, (size_t)j->s->width * (size_t)j->s->height * sizeof *pl->prev_age);
    gbuffer_free(&pl->prev_g);
    pl->prev_g = j->g;
    memset(&j->g, 0, sizeof j->g);
    pl->prev_cam = pl->cam;
    pl->prev_ctx = j->ctx;
    pl->prev_frame = (int)j->frame;
    pl->has_prev = 1;
}

/* The scene posed at `frame` (animated scenes: the copy that does not hold frame t-1, so
 * the previous frame's scene stays intact for the reverse shifts) and its context. The
 * BVH rebuild is timed as ms_pose. */
static int pose_frame(pipeline *pl, int frame, rerror *e)
{
    frame_job *j = &pl->j;
    scene *s;
    if (!pl->animated) return 0;
    if (pl->has_prev) pl->cur_copy = 1 - pl->cur_copy; /* the copy of frame t-2 is free */
    s = &pl->posed[pl->cur_copy];
    if (scene_pose_at(s, frame, e)) return -1;
    j->s = s;
    j->ctx.path.scene = s; /* rc.min_distance stays the rest pose's: one criterion for all frames */
    return 0;
}

/* One frame of the real-time pipeline (GRIS §6.3; Mutations Algorithm 2). */
static int pipeline_frame(pipeline *pl, int frame, restir_stats *times, rerror *e)
{
    frame_job *j = &pl->j;
    reservoir *final;
    double t = now_seconds();
    j->frame = (uint32_t)frame;
    if (j->hook && j->hook->frame_begin) j->hook->frame_begin(j->hook->user, j->frame);
    if (pose_frame(pl, frame, e)) return -1;
    times->ms_pose += frame_lap_ms(&t);
    camera_init(&pl->cam, scene_camera_at(j->s, frame), j->s->width, j->s->height);
    if (frame_stage_gbuffer(j, &pl->cam, times, &t, e)) return -1;
    if (threads_cancelled()) return 1;
    if (pl->has_prev &&
        gbuffer_motion(&j->g, j->s, frame, &pl->prev_cam, pl->prev_frame, &pl->prev_g, NULL, j->o->threads, e))
        return -1;
    times->ms_motion += frame_lap_ms(&t);
    if (threads_cancelled()) return 1;
    if (j->hook && j->hook->gbuffer) j->hook->gbuffer(j->hook->user, &j->g);
    if (!pipeline_stage_skipped(j, "initial")) frame_stage_initial(j, times, &t);
    if (threads_cancelled()) return 1; /* before a stage's dump: only complete stages are dumped */
    pipeline_stage_done(j, "initial", j->initial);
    if (stage_mutate(pl, j->initial, MUTATE_AFTER_INITIAL, times, &t)) return 1;
    if (j->o->temporal.enabled) {
        if (!pipeline_stage_skipped(j, "temporal")) stage_temporal(pl, j->initial, j->pong, times, &t);
        if (threads_cancelled()) return 1;
        pipeline_stage_done(j, "temporal", j->pong);
        if (stage_mutate(pl, j->pong, MUTATE_AFTER_TEMPORAL, times, &t)) return 1;
        stage_boiling(pl, j->pong, times, &t);
        final = frame_stage_spatial(j, j->pong, j->initial, times, &t);
    } else {
        stage_boiling(pl, j->initial, times, &t);
        final = frame_stage_spatial(j, j->initial, j->pong, times, &t);
    }
    if (threads_cancelled()) return 1;
    if (threads_cancelled()) return 1;
    if (j->o->spatial_passes > 0 && stage_mutate(pl, final, MUTATE_AFTER_SPATIAL, times, &t)) return 1;
    if (!j->o->no_duplicate_stats) { /* Mutations Fig. 8: duplicated samples among the shaded
       * reservoirs (timed with the duplication map: a statistic of the same kind, not shading) */
        uint64_t valid;
        times->mutate.duplicates += mutate_count_duplicates(final, (size_t)j->s->width * (size_t)j->s->height, &valid);
        times->mutate.final_valid += valid;
        times->ms_correlation += frame_lap_ms(&t);
    }
    frame_stage_shade(j, final, times, &t);
    if (j->shade_cancelled) return 1;
    /* The map is read by the next frame's --dedup cap and by --aov duplicates; otherwise it
     * is only a statistic (13% of a 256² real-time frame: docs/performance.md). */
    if (!j->o->no_duplicate_stats || j->o->correlation.dedup || j->o->output_aov == RESTIR_OUTPUT_DUPLICATES)
        stage_duplication(pl, final, times, &t);
    keep_as_previous(pl, final);
    return 0;
}

/* ---- the sequence ---------------------------------------------------------------------- */

static int validate_sequence(const scene *s, const restir_options *o, const restir_sequence *q, rerror *e)
{
    int a, b;
    if (q->first < 0 || q->last < q->first)
        return rerror_set(e, "restir: sequence %d..%d (need 0 <= first <= last)", q->first, q->last);
    if (scene_frame_range(s, &a, &b) == 0 && (q->first < a || q->last > b))
        return rerror_set(e, "restir: sequence %d..%d outside the keyframes %d..%d of %s", q->first, q->last, a, b,
                          s->path);
    if (q->resume && q->accumulate) return rerror_set(e, "restir: an accumulating sequence cannot be resumed");
    if ((uint64_t)((uint64_t)q->last + 1) * (uint64_t)o->candidates > UINT32_MAX)
        return rerror_set(e, "restir: sequence %d..%d x path trees exceeds 2^32 sample indices", q->first, q->last);
    /* rc_retrace_suffix re-derives a moved x_k's light point with the plain light sampler */
    if (o->light_ris.candidates > 0 && scene_is_animated(s))
        return rerror_set(e, "restir: light RIS in a sequence needs a static scene (%s has moving objects; "
                             "docs/enhanced.md section 6)", s->path);
    return 0;
}

static void stats_reset_workers(frame_job *j)
{
    int t;
    for (t = 0; t < j->o->threads; ++t) memset(&j->workers[t].st, 0, sizeof j->workers[t].st);
}

/* The frame's image: sum / n (n = 1, or the frames accumulated so far). */
static int frame_image(const frame_job *j, double n, image *img, rerror *e)
{
    size_t i, count = 3 * (size_t)j->s->width * (size_t)j->s->height;
    if (image_alloc(img, j->s->width, j->s->height, e)) return -1;
    for (i = 0; i < count; ++i) img->px[i] = (float)(j->sum[i] / n);
    return 0;
}

/* --aov duplicates|age: the frame's duplicate counts (0..288) or history ages (P's: the
 * frame just rendered) in all three channels. */
static int count_image(const pipeline *pl, const uint16_t *v, image *img, rerror *e)
{
    size_t i, pixels = (size_t)pl->j.s->width * (size_t)pl->j.s->height;
    if (image_alloc(img, pl->j.s->width, pl->j.s->height, e)) return -1;
    for (i = 0; i < 3 * pixels; ++i) img->px[i] = (float)v[i / 3];
    return 0;
}

/* ---- checkpoints: the previous-frame state ---------------------------------------------- */

/* The state frame t+1 needs from frame t is its final reservoirs (written as a reservoir
 * dump, docs/formats.md, tag "sequence", frame = t) plus its G-buffer, camera and posed
 * scene, which are pure functions of (scene, t, options) and are rebuilt on resume. */
static int checkpoint_write(const pipeline *pl, const char *path, int frame, rerror *e)
{
    reservoir_dump_info info;
    memset(&info, 0, sizeof info);
    info.width = (uint32_t)pl->j.s->width;
    info.height = (uint32_t)pl->j.s->height;
    info.frame = (uint32_t)frame;
    strcpy(info.tag, "sequence");
    return reservoir_dump_write(path, pl->prev, &info, e);
}

/* Loads frame k's state from the checkpoint q->resume; returns k (first frame to render is k + 1). */
static int checkpoint_resume(pipeline *pl, const restir_sequence *q, rerror *e)
{
    frame_job *j = &pl->j;
    reservoir_dump_info info;
    reservoir *rs;
    size_t pixels = (size_t)j->s->width * (size_t)j->s->height;
    int k;
    if (reservoir_dump_read(q->resume, &rs, &info, e)) return -1;
    k = (int)info.frame;
    if ((q->resume_foreign ? k != q->first - 1 : strcmp(info.tag, "sequence") != 0) ||
        info.width != (uint32_t)j->s->width || info.height != (uint32_t)j->s->height || k < q->first - 1 ||
        k >= q->last) {
        if (q->resume_foreign) {
            free(rs);
            return rerror_set(e, "%s: not frame %d's final state of this %dx%d sequence (tag '%s', %ux%u, frame %d)",
                              q->resume, q->first - 1, j->s->width, j->s->height, info.tag, info.width, info.height, k);
        }
        free(rs);
        return rerror_set(e, "%s: not a checkpoint of this sequence (tag '%s', %ux%u, frame %d; want %dx%d, frame in %d..%d)",
                          q->resume, info.tag, info.width, info.height, k, j->s->width, j->s->height,
                          q->first - 1, q->last - 1);
    }
    if (q->resume_foreign) { /* an infinite W would poison every later frame (as a restart refuses it) */
        size_t i;
        for (i = 0; i < pixels; ++i)
            if (!isfinite((double)rs[i].W) || !isfinite((double)rs[i].wsum) || !isfinite((double)rs[i].confidence)) {
                long x = (long)(i % (size_t)j->s->width), y = (long)(i / (size_t)j->s->width);
                free(rs);
                return rerror_set(e, "%s: pixel (%ld, %ld): W, wsum or confidence is not finite", q->resume, x, y);
            }
    }
    memcpy(pl->prev, rs, pixels * sizeof *rs);
    reservoir_buffer_keep_pss(pl->prev, pixels, j->o->threads); /* the numbers, before rs's rows are freed */
    free(rs);
    duplication_counts(pl->prev, j->s->width, j->s->height, DUPLICATION_RADIUS, j->o->threads, pl->dup); /* --dedup reads it */
    j->frame = (uint32_t)k;
    if (pose_frame(pl, k, e)) return -1;
    camera_init(&pl->prev_cam, scene_camera_at(j->s, k), j->s->width, j->s->height);
    if (gbuffer_build(&pl->prev_g, j->s, &pl->prev_cam, j->o->seed, initial_tree_sample(&j->io, (uint32_t)k, 0),
                      j->o->jitter, j->o->threads, e))
        return -1;
    pl->prev_ctx = j->ctx;
    pl->prev_frame = k;
    pl->has_prev = 1;
    return k;
}

static int run_sequence(pipeline *pl, const restir_sequence *q, restir_frame_sink sink, void *user,
                        restir_stats *total, rerror *e)
{
    frame_job *j = &pl->j;
    size_t pixels = (size_t)j->s->width * (size_t)j->s->height;
    progress bar;
    volatile sig_atomic_t *cancel;
    int f, status = 0, start = q->first;
    if (q->resume && (start = checkpoint_resume(pl, q, e) + 1) < 1) return -1;
    if (j->hook && j->hook->begin && j->hook->begin(j->hook->user, start, q->last, j->pss_rows, e)) return -1;
    if (j->hook && j->hook->restarts && j->o->shading == RESTIR_SHADING_VECTOR)
        return rerror_set(e, "restir: a restart from a stage dump cannot use vector shading (it needs the last "
                             "spatial pass's inputs, which a restart does not compute)");
    cancel = threads_set_cancel(j->o->stop_flag);
    progress_begin(&bar, "restir", j->o->quiet);
    progress_expect(&bar, q->last - q->first + 1);
    for (f = start; f <= q->last && !status && !(j->o->stop_flag && *j->o->stop_flag); ++f) {
        restir_stats st;
        image img;
        int frame_status;
        memset(&st, 0, sizeof st);
        if (!q->accumulate) memset(j->sum, 0, 3 * pixels * sizeof *j->sum);
        frame_status = pipeline_frame(pl, f, &st, e);
        if (frame_status < 0) {
            threads_set_cancel(cancel);
            progress_end(&bar);
            return -1;
        }
        if (frame_status > 0) break; /* cancelled at a tile boundary: frame f is not written */
        if (j->hook && j->hook->frame_end && j->hook->frame_end(j->hook->user, j->o, e)) {
            threads_set_cancel(cancel);
            progress_end(&bar);
            return -1;
        }
        frame_sum_stats(j, &st);
        stats_reset_workers(j);
        st.frames = 1;
        st.passes = j->o->spatial_passes;
        if (j->o->output_aov ? count_image(pl, j->o->output_aov == RESTIR_OUTPUT_AGE ? pl->prev_age : pl->dup, &img, e)
                             : frame_image(j, q->accumulate ? (double)(f - q->first + 1) : 1.0, &img, e)) {
            threads_set_cancel(cancel);
            progress_end(&bar);
            return -1;
        }
        st.nonfinite_pixels = image_nonfinite_pixels(&img); /* kept, counted (docs/precision.md) */
        restir_stats_add(total, &st);
        if (sink) status = sink(user, f, &img, &st, e);
        image_free(&img);
        if (!status && q->checkpoint && checkpoint_write(pl, q->checkpoint, f, e)) status = -1;
        progress_update(&bar, f - q->first + 1, q->last - q->first + 1);
    }
    progress_end(&bar);
    threads_set_cancel(cancel);
    return status ? -1 : 0;
}

int restir_render_sequence(const scene *s, const restir_options *o, const restir_sequence *q,
                           restir_frame_sink sink, void *user, restir_stats *total, rerror *e)
{
    pipeline pl;
    frame_job *j = &pl.j;
    reuse_texture textures[PAIRING_MAX_TEXTURES]; /* --pairing paired */
    size_t pixels;
    int status = 0;
    memset(total, 0, sizeof *total);
    if (restir_options_validate(o, e) || validate_sequence(s, o, q, e)) return -1;
    if (s->width < 1 || s->height < 1) return rerror_set(e, "%s: image size %dx%d", s->path, s->width, s->height);
    memset(&pl, 0, sizeof pl);
    pl.animated = scene_is_animated(s);
    if (pl.animated && (scene_clone(&pl.posed[0], s, e) || scene_clone(&pl.posed[1], s, e))) {
        scene_free(&pl.posed[0]);
        return -1;
    }
    /* lights are static (animation.h): one light set from the rest pose serves every frame */
    if (lights_build(&pl.lights, s, e)) status = -1;
    j->s = s;
    j->o = o;
    j->temporal = o->temporal.enabled;
    j->hook = q->stages;
    restir_context_for(&j->ctx, s, &pl.lights, o);
    pl.prev_ctx = j->ctx;
    restir_initial_options_for(&j->io, o);
    spatial_neighbor_options(&j->no, &o->spatial);
    if (!status && restir_pairing_build(&j->no, o, textures, e)) status = -1;
    j->max_domains = neighbor_candidate_count(&j->no) + 1;
    pixels = (size_t)s->width * (size_t)s->height;
    /* primary-sample rows (reservoir.h) where samples with explicit numbers can appear:
     * mutations, or reservoirs read from a checkpoint or a stage dump */
    j->pss_rows = o->mutation.count > 0 || q->resume || (q->stages && q->stages->restarts);
    j->initial = reservoir_buffer_alloc(pixels, j->pss_rows, e);
    j->pong = reservoir_buffer_alloc(pixels, j->pss_rows, e);
    pl.prev = reservoir_buffer_alloc(pixels, j->pss_rows, e);
    j->sum = rcalloc(3 * pixels, sizeof *j->sum, e);
    pl.dup = rcalloc(pixels, sizeof *pl.dup, e);
    pl.age = rcalloc(pixels, sizeof *pl.age, e);
    pl.prev_age = rcalloc(pixels, sizeof *pl.prev_age, e);
    if (o->shading == RESTIR_SHADING_VECTOR && o->spatial_passes > 0 &&
        !(j->vector_shade = rcalloc(pixels, sizeof *j->vector_shade, e)))
        status = -1;
    if (status || !j->initial || !j->pong || !pl.prev || !j->sum || !pl.dup || !pl.age || !pl.prev_age || frame_workers_alloc(j, e)) status = -1;
    if (!status) status = run_sequence(&pl, q, sink, user, total, e);
    if (!status) total->passes = o->spatial_passes;
    if (!status) restir_memory_per_pixel(o, 1, &total->memory);
    free(j->initial);
    free(j->pong);
    free(pl.prev);
    free(j->sum);
    free(pl.dup);
    free(pl.age);
    free(pl.prev_age);
    free(j->vector_shade);
    gbuffer_free(&j->g);
    gbuffer_free(&pl.prev_g);
    frame_workers_free(j);
    restir_pairing_free(&j->no);
    lights_free(&pl.lights);
    if (pl.animated) {
        scene_free(&pl.posed[0]);
        scene_free(&pl.posed[1]);
    }
    return status;
}
