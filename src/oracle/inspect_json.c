/* `restir inspect --json`: the numbers of inspect.c's text at 17 significant digits
 * (inspect_step.h; the keys are listed in docs/cli.md "inspect"). */
#include "inspect_json.h"

#include "inspect_step.h"

#include "restir/core/json_text.h"
#include "restir/frame/options.h"
#include "restir/restir/path_replay.h"
#include "restir/restir/shift.h"

static void json_num(FILE *out, const char *name, double v)
{
    fprintf(out, "\"%s\": ", name);
    json_put_number(out, v);
}

/* [a, b, c] */
static void json_triple(FILE *out, double a, double b, double c)
{
    fprintf(out, "[");
    json_put_number(out, a);
    fprintf(out, ", ");
    json_put_number(out, b);
    fprintf(out, ", ");
    json_put_number(out, c);
    fprintf(out, "]");
}

static void json_rgb(FILE *out, const char *name, rgb c)
{
    fprintf(out, "\"%s\": ", name);
    json_triple(out, (double)c.r, (double)c.g, (double)c.b);
}

static void json_reservoir(FILE *out, const char *name, const reservoir *r)
{
    fprintf(out, "\"%s\": {", name);
    json_num(out, "wsum", (double)r->wsum);
    fprintf(out, ", ");
    json_num(out, "W", (double)r->W);
    fprintf(out, ", ");
    json_num(out, "confidence", (double)r->confidence);
    fprintf(out, ", \"valid\": %d, \"pixel\": %u, \"sample\": %u, \"d\": %d, \"technique\": \"%s\", \"k\": %d, ",
            path_sample_is_valid(&r->y), r->y.pixel, r->y.sample, r->y.length,
            r->y.technique == PATH_TECH_NEE ? "NEE" : "BSDF", r->y.rc_k == PATH_RC_NONE ? -1 : (int)r->y.rc_k);
    json_rgb(out, "F", r->y.F);
    fprintf(out, ", ");
    json_num(out, "target", (double)r->y.target);
    fprintf(out, "}");
}

/* The vertices of the selected sample (as print_path, positions only). */
static void json_vertices(FILE *out, const restir_context *c, const path_vertex *x1, const path_sample *x)
{
    path_trunk t;
    path_end end;
    int j, d = x->length, distant = 0;
    fprintf(out, "\"vertices\": [");
    if (path_replay(&t, c, x1, x, &end) == SHIFT_OK)
        for (j = 1; j <= d; ++j) {
            vec3 q = t.v[j].position;
            if (j == d && x->technique == PATH_TECH_NEE) q = v3_from_f(end.nee.y.position);
            if (j == d) /* the vertex at infinity: its direction (docs/environment.md) */
                distant = x->technique == PATH_TECH_NEE ? end.nee.y.triangle == LIGHT_TRIANGLE_DISTANT
                                                        : path_vertex_is_distant(&t.v[d]);
            if (j == d && distant) q = light_distant_direction(v3f_from(q));
            if (j > 1) fprintf(out, ", ");
            json_triple(out, (double)q.x, (double)q.y, (double)q.z);
        }
    fprintf(out, "]");
    /* only for paths that end at the sky, so outputs of other scenes keep their bytes */
    if (distant) fprintf(out, ", \"last_vertex_at_infinity\": 1");
}

