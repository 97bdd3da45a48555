/* Test helpers for ReSTIR PT (tests/restir_util.h). */
#include "pt_util.h"
#include "restir_util.h"
#include "bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/scene/generate_rooms.h"
#include "restir/frame/offline.h"
#include "test.h"
#include "restir/scene/scene_trace.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"

int rt_load_scene(const char *path, int res, scene *s)
{
    rerror e;
    int status;
    if (!path) { /* the spot scene, prepared */
        if (rt_make_spot(s, res)) return -1;
        if (scene_prepare(s, &e)) {
            test_fail(__FILE__, __LINE__, "%s", e.msg);
            scene_free(s);
            return -1;
        }
        return 0;
    }
    status = !strcmp(path, RT_CORRIDOR) ? generate_corridor(s, &e) : scene_load(s, path, &e);
    if (status || scene_prepare(s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    s->width = s->height = res;
    return 0;
}

int rt_load_glossy_pan(scene *s, int res, double pan)
{
    return rt_load_scene_pan("scenes/cornell-glossy.scene", s, res, pan);
}

/* The scene's camera panning along x: eye and target at x - pan/2 at frame 0 to x + pan/2 at
 * frame 16; pan 0: the scene as it is. */
int rt_load_scene_pan(const char *path, scene *s, int res, double pan)
{
    camera_pose p;
    if (rt_load_scene(path, res, s)) return -1;
    if (pan == 0) return 0;
    p = s->camera;
    s->keyframes = calloc(2, sizeof *s->keyframes);
    if (!s->keyframes) {
        test_fail(__FILE__, __LINE__, "out of memory");
        scene_free(s);
        return -1;
    }
    s->keyframe_count = 2;
    s->keyframes[0].frame = 0;
    s->keyframes[0].pose = p;
    s->keyframes[0].pose.eye.x -= (real)(pan / 2);
    s->keyframes[0].pose.target.x -= (real)(pan / 2);
    s->keyframes[1].frame = 16;
    s->keyframes[1].pose = p;
    s->keyframes[1].pose.eye.x += (real)(pan / 2);
    s->keyframes[1].pose.target.x += (real)(pan / 2);
    return 0;
}

int rt_load_scene_lights(const char *path, int res, scene *s, light_set *ls)
{
    rerror e;
    if (rt_load_scene(path, res, s)) return -1;
    if (lights_build(ls, s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(s);
        return -1;
    }
    return 0;
}

static int side_begin(const scene *s, int block, check_side *side)
{
    rerror e;
    if (check_side_begin_runs(side, s->width, s->height, block, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    return 0;
}

static int side_add(check_side *side, const image *img)
{
    rerror e;
    if (check_side_add_run(side, img, "run", &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    return 0;
}

static int side_end(check_side *side)
{
    rerror e;
    if (check_side_end_runs(side, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    return 0;
}

/* Adds run k of a side to it. */
typedef int (*side_run_fn)(const scene *s, const void *ctx, int k, check_side *side);

/* A side of `runs` runs made by run(s, ctx, k, side); freed on a failure. */
static int side_of_runs(const scene *s, int runs, int block, side_run_fn run, const void *ctx, check_side *side)
{
    int k;
    if (side_begin(s, block, side)) return -1;
    for (k = 0; k < runs; ++k)
        if (run(s, ctx, k, side)) {
            check_side_free(side);
            return -1;
        }
    if (side_end(side)) {
        check_side_free(side);
        return -1;
    }
    return 0;
}

/* Run k of restir_render into the side. */
int rt_restir_run(const scene *s, const restir_options *base, int k, restir_result *r)
{
    restir_options o = *base;
    rerror e;
    o.first_frame = base->first_frame + k * base->frames;
    if (restir_render(s, &o, r, &e)) {
        test_fail(__FILE__, __LINE__, "restir_render: %s", e.msg);
        return -1;
    }
    return 0;
}

static int restir_run(const scene *s, const void *ctx, int k, check_side *side)
{
    restir_result r;
    int status;
    if (rt_restir_run(s, ctx, k, &r)) return -1;
    status = side_add(side, &r.mean);
    restir_result_free(&r);
    return status;
}

int rt_restir_side(const scene *s, const restir_options *o, int runs, int block, check_side *side)
{
    return side_of_runs(s, runs, block, restir_run, o, side);
}

typedef struct {
    pt_options base;
    int indirect_only;
} pt_side_ctx;

/* Run k of the path tracer: the samples [offset + k spp, offset + (k+1) spp); indirect_only:
 * minus the same samples' paths of at most 2 segments. */
static int pt_run(const scene *s, const void *ctx, int k, check_side *side)
{
    const pt_side_ctx *c = ctx;
    pt_options o = c->base;
    pt_result r, direct;
    int status;
    o.sample_offset = c->base.sample_offset + (uint32_t)k * c->base.spp;
    if (test_pt_render(s, &o, &r)) return -1;
    if (c->indirect_only) {
        size_t i, n = 3 * (size_t)s->width * s->height;
        o.max_depth = 2;
        if (test_pt_render(s, &o, &direct)) {
            pt_result_free(&r);
            return -1;
        }
        for (i = 0; i < n; ++i) r.mean.px[i] = (float)((r.state.sum[i] - direct.state.sum[i]) / (double)r.state.spp);
        pt_result_free(&direct);
    }
    status = side_add(side, &r.mean);
    pt_result_free(&r);
    return status;
}

int rt_pt_side_options(const scene *s, const pt_options *base, int runs, int block, check_side *side)
{
    pt_side_ctx c;
    c.base = *base;
    c.indirect_only = 0;
    return side_of_runs(s, runs, block, pt_run, &c, side);
}

int rt_pt_side(const scene *s, uint32_t seed, int runs, uint32_t spp, int max_depth, int indirect_only, int block,
               check_side *side)
{
    return rt_pt_side_at(s, seed, runs, spp, max_depth, indirect_only, 0, block, side);
}

int rt_pt_side_at(const scene *s, uint32_t seed, int runs, uint32_t spp, int max_depth, int indirect_only, int frame,
                  int block, check_side *side)
{
    pt_side_ctx c;
    test_pt_options(&c.base, seed, spp, max_depth);
    c.base.frame = frame;
    c.indirect_only = indirect_only;
    return side_of_runs(s, runs, block, pt_run, &c, side);
}

check_options rt_check_options(double alpha, int block)
{
    check_options o;
    check_options_default(&o);
    o.alpha = alpha;
    if (block > 0) o.block_size = block;
    return o;
}

int rt_compare_sides(const check_side *a, const check_side *b, double alpha, int block, int paired,
                     check_result *r)
{
    check_options opt = rt_check_options(alpha, block);
    rerror e;
    int status;
    status = paired ? check_compare_paired(a, b, &opt, r, &e) : check_compare(a, b, &opt, r, &e);
    if (status) test_fail(__FILE__, __LINE__, "%s: %s", paired ? "check_compare_paired" : "check_compare", e.msg);
    return status;
}

static bench_paired last_channels;

const struct bench_paired_s *rt_last_channels(void) { return &last_channels; }

int rt_compare_paired(const check_side *a, const check_side *b, double alpha, int block, check_result *r)
{
    int status = rt_compare_sides(a, b, alpha, block, 1, r);
    long k;
    bench_paired_init(&last_channels, "rt_compare_paired R, G, B");
    if (status || !a->run_means || !b->run_means || a->runs != b->runs || a->runs < 2) return status;
    for (k = 0; k < a->runs; ++k) bench_paired_add(&last_channels, a->run_means + 3 * k, b->run_means + 3 * k);
    bench_paired_finish(&last_channels);
    if (bench_paired_max_abs_z(&last_channels, NULL) >= BENCH_Z_CONSISTENT) r->different = 1;
    return 0;
}

int rt_compare(check_side *a, check_side *b, double alpha, int block, check_result *r)
{
    int status = rt_compare_sides(a, b, alpha, block, 0, r);
    check_side_free(a);
    check_side_free(b);
    return status;
}

double rt_mean_z(const check_result *r) { return stats_t_to_z(r->global.t, r->global.dof); }

int rt_expect_verdict(check_side *a, const check_side *ref, double alpha, int block, const char *what, int biased,
                      check_result *out)
{
    check_result c;
    int status = rt_compare_sides(a, ref, alpha, block, 0, &c), ok;
    check_side_free(a);
    if (status) return -1;
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                rt_mean_z(&c), c.lum_a.mean, c.lum_b.mean, c.rejected, c.tests, c.worst.z);
    ok = !c.different == !biased;
    if (!ok && biased)
        test_fail(__FILE__, __LINE__, "%s: the biased estimator was not detected (mean z %.2f, worst block z %.2f)",
                  what, rt_mean_z(&c), c.worst.z);
    else if (!ok)
        test_fail(__FILE__, __LINE__,
                  "%s: differs from the path tracer: mean z %.2f (p %.3g), %ld of %ld blocks rejected, worst z %.2f",
                  what, rt_mean_z(&c), c.global.p, c.rejected, c.tests, c.worst.z);
    if (out) *out = c;
    else check_result_free(&c);
    return ok ? 0 : 1;
}

int rt_bench_open(rt_bench *b, const char *path, int res, int runs, uint32_t spp, int max_depth, uint32_t pt_seed)
{
    memset(b, 0, sizeof *b);
    b->res = res;
    b->block = 4;
    b->runs = runs;
    b->max_depth = max_depth;
    if (rt_load_scene(path, res, &b->s)) return -1; /* NULL: the spot scene */
    if (rt_pt_side(&b->s, pt_seed, runs, spp, max_depth, 0, b->block, &b->pt)) {
        scene_free(&b->s);
        return -1;
    }
    return 0;
}

void rt_bench_close(rt_bench *b)
{
    check_side_free(&b->pt);
    scene_free(&b->s);
}

static int collect_frame(void *user, int frame, const image *img, const restir_stats *st, rerror *e)
{
    rt_frame_sides *q = user;
    int i;
    (void)st;
    for (i = 0; i < q->nt; ++i)
        if (q->times[i] == frame && check_side_add_run(&q->side[i], img, "run", e)) return -1;
    return 0;
}

void rt_frame_sides_free(rt_frame_sides *q)
{
    int i;
    for (i = 0; i < q->nt; ++i) check_side_free(&q->side[i]);
}

int rt_frame_sides_run(const scene *s, const restir_options *o, int runs, int block, rt_frame_sides *q)
{
    int i;
    for (i = 0; i < q->nt; ++i)
        if (side_begin(s, block, &q->side[i])) {
            while (i-- > 0) check_side_free(&q->side[i]);
            return -1;
        }
    if (rt_sequence_runs(s, o, 0, q->times[q->nt - 1], runs, collect_frame, q, NULL)) {
        rt_frame_sides_free(q);
        return -1;
    }
    for (i = 0; i < q->nt; ++i)
        if (side_end(&q->side[i])) {
            rt_frame_sides_free(q);
            return -1;
        }
    return 0;
}

int rt_render_stats(const char *args, const char *name, json_reader *jr)
{
    char out[4096], img[1024], stats[1024], file[256];
    rerror e;
    snprintf(file, sizeof file, "%s.pfm", name);
    snprintf(img, sizeof img, "%s", test_tmp_path(file));
    snprintf(file, sizeof file, "%s.json", name);
    snprintf(stats, sizeof stats, "%s", test_tmp_path(file));
    if (test_cli(out, sizeof out, "render %s --quiet --no-png -o %s --stats %s", args, img, stats) != 0) {
        test_fail(__FILE__, __LINE__, "%s", out);
        return -1;
    }
    if (json_reader_open(jr, stats, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    return 0;
}

void rt_initial_options(initial_options *io, initial_stats *ist, int trees, int max_depth)
{
    memset(io, 0, sizeof *io);
    memset(ist, 0, sizeof *ist);
    io->trees = trees;
    io->max_depth = max_depth;
    io->rr_min_depth = 3;
}

void rt_spatial_options(restir_options *o, uint32_t seed, int shift, int mis, int passes, int neighbors,
                        double radius)
{
    restir_options_default(o);
    o->seed = seed;
    o->shift = (enum restir_shift)shift;
    o->spatial.mis = (mis_family)mis;
    o->spatial_passes = passes;
    o->spatial.neighbors = neighbors;
    o->spatial.radius = radius;
    o->threads = 2;
}

int rt_primary_vertex(const scene *s, int x, int y, path_vertex *v)
{
    camera cam;
    ray r;
    surface_hit h;
    camera_init(&cam, scene_camera_at(s, 0), s->width, s->height);
    r = primary_ray(&cam, x, y, 0, 0, 0);
    if (!scene_intersect(s, &r, &h)) return 0;
    path_vertex_make(v, s, &h, v3_from_f(r.dir));
    return 1;
}

void rt_context(restir_context *c, const scene *s, const light_set *lights, int shift)
{
    restir_options o;
    restir_options_default(&o);
    o.shift = shift;
    restir_context_for(c, s, lights, &o);
}

/* A glossy floor (GGX conductor, roughness 0.3) and a white back wall with a small quad
 * light 8 cm above the floor: the light pdf of direct light changes by an order of
 * magnitude across a few pixels, and the floor's glossy reflection of the lit wall
 * changes sharply between neighbouring pixels (so E[J_{c->n}] is far from 1). */
int rt_make_spot(scene *s, int res)
{
    uint32_t metal, white, light;
    const float h = 0.08f, a = 0.15f;
    if (test_scene_begin(s, 8, 3)) return -1;
    metal = test_scene_glossy(s, MAT_CONDUCTOR, rgb_gray(0), rgb_make((real)0.9, (real)0.85, (real)0.8), (real)0.3);
    white = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.8, (real)0.8, (real)0.8), rgb_gray(0));
    light = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(4, (real)3.5, 3));
    test_scene_quad(s, v3f(-1, 0, -1), v3f(0, 0, 2), v3f(2, 0, 0), metal);        /* floor, +y */
    test_scene_quad(s, v3f(-1, 0, 0.6f), v3f(0, 1, 0), v3f(2, 0, 0), white);      /* back wall, -z */
    test_scene_quad(s, v3f(-a / 2, h, -a / 2), v3f(a, 0, 0), v3f(0, 0, a), light); /* faces -y */
    test_scene_camera(s, v3(0, (real)1.2, (real)-0.9), v3(0, 0, (real)0.05), v3(0, 1, 0), 40, res);
    return 0;
}


/* ---- a fresh evaluation of an offset path (restir_util.h) ---------------------------- */

/* f_l|cos| / (P(l|wo) pdf_l(w)) at v: the one-lobe bounce weight of the path sampler. */
static rgb lobe_weight(const path_vertex *v, unsigned lobe, vec3 w, real *pdf)
{
    rgb f;
    *pdf = 0;
    if (lobe >= PATH_LOBE_NEE || !path_vertex_eval_lobe(v, (int)lobe, w, &f, pdf)) return rgb_gray(0);
    return rgb_scale(f, 1 / *pdf);
}

/* The BSDF technique's last factor at `from`: bounce weight of `lobe` towards the emitter
 * `to` (seen along w), Le, and w_bsdf with the all-lobe pdf and the light pdf from `from`. */
static rgb bsdf_end(const restir_context *c, const path_vertex *from, unsigned lobe, vec3 w, const path_vertex *to)
{
    bsdf_bounce b;
    real light_pdf, pdf_lobe;
    rgb weight = lobe_weight(from, lobe, w, &pdf_lobe);
    if (rgb_is_black(weight)) return weight;
    memset(&b, 0, sizeof b);
    b.pdf_lobe = pdf_lobe;
    b.pdf_all = path_vertex_pdf(from, w);
    light_pdf = path_light_pdf(&c->path, to->hit.triangle, from->position, to->position, to->ng);
    return rgb_mul(weight, rgb_scale(path_vertex_emitted(&c->path, to), path_mis_weight_bsdf_hit(&c->path, &b, light_pdf)));
}

/* The NEE technique's last factor at `from` towards the light point y (normal ny, on
 * triangle tri, emitting le towards from): f_all|cos| Le / p_light times w_nee. */
static rgb nee_end(const restir_context *c, const path_vertex *from, vec3 w, uint32_t tri, vec3 y, vec3 ny, rgb le)
{
    real p_light = path_light_pdf(&c->path, tri, from->position, y, ny);
    rgb f = path_vertex_eval(from, w);
    if (!from->can_nee || !(p_light > 0) || rgb_is_black(f)) return rgb_gray(0);
    return rgb_scale(rgb_scale(rgb_mul(f, le), 1 / p_light), path_mis_weight_nee(&c->path, p_light, path_vertex_pdf(from, w)));
}

rgb rt_fresh_contribution(const restir_context *c, const path_vertex *y1, const path_vertex *x1_origin,
                          const path_sample *x)
{
    const scene *s = c->path.scene;
    path_trunk t, o;
    path_end end, end_o;
    path_vertex xk;
    int k = x->rc_k, d = x->length, j;
    unsigned lobe_prev;
    const path_vertex *prev;
    vec3f origin_f;
    vec3 xk_pos, w, to;
    rgb F, black = rgb_gray(0);
    real pdf;
    if (!path_sample_is_valid(x)) return black;
    if (k == PATH_RC_NONE) return path_replay(&t, c, y1, x, &end) == SHIFT_OK ? end.F : black;
    /* x_k .. x_d: the base path's own vertices, from its own pixel */
    if (path_replay(&o, c, x1_origin, x, &end_o) != SHIFT_OK) return black;
    if (trunk_replay(&t, c, y1, x, k - 1) != SHIFT_OK) return black;
    prev = &t.v[k - 1];
    lobe_prev = x->lobe[k - 1];
    xk_pos = k == d && x->technique == PATH_TECH_NEE ? v3_from_f(end_o.nee.y.position) : o.v[k].position;
    /* the segment starts where the path sampler starts it: the spawned ray's origin for a
     * BSDF bounce, the vertex for NEE (vertex_sample_light) */
    origin_f = lobe_prev == PATH_LOBE_NEE
                   ? prev->hit.position
                   : scene_spawn_ray(prev->hit.position, prev->hit.ng, v3f_sub(v3f_from(xk_pos), prev->hit.position),
                                     v3f_from(prev->wo)).origin;
    to = v3_sub(xk_pos, v3_from_f(origin_f));
    w = v3_normalize(to);
    /* the reconnection segment, traced again */
    if (!scene_visible(s, prev->hit.position, prev->hit.ng, v3f_from(xk_pos),
                       k == d && x->technique == PATH_TECH_NEE ? &end_o.nee.y.normal : &o.v[k].hit.ng))
        return black;
    F = t.beta[k - 1];
    if (k == d && x->technique == PATH_TECH_NEE)
        return rgb_mul(F, nee_end(c, prev, w, end_o.nee.y.triangle, xk_pos, v3_from_f(end_o.nee.y.normal),
                                  light_emitted(c->path.lights->lights[c->path.lights->light_of_triangle[end_o.nee.y.triangle]].emission,
                                                v3_from_f(end_o.nee.y.normal), v3_neg(w))));
    path_vertex_make(&xk, s, &o.v[k].hit, w); /* x_k seen from y_{k-1} */
    if (k == d) return rgb_mul(F, bsdf_end(c, prev, lobe_prev, w, &xk));
    F = rgb_mul(F, lobe_weight(prev, lobe_prev, w, &pdf));
    if (k == d - 1) {
        if (x->technique == PATH_TECH_NEE)
            return rgb_mul(F, nee_end(c, &xk, end_o.nee.wi, end_o.nee.y.triangle, v3_from_f(end_o.nee.y.position),
                                      v3_from_f(end_o.nee.y.normal), end_o.nee.emitted));
        return rgb_mul(F, bsdf_end(c, &xk, x->lobe[k], o.b[k].wi, &o.v[d]));
    }
    F = rgb_mul(F, lobe_weight(&xk, x->lobe[k], o.b[k].wi, &pdf));
    for (j = k + 1; j < d - 1; ++j) F = rgb_mul(F, o.b[j].weight);
    if (x->technique == PATH_TECH_NEE)
        return rgb_mul(F, rgb_scale(end_o.nee.contribution,
                                    path_mis_weight_nee(&c->path, end_o.nee.pdf_light, end_o.nee.pdf_bsdf)));
    return rgb_mul(F, rgb_mul(o.b[d - 1].weight, rgb_scale(path_vertex_emitted(&c->path, &o.v[d]),
                                                          path_mis_weight_bsdf_hit(&c->path, &o.b[d - 1], end_o.light_pdf))));
}

/* Determinant by Gaussian elimination with partial pivoting. */
double rt_determinant(double a[6][6], int n)
{
    double det = 1;
    int i, j, r;
    for (i = 0; i < n; ++i) {
        int p = i;
        for (r = i + 1; r < n; ++r)
            if (fabs(a[r][i]) > fabs(a[p][i])) p = r;
        if (a[p][i] == 0) return 0;
        if (p != i) {
            for (j = 0; j < n; ++j) {
                double tmp = a[i][j];
                a[i][j] = a[p][j];
                a[p][j] = tmp;
            }
            det = -det;
        }
        det *= a[i][i];
        for (r = i + 1; r < n; ++r) {
            double m = a[r][i] / a[i][i];
            for (j = i; j < n; ++j) a[r][j] -= m * a[i][j];
        }
    }
    return det;
}

/* The final confidences of frame 4 of a still-camera sequence (cornell-glossy 16^2, no
 * spatial pass, `trees` path trees, temporal M-cap C = 2.5 in `mode`): every pixel with a
 * history must hold `expect` exactly (read from the sequence checkpoint: the final
 * reservoirs of frame 4). Fails the test (naming `what`) otherwise. */
void rt_mcap_sequence_exact(int trees, enum temporal_mcap_mode mode, double expect, const char *what)
{
    scene s;
    restir_options o;
    restir_sequence q;
    restir_stats total;
    reservoir *rs;
    reservoir_dump_info info;
    rerror e;
    char ck[1100], name[128];
    long i, n, with = 0, wrong = 0;
    double first_wrong = 0;
    if (rt_load_scene("scenes/cornell-glossy.scene", 16, &s)) return;
    restir_options_default(&o);
    o.spatial_passes = 0;
    o.candidates = trees;
    o.max_depth = 3;
    o.temporal.mcap = 2.5;
    o.temporal.mcap_mode = mode;
    o.threads = 2;
    o.seed = test_seed();
    memset(&q, 0, sizeof q);
    q.first = 0;
    q.last = 4;
    snprintf(name, sizeof name, "mcap-%d-%s.checkpoint", trees, temporal_mcap_mode_names[mode]);
    snprintf(ck, sizeof ck, "%s", test_tmp_path(name));
    q.checkpoint = ck;
    if (restir_render_sequence(&s, &o, &q, NULL, NULL, &total, &e) || reservoir_dump_read(ck, &rs, &info, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(&s);
        return;
    }
    n = (long)info.width * (long)info.height;
    for (i = 0; i < n; ++i) {
        double c = (double)rs[i].confidence;
        if (c == 0) continue; /* no primary hit */
        if (c == expect)
            ++with;
        else if (!wrong++)
            first_wrong = c;
    }
    free(rs);
    scene_free(&s);
    CHECKF(wrong == 0, "%s: %ld of %ld pixels have confidence != %g after 5 frames (first: %g)", what, wrong,
           wrong + with, expect, first_wrong);
    CHECKF(with > n / 2, "%s: only %ld of %ld pixels carry a history", what, with, n);
}

/* A glossy floor (roughness 0.3: not connectable with --roughness-threshold 0.5, so paths
 * reconnect at k = 3 and prefix mutations move y_2), a back wall half red, half green, and a
 * small light in front of the red half: a pixel's colour depends on where y_2 lands, and a
 * chain that does not leave p̂ invariant drifts in colour while the luminance of F W stays
 * exact (Eq. 17). */
int rt_make_two_tone(scene *s, int res)
{
    uint32_t metal, red, green, light;
    const float h = 0.1f, a = 0.4f;
    if (test_scene_begin(s, 10, 4)) return -1;
    metal = test_scene_glossy(s, MAT_CONDUCTOR, rgb_gray(0), rgb_make((real)0.9, (real)0.9, (real)0.9), (real)0.3);
    red = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.9, (real)0.1, (real)0.1), rgb_gray(0));
    green = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.1, (real)0.9, (real)0.1), rgb_gray(0));
    light = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(1, 1, 1));
    test_scene_quad(s, v3f(-1, 0, -1), v3f(0, 0, 2), v3f(2, 0, 0), metal);
    test_scene_quad(s, v3f(-1, 0, 0.6f), v3f(0, 1, 0), v3f(1, 0, 0), red);
    test_scene_quad(s, v3f(0, 0, 0.6f), v3f(0, 1, 0), v3f(1, 0, 0), green);
    test_scene_quad(s, v3f(-0.9f, h, 0.45f), v3f(a, 0, 0), v3f(0, a, 0), light);
    test_scene_camera(s, v3(0, (real)1.2, (real)-0.9), v3(0, 0, (real)0.05), v3(0, 1, 0), 40, res);
    return test_scene_prepare(s);
}

int rt_frame_open(rt_frame *f, const char *path, int res, int shift, int max_depth, uint32_t seed)
{
    restir_options o;
    rerror e;
    memset(f, 0, sizeof *f);
    restir_options_default(&o);
    o.shift = shift;
    o.max_depth = max_depth;
    o.keep_reservoirs = 1;
    o.seed = seed;
    o.threads = 2;
    if (rt_load_scene_lights(path, res, &f->s, &f->lights)) return -1;
    if (restir_render(&f->s, &o, &f->res, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        lights_free(&f->lights);
        scene_free(&f->s);
        return -1;
    }
    restir_context_for(&f->c, &f->s, &f->lights, &o);
    return 0;
}

void rt_frame_close(rt_frame *f)
{
    lights_free(&f->lights);
    restir_result_free(&f->res);
    scene_free(&f->s);
}

void rt_mutation_options(restir_options *o)
{
    restir_options_default(o);
    o->shift = RESTIR_SHIFT_HYBRID;
    o->spatial.mis = MIS_PAIRWISE_DEFENSIVE;
    o->candidates = 2;
    o->max_depth = 4;
    o->threads = 2;
    o->mutation.count = 20;
    o->mutation.stages = MUTATE_AFTER_TEMPORAL;
}

void rt_mutation_paired(const scene *s, const restir_options *on, int runs, uint32_t seed0,
                        bench_paired *p)
{
    bench_sequence_config a, b;
    a.s = b.s = s;
    a.frame = b.frame = 4;
    a.o = b.o = *on;
    b.o.mutation.count = 0;
    bench_paired_run(p, runs, seed0, bench_sequence_run, &a, bench_sequence_run, &b);
}
