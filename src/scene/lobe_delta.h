/* Private to src/scene. The delta lobes (lobe_delta.c): mirror reflection and smooth
 * dielectric transmission. */
#ifndef RESTIR_SRC_SCENE_LOBE_DELTA_H
#define RESTIR_SRC_SCENE_LOBE_DELTA_H

#include "lobes.h"

extern const lobe_ops lobe_delta_reflection_ops;
extern const lobe_ops lobe_delta_transmission_ops;

#endif
