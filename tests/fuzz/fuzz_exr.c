/* Fuzz target: the OpenEXR reader (src/core/exr.c, with inflate.c and the PIZ decoder). */
#include "fuzz.h"
#include "restir/core/exr.h"

FUZZ_TARGET(exr)
{
    const char *path = fuzz_write_file("input.exr", data, size);
    fimage img;
    rerror e;
    if (!path || exr_read(path, &img, &e)) return 0;
    fimage_free(&img);
    return 0;
}
