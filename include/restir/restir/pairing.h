/* Reuse textures for paired spatial reuse (Enhanced §3.1-3.2, Eq. 3; docs/enhanced.md §2).
 *
 * A reuse texture of even size w pairs every texel with exactly one partner texel: texel
 * a stores the (tileable) offset to its partner b and b stores the offset back to a, so a
 * pixel pair shares its two shifts A->B and B->A. Construction (§3.1):
 *   1. link indices: texel (x, y) gets (y*w + x) / 2, so consecutive texels share one;
 *   2. n_sigma times (Eq. 3): cut the texture into 2x2 blocks, every other pass offset
 *      diagonally by one texel (wrapping at the edge), and permute each block's four
 *      link indices uniformly at random;
 *   3. the link-index table (N/2 x 2 texel indices; written in scan order where the CUDA
 *      version races) finds each texel's partner;
 *   4. the offset to the partner is made tileable: dx > w/2 -> dx - w, dx < -w/2 -> dx + w
 *      (same for dy), so partner(partner(t)) = t on the torus.
 * The offsets are then approximately normal with standard deviation sigma per axis.
 *
 * Per frame (and spatial pass), each texture is laid over the screen with a random flip,
 * mirror, transpose and offset (§3.2): the pairing stays an involution on the screen.
 *
 * Random numbers (stream RNG_NEIGHBOR, slots >= 2, disjoint from neighbors.h's slots 0-1):
 * the shuffle of pass t, block b of texture `id`: key (seed, b, PAIRING_TEXTURE_SAMPLE + id),
 * vertex t mod 256, slots 3..5 + 4 floor(t / 256) (passes t >= 256 only in the Eq. 3
 * measurement beyond sigma = 22); the screen transform of texture `id` for neighbour sample s: key
 * (seed, 0, s), vertex PAIRING_TRANSFORM_VERTEX - id, slots 2..6. */
#ifndef RESTIR_PAIRING_H
#define RESTIR_PAIRING_H

#include <stdint.h>
#include "restir/core/error.h"

#define PAIRING_MIN_SIGMA 0.8    /* one shuffle pass (Enhanced §3.1 footnote 1) */
#define PAIRING_MAX_SIGMA 22.0   /* the largest sigma of the reuse patterns (radius 41) */
#define PAIRING_MAX_PASSES 4096  /* shuffle passes (pass t: vertex t mod 256, slots + 4 floor(t / 256)) */
#define PAIRING_TEXTURE_SAMPLE 0xFFFF0000u
#define PAIRING_TRANSFORM_VERTEX 254u
#define PAIRING_MAX_TEXTURES 8 /* one per neighbour: sizes 254, 232, ..., 100 */

typedef struct {
    int size;          /* w (even) */
    double sigma;      /* the target standard deviation */
    int shuffles;      /* n_sigma (Eq. 3) */
    int16_t *dx, *dy;  /* w*w tileable offsets to the partner texel, row-major */
} reuse_texture;

/* Readings of Enhanced Eq. 3, whose extraction is garbled (a ceiling, every sign +;
 * docs/enhanced.md §2 "Eq. 3, measured"). With s = sigma:
 *   SIGNED_CEIL   ceil(s^2/2 - 1.46/s + 1.76/s^2 - 0.656/s^3 + 0.5)   the oracle's reading before issue 28
 *   PORT_ROUND    floor(s^2/2 + 1.46/s - 1.76/s^2 + 0.656/s^3 + 0.5)  an independent port's: the default
 *   SIGNED_ROUND  floor(s^2/2 - 1.46/s + 1.76/s^2 - 0.656/s^3 + 0.5)
 *   LITERAL_CEIL  ceil(s^2/2 + 1.46/s + 1.76/s^2 + 0.656/s^3 + 0.5)   the text as extracted
 *   LEADING_CEIL  ceil(s^2/2 + 0.5)                                    the paper's approximation
 * Each is clamped to at least one pass (footnote 1: sigma = 0.8 is one pass).
 * The default is PORT_ROUND: measured over sigma in [2, 32] (docs/results/eq3.md, 16 textures
 * per cell) its achieved standard deviation has the smallest mean error (2.24% against
 * signed-ceil's 2.81%) and the smallest worst error (11.0% against 13.9%), i.e. it meets the
 * paper's statement that the deltas have standard deviation sigma best; signed-ceil stays
 * selectable (--eq3-reading signed-ceil). */
