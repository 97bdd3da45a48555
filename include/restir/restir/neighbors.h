/* Spatial neighbour selection for spatial reuse (GRIS §6.3 step 3; docs/spatial-reuse.md).
 *
 * For pixel i, a pattern proposes candidate pixels j near i; a candidate is dropped if it
 * is i itself, outside the image, a repeat of an earlier candidate, or geometrically
 * dissimilar to i on the G-buffer (normal, depth). The accepted pixels, together with
 * i's own (canonical) sample, are the input domains of the GRIS step at i. The choice
 * depends only on the addressed RNG (stream RNG_NEIGHBOR) and the G-buffer, never on
 * the reservoirs being resampled: that independence is what keeps the GRIS estimator
 * unbiased (docs/spatial-reuse.md, "Why the estimator stays unbiased").
 *
 * Patterns (the offsets are whole pixels):
 *   uniform  n independent uniform points in the disk of radius R (concentric map),
 *            rounded to the nearest pixel;
 *   r2       n consecutive points of the R2 low-discrepancy sequence (Roberts 2018) with
 *            a random toroidal shift per pixel and pass (Cranley-Patterson rotation),
 *            mapped to the disk the same way: every single neighbour has exactly the
 *            uniform pattern's distribution, and the n neighbours of one pixel are
 *            spread more evenly than independent ones;
 *   box      every pixel of the (2r+1) x (2r+1) window, r = floor(R), except i, in
 *            row-major order (no randomness; the fixed windows of GRIS Figs. 7-8);
 *   paired   neighbour k is i's partner in reuse texture k (pairing.h; Enhanced §3), placed
 *            with that frame and pass's flip/mirror/transpose/offset: j's partner is i, so
 *            the pairs are reciprocal (--pairing paired). The two-shift pair step of §3
 *            (pair_step.h) files each pair's shifts by k.
 *
 * Random numbers: key (seed, pixel i, sample, RNG_NEIGHBOR, vertex, slot) with
 * sample = neighbor_sample_index(frame, passes, pass): uniform neighbour k uses vertex k,
 * slots 0-1; the r2 shift uses vertex NEIGHBOR_SHIFT_VERTEX, slots 0-1. */
#ifndef RESTIR_NEIGHBORS_H
#define RESTIR_NEIGHBORS_H

#include <stdint.h>
#include "restir/core/error.h"
#include "restir/render/gbuffer.h"
#include "restir/restir/pairing.h"
#include "restir/core/rng.h"

enum neighbor_pattern { NEIGHBOR_UNIFORM = 0, NEIGHBOR_R2 = 1, NEIGHBOR_BOX = 2, NEIGHBOR_PAIRED = 3 };

/* NULL-terminated, index = enum value: "uniform", "r2", "box", "paired". */
extern const char *const neighbor_pattern_names[];

#define NEIGHBOR_MAX_COUNT 255     /* disk patterns: n <= 255 (vertex field of the RNG key) */
#define NEIGHBOR_SHIFT_VERTEX 255  /* RNG vertex of the r2 pattern's per-pixel shift */
#define NEIGHBOR_MAX_BOX_RADIUS 64 /* box pattern: r <= 64, at most 129^2 - 1 candidates */

/* Default rejection thresholds (those of the GRIS authors' code, made symmetric). */
#define NEIGHBOR_DEFAULT_MIN_NORMAL_COS 0.5f
#define NEIGHBOR_DEFAULT_MAX_RELATIVE_DEPTH 0.1f

typedef struct {
    enum neighbor_pattern pattern;
    int count;                /* n: candidates drawn per pixel (disk patterns) */
    double radius;            /* R in pixels: disk radius, or box half-size floor(R) */
    int reject_geometry;      /* 1 (default): apply the normal and depth tests */
    float min_normal_cos;     /* accept only if dot(n_i, n_j) >= this */
    float max_relative_depth; /* accept only if |d_i - d_j| <= this * min(d_i, d_j) */
    const reuse_texture *textures; /* paired: `count` reuse textures (owned by the caller) */
    const reuse_transform *placements; /* paired, optional: the textures' placements for the
                                          (seed, sample) of every call, from neighbor_place
                                          (drawn once per pass instead of per pixel); NULL:
                                          drawn in each call */
} neighbor_options;

