/* The reference path tracer: one path per (pixel, sample index), accumulated in double
 * over whole passes of the image (include/restir/render/pt.h, docs/path-tracer.md). */
#include "restir/render/pt.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/progress.h"
#include "restir/core/threads.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/render/light_ris.h"
#include "restir/render/pt_checkpoint.h"
#include "restir/render/pt_state.h"
#include "restir/scene/scene_trace.h"

const char *const pt_strategy_names[] = {"mis", "nee", "bsdf", NULL};
const char *const pt_ablation_names[] = {"light-pdf", "mis-sum", "mis-lobe", "light-ris-pdf", NULL};

unsigned pt_ablation_from_name(const char *name)
{
    unsigned i;
    for (i = 0; pt_ablation_names[i]; ++i)
        if (!strcmp(name, pt_ablation_names[i])) return 1u << i;
    return 0;
}

void pt_options_default(pt_options *o)
{
    memset(o, 0, sizeof *o);
    light_ris_options_default(&o->light_ris);
    o->spp = 16;
    o->seed = 1;
    o->max_depth = 10;
    o->min_depth = 1;
    o->strategy = PT_STRATEGY_MIS;
    o->rr_min_depth = 3;
    o->threads = 1;
    o->quiet = 1;
}

int pt_options_validate(const pt_options *o, rerror *e)
{
    if (o->max_depth < 1 || o->max_depth > PT_MAX_DEPTH_LIMIT)
        return rerror_set(e, "pt: max depth %d is outside 1..%d (path length in segments)", o->max_depth,
                          PT_MAX_DEPTH_LIMIT);
    if (o->min_depth < 1 || o->min_depth > o->max_depth)
        return rerror_set(e, "pt: min depth %d is outside 1..%d (the max depth)", o->min_depth, o->max_depth);
    if (o->threads < 1) return rerror_set(e, "pt: %d threads", o->threads);
    if (o->strategy < PT_STRATEGY_MIS || o->strategy > PT_STRATEGY_BSDF)
        return rerror_set(e, "pt: unknown strategy %d", (int)o->strategy);
    if (o->spp == 0 && !(o->time_limit > 0))
        return rerror_set(e, "pt: give a sample count (spp > 0) or a time limit");
    if (!(o->time_limit >= 0) || !(o->checkpoint_interval >= 0))
        return rerror_set(e, "pt: negative time limit or checkpoint interval");
    if (light_ris_options_validate(&o->light_ris, e)) { /* light RIS's own rules, said by pt */
        char why[sizeof e->msg];
        if (!e) return -1;
        snprintf(why, sizeof why, "%s", e->msg);
        return rerror_set(e, "pt: %s", why);
    }
    if ((uint64_t)o->sample_offset + o->spp > UINT32_MAX)
        return rerror_set(e, "pt: sample indices %u + %u exceed 2^32 - 1", o->sample_offset, o->spp);
    return 0;
}

/* ---- one path ------------------------------------------------------------------- */

typedef struct {
    uint64_t rays, paths, nonfinite;
    uint64_t first_nonfinite; /* (sample << 32) | pixel, UINT64_MAX if none */
    char pad[32];             /* keep workers' counters on separate cache lines */
} worker_stats;

typedef struct {
    const scene *s;
    const pt_options *o;
    camera cam;
    path_context ctx;
    pt_state *st;
    uint32_t first_sample, sample_count; /* absolute sample indices of this pass */
    worker_stats *workers;
    /* With a stop flag: a pass writes each pixel's samples here (pixel-major, sample_count
     * per pixel) and is added to the state only once complete, so SIGINT can cancel it at
     * a tile boundary (threads_set_cancel) and the state keeps whole passes; the same
     * additions in the same order as without staging, so the same bits. NULL: the pass
     * adds to the state directly. */
    real *stage;
    unsigned char *stage_ok;
} pass_job;

