/* The addressed RNG (docs/rng.md). Bit-exact reproducible on any platform with
 * 32-bit unsigned wrap-around arithmetic, which a GPU build can copy. */
#include "restir/core/rng.h"

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

static void rng_address_check(rng_key k)
{
    if (k.stream > 0xffu || k.vertex > 0xffu || k.slot > 0xffffu) rng_address_overflow(k);
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

/* rng_pcg4d on an address's words (docs/rng.md, "Key layout"), computed with less work: the
 * same bits. The words differ between the numbers of one path only in v2 (stream, vertex,
 * slot); v0 = pixel, v1 = sample and v3 = seed are shared. So the first LCG step of v0, v1,
 * v3, the first `v0 += v1*v3` and v0's xorshift can be computed once for all numbers of a
 * call (pcg4d_shared: rng_u_slots), and of the last round only words 0 and 1 reach the
 * conversions (pcg4d_lane). 6 of pcg4d's 12 multiplications per number remain, in registers;
 * rng_u_slots's lanes are independent chains that the CPU overlaps. rng_pcg4d above stays
 * the definition: rng_u_slots_equals_rng_u checks every function below against it. */
typedef struct {
    uint32_t v0;  /* pixel after the LCG step and v0 += v1*v3 (before the xorshift) */
    uint32_t v0x; /* the same after v0 ^= v0 >> 16 */
    uint32_t v1;  /* sample after the LCG step */
    uint32_t v3;  /* seed after the LCG step */
} pcg4d_shared;

static inline pcg4d_shared pcg4d_shared_words(rng_key k)
{
    pcg4d_shared p;
    p.v1 = k.sample * 1664525u + 1013904223u;
    p.v3 = k.seed * 1664525u + 1013904223u;
    p.v0 = k.pixel * 1664525u + 1013904223u + p.v1 * p.v3;
    p.v0x = p.v0 ^ (p.v0 >> 16);
    return p;
}

/* pcg4d of (pixel, sample, w2, seed) given the shared words: output words 0 and 1 (2 and 3,
 * which no conversion reads, are left 0). */
static inline void pcg4d_lane(const pcg4d_shared *p, uint32_t w2, uint32_t v[4])
{
    uint32_t v1, v2, v3;
    v2 = w2 * 1664525u + 1013904223u;
    v1 = p->v1 + v2 * p->v0;
    v2 += p->v0 * v1;
    v3 = p->v3 + v1 * v2;
    v1 ^= v1 >> 16;
    v2 ^= v2 >> 16;
    v3 ^= v3 >> 16;
    v[0] = p->v0x + v1 * v3;
    v[1] = v1 + v2 * v[0];
    v[2] = v[3] = 0;
}

static uint32_t address_word2(uint32_t stream, uint32_t vertex, uint32_t slot)
{
    return (stream << 24) | (vertex << 16) | slot;
}

/* Output words 0 and 1 of rng_pcg4d on the words of address k. */
static void hashed_words(rng_key k, uint32_t v[4])
{
    pcg4d_shared p;
    rng_address_check(k);
    p = pcg4d_shared_words(k);
    pcg4d_lane(&p, address_word2(k.stream, k.vertex, k.slot), v);
}

uint32_t rng_bits(rng_key k)
{
    uint32_t v[4];
    hashed_words(k, v);
    return v[0];
}

double rng_uniform_double(rng_key k)
{
    uint32_t v[4];
    hashed_words(k, v);
    return words_to_double(v);
}

float rng_uniform_float(rng_key k)
{
    uint32_t v[4];
    hashed_words(k, v);
    return words_to_float(v);
}

real rng_uniform(rng_key k)
{
    uint32_t v[4];
    hashed_words(k, v);
    return words_to_real(v);
}

void rng_u_slots(rng_key base, uint32_t stream, uint32_t vertex, uint32_t first_slot, int n, real *out)
{
    pcg4d_shared p;
    uint32_t w2, v[4];
    int l;
    if (n > RNG_SLOTS_MAX) abort(); /* a caller's bug: out has at most RNG_SLOTS_MAX numbers */
    if (n <= 0) return;
    /* The first and the last lane's addresses in range: so are those between. */
    rng_address_check(rng_key_at(base, stream, vertex, first_slot));
    rng_address_check(rng_key_at(base, stream, vertex, first_slot + (uint32_t)(n - 1)));
    p = pcg4d_shared_words(base);
    w2 = address_word2(stream, vertex, first_slot);
    for (l = 0; l < n; ++l) {
        pcg4d_lane(&p, w2 + (uint32_t)l, v);
        out[l] = words_to_real(v);
    }
}