/* Why a candidate was not accepted (or that it was). */
enum neighbor_verdict {
    NEIGHBOR_ACCEPTED = 0,
    NEIGHBOR_CENTRE,    /* the offset rounded to (0, 0) */
    NEIGHBOR_OUTSIDE,   /* outside the image (rejected, not clamped) */
    NEIGHBOR_REPEAT,    /* the same pixel as an earlier candidate of this pixel */
    NEIGHBOR_NO_HIT,    /* i or j has no primary hit */
    NEIGHBOR_NORMAL,    /* normals differ */
    NEIGHBOR_DEPTH,     /* depths differ */
    NEIGHBOR_VERDICT_COUNT
};
extern const char *const neighbor_verdict_names[]; /* "accepted", "centre", ... */

/* Counters summed over calls (neighbor_select adds to them). */
typedef struct {
    uint64_t candidates;
    uint64_t verdict[NEIGHBOR_VERDICT_COUNT];
} neighbor_stats;

/* Defaults: r2 pattern, n = 6, R = 10 (the GRIS offline setting, §8.3), geometry
 * rejection on with the default thresholds. */
void neighbor_options_default(neighbor_options *o);
/* Checks n in [1, 255] (disk patterns), R > 0 and finite (box: 1 <= floor(R) <= 64),
 * thresholds in range. */
int neighbor_options_validate(const neighbor_options *o, rerror *e);

/* The sample index of the neighbour key for spatial pass `pass` (0-based) of `frame`. */
static inline uint32_t neighbor_sample_index(uint32_t frame, uint32_t passes, uint32_t pass)
{
    return frame * passes + pass;
}

/* Candidates proposed per pixel: n for disk patterns, (2r+1)^2 - 1 for box. */
int neighbor_candidate_count(const neighbor_options *o);

/* The disk patterns' k-th point (0 <= k < n) in the unit disk, before scaling by R and
 * rounding, for the key of pixel i (rng_key_make(seed, i, sample)). */
void neighbor_disk_point(enum neighbor_pattern pattern, rng_key key, int k, double *px, double *py);
/* The k-th candidate offset of pixel i: for disk patterns (round(R px), round(R py))
 * with round(v) = floor(v + 0.5); for box the k-th pixel of the window. */
void neighbor_offset(const neighbor_options *o, rng_key key, int k, int *dx, int *dy);

/* The geometric test on the G-buffer, symmetric in (a, b) by construction:
 * NEIGHBOR_NO_HIT if either has no hit, else NEIGHBOR_NORMAL if dot(n_a, n_b) < min cos,
 * n = geometric normal turned towards the camera, else NEIGHBOR_DEPTH if
 * |d_a - d_b| > max_relative_depth * min(d_a, d_b), d = view-space depth, else
 * NEIGHBOR_ACCEPTED. With reject_geometry = 0 only the hit test applies. */
enum neighbor_verdict neighbor_geometry_test(const neighbor_options *o, const gbuffer_texel *a, const gbuffer_texel *b);

/* Selects the neighbours of pixel (x, y): writes the accepted pixel indices (y*width+x)
 * in candidate order to out[0..capacity-1] and returns their number; -1 (with *e) if
 * capacity < neighbor_candidate_count(o). stats (may be NULL) receives the verdict of
 * every candidate. */
int neighbor_select(const neighbor_options *o, const gbuffer *g, uint32_t seed, uint32_t sample, int x, int y,
                    uint32_t *out, int capacity, neighbor_stats *stats, rerror *e);
/* Paired: the placement of each of the o->count textures for (seed, sample) into
 * out[0..count-1], the values neighbor_select would draw (for o->placements). */
void neighbor_place(const neighbor_options *o, uint32_t seed, uint32_t sample, reuse_transform *out);
/* The same, and slot[a] (if slot is not NULL) = the candidate index k that proposed the
 * a-th accepted pixel (paired: the reuse texture; the pair step, pair_step.c, files its
 * shifts by it). */
int neighbor_select_slots(const neighbor_options *o, const gbuffer *g, uint32_t seed, uint32_t sample, int x, int y,
                          uint32_t *out, int *slot, int capacity, neighbor_stats *stats, rerror *e);

#endif