/* The emitter at x_{i+1}, reached by BSDF sampling (*s) from x_i, weighted against NEE. */
static rgb emitter_hit(const pass_job *j, const path_vertex *from, const path_vertex *hit, bsdf_bounce *b,
                       const bsdf_sample_record *s, rng_key key, int i)
{
    rgb le = path_vertex_emitted(&j->ctx, hit);
    real p_light = 0;
    if (rgb_is_black(le)) return le;
    b->pdf_all = path_bounce_pdf_all(from, s); /* deferred to here: most bounces reach no emitter */
    if (!b->is_delta && j->ctx.strategy == PT_STRATEGY_MIS)
        p_light = path_light_pdf_hit(&j->ctx, from, hit, key, (uint32_t)i);
    return rgb_scale(le, path_mis_weight_bsdf_hit(&j->ctx, b, p_light));
}

/* A primary ray that leaves the scene sees the sky directly (a path of length 1, no MIS).
 * Out of line: the hot loop of skyless scenes stays as it was. */
#ifdef __GNUC__
__attribute__((noinline, cold))
#endif
static rgb sky_background(const pass_job *j, ray r)
{
    return light_set_has_sky(j->ctx.lights) ? light_distant_radiance(j->ctx.lights, v3_normalize(v3_from_f(r.dir)))
                                            : rgb_gray(0);
}

/* Russian roulette at x_i (RNG_RR, vertex i, slot 0): continue with probability
 * q = min(1, max channel of beta), and divide by q (unbiased). Returns 0 to stop. */
static int roulette_survives(const pass_job *j, rng_key key, int i, rgb *beta)
{
    real q;
    if (!j->o->russian_roulette || i < j->o->rr_min_depth) return 1;
    q = rgb_max(*beta);
    if (q >= 1) return 1;
    if (rng_u(key, RNG_RR, (uint32_t)i, 0) >= q) return 0;
    *beta = rgb_scale(*beta, 1 / q);
    return 1;
}

/* Path sample `sample` of pixel (px, py): the MC estimate L of the pixel's radiance. */
static rgb trace_path(const pass_job *j, int px, int py, uint32_t sample, uint64_t *rays)
{
    const pt_options *o = j->o;
    rng_key key = rng_key_make(o->seed, (uint32_t)(py * j->cam.width + px), sample);
    ray r = primary_ray(&j->cam, px, py, o->seed, sample, o->jitter);
    surface_hit h;
    path_vertex vertices[2], *v = &vertices[0], *next = &vertices[1], *swap;
    rgb L, beta = rgb_gray(1);
    int i;
    ++*rays;
    if (!scene_intersect(j->s, &r, &h)) return o->min_depth <= 1 ? sky_background(j, r) : rgb_gray(0);
    path_vertex_make(v, j->s, &h, v3_from_f(r.dir));
    /* emission at x1 is added directly (docs/design.md, Conventions); it is the path of length 1 */
    L = o->min_depth <= 1 ? path_vertex_emitted(&j->ctx, v) : rgb_gray(0);
    /* At x_i, both NEE and the BSDF bounce make paths of length i + 1 <= max_depth; those
     * shorter than min_depth are traced (the walk needs them) but not counted. */
    for (i = 1; i < o->max_depth; ++i) {
        bsdf_bounce b;
        bsdf_sample_record s;
        int counted = i + 1 >= o->min_depth;
        if (counted && j->ctx.strategy != PT_STRATEGY_BSDF && v->can_nee) {
            nee_sample n;
            int lit = vertex_sample_light(&j->ctx, v, &key, (uint32_t)i, &n);
            *rays += (uint64_t)n.shadow_ray;
            if (lit) L = rgb_add(L, rgb_mul(beta, rgb_scale(n.contribution, path_mis_weight_nee(&j->ctx, n.pdf_light, n.pdf_bsdf))));
        }
        if (!vertex_sample_bsdf(v, &key, (uint32_t)i, &b, &s)) break;
        beta = rgb_mul(beta, b.weight);
        if (rgb_is_black(beta) || !roulette_survives(j, key, i, &beta)) break;
        r = scene_spawn_ray(v->hit.position, v->hit.ng, v3f_from(b.wi), v3f_from(v->wo));
        ++*rays;
        if (scene_intersect(j->s, &r, &h)) path_vertex_make(next, j->s, &h, v3_from_f(r.dir));
        else if (counted && light_set_has_sky(j->ctx.lights)) path_vertex_make_distant(next, b.wi);
        else break;
        /* One call site of emitter_hit (it stays inlined): a surface, or the vertex at
         * infinity along wi when the ray escapes (docs/environment.md), which ends the path. */
        if (counted) L = rgb_add(L, rgb_mul(beta, emitter_hit(j, v, next, &b, &s, key, i)));
        if (path_vertex_is_distant(next)) break;
        swap = v; /* x_{i+1} becomes the current vertex without copying it */
        v = next;
        next = swap;
    }
    return L;
}

