/* The ReSTIR PT renderer, part 1: initial resampling, one optional two-domain spatial
 * pass, shading, frames averaged (include/restir/restir.h). */
#include "restir/restir.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/camera.h"
#include "restir/connectability.h"
#include "restir/gbuffer.h"
#include "restir/progress.h"
#include "restir/threads.h"

const char *const restir_paths_names[] = {"all", "indirect", NULL};
const char *const restir_mis_names[] = {"talbot", NULL};

void restir_options_default(restir_options *o)
{
    memset(o, 0, sizeof *o);
    o->shift = RESTIR_SHIFT_HYBRID;
    o->spatial_passes = 0;
    o->neighbors = 1;
    o->radius = 10;
    o->mis = 0;
    o->frames = 1;
    o->candidates = 1;
    o->max_depth = 10;
    o->roughness_threshold = 0.2;
    o->distance_threshold = 0.02;
    o->paths = RESTIR_PATHS_ALL;
    o->rr_min_depth = 3;
    o->seed = 1;
    o->threads = 1;
    o->quiet = 1;
}

int restir_options_validate(const restir_options *o, rerror *e)
{
    int min_depth = o->paths == RESTIR_PATHS_INDIRECT ? 3 : 2;
    if (o->shift < 0 || o->shift >= RESTIR_SHIFT_COUNT) return rerror_set(e, "restir: unknown shift %d", o->shift);
    if (o->spatial_passes < 0 || o->spatial_passes > 1)
        return rerror_set(e, "restir: %d spatial passes (this version supports 0 or 1)", o->spatial_passes);
    if (o->neighbors != 1) return rerror_set(e, "restir: %d neighbours (this version supports 1)", o->neighbors);
    if (o->mis != 0) return rerror_set(e, "restir: only --mis talbot is supported by the two-domain merge");
    if (!(o->radius >= 1) || !(o->radius <= 4096)) return rerror_set(e, "restir: radius %g outside [1, 4096]", o->radius);
    if (o->frames < 1) return rerror_set(e, "restir: %d frames", o->frames);
    if (o->first_frame < 0) return rerror_set(e, "restir: first frame %d < 0", o->first_frame);
    if (o->candidates < 1 || o->candidates > 1 << 16)
        return rerror_set(e, "restir: %d path trees (1..65536)", o->candidates);
    if ((uint64_t)(o->first_frame + (uint64_t)o->frames) * (uint64_t)o->candidates > UINT32_MAX)
        return rerror_set(e, "restir: frame range x path trees exceeds 2^32 sample indices");
    if (o->max_depth < min_depth || o->max_depth > PATH_MAX_LENGTH)
        return rerror_set(e, "restir: max depth %d outside %d..%d", o->max_depth, min_depth, PATH_MAX_LENGTH);
    if (!(o->roughness_threshold >= 0) || !(o->distance_threshold >= 0))
        return rerror_set(e, "restir: negative (or NaN) roughness or distance threshold");
    if (o->paths != RESTIR_PATHS_ALL && o->paths != RESTIR_PATHS_INDIRECT)
        return rerror_set(e, "restir: unknown --paths %d", o->paths);
    if (o->ablation < 0 || o->ablation >= RESTIR_ABLATION_COUNT)
        return rerror_set(e, "restir: unknown ablation %d", o->ablation);
    if (o->threads < 1) return rerror_set(e, "restir: %d threads", o->threads);
    return 0;
}

void restir_context_for(restir_context *c, const scene *s, const light_set *lights, const restir_options *o)
{
    memset(c, 0, sizeof *c);
    c->path.scene = s;
    c->path.lights = lights;
    c->path.strategy = PT_STRATEGY_MIS;
    c->path.ablations = 0;
    c->shift = o->shift;
    c->rc.roughness_threshold = (real)o->roughness_threshold;
    c->rc.min_distance = rc_min_distance_for_scene(s, (real)o->distance_threshold);
    c->ablation = o->ablation;
}

void restir_initial_options_for(initial_options *io, const restir_options *o)
{
    io->trees = o->candidates;
    io->max_depth = o->max_depth;
    io->indirect_only = o->paths == RESTIR_PATHS_INDIRECT;
    io->russian_roulette = o->russian_roulette;
    io->rr_min_depth = o->rr_min_depth;
}

/* ---- passes ------------------------------------------------------------------------ */

typedef struct {
    restir_stats st;
    char pad[64]; /* keep workers' counters on separate cache lines */
} worker_stats;

