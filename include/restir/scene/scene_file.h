/* The .scene file (src/scene/scene_file.c; docs/scene-format.md): meshes, materials, camera
 * and its keyframes, image size, object animation. */
#ifndef RESTIR_SCENE_SCENE_FILE_H
#define RESTIR_SCENE_SCENE_FILE_H

#include "restir/scene/scene_builder.h"

/* Reads a .scene file's directives (scene_file.c), loads the meshes in order and then
 * applies the `material` lines; camera, keyframes and size go into b->s. */
int scene_file_load(scene_builder *b, const char *path, rerror *e);

#endif
