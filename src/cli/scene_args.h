/* Private to src/cli. Scene loading shared by the commands that take a SCENE argument (.scene
 * or bare .obj), with the camera and image overrides every such command accepts. */
#ifndef RESTIR_CLI_SCENE_ARGS_H
#define RESTIR_CLI_SCENE_ARGS_H

#include "args.h"
#include "restir/scene/scene.h"

typedef struct {
    double eye[3], target[3], up[3];
    double fov;
    int size[2];
    int has_eye, has_target, has_up, has_fov, has_size;
    int allow_missing_mtl; /* a missing material library or map file is a warning, not an error */
    int quiet;             /* do not print load warnings */
} scene_overrides;

/* The option rows for the overrides (--eye --target --up --fov --size --allow-missing-mtl); copy them into a
 * command's table with scene_override_options(). Returns the number of rows written. */
int scene_override_options(cli_option *rows, scene_overrides *o);

/* scene_load + overrides + scene_prepare; prints "file:line: what" and returns 2 on failure.
 * Load warnings go to stderr unless o->quiet. */
int load_scene_for_command(const char *command, const char *path, const scene_overrides *o, scene *s,
                           double *load_seconds, double *prepare_seconds);

#endif
