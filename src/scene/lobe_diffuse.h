/* Private to src/scene. The Lambertian lobe (lobe_diffuse.c): cosine-weighted sampling and its
 * inverse. */
#ifndef RESTIR_SRC_SCENE_LOBE_DIFFUSE_H
#define RESTIR_SRC_SCENE_LOBE_DIFFUSE_H

#include "lobes.h"

extern const lobe_ops lobe_diffuse_ops;

#endif
