/* Fuzz target: the scene-file reader (src/scene/scene_file.c) through scene_load, then
 * scene_prepare (fuzz_load_scene). The fuzz directory holds quad.obj and quad.mtl, so
 * `mesh quad.obj` (the seeds use it) reaches the material, camera and animation
 * directives. */
#include "fuzz.h"

FUZZ_TARGET(scene)
{
    fuzz_load_scene("input.scene", data, size);
    return 0;
}
