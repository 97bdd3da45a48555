/* `restir inspect`: one pixel's selected path and its shift to a neighbour, printed for a
 * reader holding the papers (include/restir/restir.h, restir_inspect). */
#include "restir/restir.h"

#include <string.h>
#include "restir/camera.h"
#include "restir/gbuffer.h"
#include "restir/dump_diff.h"
#include "restir/json_text.h"
#include "restir/rng.h"
#include "restir/spatial.h"
#include "restir/temporal.h"
#include "restir/animation.h"

static const char *const lobe_kind_names[] = {"diffuse", "glossy reflection", "glossy transmission",
                                              "delta reflection", "delta transmission"};

static void print_rgb(FILE *out, const char *name, rgb c)
{
    fprintf(out, "%s (%.6g, %.6g, %.6g)", name, (double)c.r, (double)c.g, (double)c.b);
}

static void print_lobe(FILE *out, const restir_context *c, const path_vertex *v, unsigned lobe)
{
    if (lobe == PATH_LOBE_NEE) {
        fprintf(out, "NEE (all lobes), rough %d", rc_vertex_is_rough(&v->b, lobe, c->rc.roughness_threshold));
    } else if ((int)lobe < bsdf_lobe_count(&v->b)) {
        fprintf(out, "lobe %u %s, roughness %.3g, rough %d", lobe, lobe_kind_names[bsdf_lobe_kind_of(&v->b, (int)lobe)],
                (double)bsdf_lobe_roughness(&v->b, (int)lobe),
                rc_vertex_is_rough(&v->b, lobe, c->rc.roughness_threshold));
    } else {
        fprintf(out, "lobe %u", lobe);
    }
}

static const char *material_name(const scene *s, const path_vertex *v) { return s->materials[v->hit.material].name; }

/* The vertices of sample x replayed from x1 (as its own pixel traced them). */
static void print_path(FILE *out, const restir_context *c, const path_vertex *x1, const path_sample *x)
{
    const scene *s = c->path.scene;
    path_trunk t;
    path_end end;
    int j, d = x->length;
    enum shift_failure why = path_replay(&t, c, x1, x, &end);
    if (why != SHIFT_OK) {
        fprintf(out, "  (replay failed: %s)\n", shift_failure_names[why]);
        return;
    }
    for (j = 1; j < d; ++j) {
        const path_vertex *v = &t.v[j];
        fprintf(out, "  x%d (%.6g, %.6g, %.6g) %s, ", j, (double)v->position.x, (double)v->position.y,
                (double)v->position.z, material_name(s, v));
        print_lobe(out, c, v, x->lobe[j]);
        fprintf(out, "%s\n", j == x->rc_k ? "   <- x_k" : "");
    }
    if (x->technique == PATH_TECH_NEE)
        fprintf(out, "  x%d (%.6g, %.6g, %.6g) light point (NEE from x%d), light pdf %.6g%s\n", d,
                (double)end.nee.y.position.x, (double)end.nee.y.position.y, (double)end.nee.y.position.z, d - 1,
                (double)end.light_pdf, d == x->rc_k ? "   <- x_k" : "");
    else
        fprintf(out, "  x%d (%.6g, %.6g, %.6g) emitter hit (BSDF from x%d), light pdf %.6g%s\n", d,
                (double)t.v[d].position.x, (double)t.v[d].position.y, (double)t.v[d].position.z, d - 1,
                (double)end.light_pdf, d == x->rc_k ? "   <- x_k" : "");
}

