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

/* The uniform numbers from the hashed words (docs/rng.md). */
static double words_to_double(const uint32_t v[4])
{
    uint64_t bits = ((uint64_t)v[0] << 21) | (uint64_t)(v[1] >> 11); /* 53 bits */
    return (double)bits * (1.0 / 9007199254740992.0);                /* 2^-53 */
}

static float words_to_float(const uint32_t v[4])
{
    return (float)(v[0] >> 8) * (1.0f / 16777216.0f); /* 24 bits, 2^-24 */
}

static real words_to_real(const uint32_t v[4])
{
#ifdef RESTIR_REAL_FLOAT
    return words_to_float(v);
#else
    return words_to_double(v);
#endif
}

double rng_uniform_double(rng_key k)
{
    uint32_t v[4];
    rng_words(k, v);
    rng_pcg4d(v);
    return words_to_double(v);
}

float rng_uniform_float(rng_key k)
{
    uint32_t v[4];
    rng_words(k, v);
    rng_pcg4d(v);
    return words_to_float(v);
}

real rng_uniform(rng_key k)
{
    uint32_t v[4];
    rng_words(k, v);
    rng_pcg4d(v);
    return words_to_real(v);
}

/* rng_pcg4d on n address words at once, one step of all lanes after the other, so the
 * lanes' independent multiplication chains interleave. The same arithmetic per lane. */
static void pcg4d_lanes(uint32_t v[RNG_SLOTS_MAX][4], int n)
{
    int i, l;
    for (l = 0; l < n; ++l)
        for (i = 0; i < 4; ++i) v[l][i] = v[l][i] * 1664525u + 1013904223u;
    for (l = 0; l < n; ++l) v[l][0] += v[l][1] * v[l][3];
    for (l = 0; l < n; ++l) v[l][1] += v[l][2] * v[l][0];
    for (l = 0; l < n; ++l) v[l][2] += v[l][0] * v[l][1];
    for (l = 0; l < n; ++l) v[l][3] += v[l][1] * v[l][2];
    for (l = 0; l < n; ++l)
        for (i = 0; i < 4; ++i) v[l][i] ^= v[l][i] >> 16;
    for (l = 0; l < n; ++l) v[l][0] += v[l][1] * v[l][3];
    for (l = 0; l < n; ++l) v[l][1] += v[l][2] * v[l][0];
    for (l = 0; l < n; ++l) v[l][2] += v[l][0] * v[l][1];
    for (l = 0; l < n; ++l) v[l][3] += v[l][1] * v[l][2];
}

void rng_u_slots(rng_key base, uint32_t stream, uint32_t vertex, uint32_t first_slot, int n, real *out)
{
    uint32_t v[RNG_SLOTS_MAX][4];
    int l;
    if (n > RNG_SLOTS_MAX) abort(); /* a caller's bug: the lanes are a fixed array */
    for (l = 0; l < n; ++l) rng_words(rng_key_at(base, stream, vertex, first_slot + (uint32_t)l), v[l]);
    pcg4d_lanes(v, n);
    for (l = 0; l < n; ++l) out[l] = words_to_real(v[l]);
}
