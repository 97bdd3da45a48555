/* `restir inspect`: one pixel's selected path and its shift to a neighbour, printed for a
 * reader holding the papers (include/restir/restir.h, restir_inspect). */
#include "restir/restir.h"

#include <string.h>
#include "restir/camera.h"
#include "restir/gbuffer.h"

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

static int primary_vertex_of(const scene *s, const restir_options *o, const initial_options *io, int x, int y,
                             path_vertex *v)
{
    camera cam;
    surface_hit h;
    ray r;
    camera_init(&cam, scene_camera_at(s, 0), s->width, s->height);
    r = primary_ray(&cam, x, y, o->seed, initial_tree_sample(io, (uint32_t)o->first_frame, 0), o->jitter);
    if (!scene_intersect(s, &r, &h)) return 0;
    path_vertex_make(v, s, &h, v3_from_f(r.dir));
    return 1;
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

int restir_inspect(FILE *out, const scene *s, const restir_options *o, int x, int y, int nx, int ny, rerror *e)
{
    light_set lights;
    restir_context c;
    initial_options io;
    initial_stats st;
    path_vertex xa, xb;
    reservoir r;
    if (restir_options_validate(o, e)) return -1;
    if (x < 0 || y < 0 || x >= s->width || y >= s->height || nx < 0 || ny < 0 || nx >= s->width || ny >= s->height)
        return rerror_set(e, "inspect: pixel (%d, %d) or neighbour (%d, %d) outside the %dx%d image", x, y, nx, ny,
                          s->width, s->height);
    if (lights_build(&lights, s, e)) return -1;
    restir_context_for(&c, s, &lights, o);
    restir_initial_options_for(&io, o);
    memset(&st, 0, sizeof st);
    fprintf(out, "pixel (%d, %d), frame %d, %d path tree(s), shift %s, d_min %.6g, roughness threshold %.3g\n", x, y,
            o->first_frame, o->candidates, restir_shift_names[o->shift], (double)c.rc.min_distance,
            (double)c.rc.roughness_threshold);
    if (!primary_vertex_of(s, o, &io, x, y, &xa)) {
        fprintf(out, "  the primary ray leaves the scene\n");
        lights_free(&lights);
        return 0;
    }
    initial_sample_pixel(&c, &io, &xa, o->seed, (uint32_t)(y * s->width + x), (uint32_t)o->first_frame, &r, &st);
    fprintf(out, "initial reservoir: %llu candidates, wsum %.6g, W %.6g, confidence %.6g; ",
            (unsigned long long)st.candidates, (double)r.wsum, (double)r.W, (double)r.confidence);
    print_rgb(out, "estimate F W", reservoir_estimate(&r));
    fprintf(out, "\n");
    if (!path_sample_is_valid(&r.y)) {
        fprintf(out, "  no path selected\n");
        lights_free(&lights);
        return 0;
    }
    print_sample(out, &r.y);
    print_path(out, &c, &xa, &r.y);
    fprintf(out, "shift to pixel (%d, %d):\n", nx, ny);
    if (!primary_vertex_of(s, o, &io, nx, ny, &xb)) fprintf(out, "  the neighbour's primary ray leaves the scene\n");
    else print_shift(out, &c, &xa, &xb, &r.y);
    lights_free(&lights);
    return 0;
}