static void print_sample(FILE *out, const path_sample *x)
{
    fprintf(out, "  identity (seed %u, pixel %u, sample %u), d = %d, technique %s, k = ", x->seed, x->pixel, x->sample,
            x->length, x->technique == PATH_TECH_NEE ? "NEE" : "BSDF");
    if (x->rc_k == PATH_RC_NONE) fprintf(out, "none (random replay)");
    else fprintf(out, "%d%s", x->rc_k, (x->rc_flags & PATH_RC_FLAG_UNSHIFTABLE) ? " (unshiftable)" : "");
    fprintf(out, "\n  ");
    print_rgb(out, "F", x->F);
    fprintf(out, ", target p^ = %.6g\n", (double)x->target);
    if (x->rc_k != PATH_RC_NONE) {
        fprintf(out, "  x_k on triangle %u at (%.6g, %.6g, %.6g), w_k (%.6g, %.6g, %.6g)\n", x->rc_triangle,
                (double)x->rc_position.x, (double)x->rc_position.y, (double)x->rc_position.z, (double)x->rc_wo.x,
                (double)x->rc_wo.y, (double)x->rc_wo.z);
        fprintf(out, "  source terms of Enhanced Eq. 2: p_{k-1} %.6g, G %.6g, p_k %.6g; ", (double)x->rc_pdf_prev,
                (double)x->rc_geom, (double)x->rc_pdf);
        print_rgb(out, "suffix radiance", x->rc_radiance);
        fprintf(out, "\n");
    }
}

static int primary_vertex_at(const scene *s, const restir_options *o, const initial_options *io, int frame, int x,
                             int y, path_vertex *v)
{
    camera cam;
    surface_hit h;
    ray r;
    camera_init(&cam, scene_camera_at(s, frame), s->width, s->height); /* the frame's camera */
    r = primary_ray(&cam, x, y, o->seed, initial_tree_sample(io, (uint32_t)frame, 0), o->jitter);
    if (!scene_intersect(s, &r, &h)) return 0;
    path_vertex_make(v, s, &h, v3_from_f(r.dir));
    return 1;
}

static int primary_vertex_of(const scene *s, const restir_options *o, const initial_options *io, int x, int y,
                             path_vertex *v)
{
    return primary_vertex_at(s, o, io, o->first_frame, x, y, v);
}

static void print_shift(FILE *out, const restir_context *c, const path_vertex *xa, const path_vertex *xb,
                        const path_sample *x)
{
    path_sample y, back;
    shift_info info;
    real j_ab, j_ba;
    enum shift_failure why = shift_path(c, xb, x, &y, &j_ab, &info);
    fprintf(out, "  %s shift: %s (%d vertices replayed)\n", restir_shift_names[c->shift], shift_failure_names[why],
            info.replayed);
    if (info.reconnected)
        fprintf(out, "  destination terms: p_{k-1} %.6g, G %.6g, p_k %.6g, light pdf %.6g\n",
                (double)info.terms.pdf_prev, (double)info.terms.geom, (double)info.terms.pdf_k,
                (double)info.terms.light_pdf);
    if (why != SHIFT_OK) return;
    fprintf(out, "  J = %.9g (= p_{k-1} ratio %.6g x G ratio %.6g x p_k ratio %.6g)\n", (double)j_ab,
            x->rc_k ? (double)(info.terms.pdf_prev / x->rc_pdf_prev) : 1.0,
            x->rc_k ? (double)(info.terms.geom / x->rc_geom) : 1.0,
            x->rc_k ? (double)(info.terms.pdf_k / x->rc_pdf) : 1.0);
    fprintf(out, "  ");
    print_rgb(out, "F(y)", y.F);
    fprintf(out, ", p^(y) = %.6g, p^(y) J = %.6g\n", (double)y.target, (double)(y.target * j_ab));
    why = shift_path(c, xa, &y, &back, &j_ba, NULL);
    if (why != SHIFT_OK) {
        fprintf(out, "  inverse shift FAILED: %s (a logic error: please report)\n", shift_failure_names[why]);
        return;
    }
    fprintf(out, "  inverse shift: J(a->b) J(b->a) = %.17g, F(T^-1(T(x))) / F(x) = %.9g (luminance)\n",
            (double)(j_ab * j_ba), x->target > 0 ? (double)(back.target / x->target) : 0.0);
}

/* One spatial GRIS step at pixel p with two domains (GRIS §6.3, Alg. 2 for M = 2):
 * domain 0 = p's initial reservoir (canonical), domain 1 = the neighbour's, with the
 * selection numbers of spatial pass 1 (restir_render.c spatial_pixel). The workspace keeps
 * everything the tour's hand computation needs: ptarget (GRIS Eq. 35), J, m_j (Eqs. 36-38),
 * and out->wsum, out->W (Eqs. 19, 22). */
