/* `restir inspect`: one pixel's selected path, its shift to a neighbour and two-domain GRIS
 * steps, printed for a reader holding the papers (include/restir/frame/restir.h, restir_inspect;
 * the steps: inspect_step.c, the JSON: inspect_json.c). */
#include "restir/oracle/inspect.h"

#include "restir/frame/options.h"

#include <string.h>
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/scene/animation.h"
#include "restir/scene/scene_trace.h"
#include "inspect_json.h"
#include "inspect_step.h"

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
    if (x->technique == PATH_TECH_NEE ? end.nee.y.triangle == LIGHT_TRIANGLE_DISTANT : path_vertex_is_distant(&t.v[d]))
        fprintf(out, "  x%d at infinity, direction (%.6g, %.6g, %.6g): environment/sun (%s from x%d), light pdf %.6g "
                     "(solid angle)%s\n", d,
                (double)light_distant_direction(x->technique == PATH_TECH_NEE ? end.nee.y.position : t.v[d].hit.position).x,
                (double)light_distant_direction(x->technique == PATH_TECH_NEE ? end.nee.y.position : t.v[d].hit.position).y,
                (double)light_distant_direction(x->technique == PATH_TECH_NEE ? end.nee.y.position : t.v[d].hit.position).z,
                x->technique == PATH_TECH_NEE ? "NEE" : "BSDF", d - 1, (double)end.light_pdf,
                d == x->rc_k ? "   <- x_k" : "");
    else if (x->technique == PATH_TECH_NEE)
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
    if (x->rc_k != PATH_RC_NONE && (x->rc_flags & PATH_RC_FLAG_DISTANT)) {
        fprintf(out, "  x_k at infinity (docs/environment.md), direction (%.6g, %.6g, %.6g)\n", (double)x->rc_position.x,
                (double)x->rc_position.y, (double)x->rc_position.z);
        fprintf(out, "  source terms of Enhanced Eq. 2 at infinity: p_{k-1} %.6g, G %.6g (solid angle), p_k %.6g; ",
                (double)x->rc_pdf_prev, (double)x->rc_geom, (double)x->rc_pdf);
        print_rgb(out, "suffix radiance", x->rc_radiance);
        fprintf(out, "\n");
    } else if (x->rc_k != PATH_RC_NONE) {
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

static void print_step_text(FILE *out, const restir_options *o, int nx, int ny, const inspect_step *g)
{
    const real *P = g->ws.ptarget;
    int j;
    if (g->temporal)
        fprintf(out, "temporal GRIS step (M = 2, MIS %s, M-cap %g%s): domain 0 = this pixel's reservoir of frame %d "
                     "(canonical), domain 1 = its initial reservoir of frame %d\n",
                mis_family_name(o->temporal.mis), o->temporal.mcap,
                o->temporal.mcap_mode == TEMPORAL_MCAP_ABSOLUTE ? " absolute" : "", o->first_frame, o->first_frame - 1);
    else
        fprintf(out, "one GRIS step (spatial, M = 2, MIS %s): domain 0 = this pixel's reservoir (canonical), domain 1 = "
                     "pixel (%d, %d)'s\n",
                spatial_mis_name(&o->spatial), nx, ny);
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
        status = inspect_spatial_step(&c, o, &io, &xa, &xb, &r, &rn, (uint32_t)(y * s->width + x), &g, e);
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
        status = inspect_temporal_step(&c, o, &io, &xa, &xp, &r, &rp, (uint32_t)(y * s->width + x), &tg, e);
    }
    if (status) {
        spatial_workspace_free(&g.ws);
        lights_free(&lights);
        return -1;
    }
    if (json) {
        inspect_print_json(out, &c, o, x, y, nx, ny, has_a ? &xa : NULL, has_b ? &xb : NULL, &r,
                           has_a && has_b ? &g : NULL, has_a && temporal ? &tg : NULL);
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