/* ---- passes ---------------------------------------------------------------------- */

static int rgb_finite(rgb c) { return isfinite(c.r) && isfinite(c.g) && isfinite(c.b); }

static void record_nonfinite(worker_stats *w, uint32_t pixel, uint32_t sample)
{
    uint64_t id = ((uint64_t)sample << 32) | pixel;
    w->nonfinite++;
    if (id < w->first_nonfinite) w->first_nonfinite = id;
}

static void pass_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    pass_job *j = ctx;
    worker_stats *w = &j->workers[worker];
    int x, y;
    for (y = y0; y < y1; ++y) {
        for (x = x0; x < x1; ++x) {
            uint32_t pixel = (uint32_t)(y * j->cam.width + x), s;
            double *sum = j->st->sum + 3 * (size_t)pixel, *sq = j->st->sum_sq + 3 * (size_t)pixel;
            if (j->stage) { /* the pass's samples of the pixel, kept until the pass is complete */
                for (s = 0; s < j->sample_count; ++s) {
                    size_t slot = (size_t)pixel * j->sample_count + s;
                    rgb L = trace_path(j, x, y, j->first_sample + s, &w->rays);
                    w->paths++;
                    j->stage_ok[slot] = (unsigned char)rgb_finite(L);
                    if (!j->stage_ok[slot]) record_nonfinite(w, pixel, j->first_sample + s);
                    j->stage[3 * slot + 0] = L.r;
                    j->stage[3 * slot + 1] = L.g;
                    j->stage[3 * slot + 2] = L.b;
                }
                continue;
            }
            for (s = j->first_sample; s < j->first_sample + j->sample_count; ++s) {
                rgb L = trace_path(j, x, y, s, &w->rays);
                w->paths++;
                /* NaN/Inf policy (docs/path-tracer.md): counted, reported, accumulated as 0
                 * so that one bad sample cannot erase a pixel; the count stays uniform. */
                if (!rgb_finite(L)) {
                    record_nonfinite(w, pixel, s);
                    continue;
                }
                sum[0] += (double)L.r;
                sum[1] += (double)L.g;
                sum[2] += (double)L.b;
                sq[0] += (double)L.r * (double)L.r;
                sq[1] += (double)L.g * (double)L.g;
                sq[2] += (double)L.b * (double)L.b;
            }
        }
    }
}

/* A staged pass, complete: each pixel's samples added in sample order, as pass_tile adds
 * them without staging (the same sums, bit for bit). */
static void apply_stage(pass_job *j)
{
    size_t p, n = (size_t)j->cam.width * (size_t)j->cam.height;
    uint32_t k;
    for (p = 0; p < n; ++p) {
        double *sum = j->st->sum + 3 * p, *sq = j->st->sum_sq + 3 * p;
        for (k = 0; k < j->sample_count; ++k) {
            size_t slot = p * j->sample_count + k;
            const real *L = j->stage + 3 * slot;
            int c;
            if (!j->stage_ok[slot]) continue;
            for (c = 0; c < 3; ++c) {
                sum[c] += (double)L[c];
                sq[c] += (double)L[c] * (double)L[c];
            }
        }
    }
}