typedef struct {
    const scene *s;
    const restir_options *o;
    restir_context ctx;
    initial_options io;
    gbuffer g;
    uint32_t frame;
    reservoir *initial, *spatial; /* per pixel: initial output, spatial output */
    const reservoir *final;      /* what the frame shades */
    double *sum;                 /* 3 per pixel */
    worker_stats *workers;
} frame_job;

/* x1 of pixel p as the path sampler builds it from the frame's primary ray. */
static int primary_vertex(const frame_job *j, long p, path_vertex *v)
{
    const gbuffer_texel *t = &j->g.texels[p];
    if (!t->valid) return 0;
    path_vertex_make(v, j->s, &t->hit, v3_from_f(t->view_dir));
    return 1;
}

static void initial_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            long p = (long)y * j->s->width + x;
            path_vertex v;
            if (!primary_vertex(j, p, &v)) {
                reservoir_init(&j->initial[p]);
                continue;
            }
            initial_sample_pixel(&j->ctx, &j->io, &v, j->o->seed, (uint32_t)p, j->frame, &j->initial[p],
                                 &j->workers[worker].st.initial);
        }
}

/* A neighbour uniformly in the disk of the given radius (RNG_NEIGHBOR), rounded to a
 * pixel; -1 if that is the pixel itself or lies outside the image. The choice does not
 * depend on any sample, so any rule keeps the merge unbiased. */
static long pick_neighbor(const frame_job *j, int x, int y, int pass)
{
    rng_key key = rng_key_make(j->o->seed, (uint32_t)((long)y * j->s->width + x), j->frame);
    real r = (real)j->o->radius * (real)sqrt(rng_u(key, RNG_NEIGHBOR, (uint32_t)pass, 0));
    real phi = 2 * PI_R * rng_u(key, RNG_NEIGHBOR, (uint32_t)pass, 1);
    int nx = x + (int)lround(r * cos(phi)), ny = y + (int)lround(r * sin(phi));
    if ((nx == x && ny == y) || nx < 0 || ny < 0 || nx >= j->s->width || ny >= j->s->height) return -1;
    return (long)ny * j->s->width + nx;
}

static void spatial_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    merge_stats *st = &j->workers[worker].st.merge;
    int x, y, pass = 0;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            long p = (long)y * j->s->width + x, n;
            path_vertex vc, vn;
            rng_key key = rng_key_make(j->o->seed, (uint32_t)p, initial_tree_sample(&j->io, j->frame, 0));
            if (!primary_vertex(j, p, &vc)) {
                reservoir_init(&j->spatial[p]);
                continue;
            }
            n = pick_neighbor(j, x, y, pass);
            if (n < 0 || !primary_vertex(j, n, &vn)) {
                st->no_neighbor++;
                j->spatial[p] = j->initial[p];
                continue;
            }
            merge_two_domains(&j->ctx, &vc, &j->initial[p], &vn, &j->initial[n],
                              rng_u(key, RNG_RIS, 0, (uint32_t)(2 * pass)),
                              rng_u(key, RNG_RIS, 0, (uint32_t)(2 * pass + 1)), &j->spatial[p], st);
        }
}

static void shade_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    frame_job *j = ctx;
    int x, y;
    (void)worker;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            long p = (long)y * j->s->width + x;
            path_vertex v;
            rgb L;
            if (!primary_vertex(j, p, &v)) continue;
            /* Emission at x1 is added, never resampled (DESIGN §3); F(Y) W_Y is GRIS Eq. 3. */
            L = reservoir_estimate(&j->final[p]);
            if (j->o->paths == RESTIR_PATHS_ALL) L = rgb_add(path_vertex_emitted(&j->ctx.path, &v), L);
            j->sum[3 * p + 0] += (double)L.r;
            j->sum[3 * p + 1] += (double)L.g;
            j->sum[3 * p + 2] += (double)L.b;
        }
}

static int render_frame(frame_job *j, const camera *cam, rerror *e)
{
    const restir_options *o = j->o;
    if (gbuffer_build(&j->g, j->s, cam, o->seed, initial_tree_sample(&j->io, j->frame, 0), o->jitter, o->threads, e))
        return -1;
    parallel_tiles(j->s->width, j->s->height, 16, o->threads, initial_tile, j, NULL, NULL);
    j->final = j->initial;
    if (o->spatial_passes > 0) {
        parallel_tiles(j->s->width, j->s->height, 16, o->threads, spatial_tile, j, NULL, NULL);
        j->final = j->spatial;
    }
    parallel_tiles(j->s->width, j->s->height, 16, o->threads, shade_tile, j, NULL, NULL);
    gbuffer_free(&j->g);
    return 0;
}

