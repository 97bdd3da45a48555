/* Offline ReSTIR PT in the benchmark and the equal-time harness (restir_bench.h). */
#include "restir/bench/restir_bench.h"

#include <math.h>
#include <string.h>
#include "restir/frame/frame_stats.h"
#include "restir/frame/offline.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"
#include "restir/render/gbuffer.h"
#include "restir/restir/reservoir_dump.h"

static int restir_units(void *ctx, uint32_t first, uint32_t count, int width, int height, double *sum, rerror *e)
{
    equal_time_restir_ctx *c = ctx;
    restir_options o = c->options;
    restir_result r;
    size_t i, n = (size_t)width * (size_t)height * 3;
    if (c->s->width != width || c->s->height != height)
        return rerror_set(e, "restir: renders %dx%d, not %dx%d", c->s->width, c->s->height, width, height);
    o.first_frame = c->options.first_frame + (int)first;
    o.frames = (int)count;
    o.time_limit = 0;
    if (restir_render(c->s, &o, &r, e)) return -1;
    for (i = 0; i < n; ++i) sum[i] += (double)r.mean.px[i] * (double)count; /* frame sum = mean x frames */
    restir_result_free(&r);
    return 0;
}

void equal_time_restir_method(equal_time_restir_ctx *ctx, const scene *s, const restir_options *o, const char *name,
                              equal_time_method *m)
{
    ctx->s = s;
    ctx->options = *o;
    m->name = name;
    m->render = restir_units;
    m->ctx = ctx;
}

static void write_pass_array(FILE *out, const double *v, int n, double scale)
{
    int i;
    fputc('[', out);
    for (i = 0; i < n; ++i) fprintf(out, "%s%.3f", i ? ", " : "", v[i] * scale);
    fputc(']', out);
}

/* How often the criterion (--rc-criterion) picked a reconnection vertex: the initial
 * samples by reconnection index, and the shifts refused because the offset path's own
 * criterion disagrees (the bijectivity tests of shift.c). */
static void write_reconnection_rates(FILE *out, const restir_stats *st)
{
    static const enum shift_failure refused[] = {SHIFT_FAIL_RC_EARLIER, SHIFT_FAIL_RC_PREV, SHIFT_FAIL_RC_DISTANCE,
                                                 SHIFT_FAIL_RC_ROUGHNESS, SHIFT_FAIL_RC_FOOTPRINT,
                                                 SHIFT_FAIL_RC_OFFSET_RECONNECTS};
    double selected = st->initial.selected > 0 ? (double)st->initial.selected : 1;
    double shifts = st->spatial.shifts > 0 ? (double)st->spatial.shifts : 1;
    uint64_t none = st->initial.rc_index[0];
    int i;
    fprintf(out, "   \"reconnection\": {\"initial_rate\": %.4f, \"initial_by_index\": [",
            1 - (double)none / selected);
    for (i = 0; i <= PATH_MAX_LENGTH; ++i) fprintf(out, "%s%llu", i ? ", " : "", (unsigned long long)st->initial.rc_index[i]);
    fprintf(out, "], \"shifts_refused_by_offset_criterion\": {");
    for (i = 0; i < (int)(sizeof refused / sizeof refused[0]); ++i)
        fprintf(out, "%s\"%s\": %.5f", i ? ", " : "", shift_failure_names[refused[i]],
                (double)st->spatial.outcome[refused[i]] / shifts);
    fprintf(out, "}}");
}

static void write_one(FILE *out, const char *name, const restir_options *o, const restir_result *r)
{
    const restir_stats *st = &r->stats;
    double pixels = st->initial.pixels > 0 ? (double)st->initial.pixels : 1;
    double frames = st->frames > 0 ? (double)st->frames : 1;
    double passes = st->passes > 0 ? st->passes : 1;
    int i;
    fprintf(out, "  {\"bench\": \"restir\", \"scene\": \"%s\", \"width\": %d, \"height\": %d,\n   \"config\": ", name,
            r->mean.width, r->mean.height);
    restir_options_write_json(out, o, "   ");
    fprintf(out, ",\n   \"ms_per_frame\": {\"gbuffer\": %.3f, \"initial\": %.3f, \"spatial\": ", st->ms_gbuffer / frames,
            st->ms_initial / frames);
    write_pass_array(out, st->ms_spatial, st->passes, 1 / frames);
    fprintf(out, ", \"shade\": %.3f},\n", st->ms_shade / frames);
    fprintf(out, "   \"shifts_per_pixel_per_pass\": %.3f, \"mis_shifts_per_pixel_per_pass\": %.3f, "
                 "\"domains_per_pixel\": %.3f,\n",
            (double)st->spatial.shifts / pixels / passes, (double)st->spatial.mis_shifts / pixels / passes,
            st->spatial.pixels ? (double)st->spatial.domains / (double)st->spatial.pixels : 0.0);
    fprintf(out, "   \"shift_outcomes\": {");
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", shift_failure_names[i],
                (unsigned long long)st->spatial.outcome[i]);
    fprintf(out, "},\n");
    write_reconnection_rates(out, st);
    fprintf(out, "}");
}

