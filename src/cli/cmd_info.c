/* restir info SCENE: what the scene contains and how its BVH came out. */
#include "cmd_info.h"

#include <stdio.h>
#include <string.h>
#include "restir/scene/animation.h"
#include "restir/scene/sky.h"
#include "args.h"
#include "scene_args.h"

static void print_materials(const scene *s)
{
    size_t i;
    for (i = 0; i < s->material_count; ++i) {
        const material *m = &s->materials[i];
        printf("  material %-20s %-16s kd (%g %g %g) ks (%g %g %g) ke (%g %g %g) roughness %g ior %g\n", m->name,
               material_type_names[m->type], (double)m->diffuse.r, (double)m->diffuse.g, (double)m->diffuse.b,
               (double)m->specular.r, (double)m->specular.g, (double)m->specular.b, (double)m->emission.r,
               (double)m->emission.g, (double)m->emission.b, (double)m->roughness, (double)m->ior);
    }
}

/* Animated objects (their keyframe counts) and the frame range of all keyframes. */
static void print_animation(const scene *s)
{
    size_t i, keys;
    int first, last;
    if (scene_frame_range(s, &first, &last)) return;
    printf("frames       %d..%d", first, last);
    for (i = 0; i < scene_animated_object_count(s); ++i) {
        uint32_t object;
        scene_animated_object(s, i, &object, NULL, &keys);
        printf("%s'%s' (%zu keyframes)", i ? ", " : "; animated: ", s->object_names[object], keys);
    }
    printf("\n");
}

/* The distant lights (docs/environment.md). */
static void print_sky(const scene_sky *k)
{
    if (k->has_env && k->env_is_map)
        printf("environment  map %s, %dx%d, rotate %g, scale %g\n", k->env_path, k->width, k->height,
               (double)k->rotate_degrees, (double)k->scale);
    else if (k->has_env)
        printf("environment  constant (%g %g %g)\n", (double)k->env_constant.r, (double)k->env_constant.g,
               (double)k->env_constant.b);
    if (k->has_sun)
        printf("sun          direction (%g %g %g), radius %g degrees, radiance (%g %g %g)\n", (double)k->sun_direction.x,
               (double)k->sun_direction.y, (double)k->sun_direction.z, (double)k->sun_angle_degrees,
               (double)k->sun_radiance.r, (double)k->sun_radiance.g, (double)k->sun_radiance.b);
}

static void print_info(const scene *s, double load_seconds, double bvh_seconds)
{
    const camera_pose *c = &s->camera;
    printf("scene        %s\n", s->path);
    printf("triangles    %zu\n", s->triangle_count);
    printf("vertices     %zu (normals %zu)\n", s->position_count, s->normal_count);
    printf("objects      %zu\n", s->object_count);
    printf("materials    %zu\n", s->material_count);
    printf("emitters     %zu triangles\n", scene_emitter_count(s));
    if (s->sky) print_sky(s->sky); /* scenes without a sky print as before */
    printf("bounds       (%g %g %g) - (%g %g %g)\n", s->bounds_min.x, s->bounds_min.y, s->bounds_min.z,
           s->bounds_max.x, s->bounds_max.y, s->bounds_max.z);
    printf("bvh          %zu nodes, depth %d, SAH cost %.3f\n", s->accel.node_count, s->accel.depth, s->accel.sah_cost);
    printf("camera       eye (%g %g %g) target (%g %g %g) up (%g %g %g) fov %g%s\n", (double)c->eye.x,
           (double)c->eye.y, (double)c->eye.z, (double)c->target.x, (double)c->target.y, (double)c->target.z,
           (double)c->up.x, (double)c->up.y, (double)c->up.z, (double)c->fov_y_degrees,
           s->has_camera ? "" : " (framed on the bounds)");
    printf("image        %dx%d, %zu camera keyframes\n", s->width, s->height, s->keyframe_count);
    print_animation(s);
    printf("seconds      load %.3f, bvh %.3f\n", load_seconds, bvh_seconds);
    print_materials(s);
}

int cmd_info(int argc, char **argv)
{
    scene_overrides ov;
    cli_option options[10];
    const char *positional[1];
    int n, count, status;
    double load_s, bvh_s;
    scene s;
    memset(&ov, 0, sizeof ov);
    n = scene_override_options(options, &ov);
    memset(&options[n], 0, sizeof options[n]);
    status = cli_parse("info", argc, argv, options, positional, 1, &count);
    if (status == 1) {
        cli_print_help(stdout, "info", "SCENE(.scene|.obj) [options]", options);
        return 0;
    }
    if (status) return status;
    if (count != 1) {
        fprintf(stderr, "restir info: expected one SCENE argument\n");
        return 2;
    }
    status = load_scene_for_command("info", positional[0], &ov, &s, &load_s, &bvh_s);
    if (status) return status;
    print_info(&s, load_s, bvh_s);
    scene_free(&s);
    return 0;
}
