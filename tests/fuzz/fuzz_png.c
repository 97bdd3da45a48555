/* Fuzz target: the PNG reader (src/core/png_read.c, with inflate.c). The input's length
 * parity picks the sRGB or the linear decode, so both paths run. */
#include "fuzz.h"
#include "restir/core/png_read.h"

FUZZ_TARGET(png)
{
    const char *path = fuzz_write_file("input.png", data, size);
    fimage img;
    rerror e;
    if (!path || png_read(path, size % 2 ? PNG_SRGB : PNG_LINEAR, &img, &e)) return 0;
    fimage_free(&img);
    return 0;
}
