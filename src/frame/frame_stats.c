/* Counters, timings and memory of a ReSTIR PT run, and their JSON (include/restir/frame/frame_stats.h). */
#include "restir/frame/frame_stats.h"

#include <string.h>
#include "restir/frame/options.h"

void restir_stats_add(restir_stats *st, const restir_stats *w)
{
    int i;
    initial_stats_add(&st->initial, &w->initial);
    spatial_stats_add(&st->spatial, &w->spatial);
    temporal_stats_add(&st->temporal, &w->temporal);
    mutate_stats_add(&st->mutate, &w->mutate);
    st->neighbors.candidates += w->neighbors.candidates;
    for (i = 0; i < NEIGHBOR_VERDICT_COUNT; ++i) st->neighbors.verdict[i] += w->neighbors.verdict[i];
    st->frames += w->frames;
    st->nonfinite_pixels += w->nonfinite_pixels;
    st->ms_gbuffer += w->ms_gbuffer;
    st->ms_initial += w->ms_initial;
    st->ms_temporal += w->ms_temporal;
    st->ms_pose += w->ms_pose;
    st->ms_motion += w->ms_motion;
    st->ms_mutate += w->ms_mutate;
    st->ms_shade += w->ms_shade;
    for (i = 0; i < RESTIR_MAX_SPATIAL_PASSES; ++i) st->ms_spatial[i] += w->ms_spatial[i];
    duplication_summary_add(&st->correlation, &w->correlation);
    st->boiling_cleared += w->boiling_cleared;
    st->ms_correlation += w->ms_correlation;
}

/* ---- statistics ---------------------------------------------------------------------- */

static void write_histogram(FILE *out, const uint64_t *h, int n)
{
    int i;
    fputc('[', out);
    for (i = 0; i < n; ++i) fprintf(out, "%s%llu", i ? ", " : "", (unsigned long long)h[i]);
    fputc(']', out);
}

/* "temporal": steps, reprojection failures, capped histories, outputs from frame t-1,
 * shifts (forward and reverse) by outcome; rates per step. */
static void temporal_stats_write_json(FILE *out, const temporal_stats *t, const char *indent)
{
    double steps = t->pixels > 0 ? (double)t->pixels : 1;
    int i;
    fprintf(out, "%s  \"temporal\": {\"pixels\": %llu, \"no_history\": %llu, \"capped\": %llu, "
                 "\"selected_previous\": %llu, \"shifts\": %llu, \"mis_shifts\": %llu, \"dual_mv\": %llu, "
                 "\"dedup_lowered\": %llu, ",
            indent, (unsigned long long)t->pixels, (unsigned long long)t->no_history, (unsigned long long)t->capped,
            (unsigned long long)t->step.selected_neighbor, (unsigned long long)t->step.shifts,
            (unsigned long long)t->step.mis_shifts, (unsigned long long)t->dual,
            (unsigned long long)t->dedup_lowered);
    fprintf(out, "\"history_rate\": %.6f, \"shifts_per_pixel\": %.3f, \"shift_success_rate\": %.6f,\n%s    \"shift_outcomes\": {",
            (double)(t->pixels - t->no_history) / steps, (double)t->step.shifts / steps,
            t->step.shifts > 0 ? (double)t->step.outcome[SHIFT_OK] / (double)t->step.shifts : 0.0, indent);
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", shift_failure_names[i], (unsigned long long)t->step.outcome[i]);
    fprintf(out, "}}");
}

/* "correlation" (sequences; docs/correlation.md): the duplication maps of the final
 * reservoirs summed over frames (mean duplicate count per pixel, share of pixels holding a
 * duplicated sample, the largest count) and the boiling filter's clears. */
static void correlation_stats_write_json(FILE *out, const restir_stats *st, const char *indent)
{
    const duplication_summary *c = &st->correlation;
    double px = c->pixels > 0 ? (double)c->pixels : 1;
    fprintf(out, ",\n%s  \"correlation\": {\"pixels\": %llu, \"duplicated_pixels\": %llu, \"duplicates\": %llu, "
                 "\"mean_duplicates\": %.6f, \"mean_duplication_score\": %.8f, \"duplicated_fraction\": %.6f, "
                 "\"max_duplicates\": %u, \"boiling_cleared\": %llu, \"milliseconds\": %.3f}",
            indent, (unsigned long long)c->pixels, (unsigned long long)c->duplicated,
            (unsigned long long)c->count_sum, (double)c->count_sum / px,
            (double)c->count_sum / px / duplication_score_denominator(DUPLICATION_RADIUS),
            (double)c->duplicated / px, c->count_max, (unsigned long long)st->boiling_cleared, st->ms_correlation);
}

