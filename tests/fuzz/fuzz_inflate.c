/* Fuzz target: inflate (src/core/inflate.c) on an arbitrary stream, and the deflate
 * writer on arbitrary bytes. Input: 2 bytes of output limit (x 4, at most 64 KiB),
 * 1 byte of mode (bit 0: zlib or raw DEFLATE), then the stream. The first
 * ROUND_TRIP_MAX bytes of the stream are then compressed with deflate_zlib and must
 * inflate back to themselves: a difference aborts (a finding).
 *
 * Both bounds are for speed (docs/fuzzing.md): a stream that expands to the full limit
 * (a small zip bomb) costs time in proportion to its output, and the writer's cost grows
 * with its input; 64 KiB of output and 1 KiB of round trip cover every block type,
 * window distance (32 KiB) and match length the code has. */
#include <stdlib.h>
#include <string.h>
#include "fuzz.h"
#include "restir/core/inflate.h"

#define OUTPUT_MAX 65536
#define ROUND_TRIP_MAX 1024

FUZZ_TARGET(inflate)
{
    size_t cap, n = 0, zn, m;
    unsigned char *out, *z;
    rerror e;
    if (size < 3) return 0;
    cap = 4 * ((size_t)data[0] | (size_t)data[1] << 8);
    if (cap > OUTPUT_MAX) cap = OUTPUT_MAX;
    out = malloc(cap + 1);
    if (!out) return 0;
    if (data[2] & 1) inflate_zlib(data + 3, size - 3, out, cap, &n, &e);
    else inflate_raw(data + 3, size - 3, out, cap, &n, NULL, &e);
    free(out);
    m = size - 3 < ROUND_TRIP_MAX ? size - 3 : ROUND_TRIP_MAX;
    z = malloc(deflate_zlib_bound(m));
    out = malloc(m + 1);
    if (z && out) {
        zn = deflate_zlib(data + 3, m, z);
        if (zn == 0 || inflate_zlib(z, zn, out, m, &n, &e) || n != m || memcmp(out, data + 3, n) != 0) abort();
    }
    free(z);
    free(out);
    return 0;
}
