/* Fuzz target: the PFM reader (src/core/pfm.c). */
#include "fuzz.h"
#include "restir/core/image.h"
#include "restir/core/pfm.h"

FUZZ_TARGET(pfm)
{
    const char *path = fuzz_write_file("input.pfm", data, size);
    image img;
    int channels;
    rerror e;
    if (!path || pfm_read(path, &img, &channels, &e)) return 0;
    image_free(&img);
    return 0;
}
