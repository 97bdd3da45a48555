/* Fuzz target: the MTL reader (src/scene/mtl.c) on its own, as an OBJ's mtllib loads it. */
#include <string.h>
#include "fuzz.h"
#include "restir/scene/scene_builder.h"
#include "restir/scene/mtl.h"

FUZZ_TARGET(mtl)
{
    const char *path = fuzz_write_file("input.mtl", data, size);
    scene s;
    scene_builder b;
    rerror e;
    if (!path) return 0;
    memset(&s, 0, sizeof s);
    if (builder_init(&b, &s, NULL, &e)) return 0;
    mtl_load(&b, path, &e);
    builder_finish(&b);
    scene_free(&s);
    return 0;
}
