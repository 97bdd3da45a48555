/* The generated many-lights hall open to the sky (generate_many_lights_sky, docs/scenes.md):
 * 1000 emitters, a constant environment and a sun, all in one light table. ReSTIR with light
 * RIS and tiles (the sky as one more light, Enhanced §6.1) against the path tracer with the
 * plain light sampler, unpaired, per block and per channel R, G, B; and the generated scene
 * file states the sky. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"
#include "restir/scene/generate.h"
#include "restir/scene/generate_rooms.h"
#include "restir/scene/lights.h"
#include "restir/scene/sky.h"

#define RES 16
#define RUNS 16
#define BLOCK 4

static int make_hall(scene *s)
{
    rerror e;
    memset(s, 0, sizeof *s);
    if (generate_many_lights_sky(s, &e) || scene_prepare(s, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        scene_free(s);
        return -1;
    }
    s->width = s->height = RES;
    return 0;
}

TEST(many_lights_sky_generated)
{
    scene s, back;
    light_set ls;
    rerror e;
    char path[4096];
    if (make_hall(&s)) return;
    CHECK(s.sky && s.sky->has_env && s.sky->has_sun);
    CHECKF(!lights_build(&ls, &s, &e), "%s", e.msg);
    if (!test_has_failed()) {
        CHECKF(ls.count == 2000 && ls.env_entry != LIGHT_NONE && ls.sun_entry != LIGHT_NONE,
               "%zu triangle lights, env entry %u, sun entry %u", ls.count, ls.env_entry, ls.sun_entry);
        lights_free(&ls);
    }
    /* the written scene file loads back with the same sky */
    snprintf(path, sizeof path, "%s", test_tmp_path("mls.scene"));
    CHECKF(!generate_write_scene_file(&s, path, "mls.obj", NULL, &e) && !generate_write_obj(&s, test_tmp_path("mls.obj"), &e),
           "%s", e.msg);
    if (!test_has_failed() && !scene_load(&back, path, &e)) {
        CHECK(back.sky && back.sky->has_env && back.sky->has_sun);
        if (back.sky) {
            CHECK(fabs(back.sky->env_constant.b - s.sky->env_constant.b) < 1e-7);
            CHECK(fabs(back.sky->sun_angle_degrees - 1.5) < 1e-7 && fabs(back.sky->sun_radiance.r - 60) < 1e-6);
            CHECK(fabs(back.sky->sun_direction.z - s.sky->sun_direction.z) < 1e-6);
        }
        scene_free(&back);
    } else
        CHECKF(0, "%s", e.msg);
    scene_free(&s);
}

TEST(many_lights_sky_restir_light_ris)
{
    scene s;
    check_side pt, a;
    pt_options ref;
    restir_options o;
    check_options opt;
    check_result c;
    rerror e;
    int status;
    if (make_hall(&s)) return;
    pt_options_default(&ref);
    ref.seed = test_seed() * 7919u + 11;
    ref.spp = 32;
    ref.max_depth = 3;
    ref.threads = 2;
    if (rt_pt_side_options(&s, &ref, RUNS, BLOCK, &pt)) {
        scene_free(&s);
        return;
    }
    rt_spatial_options(&o, test_seed() * 4099u + 31u, RESTIR_SHIFT_HYBRID, MIS_PAIRWISE_DEFENSIVE, 1, 3, 4.0);
    o.frames = 2;
    o.candidates = 2;
    o.max_depth = 3;
    o.light_ris.candidates = 8;
    o.light_ris.tiles = 1;
    if (rt_restir_side(&s, &o, RUNS, BLOCK, &a)) {
        check_side_free(&pt);
        scene_free(&s);
        return;
    }
    check_options_default(&opt);
    opt.alpha = 1e-3;
    opt.block_size = BLOCK;
    status = check_compare(&a, &pt, &opt, &c, &e);
    CHECKF(status == 0, "check_compare: %s", e.msg);
    if (!status) {
        if (getenv("RESTIR_TEST_VERBOSE"))
            fprintf(stderr, "  many-lights-sky hybrid light-ris 8 tiles: mean z %.2f (lum %.6g vs %.6g), worst block z %.2f\n",
                    rt_mean_z(&c), c.lum_a.mean, c.lum_b.mean, c.worst.z);
        test_margin(fabs(rt_mean_z(&c)) > fabs(c.worst.z) ? rt_mean_z(&c) : c.worst.z);
        CHECKF(!c.different, "differs: mean z %.2f, %ld of %ld blocks rejected, worst z %.2f", rt_mean_z(&c), c.rejected,
               c.tests, c.worst.z);
        check_result_free(&c);
    }
    check_side_free(&a);
    check_side_free(&pt);
    scene_free(&s);
}
