/* The addressed counter-based random number generator (docs/design.md, Conventions, docs/rng.md).
 *
 * A random number is a pure function of its address:
 *     u = U(seed, pixel, sample, stream, vertex, slot)
 * so a path can be replayed from its identity alone, and nothing consumed in one
 * stream can put another stream out of step (the failure mode of streamed RNGs in
 * random replay, pitfall 1, docs/restir-pt.md §11). The hash is pcg4d (Jarzynski & Olano 2020). */
#ifndef RESTIR_RNG_H
#define RESTIR_RNG_H

#include <stdint.h>
#include "restir/core/vec.h"

/* Streams: each purpose draws from its own stream. Only RNG_BSDF is replayed by
 * the random-replay shift. Values are part of the documented bit-exact scheme. */
enum rng_stream {
    RNG_CAMERA = 0,    /* sub-pixel jitter */
    RNG_BSDF = 1,      /* lobe choice + direction sampling at each vertex (replayed) */
    RNG_NEE = 2,       /* light selection + point on the light */
    RNG_RR = 3,        /* Russian roulette */
    RNG_RIS = 4,       /* reservoir selection */
    RNG_NEIGHBOR = 5,  /* spatial neighbour choice */
    RNG_MUTATE = 6,    /* MCMC proposals and acceptance */
    RNG_THRESHOLD = 7, /* randomised thresholds (e.g. footprint criterion) */
    RNG_TEST = 8       /* tests and tools (never used by estimators) */
};

/* The RNG_RIS vertex field of ReSTIR's selection numbers (docs/rng.md, "ReSTIR's addresses",
 * whose table the test rng_vertex_table_matches_docs checks against these): each resampling
 * step owns a range, so no two steps ever read the same number. The key is the pixel's
 * (initial_pixel_key, initial.h) except for initial resampling, which uses each tree's own. */
#define RNG_VERTEX_INITIAL_RIS(d) ((uint32_t)(d))               /* 2..16: initial RIS, path length d; slot = technique */
#define RNG_VERTEX_SPATIAL_RIS(pass) (32u + (uint32_t)(pass))   /* 32..47: spatial pass p; slot = domain */
#define RNG_VERTEX_TEMPORAL_RIS 48u                             /* 48: temporal reuse; slot 0 current, 1 previous */
#define RNG_VERTEX_STOCHASTIC_PICK(pass) (64u + (uint32_t)(pass))      /* 64..79: Ñ picks of pass p; slot = pick */
#define RNG_VERTEX_STOCHASTIC_CANONICAL(pass) (80u + (uint32_t)(pass)) /* 80..95: Ñ_c canonical picks of pass p */
#define RNG_VERTEX_PASSES 16 /* spatial passes a range holds (RESTIR_MAX_SPATIAL_PASSES) */

/* The address of one random number. `sample` identifies the path (or sample) within
 * the pixel: e.g. spp index for the path tracer, frame*trees+tree for ReSTIR.
 * stream < 256, vertex < 256, slot < 65536. */
typedef struct {
    uint32_t seed;
    uint32_t pixel;
    uint32_t sample;
    uint32_t stream;
    uint32_t vertex;
    uint32_t slot;
} rng_key;

static inline rng_key rng_key_make(uint32_t seed, uint32_t pixel, uint32_t sample)
{
    rng_key k;
    k.seed = seed;
    k.pixel = pixel;
    k.sample = sample;
    k.stream = 0;
    k.vertex = 0;
    k.slot = 0;
    return k;
}

static inline rng_key rng_key_at(rng_key base, uint32_t stream, uint32_t vertex, uint32_t slot)
{
    base.stream = stream;
    base.vertex = vertex;
    base.slot = slot;
    return base;
}

/* pcg4d: four 32-bit words in, four well-mixed 32-bit words out. */
void rng_pcg4d(uint32_t v[4]);

/* 32 random bits of the address. */
uint32_t rng_bits(rng_key k);
/* Uniform in [0,1) with 24 (float build) or 53 (double build) random mantissa bits. */
real rng_uniform(rng_key k);
/* Always 53 bits / always 24 bits, independent of PRECISION. */
double rng_uniform_double(rng_key k);
float rng_uniform_float(rng_key k);

/* out[i] = rng_u(base, stream, vertex, first_slot + i) for i < n (n <= RNG_SLOTS_MAX):
 * the same numbers, with the n hashes computed side by side. Each pcg4d is a chain of
 * dependent multiplications; interleaving independent chains lets the CPU overlap them
 * (docs/performance.md: the RNG was ~20% of a path-tracer profile). The lanes share the
 * part of the hash that depends only on pixel, sample and seed, and skip what the
 * conversion to [0,1) does not read: 6 multiplications per number instead of 12. */
#define RNG_SLOTS_MAX 4
void rng_u_slots(rng_key base, uint32_t stream, uint32_t vertex, uint32_t first_slot, int n, real *out);

/* Convenience: rng_uniform at (stream, vertex, slot) of a path's base key. */
static inline real rng_u(rng_key base, uint32_t stream, uint32_t vertex, uint32_t slot)
{
    return rng_uniform(rng_key_at(base, stream, vertex, slot));
}

#endif