static void json_shift(FILE *out, const restir_context *c, const path_vertex *xb, const path_sample *x)
{
    path_sample y;
    shift_info info;
    real j_ab;
    enum shift_failure why = shift_path(c, xb, x, &y, &j_ab, &info);
    fprintf(out, "\"shift\": {\"mapping\": \"%s\", \"result\": \"%s\", ", restir_shift_names[c->shift],
            shift_failure_names[why]);
    json_num(out, "J", (double)j_ab);
    fprintf(out, ", ");
    json_num(out, "target", (double)y.target);
    fprintf(out, ", ");
    json_num(out, "target_times_J", (double)(y.target * j_ab));
    fprintf(out, ", ");
    json_rgb(out, "F", y.F);
    if (info.reconnected) {
        fprintf(out, ", \"destination_terms\": {");
        json_num(out, "pdf_prev", (double)info.terms.pdf_prev);
        fprintf(out, ", ");
        json_num(out, "geom", (double)info.terms.geom);
        fprintf(out, ", ");
        json_num(out, "pdf_k", (double)info.terms.pdf_k);
        fprintf(out, "}, \"source_terms\": {");
        json_num(out, "pdf_prev", (double)x->rc_pdf_prev);
        fprintf(out, ", ");
        json_num(out, "geom", (double)x->rc_geom);
        fprintf(out, ", ");
        json_num(out, "pdf_k", (double)x->rc_pdf);
        fprintf(out, "}");
    }
    fprintf(out, "}");
}

static void json_step(FILE *out, const restir_options *o, const inspect_step *g)
{
    int j;
    fprintf(out, "\"%s\": {\"mis\": \"%s\"", g->temporal ? "temporal_step" : "gris_step",
            g->temporal ? mis_family_name(o->temporal.mis) : spatial_mis_name(&o->spatial));
    if (g->shown) {
        fprintf(out, ", \"domains\": [");
        for (j = 0; j < 2; ++j) {
            fprintf(out, "%s{", j ? ", " : "");
            json_num(out, "c", (double)g->ws.confidence[j]);
            fprintf(out, ", ");
            json_num(out, "W", (double)g->in[j].W);
            fprintf(out, ", ");
            json_num(out, "target_X", (double)g->in[j].y.target);
            fprintf(out, ", \"valid\": %d, ", g->ws.valid[j]);
            json_num(out, "J", (double)g->ws.jacobian[j]);
            fprintf(out, ", ");
            json_num(out, "target_y", (double)g->ws.ptarget[j]);
            fprintf(out, ", ");
            json_num(out, "target_from_1_y", (double)g->ws.ptarget[2 + j]);
            fprintf(out, ", ");
            json_num(out, "m", (double)g->ws.mis[j]);
            fprintf(out, ", ");
            json_num(out, "w", (double)g->w[j]);
            fprintf(out, ", ");
            json_num(out, "u", (double)g->u[j]);
            fprintf(out, "}");
        }
        fprintf(out, "], \"selected\": %d, ", g->selected);
        json_num(out, "wsum", (double)g->out.wsum);
        fprintf(out, ", ");
        json_num(out, "target_Y", (double)g->out.y.target);
        fprintf(out, ", ");
        json_num(out, "W", (double)g->out.W);
        fprintf(out, ", ");
        json_num(out, "confidence", (double)g->out.confidence);
    }
    fprintf(out, "}");
}

void inspect_print_json(FILE *out, const restir_context *c, const restir_options *o, int x, int y, int nx, int ny,
                        const path_vertex *xa, const path_vertex *xb, const reservoir *r, const inspect_step *g,
                        const inspect_step *tg)
{
    fprintf(out, "{\"pixel\": [%d, %d], \"neighbor\": [%d, %d], \"frame\": %d, \"seed\": %u, \"shift_mapping\": \"%s\", ", x,
            y, nx, ny, o->first_frame, o->seed, restir_shift_names[o->shift]);
    json_reservoir(out, "initial", r);
    if (xa && path_sample_is_valid(&r->y)) {
        fprintf(out, ", ");
        json_vertices(out, c, xa, &r->y);
        if (xb) {
            fprintf(out, ", ");
            json_shift(out, c, xb, &r->y);
        }
    }
    if (g) {
        fprintf(out, ", ");
        json_reservoir(out, "neighbor_initial", &g->in[1]);
        fprintf(out, ", ");
        json_step(out, o, g);
    }
    if (tg) {
        fprintf(out, ", ");
        json_reservoir(out, "previous_initial", &tg->in[1]);
        fprintf(out, ", ");
        json_step(out, o, tg);
    }
    fprintf(out, "}\n");
}
