/* Path-tracer benchmark: samples/s and rays/s as one JSON object (restir/bench/bench.h). */
#include "restir/bench/pt_bench.h"

#include "restir/bench/bench_rays.h"
#include "restir/render/pt.h"

#include <string.h>
#include "restir/core/json_text.h"

int bench_pt(FILE *out, const scene *s, const char *name, uint32_t spp, int threads, rerror *e)
{
    pt_options o;
    pt_result r;
    double paths_per_s, rays_per_s;
    pt_options_default(&o);
    o.spp = spp;
    o.threads = threads;
    if (pt_render(s, &o, &r, e)) return -1;
    paths_per_s = r.seconds > 0 ? (double)r.paths / r.seconds : 0;
    rays_per_s = r.seconds > 0 ? (double)r.rays / r.seconds : 0;
    fprintf(out, "{\"bench\": \"pt\", \"scene\": ");
    json_put_string(out, name ? name : s->path);
    fprintf(out,
            ", \"width\": %d, \"height\": %d, \"spp\": %u, \"threads\": %d, \"max_depth\": %d, "
            "\"strategy\": \"%s\", \"seconds\": %.6f, \"paths\": %llu, \"rays\": %llu, "
            "\"samples_per_second\": %.1f, \"rays_per_second\": %.1f, \"rays_per_path\": %.3f}\n",
            s->width, s->height, r.state.spp, threads, o.max_depth, pt_strategy_names[o.strategy], r.seconds,
            (unsigned long long)r.paths, (unsigned long long)r.rays, paths_per_s, rays_per_s,
            r.paths ? (double)r.rays / (double)r.paths : 0.0);
    pt_result_free(&r);
    return 0;
}