typedef struct {
    int temporal;         /* 0: the spatial step, 1: the temporal step (domain 1 = frame f - 1) */
    int shown;            /* 0: --mis stochastic-pairwise (no 2-domain dispatch to show) */
    real u[2], w[2];      /* selection numbers, resampling weights w_j (GRIS Eq. 19) */
    int selected;         /* j of the selected candidate, -1 if none */
    reservoir in[2], out; /* the inputs and the step's output */
    spatial_workspace ws;
} inspect_step;

/* The common set-up: g cleared, the two inputs, the selection numbers (RNG_RIS, `vertex`);
 * g->shown = 0 (and nothing else) for a family without a two-domain form. */
static int step_begin(inspect_step *g, int temporal, int mis, const reservoir *ra, const reservoir *rb, rng_key key,
                      uint32_t vertex, rerror *e)
{
    int j;
    memset(g, 0, sizeof *g);
    g->temporal = temporal;
    g->selected = -1;
    if (mis >= MIS_FAMILY_COUNT) return 0;
    if (spatial_workspace_alloc(&g->ws, 2, e)) return -1;
    g->shown = 1;
    g->in[0] = *ra;
    g->in[1] = *rb;
    for (j = 0; j < 2; ++j) g->u[j] = rng_u(key, RNG_RIS, vertex, (uint32_t)j);
    return 0;
}

/* After the step: the resampling weights w_j (GRIS Eq. 19) and the selected candidate. */
static void step_end(inspect_step *g)
{
    int j;
    for (j = 0; j < 2; ++j) {
        g->w[j] = g->ws.valid[j] ? gris_resampling_weight(g->ws.mis[j], g->ws.ptarget[j], g->in[j].W, g->ws.jacobian[j])
                                 : 0;
        if (g->ws.valid[j] && dump_same_sample(&g->ws.shifted[j], &g->out.y)) g->selected = j;
    }
}

static int gris_step_of(const restir_context *c, const restir_options *o, const initial_options *io,
                        const path_vertex *xa, const path_vertex *xb, const reservoir *ra, const reservoir *rb,
                        uint32_t p, inspect_step *g, rerror *e)
{
    const path_vertex *x1[2];
    const reservoir *in[2];
    spatial_stats st;
    rng_key key = rng_key_make(o->seed, p, initial_tree_sample(io, (uint32_t)o->first_frame, 0));
    if (step_begin(g, 0, o->mis, ra, rb, key, 32u, e)) return -1; /* spatial pass 1: vertex 32 */
    if (!g->shown) return 0;
    x1[0] = xa;
    x1[1] = xb;
    in[0] = &g->in[0];
    in[1] = &g->in[1];
    memset(&st, 0, sizeof st);
    spatial_resample(c, (mis_family)o->mis, 2, x1, in, g->u, &g->out, &g->ws, &st);
    step_end(g);
    return 0;
}

/* The temporal GRIS step of pixel p (GRIS §6.3 step 2, temporal.h) in a static scene:
 * domain 0 = p's initial reservoir of frame f, domain 1 = p's initial reservoir of frame
 * f - 1 (the real-time pipeline feeds the previous frame's FINAL reservoir, after its
 * spatial passes, at the motion-reprojected pixel: the same arithmetic on other inputs),
 * capped at --mcap times the current confidence, --temporal-mis, the selection numbers of
 * RNG_RIS vertex 48 (pipeline.c temporal_pixel). */
static int temporal_step_of(const restir_context *c, const restir_options *o, const initial_options *io,
                            const path_vertex *xa, const path_vertex *xprev, const reservoir *ra, const reservoir *rprev,
                            uint32_t p, inspect_step *g, rerror *e)
{
    temporal_stats st;
    rng_key key = rng_key_make(o->seed, p, initial_tree_sample(io, (uint32_t)o->first_frame, 0));
    if (step_begin(g, 1, o->temporal_mis, ra, rprev, key, 48u, e)) return -1;
    if (!g->shown) return 0;
    memset(&st, 0, sizeof st);
    temporal_resample(c, c, NULL, (mis_family)o->temporal_mis, xa, xprev, &g->in[0], &g->in[1], (real)o->mcap, g->u,
                      &g->out, &g->ws, &st);
    step_end(g);
    return 0;
}

