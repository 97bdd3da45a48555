/* Wavefront OBJ loader (src/scene/obj.c; docs/scene-format.md): vertices, normals, faces
 * (triangulated by triangulate.h), groups and usemtl, with mtllib resolved relative to the
 * file; every error as file:line. */
#ifndef RESTIR_SCENE_OBJ_H
#define RESTIR_SCENE_OBJ_H

#include "restir/scene/scene_builder.h"

/* Loads an OBJ file into b (obj.c). */
int obj_load(scene_builder *b, const char *path, rerror *e);

#endif
