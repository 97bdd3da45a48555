/* Fuzz target: the scene-file reader (src/scene/scene_file.c) through scene_load, then
 * scene_prepare (fuzz_load_scene). The fuzz directory holds quad.obj and quad.mtl, tex.obj
 * and tex.mtl (every texture map) and sky.pfm (an environment map), so `mesh quad.obj`,
 * `mesh tex.obj` and `environment map sky.pfm` (the seeds use them) reach the material,
 * texture, sky, camera and animation code. */
#include <string.h>
#include "fuzz.h"

/* How often `word` occurs in the input. */
static int occurrences(const uint8_t *data, size_t size, const char *word)
{
    size_t n = strlen(word), i;
    int count = 0;
    for (i = 0; i + n <= size; ++i)
        if (data[i] == (uint8_t)word[0] && !memcmp(data + i, word, n)) ++count;
    return count;
}

FUZZ_TARGET(scene)
{
    /* At most one sphere light: each is 8 000 triangles that every later stage walks (the
     * camera framing, the emitters; the BVH up to FUZZ_PREPARE_MAX_TRIANGLES), so inputs
     * with several ran at a fraction of the speed, and a second one adds no parsing. */
    if (occurrences(data, size, "sphere") > 1) return 0;
    fuzz_load_scene("input.scene", data, size);
    return 0;
}
