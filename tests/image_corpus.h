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

/* EXR HALF bits: rows cycle through a ramp, a constant (runs for RLE and PIZ), and
 * arbitrary bits (subnormals, infinities and NaNs included). */
static inline uint16_t corpus_half(int x, int y, int c)
{
    int m = ((y % 3) + 3) % 3;
    if (m == 0) return (uint16_t)(0x3c00 + 16 * (x & 63) + c);
    if (m == 1) return (uint16_t)(0x4000 + c);
    return (uint16_t)(corpus_mix(corpus_key(x, y, c)) & 0xffffu);
}

/* EXR FLOAT bits, same pattern. */
static inline uint32_t corpus_float(int x, int y, int c)
{
    int m = ((y % 3) + 3) % 3;
    if (m == 0) return 0x3f800000u + ((uint32_t)(x & 1023) << 12) + (uint32_t)c;
    if (m == 1) return 0xc0000000u + (uint32_t)c;
    return corpus_mix(corpus_key(x, y, c) + 1u);
}

/* EXR UINT values. */
static inline uint32_t corpus_uint(int x, int y, int c) { return corpus_mix(corpus_key(x, y, c) + 2u); }

/* PNG sample (0 .. 2^depth - 1) of channel c; palette images use it as the index. */
static inline unsigned corpus_png(int x, int y, int c, int depth)
{
    return (unsigned)(corpus_mix(corpus_key(x, y, c) + (uint32_t)depth * 7u) & ((1u << depth) - 1));
}

/* Palette entry i (RGB + alpha) of the palette images. */
static inline unsigned corpus_palette(int i, int c) { return (unsigned)(corpus_mix((uint32_t)i * 3u + (uint32_t)c + 99u) & 0xffu); }

#endif
