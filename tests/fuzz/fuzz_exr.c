/* Fuzz target: the OpenEXR reader (src/core/exr.c, with inflate.c and the PIZ decoder).
 * exr_read_bounded with a 256 KiB bound: the same code as exr_read, but a header that
 * claims a big image (the reader accepts up to 1100 decoded bytes per file byte) is
 * refused before decoding, so such inputs do not take most of the run's time
 * (docs/fuzzing.md). Every code path is reachable with images under the bound. */
#include "fuzz.h"
#include "restir/core/exr.h"

#define FUZZ_EXR_MAX_BYTES ((size_t)1 << 18)

FUZZ_TARGET(exr)
{
    const char *path = fuzz_write_file("input.exr", data, size);
    fimage img;
    rerror e;
    if (!path || exr_read_bounded(path, FUZZ_EXR_MAX_BYTES, &img, &e)) return 0;
    fimage_free(&img);
    return 0;
}