int bench_restir(FILE *out, const scene *s, const char *name, const restir_options *o, int *first, rerror *e)
{
    static const int families[] = {MIS_TALBOT, MIS_PAIRWISE_DEFENSIVE};
    int shift, f;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT; ++shift)
        for (f = 0; f < 2; ++f) {
            restir_options b = *o;
            restir_result r;
            b.shift = shift;
            b.spatial.mis = families[f];
            if (restir_render(s, &b, &r, e)) return -1;
            if (!*first) fprintf(out, ",\n");
            *first = 0;
            write_one(out, name, &b, &r);
            fflush(out);
            restir_result_free(&r);
        }
    return 0;
}

static int reference_image(const scene *s, uint32_t spp, int threads, int max_depth, image *ref, rerror *e)
{
    pt_options po;
    pt_result pr;
    pt_options_default(&po);
    po.spp = spp;
    po.seed = 0x5eed;
    po.threads = threads;
    po.max_depth = max_depth;
    if (pt_render(s, &po, &pr, e)) return -1;
    *ref = pr.mean;
    pr.mean.px = NULL;
    pt_result_free(&pr);
    return 0;
}

int bench_restir_equal_time(FILE *out, const scene *s, const char *name, const restir_options *o, uint32_t ref_spp,
                            double seconds, int *first, rerror *e)
{
    image ref;
    equal_time_options eo;
    equal_time_pt_ctx ptc;
    equal_time_restir_ctx rc;
    equal_time_method m[2];
    equal_time_curve c[2];
    pt_options po;
    double target, t[2];
    int k, status = 0;
    memset(c, 0, sizeof c);
    if (reference_image(s, ref_spp, o->threads, o->max_depth, &ref, e)) return -1;
    pt_options_default(&po);
    po.seed = o->seed + 1;
    po.threads = o->threads;
    po.max_depth = o->max_depth;
    equal_time_pt_method(&ptc, s, &po, "pt", &m[0]);
    equal_time_restir_method(&rc, s, o, "restir", &m[1]);
    equal_time_options_default(&eo);
    eo.time_budget = seconds;
    for (k = 0; k < 2 && !status; ++k) status = equal_time_run(&m[k], &ref, &eo, &c[k], e);
    if (!status) {
        double last0 = c[0].points[c[0].count - 1].mape, last1 = c[1].points[c[1].count - 1].mape;
        target = last0 > last1 ? last0 : last1;
        equal_time_time_to_reach(&c[0], EQUAL_TIME_MAPE, target, &t[0]);
        equal_time_time_to_reach(&c[1], EQUAL_TIME_MAPE, target, &t[1]);
        if (!*first) fprintf(out, ",\n");
        *first = 0;
        fprintf(out, "  {\"bench\": \"restir_equal_time\", \"scene\": \"%s\", \"width\": %d, \"height\": %d, "
                     "\"reference_spp\": %u, \"budget_seconds\": %g,\n   \"config\": ",
                name, s->width, s->height, ref_spp, seconds);
        restir_options_write_json(out, o, "   ");
        fprintf(out, ",\n   \"pt\": {\"seconds\": %.3f, \"units\": %u, \"mape\": %.5f}, ",
                c[0].points[c[0].count - 1].seconds, c[0].points[c[0].count - 1].units, last0);
        fprintf(out, "\"restir\": {\"seconds\": %.3f, \"frames\": %u, \"mape\": %.5f},\n",
                c[1].points[c[1].count - 1].seconds, c[1].points[c[1].count - 1].units, last1);
        fprintf(out, "   \"target_mape\": %.5f, \"pt_seconds_to_target\": %.4g, \"restir_seconds_to_target\": %.4g, "
                     "\"speedup\": %.3g}",
                target, t[0], t[1], t[0] / t[1]);
        fflush(out);
    }
    for (k = 0; k < 2; ++k) equal_time_curve_free(&c[k]);
    image_free(&ref);
    return status;
}