uint64_t restir_stats_invalid_weights(const restir_stats *st)
{
    return st->initial.invalid_weights + st->spatial.invalid_weights + st->temporal.step.invalid_weights;
}

/* "mutations": proposals, acceptances, rejections by reason (Mutations §3, mutate.h). */
static void mutate_stats_write_json(FILE *out, const mutate_stats *m, double ms, const char *indent)
{
    int i;
    fprintf(out, "%s  \"mutations\": {\"pixels\": %llu, \"skipped\": %llu, \"proposals\": %llu, \"accepted\": %llu, "
                 "\"rejected_mh\": %llu, \"acceptance_rate\": %.6f, \"milliseconds\": %.3f,\n%s    \"rejected\": {",
            indent, (unsigned long long)m->pixels, (unsigned long long)m->skipped, (unsigned long long)m->proposals,
            (unsigned long long)m->accepted, (unsigned long long)m->rejected_mh,
            m->proposals ? (double)m->accepted / (double)m->proposals : 0.0, ms, indent);
    for (i = 0; i < MUTATE_REJECT_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i > 0 ? ", " : "", mutate_reject_names[i], (unsigned long long)m->rejected[i]);
    fprintf(out, "}, \"duplicates\": %llu, \"final_valid\": %llu, \"pss_bytes_per_pixel\": %.1f, \"skip\": {",
            (unsigned long long)m->duplicates, (unsigned long long)m->final_valid,
            m->pixels ? (double)m->pss_numbers / (double)m->pixels * (double)sizeof(real) : 0.0);
    for (i = 0; i < MUTATE_REASON_SKIP_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i > 0 ? ", " : "", mutate_skip_names[i], (unsigned long long)m->skip[i]);
    fprintf(out, "}}");
}

void restir_memory_per_pixel(const restir_options *o, int sequence, restir_memory *m)
{
    unsigned per_buffer;
    memset(m, 0, sizeof *m);
    m->reservoir = (unsigned)sizeof(reservoir);
    /* the primary-sample rows of every buffer (reservoir.h), allocated by mutation runs only
     * (and by sequences that read a checkpoint or a stage dump) */
    m->reservoir_pss = sequence && o->mutation.count > 0 ? (unsigned)(PATH_MAX_PSS * sizeof(real)) : 0;
    per_buffer = m->reservoir + m->reservoir_pss;
    m->reservoirs_initial = per_buffer;
    m->reservoirs_spatial = sequence || o->spatial_passes > 0 ? per_buffer : 0; /* ping-pong */
    m->reservoirs_previous = sequence ? per_buffer : 0;                         /* temporal input */
    m->gbuffer = (unsigned)sizeof(gbuffer_texel);
    m->gbuffer_previous = sequence ? m->gbuffer : 0;
    m->accumulation = (unsigned)(3 * sizeof(double));
    m->vector_shade = o->shading == RESTIR_SHADING_VECTOR && o->spatial_passes > 0 ? (unsigned)sizeof(rgb) : 0;
    /* reuse_cells.h: cell_of, start, pixels, nz_start, nz_pixels, hash per pixel, and at most
     * one confidence per pixel (one cell per pixel at worst). */
    m->reuse_cells = o->spatial.cells ? (unsigned)(3 * sizeof(int) + 3 * sizeof(uint32_t) + sizeof(double)) : 0;
    /* pair_step.c: one pre-pass shift, partner pixel and texture per neighbour, the accepted
     * count and x1 of every pixel (Enhanced §3) */
    m->pair_step = restir_pair_step_active(o) && o->spatial_passes > 0
                       ? (unsigned)((size_t)o->spatial.neighbors * (sizeof(pair_shift) + sizeof(uint32_t) + 1) + sizeof(int) +
                                    sizeof(path_vertex))
                       : 0;
    /* pipeline.c: the duplication map and the history ages of frames t and t-1 (issue 12) */
    m->correlation = sequence ? (unsigned)(3 * sizeof(uint16_t)) : 0;
    m->total = m->reservoirs_initial + m->reservoirs_spatial + m->reservoirs_previous + m->gbuffer +
               m->gbuffer_previous + m->accumulation + m->vector_shade + m->reuse_cells + m->pair_step +
               m->correlation;
}