static void sum_stats(const frame_job *j, restir_stats *st)
{
    int t;
    for (t = 0; t < j->o->threads; ++t) {
        initial_stats_add(&st->initial, &j->workers[t].st.initial);
        merge_stats_add(&st->merge, &j->workers[t].st.merge);
    }
}

void restir_result_free(restir_result *r)
{
    image_free(&r->mean);
    free(r->reservoirs);
    memset(r, 0, sizeof *r);
}

static int run_frames(frame_job *j, restir_result *out, rerror *e)
{
    const restir_options *o = j->o;
    camera cam;
    progress bar;
    size_t pixels = (size_t)j->s->width * (size_t)j->s->height, i;
    int f;
    camera_init(&cam, scene_camera_at(j->s, 0), j->s->width, j->s->height);
    progress_begin(&bar, "restir", o->quiet);
    for (f = 0; f < o->frames; ++f) {
        j->frame = (uint32_t)(o->first_frame + f);
        if (render_frame(j, &cam, e)) return -1;
        progress_update(&bar, f + 1, o->frames);
    }
    progress_end(&bar);
    if (image_alloc(&out->mean, j->s->width, j->s->height, e)) return -1;
    for (i = 0; i < 3 * pixels; ++i) out->mean.px[i] = (float)(j->sum[i] / o->frames); /* GRIS Eq. 47 */
    if (o->keep_reservoirs) {
        out->reservoirs = rmalloc(pixels, sizeof *out->reservoirs, e);
        if (!out->reservoirs) return -1;
        memcpy(out->reservoirs, j->final, pixels * sizeof *out->reservoirs);
    }
    return 0;
}

int restir_render(const scene *s, const restir_options *o, restir_result *out, rerror *e)
{
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
    pixels = (size_t)s->width * (size_t)s->height;
    j.initial = rmalloc(pixels, sizeof *j.initial, e);
    j.spatial = o->spatial_passes > 0 ? rmalloc(pixels, sizeof *j.spatial, e) : NULL;
    j.sum = rcalloc(3 * pixels, sizeof *j.sum, e);
    j.workers = rcalloc((size_t)o->threads, sizeof *j.workers, e);
    if (!j.initial || (o->spatial_passes > 0 && !j.spatial) || !j.sum || !j.workers) status = -1;
    if (!status) status = run_frames(&j, out, e);
    if (!status) {
        sum_stats(&j, &out->stats);
        out->stats.frames = (uint64_t)o->frames;
        out->seconds = now_seconds() - t0;
    }
    free(j.initial);
    free(j.spatial);
    free(j.sum);
    free(j.workers);
    lights_free(&lights);
    if (status) restir_result_free(out);
    return status;
}

/* ---- statistics ---------------------------------------------------------------------- */

static void write_histogram(FILE *out, const uint64_t *h, int n)
{
    int i;
    fputc('[', out);
    for (i = 0; i < n; ++i) fprintf(out, "%s%llu", i ? ", " : "", (unsigned long long)h[i]);
    fputc(']', out);
}

void restir_stats_write_json(FILE *out, const restir_stats *st, const char *indent)
{
    const initial_stats *in = &st->initial;
    const merge_stats *m = &st->merge;
    int i;
    fprintf(out, "{\n%s  \"frames\": %llu,\n", indent, (unsigned long long)st->frames);
    fprintf(out, "%s  \"initial\": {\"pixels\": %llu, \"trees\": %llu, \"candidates\": %llu, \"selected\": %llu, ",
            indent, (unsigned long long)in->pixels, (unsigned long long)in->trees,
            (unsigned long long)in->candidates, (unsigned long long)in->selected);
    fprintf(out, "\"record_failed\": %llu, \"record_mismatch\": %llu, \"unshiftable\": %llu,\n", 
            (unsigned long long)in->record_failed, (unsigned long long)in->record_mismatch,
            (unsigned long long)in->unshiftable);
    fprintf(out, "%s    \"selected_by_length\": ", indent);
    write_histogram(out, in->length, PATH_MAX_LENGTH + 1);
    fprintf(out, ",\n%s    \"selected_by_reconnection_index\": ", indent);
    write_histogram(out, in->rc_index, PATH_MAX_LENGTH + 1);
    fprintf(out, "},\n%s  \"merge\": {\"merges\": %llu, \"no_neighbor\": %llu, \"shifts\": %llu, "
                 "\"selected_neighbor\": %llu,\n%s    \"shift_outcomes\": {",
            indent, (unsigned long long)m->merges, (unsigned long long)m->no_neighbor,
            (unsigned long long)m->shifts, (unsigned long long)m->selected_neighbor, indent);
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", shift_failure_names[i], (unsigned long long)m->outcome[i]);
    fprintf(out, "}}\n%s}", indent);
}