/* ---- the real-time pipeline ---------------------------------------------------------------- */

/* Per-frame statistics of a bench_realtime sequence, summed by the sink. */
typedef struct {
    restir_stats sum;
    int frames;
} realtime_acc;

static int realtime_sink(void *user, int frame, const image *img, const restir_stats *st, rerror *e)
{
    realtime_acc *a = user;
    (void)frame;
    (void)img;
    (void)e;
    restir_stats_add(&a->sum, st);
    a->frames++;
    return 0;
}

static void write_outcomes(FILE *out, const uint64_t *outcome)
{
    int i;
    fputc('{', out);
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", shift_failure_names[i], (unsigned long long)outcome[i]);
    fputc('}', out);
}

int bench_realtime(FILE *out, const scene *s, const char *name, const restir_options *o, int first_frame,
                   int last_frame, int *first, rerror *e)
{
    restir_sequence q;
    realtime_acc acc;
    restir_stats total;
    const restir_stats *st = &acc.sum;
    const temporal_stats *t = &st->temporal;
    double frames, pixels, steps, tshifts;
    memset(&q, 0, sizeof q);
    memset(&acc, 0, sizeof acc);
    q.first = first_frame;
    q.last = last_frame;
    if (restir_render_sequence(s, o, &q, realtime_sink, &acc, &total, e)) return -1;
    frames = acc.frames > 0 ? acc.frames : 1;
    pixels = st->initial.pixels > 0 ? (double)st->initial.pixels : 1;
    steps = t->pixels > 0 ? (double)t->pixels : 1;
    tshifts = t->step.shifts > 0 ? (double)t->step.shifts : 1;
    if (!*first) fprintf(out, ",\n");
    *first = 0;
    fprintf(out, "  {\"bench\": \"restir-realtime\", \"scene\": \"%s\", \"width\": %d, \"height\": %d, \"frames\": [%d, %d],\n"
                 "   \"config\": ",
            name, s->width, s->height, first_frame, last_frame);
    restir_options_write_json(out, o, "   ");
    fprintf(out, ",\n   \"ms_per_frame\": {\"pose_bvh\": %.3f, \"gbuffer\": %.3f, \"motion\": %.3f, \"initial\": %.3f, "
                 "\"temporal\": %.3f, \"spatial\": ",
            st->ms_pose / frames, st->ms_gbuffer / frames, st->ms_motion / frames, st->ms_initial / frames,
            st->ms_temporal / frames);
    write_pass_array(out, st->ms_spatial, o->spatial_passes, 1 / frames);
    fprintf(out, ", \"shade\": %.3f},\n", st->ms_shade / frames);
    fprintf(out, "   \"shifts_per_pixel\": {\"temporal\": %.3f, \"spatial\": %.3f},\n", (double)t->step.shifts / pixels,
            (double)st->spatial.shifts / pixels);
    fprintf(out, "   \"temporal\": {\"history_rate\": %.4f, \"capped_rate\": %.4f, \"selected_previous_rate\": %.4f, "
                 "\"shift_success_rate\": %.4f, \"shift_failure_rate\": %.4f, \"shift_outcomes\": ",
            (double)(t->pixels - t->no_history) / steps, (double)t->capped / steps,
            (double)t->step.selected_neighbor / steps, (double)t->step.outcome[SHIFT_OK] / tshifts,
            1 - (double)t->step.outcome[SHIFT_OK] / tshifts);
    write_outcomes(out, t->step.outcome);
    /* State kept per pixel between frames: the previous frame's reservoir (the G-buffer
     * texel is rebuilt each frame anyway); in memory the reservoir struct, on the wire the
     * dump record (docs/formats.md) that a GPU layout would resemble. */
    fprintf(out, "},\n   \"bytes_per_pixel\": {\"temporal_state_in_memory\": %u, \"temporal_state_record\": %u, "
                 "\"reservoir_buffers_in_memory\": %u, \"gbuffer_texels_in_memory\": %u}}",
            (unsigned)sizeof(reservoir), (unsigned)reservoir_record_size(0), (unsigned)(3 * sizeof(reservoir)),
            (unsigned)(2 * sizeof(gbuffer_texel)));
    fflush(out);
    return 0;
}

/* ---- MCMC mutations (Mutations §5; docs/mutations.md) ------------------------------------- */

