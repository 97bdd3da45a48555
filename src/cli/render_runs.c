/* `restir render --runs K` (src/cli/render_runs.h). */
#include "render_runs.h"

#include <stdio.h>
#include "restir/core/image_io.h"
#include "restir/frame/options.h"
#include "restir/metrics/moments.h"
#include "output.h"
#include "stop.h"

/* The sidecar's "renderer" object of a --runs file set (the options of the first run). */
static void write_runs_config(FILE *fp, const void *ctx, const char *indent)
{
    const render_args *a = ctx;
    if (a->method == METHOD_RESTIR) {
        restir_options_write_json(fp, &a->restir, indent);
    } else if (a->method == METHOD_PT) {
        fprintf(fp, "{\"spp\": %u, \"max_depth\": %d, \"jitter\": %s, \"seed\": %u}", a->pt.o.spp,
                a->pt.o.max_depth, a->jitter ? "true" : "false", a->seed);
    } else {
        fprintf(fp, "{\"aov\": \"%s\", \"jitter\": %s, \"seed\": %u}", aov_names[a->aov],
                a->jitter ? "true" : "false", a->seed);
    }
}

/* --time-limit that ends before the first pass of the path tracer is complete left a
 * black image of 0 spp, written with exit 0 (issue 27's audit): an error, nothing written. */
int pt_time_limit_empty(const render_args *a, const render_timings *t)
{
    if (a->method != METHOD_PT || t->pt.state.spp > 0) return 0;
    fprintf(stderr, "restir render: --time-limit %g s ended before the first pass was complete (0 spp): nothing "
                    "written (give more time or a smaller image)\n", a->pt.o.time_limit);
    return 1;
}

/* --runs K: K renders with seeds seed, seed+1, ..., seed+K-1 (independent, since every
 * random number's address contains the seed), reduced to per-pixel mean and sample
 * variance, plus the per-run image and block means that keep `restir check` exact when
 * the renderer correlates pixels (ReSTIR's spatial reuse; docs/statistics.md, "moments
 * files"). The mean goes to `img` for the preview. */
int render_runs(const render_args *a, const scene *s, const char *out, image *img, render_timings *t,
                render_one_fn render_one)
{
    moments m;
    moments_meta meta;
    rerror e;
    char prefix[4096], name[64];
    int k, status = 0;
    e.msg[0] = '\0';
    output_prefix(prefix, sizeof prefix, out);
    if (moments_init(&m, s->width, s->height, &e) ||
        moments_set_block_sizes(&m, moments_default_block_sizes, 4, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        moments_free(&m);
        return 2;
    }
    meta.method = method_names[a->method];
    meta.write_config = write_runs_config;
    meta.ctx = a;
    meta.image_ext = image_output_ext(out);
    /* Spatial reuse shares samples between pixels of one run; everything else keeps the
     * pixels of a run independent (their random numbers are addressed by pixel). */
    meta.correlation =
        a->method == METHOD_RESTIR && a->restir.spatial_passes > 0 ? MOMENTS_CORRELATED : MOMENTS_INDEPENDENT;
    for (k = 0; k < a->runs && !status && !stop_signal(); ++k) {
        image run;
        status = render_one(a, s, a->seed + (uint32_t)k, NULL, &run, t);
        if (status) break;
        if (!stop_signal() && pt_time_limit_empty(a, t)) { /* a run of 0 spp is no run */
            image_free(&run);
            status = 2;
            break;
        }
        /* A run cut short by SIGINT/SIGTERM has fewer samples than the others: adding it
         * would mix two estimators in one mean and variance, so it is dropped. */
        if (!stop_signal()) {
            snprintf(name, sizeof name, "seed %u", a->seed + (uint32_t)k);
            if (moments_add(&m, &run, name, &e)) status = 2;
        }
        image_free(&run);
    }
    if (!status && stop_signal() && m.runs < 2) {
        /* A variance needs two runs: nothing is written, and the status says so. */
        fprintf(stderr, "restir render: interrupted by %s after %ld finished run(s); fewer than 2, nothing written\n",
                stop_signal_name(), m.runs);
        moments_free(&m);
        return 128 + stop_signal();
    }
    if (!status && moments_write_meta(prefix, &m, &meta, &e)) status = 2;
    if (!status) {
        image var;
        if (moments_images(&m, img, &var, &e)) status = 2;
        else image_free(&var);
    }
    if (status == 2 && e.msg[0]) fprintf(stderr, "%s\n", e.msg);
    moments_free(&m);
    return status;
}