static void print_step_text(FILE *out, const restir_options *o, int nx, int ny, const inspect_step *g)
{
    const real *P = g->ws.ptarget;
    int j;
    int mis = g->temporal ? o->temporal_mis : o->mis;
    if (g->temporal)
        fprintf(out, "temporal GRIS step (M = 2, MIS %s, M-cap %g): domain 0 = this pixel's reservoir of frame %d "
                     "(canonical), domain 1 = its initial reservoir of frame %d\n",
                mis < MIS_FAMILY_COUNT ? mis_family_name((mis_family)mis) : "stochastic-pairwise", o->mcap,
                o->first_frame, o->first_frame - 1);
    else
        fprintf(out, "one GRIS step (spatial, M = 2, MIS %s): domain 0 = this pixel's reservoir (canonical), domain 1 = "
                     "pixel (%d, %d)'s\n",
                mis < MIS_FAMILY_COUNT ? mis_family_name((mis_family)mis) : "stochastic-pairwise", nx, ny);
    if (!g->shown) {
        fprintf(out, "  (not shown for --mis stochastic-pairwise: docs/stochastic-mis.md)\n");
        return;
    }
    for (j = 0; j < 2; ++j) {
        const reservoir *r = &g->in[j];
        fprintf(out, "  X_%d: c %.17g, W %.17g, p^_%d(X_%d) %.17g, %s\n", j, (double)g->ws.confidence[j], (double)r->W, j, j,
                (double)r->y.target, g->ws.valid[j] ? "valid" : "no sample or failed shift: w = 0");
        if (path_sample_is_valid(&r->y))
            fprintf(out, "    (pixel %u's sample %u: d = %d, %s, k = %d)\n", r->y.pixel, r->y.sample, r->y.length,
                    r->y.technique == PATH_TECH_NEE ? "NEE" : "BSDF", r->y.rc_k == PATH_RC_NONE ? -1 : (int)r->y.rc_k);
        fprintf(out, "    y_%d = T_%d(X_%d): J %.17g, p^(y_%d) = p^_{<-0}(y_%d) %.17g, p^_{<-1}(y_%d) %.17g\n", j, j, j,
                (double)g->ws.jacobian[j], j, j, (double)P[j], j, (double)P[2 + j]);
        fprintf(out, "    m_%d(y_%d) %.17g, w_%d = m p^ W J = %.17g, u_%d %.17g\n", j, j, (double)g->ws.mis[j], j,
                (double)g->w[j], j, (double)g->u[j]);
    }
    fprintf(out, "  wsum %.17g, selected y_%d (p^(Y) %.17g), W = wsum / p^(Y) = %.17g, confidence %.17g\n",
            (double)g->out.wsum, g->selected, (double)g->out.y.target, (double)g->out.W, (double)g->out.confidence);
}

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
    int j, d = x->length;
    fprintf(out, "\"vertices\": [");
    if (path_replay(&t, c, x1, x, &end) == SHIFT_OK)
        for (j = 1; j <= d; ++j) {
            vec3 q = t.v[j].position;
            if (j == d && x->technique == PATH_TECH_NEE) q = v3_from_f(end.nee.y.position);
            if (j > 1) fprintf(out, ", ");
            json_triple(out, (double)q.x, (double)q.y, (double)q.z);
        }
    fprintf(out, "]");
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
    int j, mis = g->temporal ? o->temporal_mis : o->mis;
    fprintf(out, "\"%s\": {\"mis\": \"%s\"", g->temporal ? "temporal_step" : "gris_step",
            mis < MIS_FAMILY_COUNT ? mis_family_name((mis_family)mis) : "stochastic-pairwise");
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

