/* Fuzz target: the OBJ reader (src/scene/obj.c, triangulate.c) through scene_load,
 * then scene_prepare on whatever it accepts (fuzz_load_scene). */
#include "fuzz.h"

FUZZ_TARGET(obj)
{
    fuzz_load_scene("input.obj", data, size);
    return 0;
}
