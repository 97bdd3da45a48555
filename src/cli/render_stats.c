/* `restir render --stats` (src/cli/render_stats.h). */
#include "render_stats.h"

#include <stdio.h>
#include "restir/core/atomic_file.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"

int write_stats(const char *path, const render_args *a, const scene *s, const render_timings *t)
{
    rerror e;
    atomic_file f;
    if (atomic_file_open(&f, path, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    fprintf(f.fp, "{\n  \"command\": \"render\",\n  \"scene\": \"%s\",\n  \"method\": \"%s\",\n", s->path,
            method_names[a->method]);
    fprintf(f.fp, "  \"width\": %d,\n  \"height\": %d,\n  \"threads\": %d,\n  \"seed\": %u,\n  \"frame\": %d,\n",
            s->width, s->height, a->threads, a->seed, a->frame);
    if (a->method == METHOD_AOV) fprintf(f.fp, "  \"aov\": \"%s\",\n", aov_names[a->aov]);
    if (a->method == METHOD_PT) render_pt_stats_json(f.fp, &a->pt, &t->pt);
    if (a->method == METHOD_RESTIR) {
        fprintf(f.fp, "  \"restir\": {\"seconds\": %.6f, \"config\": ", t->restir_seconds);
        restir_options_write_json(f.fp, &a->restir, "    ");
        fprintf(f.fp, ",\n    \"stats\":\n");
        restir_stats_write_json(f.fp, &t->restir, "    ");
        if (a->sequence) {
            int i;
            fprintf(f.fp, ",\n    \"sequence\": {\"first\": %d, \"last\": %d, \"accumulate\": %s},\n",
                    a->seq.first, a->seq.last, a->seq.accumulate ? "true" : "false");
            fprintf(f.fp, "    \"frames\": [");
            for (i = 0; i < t->frame_count; ++i) {
                fprintf(f.fp, "%s\n      {\"frame\": %d, \"stats\":\n", i ? "," : "", t->frame_numbers[i]);
                restir_stats_write_json(f.fp, &t->frame_stats[i], "      ");
                fprintf(f.fp, "}");
            }
            fprintf(f.fp, "]");
        }
        fprintf(f.fp, "\n  },\n");
    }
    fprintf(f.fp, "  \"triangles\": %zu,\n", s->triangle_count);
    fprintf(f.fp, "  \"seconds\": {\"load\": %.6f, \"bvh\": %.6f, \"render\": %.6f, \"write\": %.6f}\n}\n", t->load,
            t->prepare, t->render, t->write);
    if (atomic_file_commit(&f, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    return 0;
}
