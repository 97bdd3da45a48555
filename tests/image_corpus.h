/* The pixel values of the image corpus in tests/data/images (docs/images.md): the
 * writers (tools/images/, built against libOpenEXR and libpng, never by make) were given
 * exactly these values, and tests/test_image_formats.c recomputes them to check that our
 * readers return them bit for bit. C99 and C++. Coordinates are the file's own pixel
 * coordinates (data-window coordinates for EXR); c is the channel (0 R or Y, 1 G, 2 B, 3 A). */
#ifndef RESTIR_TESTS_IMAGE_CORPUS_H
#define RESTIR_TESTS_IMAGE_CORPUS_H

#include <stdint.h>

static inline uint32_t corpus_mix(uint32_t v)
{
    v ^= v >> 16;
    v *= 0x7feb352du;
    v ^= v >> 15;
    v *= 0x846ca68bu;
    v ^= v >> 16;
    return v;
}

static inline uint32_t corpus_key(int x, int y, int c)
{
    return (uint32_t)(x + 4096) * 2654435761u ^ (uint32_t)(y + 4096) * 40503u ^ (uint32_t)c * 0x9e3779b9u;
}

/* Most pixels are smooth (ramps and constants: PIZ, ZIP and RLE must really compress
 * them, or the writer stores the chunk raw and the decoder goes untested); every fourth
 * pixel of every third row is arbitrary bits (subnormals, infinities, NaNs included). */
static inline int corpus_wild(int x, int y) { return ((y % 3) + 3) % 3 == 2 && ((x + y) % 4 + 4) % 4 == 0; }

/* PIZ files are "tame": their arbitrary bits are kept in a narrow band (PIZ stores a
 * bitmap of the 16-bit words present, up to 8 KB: words spread over the whole range
 * would make a small file's chunks incompressible, stored raw, the decoder untested). */

/* EXR HALF bits. */
static inline uint16_t corpus_half(int x, int y, int c, int tame)
{
    int m = ((y % 3) + 3) % 3;
    if (corpus_wild(x, y)) {
        uint32_t r = corpus_mix(corpus_key(x, y, c));
        return (uint16_t)(tame ? 0x3c00u | (r & 0x3ffu) : r & 0xffffu);
    }
    if (m == 0) return (uint16_t)(0x3c00 + 16 * (x & 63) + c);
    if (m == 1) return (uint16_t)(0x4000 + c);
    return (uint16_t)(0x3800 + ((x * 5 + c) & 15));
}

/* EXR FLOAT bits, same pattern. */
static inline uint32_t corpus_float(int x, int y, int c, int tame)
{
    int m = ((y % 3) + 3) % 3;
    if (corpus_wild(x, y)) {
        uint32_t r = corpus_mix(corpus_key(x, y, c) + 1u);
        return tame ? 0x3f800000u | (r & 0x7fe000u) : r;
    }
    if (m == 0) return 0x3f800000u + ((uint32_t)(x & 1023) << 12) + (uint32_t)c;
    if (m == 1) return 0xc0000000u + (uint32_t)c;
    return 0x3f000000u + ((uint32_t)((x * 5 + c) & 15) << 13);
}

/* EXR UINT values. */
static inline uint32_t corpus_uint(int x, int y, int c, int tame)
{
    if (corpus_wild(x, y)) return corpus_mix(corpus_key(x, y, c) + 2u) & (tame ? 0xffu : 0xffffffffu);
    return (uint32_t)(x + 16 * y + c);
}

/* HALF bits of the PIZ file that needs the 16-bit wavelet: ramps whose 3 channels take
 * more than 2^14 distinct values in one 32-line chunk, yet compress. */
static inline uint16_t corpus_ramp_half(int x, int y, int c) { return (uint16_t)(c * 21000 + (y % 32) * 256 + x); }

/* PNG sample (0 .. 2^depth - 1) of channel c; palette images use it as the index. */
static inline unsigned corpus_png(int x, int y, int c, int depth)
{
    return (unsigned)(corpus_mix(corpus_key(x, y, c) + (uint32_t)depth * 7u) & ((1u << depth) - 1));
}

/* Palette entry i (RGB + alpha) of the palette images. */
static inline unsigned corpus_palette(int i, int c) { return (unsigned)(corpus_mix((uint32_t)i * 3u + (uint32_t)c + 99u) & 0xffu); }

#endif
