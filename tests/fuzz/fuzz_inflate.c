/* Fuzz target: inflate (src/core/inflate.c) on an arbitrary stream, and the deflate
 * writer on arbitrary bytes. Input: 2 bytes of output limit (x 4), 1 byte of mode
 * (bit 0: zlib or raw DEFLATE), then the stream. The same stream is then compressed with
 * deflate_zlib and must inflate back to itself: a difference aborts (a finding). */
#include <stdlib.h>
#include <string.h>
#include "fuzz.h"
#include "restir/core/inflate.h"

FUZZ_TARGET(inflate)
{
    size_t cap, n = 0, zn;
    unsigned char *out, *z;
    rerror e;
    if (size < 3) return 0;
    cap = 4 * ((size_t)data[0] | (size_t)data[1] << 8);
    out = malloc(cap + 1);
    if (!out) return 0;
    if (data[2] & 1) inflate_zlib(data + 3, size - 3, out, cap, &n, &e);
    else inflate_raw(data + 3, size - 3, out, cap, &n, NULL, &e);
    free(out);
    z = malloc(deflate_zlib_bound(size - 3));
    out = malloc(size - 3 + 1);
    if (z && out) {
        zn = deflate_zlib(data + 3, size - 3, z);
        if (zn == 0 || inflate_zlib(z, zn, out, size - 3, &n, &e) || n != size - 3 ||
            memcmp(out, data + 3, n) != 0)
            abort();
    }
    free(z);
    free(out);
    return 0;
}