static void print_json(FILE *out, const restir_context *c, const restir_options *o, int x, int y, int nx, int ny,
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

int restir_inspect(FILE *out, const scene *s, const restir_options *o, int x, int y, int nx, int ny, int json,
                   int temporal, rerror *e)
{
    light_set lights;
    restir_context c;
    initial_options io;
    initial_stats st;
    path_vertex xa, xb;
    reservoir r, rn;
    inspect_step g, tg;
    int has_a, has_b, status = 0;
    if (restir_options_validate(o, e)) return -1;
    if (temporal && (o->first_frame < 1 || scene_is_animated(s)))
        return rerror_set(e, "inspect --temporal: needs --first-frame >= 1 and a static scene (this one %s)",
                          o->first_frame < 1 ? "is at frame 0" : "is animated");
    if (x < 0 || y < 0 || x >= s->width || y >= s->height || nx < 0 || ny < 0 || nx >= s->width || ny >= s->height)
        return rerror_set(e, "inspect: pixel (%d, %d) or neighbour (%d, %d) outside the %dx%d image", x, y, nx, ny,
                          s->width, s->height);
    if (lights_build(&lights, s, e)) return -1;
    restir_context_for(&c, s, &lights, o);
    restir_initial_options_for(&io, o);
    memset(&st, 0, sizeof st);
    reservoir_init(&r);
    has_a = primary_vertex_of(s, o, &io, x, y, &xa);
    has_b = primary_vertex_of(s, o, &io, nx, ny, &xb);
    if (has_a)
        initial_sample_pixel(&c, &io, &xa, o->seed, (uint32_t)(y * s->width + x), (uint32_t)o->first_frame, &r, &st);
    memset(&g, 0, sizeof g);
    if (has_a && has_b) {
        initial_stats stn;
        memset(&stn, 0, sizeof stn);
        initial_sample_pixel(&c, &io, &xb, o->seed, (uint32_t)(ny * s->width + nx), (uint32_t)o->first_frame, &rn,
                             &stn);
        status = gris_step_of(&c, o, &io, &xa, &xb, &r, &rn, (uint32_t)(y * s->width + x), &g, e);
    }
    memset(&tg, 0, sizeof tg);
    if (!status && has_a && temporal) {
        path_vertex xp;
        reservoir rp;
        initial_stats stp;
        memset(&stp, 0, sizeof stp);
        reservoir_init(&rp);
        /* a static scene: frame f - 1's primary hit of the same pixel (jitter: its own ray) */
        if (primary_vertex_at(s, o, &io, o->first_frame - 1, x, y, &xp))
            initial_sample_pixel(&c, &io, &xp, o->seed, (uint32_t)(y * s->width + x), (uint32_t)(o->first_frame - 1),
                                 &rp, &stp);
        status = temporal_step_of(&c, o, &io, &xa, &xp, &r, &rp, (uint32_t)(y * s->width + x), &tg, e);
    }
    if (status) {
        spatial_workspace_free(&g.ws);
        lights_free(&lights);
        return -1;
    }
    if (json) {
        print_json(out, &c, o, x, y, nx, ny, has_a ? &xa : NULL, has_b ? &xb : NULL, &r, has_a && has_b ? &g : NULL,
                   has_a && temporal ? &tg : NULL);
        goto done;
    }
    fprintf(out, "pixel (%d, %d), frame %d, %d path tree(s), shift %s, d_min %.6g, roughness threshold %.3g\n", x, y,
            o->first_frame, o->candidates, restir_shift_names[o->shift], (double)c.rc.min_distance,
            (double)c.rc.roughness_threshold);
    if (!has_a) {
        fprintf(out, "  the primary ray leaves the scene\n");
        goto done;
    }
    fprintf(out, "initial reservoir: %llu candidates, wsum %.6g, W %.6g, confidence %.6g; ",
            (unsigned long long)st.candidates, (double)r.wsum, (double)r.W, (double)r.confidence);
    print_rgb(out, "estimate F W", reservoir_estimate(&r));
    fprintf(out, "\n");
    if (!path_sample_is_valid(&r.y)) {
        fprintf(out, "  no path selected\n");
    } else {
        print_sample(out, &r.y);
        print_path(out, &c, &xa, &r.y);
        fprintf(out, "shift to pixel (%d, %d):\n", nx, ny);
        if (!has_b) fprintf(out, "  the neighbour's primary ray leaves the scene\n");
        else print_shift(out, &c, &xa, &xb, &r.y);
    }
    if (has_b) print_step_text(out, o, nx, ny, &g);
    if (temporal) print_step_text(out, o, nx, ny, &tg);
done:
    spatial_workspace_free(&g.ws);
    spatial_workspace_free(&tg.ws);
    lights_free(&lights);
    return 0;
}