/* One sequence, the summed stats and the mean frame time (ms, all stages). */
static int mutation_run(const scene *s, const restir_options *o, int f0, int f1, restir_stats *sum, double *ms_frame,
                        rerror *e)
{
    restir_sequence q;
    realtime_acc acc;
    restir_stats total;
    double t;
    int i;
    memset(&q, 0, sizeof q);
    memset(&acc, 0, sizeof acc);
    q.first = f0;
    q.last = f1;
    if (restir_render_sequence(s, o, &q, realtime_sink, &acc, &total, e)) return -1;
    *sum = acc.sum;
    t = sum->ms_pose + sum->ms_gbuffer + sum->ms_motion + sum->ms_initial + sum->ms_temporal + sum->ms_shade +
        sum->ms_mutate;
    for (i = 0; i < RESTIR_MAX_SPATIAL_PASSES; ++i) t += sum->ms_spatial[i];
    *ms_frame = t / (acc.frames > 0 ? acc.frames : 1);
    return 0;
}

int bench_mutations(FILE *out, const scene *s, const char *name, const restir_options *o, int f0, int f1, int *first,
                    rerror *e)
{
    restir_options off = *o;
    restir_stats a;
    double ms_off, frames = f1 - f0 + 1;
    int strategy, i;
    off.shift = RESTIR_SHIFT_HYBRID; /* the paper's shift (Mutations §4.3) */
    off.mutation.count = 0;
    if (mutation_run(s, &off, f0, f1, &a, &ms_off, e)) return -1;
    for (strategy = 0; strategy < MUTATE_STRATEGY_COUNT; ++strategy) {
        restir_options on = off;
        restir_stats b;
        double ms_on;
        const mutate_stats *m = &b.mutate;
        on.mutation.count = o->mutation.count > 0 ? o->mutation.count : 1;
        on.mutation.strategy = strategy;
        if (mutation_run(s, &on, f0, f1, &b, &ms_on, e)) return -1;
        if (!*first) fprintf(out, ",\n");
        *first = 0;
        fprintf(out, "  {\"bench\": \"restir-mutations\", \"scene\": \"%s\", \"width\": %d, \"height\": %d, \"frames\": [%d, %d], "
                     "\"strategy\": \"%s\", \"shift\": \"%s\", \"mutations\": %d,\n",
                name, s->width, s->height, f0, f1, mutate_strategy_names[strategy], restir_shift_names[on.shift],
                on.mutation.count);
        fprintf(out, "   \"ms_per_mutation_iteration\": %.3f, \"ms_frame_without\": %.3f, \"ms_frame_with\": %.3f, "
                     "\"frame_cost_ratio\": %.3f,\n",
                b.ms_mutate / frames / on.mutation.count, ms_off, ms_on, ms_off > 0 ? ms_on / ms_off : 0.0);
        fprintf(out, "   \"pixels\": %llu, \"skipped_rate\": %.4f, \"proposals\": %llu, \"acceptance_rate\": %.4f, "
                     "\"rejected_mh\": %llu, \"rejected\": {",
                (unsigned long long)m->pixels, m->pixels ? (double)m->skipped / (double)m->pixels : 0.0,
                (unsigned long long)m->proposals, m->proposals ? (double)m->accepted / (double)m->proposals : 0.0,
                (unsigned long long)m->rejected_mh);
        for (i = 0; i < MUTATE_REJECT_COUNT; ++i)
            fprintf(out, "%s\"%s\": %llu", i ? ", " : "", mutate_reject_names[i], (unsigned long long)m->rejected[i]);
        /* Reservoir storage (Mutations §4.3 "Reservoir storage"): in memory the reservoir and
         * its buffer's primary-sample row (reservoir.h; mutation runs only), the same for every
         * strategy; what the strategy makes a pixel keep is the explicit numbers pss[] (mean
         * over the chains' final samples). */
        fprintf(out, "},\n   \"bytes_per_pixel\": {\"reservoir_in_memory\": %u, \"pss_kept_mean\": %.1f, \"pss_max\": %u, "
                     "\"dump_record_with_pss\": %u}}",
                (unsigned)(sizeof(reservoir) + PATH_MAX_PSS * sizeof(real)),
                m->pixels ? (double)m->pss_numbers / (double)m->pixels * (double)sizeof(real) : 0.0,
                (unsigned)(PATH_MAX_PSS * sizeof(real)), (unsigned)reservoir_record_size(RESERVOIR_DUMP_FLAG_PSS));
        fflush(out);
    }
    return 0;
}