/* Returns 0 if the pass was cancelled (staged passes only): nothing of it is kept. */
static int run_pass(pass_job *j, uint32_t count, pt_result *res)
{
    int t;
    j->first_sample = j->st->sample_offset + j->st->spp;
    j->sample_count = count;
    for (t = 0; t < j->o->threads; ++t) {
        memset(&j->workers[t], 0, sizeof j->workers[t]);
        j->workers[t].first_nonfinite = UINT64_MAX;
    }
    parallel_tiles(j->cam.width, j->cam.height, 16, j->o->threads, pass_tile, j, NULL, NULL);
    if (j->stage) {
        if (threads_cancelled()) return 0;
        apply_stage(j);
    }
    for (t = 0; t < j->o->threads; ++t) {
        const worker_stats *w = &j->workers[t];
        uint64_t first = ((uint64_t)j->st->first_nonfinite_sample << 32) | j->st->first_nonfinite_pixel;
        res->rays += w->rays;
        res->paths += w->paths;
        if (w->nonfinite && (j->st->nonfinite == 0 || w->first_nonfinite < first)) {
            j->st->first_nonfinite_sample = (uint32_t)(w->first_nonfinite >> 32);
            j->st->first_nonfinite_pixel = (uint32_t)(w->first_nonfinite & 0xffffffffu);
        }
        j->st->nonfinite += w->nonfinite;
    }
    j->st->spp += count;
    return 1;
}

/* ---- the render loop ------------------------------------------------------------- */

static int start_state(const scene *s, const pt_options *o, pt_state *st, rerror *e)
{
    uint64_t fp = pt_fingerprint(s, o);
    if (o->resume_path) {
        if (pt_checkpoint_read(o->resume_path, st, e)) return -1;
        if (st->width != s->width || st->height != s->height || st->fingerprint != fp || st->seed != o->seed) {
            /* The message is formatted before the state is freed (it prints the state's fields). */
            rerror_set(e, "%s: checkpoint of a different scene or estimator (size %dx%d, seed %u, "
                          "fingerprint %016llx; this run: %dx%d, seed %u, fingerprint %016llx)",
                       o->resume_path, st->width, st->height, st->seed, (unsigned long long)st->fingerprint,
                       s->width, s->height, o->seed, (unsigned long long)fp);
            pt_state_free(st);
            return -1;
        }
        /* A resumed run continues the checkpoint's sample range; another first sample
         * cannot be honoured, so it is not silently ignored either. */
        if (o->sample_offset != 0 && o->sample_offset != st->sample_offset) {
            rerror_set(e, "%s: the checkpoint holds samples from %u on; --sample-offset %u cannot apply to a resumed run",
                       o->resume_path, st->sample_offset, o->sample_offset);
            pt_state_free(st);
            return -1;
        }
        return 0;
    }
    if (pt_state_alloc(st, s->width, s->height, e)) return -1;
    st->seed = o->seed;
    st->sample_offset = o->sample_offset;
    st->fingerprint = fp;
    return 0;
}

/* Samples per pixel of the next pass: 1 when time or callbacks need a fine granularity;
 * otherwise enough that small images keep the threads busy (at most 65536 paths a pass,
 * also the size of the stage of a cancellable pass). The per-pixel sums do not depend on
 * this choice (samples are added in index order). */
static uint32_t next_pass_size(const pt_options *o, const pt_state *st)
{
    uint32_t remaining, batch = 1;
    long pixels = (long)st->width * st->height;
    uint64_t end = o->spp ? (uint64_t)o->spp : (uint64_t)UINT32_MAX - st->sample_offset;
    remaining = (uint32_t)(end - st->spp);
    if (!(o->time_limit > 0) && o->callback_every == 0 && pixels < 65536) batch = (uint32_t)(65536 / pixels);
    return batch < remaining ? batch : remaining;
}

static int render_done(const pt_options *o, const pt_state *st, double elapsed)
{
    if (o->spp && st->spp >= o->spp) return 1;
    if ((uint64_t)st->sample_offset + st->spp >= UINT32_MAX) return 1;
    return o->time_limit > 0 && elapsed >= o->time_limit;
}

