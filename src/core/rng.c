/* The addressed RNG (docs/rng.md). Bit-exact reproducible on any platform with
 * 32-bit unsigned wrap-around arithmetic, which a GPU build can copy. */
#include "restir/rng.h"

#include <stdio.h>
#include <stdlib.h>

/* pcg4d, Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 9(3), 2020. */
void rng_pcg4d(uint32_t v[4])
{
    int i;
    for (i = 0; i < 4; ++i) v[i] = v[i] * 1664525u + 1013904223u;
    v[0] += v[1] * v[3];
    v[1] += v[2] * v[0];
    v[2] += v[0] * v[1];
    v[3] += v[1] * v[2];
    for (i = 0; i < 4; ++i) v[i] ^= v[i] >> 16;
    v[0] += v[1] * v[3];
    v[1] += v[2] * v[0];
    v[2] += v[0] * v[1];
    v[3] += v[1] * v[2];
}

/* An address whose fields do not fit the key layout would alias another address (a slot
 * >= 65536 lands in the vertex field: the spatial-selection bug fixed in f5df7f5 made
 * spatial reuse reuse initial sampling's numbers). Masking it silently would hide such a
 * collision, so the program stops instead: an oracle must never run on aliased numbers. */
static void rng_address_overflow(rng_key k)
{
    fprintf(stderr, "rng: address out of range (stream %lu < 256, vertex %lu < 256, slot %lu < 65536 required; "
                    "docs/rng.md)\n",
            (unsigned long)k.stream, (unsigned long)k.vertex, (unsigned long)k.slot);
    abort();
}

/* The four input words of an address (docs/rng.md, "Key layout"). */
static void rng_words(rng_key k, uint32_t v[4])
{
    if (k.stream > 0xffu || k.vertex > 0xffu || k.slot > 0xffffu) rng_address_overflow(k);
    v[0] = k.pixel;
    v[1] = k.sample;
    v[2] = ((k.stream & 0xffu) << 24) | ((k.vertex & 0xffu) << 16) | (k.slot & 0xffffu);
    v[3] = k.seed;
}

uint32_t rng_bits(rng_key k)
{
    uint32_t v[4];
    rng_words(k, v);
    rng_pcg4d(v);
    return v[0];
}

double rng_uniform_double(rng_key k)
{
    uint32_t v[4];
    uint64_t bits;
    rng_words(k, v);
    rng_pcg4d(v);
    bits = ((uint64_t)v[0] << 21) | (uint64_t)(v[1] >> 11); /* 53 bits */
    return (double)bits * (1.0 / 9007199254740992.0);      /* 2^-53 */
}

float rng_uniform_float(rng_key k)
{
    return (float)(rng_bits(k) >> 8) * (1.0f / 16777216.0f); /* 24 bits, 2^-24 */
}

real rng_uniform(rng_key k)
{
#ifdef RESTIR_REAL_FLOAT
    return rng_uniform_float(k);
#else
    return rng_uniform_double(k);
#endif
}
