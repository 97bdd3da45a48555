/* Mesh properties the scene and BVH tests check on loaded and generated scenes. */
#ifndef RESTIR_TESTS_MESH_UTIL_H
#define RESTIR_TESTS_MESH_UTIL_H

#include "restir/scene/scene.h"

/* Object `o` of s is a closed, consistently oriented surface (every directed edge once, its
 * reverse once) enclosing positive signed volume (faces outward; *volume receives it).
 * Returns what is wrong, or NULL. */
const char *check_closed_outward(const scene *s, uint32_t o, double *volume);

#endif
