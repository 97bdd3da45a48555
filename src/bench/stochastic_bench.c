/* `restir bench stochastic` (include/restir/bench/stochastic_bench.h). */
#include "restir/bench/stochastic_bench.h"

#include <stdlib.h>
#include <string.h>
#include "restir/core/progress.h"
#include "restir/frame/offline.h"
#include "restir/frame/options.h"
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/restir/reuse_cells.h"

static void separator(FILE *out, int *first)
{
    fprintf(out, *first ? "  " : ",\n  ");
    *first = 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Cell construction on the G-buffer and initial reservoirs of frame 0. */
static int bench_cells(FILE *out, const scene *s, const char *name, int threads, int *first, rerror *e)
{
    restir_options o;
    restir_result r;
    gbuffer g;
    camera cam;
    reuse_cells rc;
    double ms[9];
    long i, n = (long)s->width * s->height, nz = 0;
    int k;
    restir_options_default(&o);
    o.threads = threads;
    o.keep_reservoirs = 1;
    if (restir_render(s, &o, &r, e)) return -1;
    memset(&g, 0, sizeof g);
    memset(&rc, 0, sizeof rc);
    camera_init(&cam, scene_camera_at(s, 0), s->width, s->height);
    if (gbuffer_build(&g, s, &cam, o.seed, 0, o.jitter, threads, e) || reuse_cells_alloc(&rc, s->width, s->height, e)) {
        restir_result_free(&r);
        gbuffer_free(&g);
        return -1;
    }
    for (k = 0; k < 9; ++k) {
        double t0 = now_seconds();
        reuse_cells_build(&rc, &g, r.reservoirs, NULL);
        ms[k] = 1e3 * (now_seconds() - t0);
    }
    qsort(ms, 9, sizeof *ms, cmp_double);
    for (i = 0; i < n; ++i) nz += rc.cell_of[i] >= 0 && reuse_cell_nonzero(&rc, rc.cell_of[i]) > 0 &&
                                  path_sample_is_valid(&r.reservoirs[i].y) && r.reservoirs[i].W > 0;
    separator(out, first);
    fprintf(out, "{\"bench\": \"reuse-cells\", \"scene\": \"%s\", \"width\": %d, \"height\": %d, \"ms_build_median\": %.3f, "
                 "\"cells\": %d, \"tiles\": %d, \"cells_per_tile\": %.3f, \"pixels_per_cell\": %.2f, "
                 "\"nonzero_fraction\": %.4f}",
            name, s->width, s->height, ms[4], rc.cell_count, rc.tiles, (double)rc.cell_count / rc.tiles,
            rc.cell_count ? (double)rc.start[rc.cell_count] / rc.cell_count : 0.0, (double)nz / (double)n);
    reuse_cells_free(&rc);
    gbuffer_free(&g);
    restir_result_free(&r);
    return 0;
}

static int bench_pass(FILE *out, const scene *s, const char *name, const char *label, const restir_options *o,
                      int *first, rerror *e)
{
    restir_result r;
    const restir_stats *st;
    double pixels;
    if (restir_render(s, o, &r, e)) return -1;
    st = &r.stats;
    pixels = st->spatial.pixels > 0 ? (double)st->spatial.pixels : 1;
    separator(out, first);
    fprintf(out, "{\"bench\": \"stochastic\", \"scene\": \"%s\", \"config\": \"%s\", \"mis\": \"%s\", \"n\": %d, "
                 "\"nc\": %d, \"cells\": %s, \"ms_spatial_pass\": %.3f, \"shifts_per_pixel\": %.3f, "
                 "\"mis_shifts_per_pixel\": %.3f, \"domains_per_pixel\": %.3f}",
            name, label, spatial_mis_name(&o->spatial), o->stochastic.n_picks, o->stochastic.n_canonical_picks, o->spatial.cells ? "true" : "false",
            st->ms_spatial[0], (double)st->spatial.shifts / pixels, (double)st->spatial.mis_shifts / pixels,
            (double)st->spatial.domains / pixels);
    restir_result_free(&r);
    return 0;
}

int bench_stochastic(FILE *out, const scene *s, const char *name, int threads, int *first, rerror *e)
{
    static const int picks[] = {1, 2, 4, 8, 16};
    restir_options o;
    size_t i;
    char label[64];
    if (bench_cells(out, s, name, threads, first, e)) return -1;
    restir_options_default(&o);
    o.threads = threads;
    o.spatial_passes = 1;
    o.spatial.cells = 1;
    o.spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE;
    for (i = 0; i < sizeof picks / sizeof *picks; ++i) {
        o.stochastic.n_picks = picks[i];
        snprintf(label, sizeof label, "cells stochastic N~ %d", picks[i]);
        if (bench_pass(out, s, name, label, &o, first, e)) return -1;
    }
    o.spatial.algorithm = SPATIAL_GRIS_STEP;
    o.spatial.mis = MIS_PAIRWISE_DEFENSIVE;
    if (bench_pass(out, s, name, "cells all-M pairwise-defensive", &o, first, e)) return -1;
    o.spatial.cells = 0;
    o.spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE;
    o.stochastic.n_picks = 1;
    if (bench_pass(out, s, name, "r2 neighbours stochastic N~ 1", &o, first, e)) return -1;
    o.spatial.algorithm = SPATIAL_GRIS_STEP;
    o.spatial.mis = MIS_PAIRWISE_DEFENSIVE;
    if (bench_pass(out, s, name, "r2 neighbours pairwise-defensive", &o, first, e)) return -1;
    return 0;
}