static int render_passes(pass_job *j, pt_result *res, rerror *e)
{
    const pt_options *o = j->o;
    progress bar;
    double t0 = now_seconds(), last_checkpoint = t0;
    long passes = 0;
    volatile sig_atomic_t *old_cancel = threads_set_cancel(j->stage ? o->stop_flag : NULL);
    progress_begin(&bar, "pt", o->quiet);
    if (o->spp) progress_expect(&bar, (long)o->spp);
    while (!render_done(o, j->st, now_seconds() - t0)) {
        uint32_t count;
        if (o->stop_flag && *o->stop_flag) {
            res->stopped = 1;
            break;
        }
        count = next_pass_size(o, j->st);
        if (!run_pass(j, count, res)) { /* cancelled at a tile boundary: the pass is dropped */
            res->stopped = 1;
            break;
        }
        res->spp_added += count;
        passes++;
        if (o->spp) progress_update(&bar, (long)j->st->spp, (long)o->spp);
        else progress_update(&bar, (long)((now_seconds() - t0) * 1000), (long)(o->time_limit * 1000));
        if (o->callback_every > 0 && o->on_passes && passes % o->callback_every == 0) o->on_passes(o->callback_ctx, j->st);
        if (o->checkpoint_path && o->checkpoint_interval > 0 && now_seconds() - last_checkpoint >= o->checkpoint_interval) {
            if (pt_checkpoint_write(o->checkpoint_path, j->st, e)) {
                threads_set_cancel(old_cancel);
                progress_end(&bar);
                return -1;
            }
            last_checkpoint = now_seconds();
        }
    }
    progress_end(&bar);
    threads_set_cancel(old_cancel);
    res->seconds = now_seconds() - t0;
    return 0;
}

void pt_result_free(pt_result *r)
{
    pt_state_free(&r->state);
    image_free(&r->mean);
    memset(r, 0, sizeof *r);
}

int pt_render(const scene *s, const pt_options *o, pt_result *out, rerror *e)
{
    pass_job j;
    light_set lights;
    int status = 0;
    memset(out, 0, sizeof *out);
    if (pt_options_validate(o, e)) return -1;
    if (s->width < 1 || s->height < 1) return rerror_set(e, "%s: image size %dx%d", s->path, s->width, s->height);
    if (lights_build(&lights, s, e)) return -1;
    memset(&j, 0, sizeof j);
    j.s = s;
    j.o = o;
    camera_init(&j.cam, scene_camera_at(s, o->frame), s->width, s->height);
    j.ctx.scene = s;
    j.ctx.lights = &lights;
    j.ctx.strategy = o->strategy;
    j.ctx.ablations = o->ablations;
    j.ctx.light_ris = o->light_ris.candidates;
    j.ctx.light_tiles = o->light_ris.tiles;
    j.ctx.image_width = s->width;
    j.st = &out->state;
    j.workers = rcalloc((size_t)o->threads, sizeof *j.workers, e);
    if (o->stop_flag) { /* staged, cancellable passes: room for the largest (next_pass_size) */
        size_t pixels = (size_t)s->width * (size_t)s->height, slots = pixels < 65536 ? 65536 / pixels * pixels : pixels;
        j.stage = rmalloc(3 * slots, sizeof *j.stage, e);
        j.stage_ok = j.stage ? rmalloc(slots, 1, e) : NULL;
        if (!j.stage_ok) status = -1;
    }
    if (!j.workers || start_state(s, o, &out->state, e)) status = -1;
    if (!status) status = render_passes(&j, out, e);
    /* A state without samples (stopped during the first pass) is no checkpoint to resume. */
    if (!status && o->checkpoint_path && out->state.spp > 0)
        status = pt_checkpoint_write(o->checkpoint_path, &out->state, e);
    if (!status) status = pt_state_mean(&out->state, &out->mean, e);
    free(j.workers);
    free(j.stage);
    free(j.stage_ok);
    lights_free(&lights);
    if (status) pt_result_free(out);
    return status;
}
