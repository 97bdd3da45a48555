/* Test helpers for ReSTIR PT (tests/restir_util.h). */
#include "pt_util.h"
#include "restir_util.h"

#include <string.h>
#include "restir/camera.h"
#include "restir/gbuffer.h"
#include "restir/generate_rooms.h"
#include "test.h"

int rt_load_scene(const char *path, int res, scene *s)
{
    rerror e;
    int status = !strcmp(path, RT_CORRIDOR) ? generate_corridor(s, &e) : scene_load(s, path, &e);
    if (status || scene_prepare(s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    s->width = s->height = res;
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

int rt_restir_side(const scene *s, const restir_options *o, int runs, int block, check_side *side)
{
    int k;
    if (side_begin(s, block, side)) return -1;
    for (k = 0; k < runs; ++k) {
        restir_options ok = *o;
        restir_result r;
        rerror e;
        int status;
        ok.first_frame = o->first_frame + k * o->frames;
        if (restir_render(s, &ok, &r, &e)) {
            test_fail(__FILE__, __LINE__, "restir_render: %s", e.msg);
            check_side_free(side);
            return -1;
        }
        status = side_add(side, &r.mean);
        restir_result_free(&r);
        if (status) {
            check_side_free(side);
            return -1;
        }
    }
    if (side_end(side)) {
        check_side_free(side);
        return -1;
    }
    return 0;
}

static int pt_run(const scene *s, uint32_t seed, uint32_t offset, uint32_t spp, int depth, pt_result *r)
{
    pt_options o;
    rerror e;
    pt_options_default(&o);
    o.seed = seed;
    o.sample_offset = offset;
    o.spp = spp;
    o.max_depth = depth;
    o.threads = 2;
    if (pt_render(s, &o, r, &e)) {
        test_fail(__FILE__, __LINE__, "pt_render: %s", e.msg);
        return -1;
    }
    return 0;
}

int rt_pt_side(const scene *s, uint32_t seed, int runs, uint32_t spp, int max_depth, int indirect_only, int block,
               check_side *side)
{
    int k;
    if (side_begin(s, block, side)) return -1;
    for (k = 0; k < runs; ++k) {
        pt_result r, direct;
        int status;
        if (pt_run(s, seed, (uint32_t)k * spp, spp, max_depth, &r)) {
            check_side_free(side);
            return -1;
        }
        if (indirect_only) {
            size_t i, n = 3 * (size_t)s->width * s->height;
            if (pt_run(s, seed, (uint32_t)k * spp, spp, 2, &direct)) {
                pt_result_free(&r);
                check_side_free(side);
                return -1;
            }
            for (i = 0; i < n; ++i)
                r.mean.px[i] = (float)((r.state.sum[i] - direct.state.sum[i]) / (double)r.state.spp);
            pt_result_free(&direct);
        }
        status = side_add(side, &r.mean);
        pt_result_free(&r);
        if (status) {
            check_side_free(side);
            return -1;
        }
    }
    if (side_end(side)) {
        check_side_free(side);
        return -1;
    }
    return 0;
}

int rt_compare(check_side *a, check_side *b, double alpha, int block, check_result *r)
{
    check_options opt;
    rerror e;
    int status;
    check_options_default(&opt);
    opt.alpha = alpha;
    opt.block_size = block;
    status = check_compare(a, b, &opt, r, &e);
    check_side_free(a);
    check_side_free(b);
    if (status) test_fail(__FILE__, __LINE__, "check_compare: %s", e.msg);
    return status;
}

double rt_mean_z(const check_result *r) { return stats_t_to_z(r->global.t, r->global.dof); }

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
    metal = test_scene_material(s, MAT_CONDUCTOR, rgb_gray(0), rgb_gray(0));
    test_scene_last_material(s)->specular = rgb_make((real)0.9, (real)0.85, (real)0.8);
    test_scene_last_material(s)->roughness = (real)0.3;
    white = test_scene_material(s, MAT_LAMBERT, rgb_make((real)0.8, (real)0.8, (real)0.8), rgb_gray(0));
    light = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(4, (real)3.5, 3));
    test_scene_quad(s, v3f(-1, 0, -1), v3f(0, 0, 2), v3f(2, 0, 0), metal);        /* floor, +y */
    test_scene_quad(s, v3f(-1, 0, 0.6f), v3f(0, 1, 0), v3f(2, 0, 0), white);      /* back wall, -z */
    test_scene_quad(s, v3f(-a / 2, h, -a / 2), v3f(a, 0, 0), v3f(0, 0, a), light); /* faces -y */
    test_scene_camera(s, v3(0, (real)1.2, (real)-0.9), v3(0, 0, (real)0.05), v3(0, 1, 0), 40, res);
    return 0;
}

