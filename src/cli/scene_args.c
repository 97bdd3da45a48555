/* Loading the scene named on the command line, with camera/image overrides. */
#include "scene_args.h"

#include <math.h>
#include <stdio.h>
#include "restir/core/progress.h"
#include "restir/scene/camera_path.h"

int scene_override_options(cli_option *rows, scene_overrides *o)
{
    const cli_option defs[] = {
        {"--eye", OPT_VEC3, o->eye, "camera position (overrides the scene)", NULL, 0, 0, &o->has_eye},
        {"--target", OPT_VEC3, o->target, "point the camera looks at", NULL, 0, 0, &o->has_target},
        {"--up", OPT_VEC3, o->up, "camera up vector", NULL, 0, 0, &o->has_up},
        {"--fov", OPT_REAL, &o->fov, "vertical field of view in degrees", NULL, 0.001, 179.999, &o->has_fov},
        {"--size", OPT_SIZE, o->size, "image size, e.g. 512x512", NULL, 0, 0, &o->has_size},
        {"--allow-missing-mtl", OPT_FLAG, &o->allow_missing_mtl, "a missing material library or map file is a warning (default: an error)", NULL, 0, 0, NULL},
    };
    int i, n = (int)(sizeof defs / sizeof defs[0]);
    for (i = 0; i < n; ++i) rows[i] = defs[i];
    return n;
}

static vec3 vec3_of(const double v[3]) { return v3((real)v[0], (real)v[1], (real)v[2]); }

static int apply_overrides(const scene_overrides *o, scene *s, rerror *e)
{
    camera_pose *poses[1];
    if (o->has_size) {
        s->width = o->size[0];
        s->height = o->size[1];
    }
    poses[0] = &s->camera;
    if (o->has_eye) poses[0]->eye = vec3_of(o->eye);
    if (o->has_target) poses[0]->target = vec3_of(o->target);
    if (o->has_up) poses[0]->up = vec3_of(o->up);
    if (o->has_fov) poses[0]->fov_y_degrees = (real)o->fov;
    /* A camera given on the command line replaces any animation of the scene file. */
    if (o->has_eye || o->has_target || o->has_up || o->has_fov) {
        s->has_camera = 1;
        s->keyframe_count = 0;
    }
    {
        const double *v[3];
        int i, j;
        enum camera_pose_problem problem;
        v[0] = o->has_eye ? o->eye : NULL, v[1] = o->has_target ? o->target : NULL, v[2] = o->has_up ? o->up : NULL;
        for (i = 0; i < 3; ++i)
            for (j = 0; v[i] && j < 3; ++j)
                if (!(fabs(v[i][j]) <= SCENE_COORD_MAX))
                    return rerror_set(e, "%s: %g is out of range (|coordinate| <= %g: float geometry)",
                                      i == 0 ? "--eye" : i == 1 ? "--target" : "--up", v[i][j], SCENE_COORD_MAX);
        problem = camera_pose_check(&s->camera);
        if (problem != CAMERA_POSE_OK)
            return rerror_set(e, "%s: the camera given on the command line is degenerate: %s", s->path,
                              camera_pose_problem_text(problem));
    }
    return 0;
}

int load_scene_for_command(const char *command, const char *path, const scene_overrides *o, scene *s,
                           double *load_seconds, double *prepare_seconds)
{
    rerror e;
    scene_load_options load_options;
    double t0 = now_seconds(), t1;
    size_t i;
    load_options.allow_missing_mtl = o->allow_missing_mtl;
    if (scene_load_with_options(s, path, &load_options, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    t1 = now_seconds();
    for (i = 0; i < s->warning_count && !o->quiet; ++i) fprintf(stderr, "warning: %s\n", s->warnings[i]);
    if (apply_overrides(o, s, &e) || scene_prepare(s, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        scene_free(s);
        return 2;
    }
    (void)command;
    if (load_seconds) *load_seconds = t1 - t0;
    if (prepare_seconds) *prepare_seconds = now_seconds() - t1;
    return 0;
}