static void restir_memory_write_json(FILE *out, const restir_memory *m, const char *indent)
{
    fprintf(out, ",\n%s  \"bytes_per_pixel\": {\"reservoir\": %u, \"reservoir_pss\": %u, \"reservoirs_initial\": %u, "
                 "\"reservoirs_spatial\": %u, \"reservoirs_previous\": %u,\n%s    \"gbuffer\": %u, "
                 "\"gbuffer_previous\": %u, \"accumulation\": %u, \"vector_shade\": %u, \"reuse_cells\": %u, "
                 "\"pair_step\": %u, \"correlation\": %u, \"total\": %u}",
            indent, m->reservoir, m->reservoir_pss, m->reservoirs_initial, m->reservoirs_spatial,
            m->reservoirs_previous, indent, m->gbuffer, m->gbuffer_previous, m->accumulation, m->vector_shade,
            m->reuse_cells, m->pair_step, m->correlation, m->total);
}

void restir_stats_write_json(FILE *out, const restir_stats *st, const char *indent)
{
    const initial_stats *in = &st->initial;
    const spatial_stats *sp = &st->spatial;
    /* per surface pixel and frame: a spatial pass steps every surface pixel once, and unlike
     * the initial count this holds after a restart that read the initial stage from a dump */
    double px = st->passes > 0 && sp->pixels > 0 ? (double)sp->pixels / st->passes
                : in->pixels > 0                 ? (double)in->pixels
                                                 : 1;
    int i;
    fprintf(out, "{\n%s  \"frames\": %llu,\n", indent, (unsigned long long)st->frames);
    fprintf(out, "%s  \"milliseconds\": {\"gbuffer\": %.3f, \"initial\": %.3f, \"spatial\": [", indent, st->ms_gbuffer,
            st->ms_initial);
    for (i = 0; i < st->passes && i < RESTIR_MAX_SPATIAL_PASSES; ++i)
        fprintf(out, "%s%.3f", i ? ", " : "", st->ms_spatial[i]);
    fprintf(out, "], \"temporal\": %.3f, \"shade\": %.3f, \"pose\": %.3f, \"motion\": %.3f},\n", st->ms_temporal,
            st->ms_shade, st->ms_pose, st->ms_motion);
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
    fprintf(out, "},\n%s  \"spatial\": {\"passes\": %d, \"steps\": %llu, \"domains\": %llu, \"shifts\": %llu, "
                 "\"mis_shifts\": %llu, \"shifts_per_pixel_per_frame\": %.3f, \"selected_neighbor\": %llu,\n",
            indent, st->passes, (unsigned long long)sp->pixels, (unsigned long long)sp->domains,
            (unsigned long long)sp->shifts, (unsigned long long)sp->mis_shifts, (double)sp->shifts / px,
            (unsigned long long)sp->selected_neighbor);
    fprintf(out, "%s    \"shift_outcomes\": {", indent);
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", shift_failure_names[i], (unsigned long long)sp->outcome[i]);
    fprintf(out, "},\n%s    \"neighbor_verdicts\": {", indent);
    for (i = 0; i < NEIGHBOR_VERDICT_COUNT; ++i)
        fprintf(out, "%s\"%s\": %llu", i ? ", " : "", neighbor_verdict_names[i],
                (unsigned long long)st->neighbors.verdict[i]);
    fprintf(out, "}},\n");
    temporal_stats_write_json(out, &st->temporal, indent);
    correlation_stats_write_json(out, st, indent);
    fprintf(out, ",\n%s  \"guards\": {\"invalid_weights\": %llu, \"nonfinite_pixels\": %llu}", indent,
            (unsigned long long)restir_stats_invalid_weights(st), (unsigned long long)st->nonfinite_pixels);
    fprintf(out, ",\n");
    mutate_stats_write_json(out, &st->mutate, st->ms_mutate, indent);
    if (st->memory.total) restir_memory_write_json(out, &st->memory, indent);
    fprintf(out, "\n%s}", indent);
}