enum pairing_eq3 {
    PAIRING_EQ3_SIGNED_CEIL = 0,
    PAIRING_EQ3_PORT_ROUND,
    PAIRING_EQ3_SIGNED_ROUND,
    PAIRING_EQ3_LITERAL_CEIL,
    PAIRING_EQ3_LEADING_CEIL,
    PAIRING_EQ3_COUNT
};
extern const char *const pairing_eq3_names[]; /* "signed-ceil", "port-round", ... */
/* Enhanced Eq. 3 (reading `r`): the number of 2x2 shuffle passes for sigma >= 0.8. */
int pairing_shuffle_count_as(double sigma, enum pairing_eq3 r);
#define PAIRING_EQ3_DEFAULT PAIRING_EQ3_PORT_ROUND
/* Enhanced Eq. 3 as the oracle reads it by default (PAIRING_EQ3_DEFAULT). */
int pairing_shuffle_count(double sigma);
/* Builds texture `id` of size w (even, 4..4096) for sigma in [0.8, PAIRING_MAX_SIGMA] with
 * pairing_shuffle_count(sigma) passes. 0 or -1 with *e. */
int reuse_texture_build(reuse_texture *t, int w, double sigma, uint32_t seed, uint32_t id, rerror *e);
/* The same with the passes of Eq. 3 reading r (--eq3-reading). */
int reuse_texture_build_as(reuse_texture *t, int w, double sigma, enum pairing_eq3 r, uint32_t seed, uint32_t id,
                           rerror *e);
/* The same with an explicit pass count (1..PAIRING_MAX_PASSES): the measurement of Eq. 3's
 * readings (restir bench pairing-sigma). */
int reuse_texture_build_passes(reuse_texture *t, int w, double sigma, int passes, uint32_t seed, uint32_t id,
                               rerror *e);
void reuse_texture_free(reuse_texture *t);

/* The per-frame placement of a texture over the screen (§3.2). */
typedef struct {
    int flip, mirror, transpose; /* x -> -x, y -> -y, swap x and y (applied in this order) */
    int ox, oy;                  /* offset in [0, w) */
} reuse_transform;

reuse_transform reuse_transform_draw(const reuse_texture *t, uint32_t seed, uint32_t sample, uint32_t id);

/* The screen offset from pixel (x, y) to its partner under placement f (x, y >= 0). */
void reuse_partner_offset(const reuse_texture *t, const reuse_transform *f, int x, int y, int *dx, int *dy);

/* The standard deviation whose mean partner distance matches the uniform disk of radius
 * R (mean distance 2R/3; a 2D normal with per-axis sigma has mean distance
 * sigma sqrt(pi/2)): sigma = 2R / (3 sqrt(pi/2)) = 0.532 R, clamped to [0.8, 22]. */
double pairing_sigma_for_radius(double radius);

/* The textures of `count` neighbours (1..PAIRING_MAX_TEXTURES), sizes 254 - 22k (k = 0..):
 * different sizes so their repeats do not line up (§3.2). 0, or -1 with *e (nothing kept). */
int reuse_textures_build(reuse_texture *tex, int count, double sigma, uint32_t seed, rerror *e);
/* The same with Eq. 3 reading r (spatial_options.eq3_reading). */
int reuse_textures_build_as(reuse_texture *tex, int count, double sigma, enum pairing_eq3 r, uint32_t seed,
                            rerror *e);
void reuse_textures_free(reuse_texture *tex, int count);

#endif
