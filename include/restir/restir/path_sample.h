/* The path sample of ReSTIR PT: what a reservoir must remember about its selected
 * path so that the path can be shifted to another pixel (docs/formats.md).
 *
 * A sample is a lobe-extended primary-sample-space (PSS) path (GRIS §7.6): the
 * random numbers that built it (its replay identity, or an explicit vector of
 * mutated numbers), the lobe chosen at every scattering vertex, the technique of
 * the last vertex, and a copy of the reconnection vertex x_k with everything the
 * reconnection Jacobian (Enhanced Eq. 2 = GRIS Eqs. 52-54) and the re-evaluation
 * of the path contribution at x_k need, so neither the base path nor its pixel
 * must be revisited.
 *
 * INDEXING (GRIS §7.1; docs/design.md, Conventions): x0 camera, x1 primary hit, ..., x_d the emitter
 * vertex; d = number of segments (d = 2: direct light at x1, d >= 3: indirect).
 * Lobe ell_j (GRIS §7.6) is the lobe chosen at x_j to sample x_{j+1}, 1 <= j <= d-1;
 * ell_{d-1} = PATH_LOBE_NEE when the last vertex was NEE-sampled (x_{d-1} is then
 * evaluated with all lobes: GRIS Eq. 50). The reconnection index k satisfies
 * 2 <= k <= d (x_{k-1} is at least the primary hit) or k = PATH_RC_NONE.
 *
 * UNITS: F is the PSS path contribution f/p with every sampling pdf divided out
 * and Russian roulette excluded (docs/design.md, Conventions), an RGB triple; the target
 * function is p̂ = luminance(F) (vec.h). docs/formats.md lists every field again
 * with its byte offset in the dump format. */
#ifndef RESTIR_PATH_SAMPLE_H
#define RESTIR_PATH_SAMPLE_H

#include <stdint.h>
#include "restir/core/error.h"
#include "restir/core/rng.h"
#include "restir/core/vec.h"

/* Longest path: d <= 16 segments (vertices x0..x16). */
#define PATH_MAX_LENGTH 16
/* RNG_BSDF numbers per scattering vertex: the lobe choice and a 2-D direction
 * sample (bsdf.h: one number picks the lobe, two pick the direction). */
#define PATH_PSS_PER_VERTEX 3
/* Scattering vertices are x1..x_{d-1}, at most 15 of them. */
#define PATH_MAX_PSS (PATH_PSS_PER_VERTEX * (PATH_MAX_LENGTH - 1))

#define PATH_LOBE_NONE 0xFFu /* no lobe: x0, x_d and beyond the path */
#define PATH_LOBE_NEE 0xFEu  /* GRIS §7.6 ell_{d-1} = N: NEE-sampled last vertex */
#define PATH_RC_NONE 0u      /* no reconnection vertex: a shift is pure random replay */
/* rc_flags bit: the reconnection evaluated from the sample's OWN x_{k-1} failed (the
 * segment x_{k-1} -> x_k fails the visibility test, or the reconnected contribution is
 * zero), so no shift T_{j->i}(y) can produce this sample; for symmetry every shift of it
 * fails too (docs/restir-pt.md, "Symmetric shift domains"). */
#define PATH_RC_FLAG_UNSHIFTABLE 0x1u
/* rc_flags bit: x_k is the vertex at infinity (k = d, a path that ends at the environment
 * or the sun; docs/environment.md): rc_triangle = LIGHT_TRIANGLE_DISTANT, rc_position its
 * unit direction w (towards the sky, as float), rc_normal = -w, rc_bary = 0. */
#define PATH_RC_FLAG_DISTANT 0x2u

/* Technique of the last vertex x_d; the values are GRIS §7.6's n(ell) in {1, 2}. */
enum path_technique {
    PATH_TECH_NONE = 0, /* empty sample (an empty reservoir holds one) */
    PATH_TECH_NEE = 1,  /* x_d sampled by next-event estimation from x_{d-1} */
    PATH_TECH_BSDF = 2  /* x_d hit by the BSDF-sampled ray from x_{d-1} */
};

typedef struct {
    /* ---- replay identity: rng_key_make(seed, pixel, sample) regenerates every
     * random number of the path (rng.h); only RNG_BSDF is replayed by shifts. */
    uint32_t seed;
    uint32_t pixel;  /* pixel index y * width + x of the pixel that traced it */
    uint32_t sample; /* sample index within the pixel (e.g. frame * trees + tree) */

    /* ---- structure */
    uint8_t length;    /* d, 2..PATH_MAX_LENGTH (0 for an empty sample) */
    uint8_t technique; /* enum path_technique */
    uint8_t rc_k;      /* reconnection index k in [2, d], or PATH_RC_NONE */
    uint8_t n_pss;     /* number of explicit primary-sample numbers in pss[] (0: none) */
    uint8_t rc_flags;  /* PATH_RC_FLAG_* bits (0 unless rc_k != PATH_RC_NONE) */
    uint8_t lobe[PATH_MAX_LENGTH]; /* lobe[j] = ell_j for 1 <= j <= d-1, else PATH_LOBE_NONE */

    /* ---- the reconnection vertex x_k (meaningful iff rc_k != PATH_RC_NONE) */
    uint32_t rc_triangle; /* scene triangle index of x_k */
    float rc_bary[2];     /* (b1, b2): x_k = (1-b1-b2) v0 + b1 v1 + b2 v2 */
    vec3f rc_position;    /* x_k (float geometry, docs/design.md, Conventions) */
    vec3f rc_normal;      /* geometric normal at x_k (front face (v1-v0)x(v2-v0), unit) */
    vec3 rc_wo;           /* omega_k: unit direction x_k -> x_{k+1}; zero vector if k = d */
    /* Source pdfs of the reconnection Jacobian (Enhanced Eq. 2 denominator), evaluated
     * from the vertex positions (omega_{k-1} = normalize(x_k - x_{k-1})) by the same code
     * as every shift, so that a shift to the own pixel has J = 1 exactly: */
    real rc_pdf_prev; /* p_{k-1}(omega_{k-1}): pdf with which x_{k-1} samples the direction
                       * to x_k in the lobe-extended primary sample space: P(ell_{k-1}|wo)
                       * pdf_{ell_{k-1}}(omega_{k-1}) (lobe selection INCLUDED; the number
                       * that picks the lobe is a PSS dimension: docs/restir-pt.md), or the
                       * NEE solid-angle pdf if x_k = x_d is an NEE-sampled light vertex */
    real rc_geom;     /* G(x_{k-1} -> x_k) = |n_g(x_k) . omega_{k-1}| / ||x_k - x_{k-1}||^2 */
    real rc_pdf;      /* p_k(omega_k) = P(ell_k|wo) pdf_{ell_k}(omega_k) at x_k with wo
                       * towards x_{k-1}; 1 when k = d (Enhanced Eq. 2) and when omega_k is
                       * the NEE direction (k = d-1, NEE: the light sample does not depend on
                       * the incoming direction, so its PSS ratio is 1) */
    /* Suffix radiance L_k arriving at x_k along omega_k (leaving x_{k+1} towards x_k):
     *   k <= d-2:  (product of the PSS bounce weights at x_{k+1}..x_{d-1}) x Le x
     *              the final-vertex NEE/BSDF MIS weight (none of these depend on x_{k-1});
     *   k = d-1:   Le(x_d -> x_k) alone: the BSDF at x_k and the final MIS weight depend
     *              on the incoming direction and are re-evaluated by the shift;
     *   k = d:     Le(x_d -> x_{d-1}) alone (x_k is the emitter; omega_k is undefined). */
    rgb rc_radiance;
    /* Solid-angle pdf with which NEE samples x_d from x_{d-1} (light selection included),
     * for the final-vertex MIS weight; 0 if NEE cannot produce x_d. It depends on x_{d-1},
     * so a shift that moves x_{d-1} must recompute it (pitfall 6, docs/restir-pt.md §11). */
    real light_pdf;

    /* ---- cached contribution in the domain (pixel) that owns the sample */
    rgb F;       /* PSS path contribution f/p (RGB) */
    real target; /* p̂ = luminance(F) */

    /* ---- explicit primary-sample numbers (MCMC mutations, Mutations §4): pss[i], i < n_pss,
     * replaces the RNG_BSDF number at vertex 1 + i / PATH_PSS_PER_VERTEX, slot
     * i % PATH_PSS_PER_VERTEX (slot 0 lobe choice, slots 1-2 direction); all other numbers
     * still come from the replay identity. Each in [0, 1). For an NEE path (technique NEE) the
     * slots of vertex d-1, which samples no BSDF, hold (unused, u_2, u_3): they replace the
     * RNG_NEE numbers 2-3 that place the point on the light (path_nee_numbers); the light
     * selection numbers 0-1 always come from the replay identity.
     *
     * OUT OF LINE (issue 17: 360 B of a 576-B reservoir, used only by --mutations): pss points
     * to PATH_MAX_PSS numbers, or is NULL for a vector of zeros (a sample no mutation touched).
     * The numbers are never written through a copied sample: a copy by value shares them, and
     * whoever changes them gives the sample its own storage first (path_sample_copy_pss).
     * Reservoir buffers keep every sample's numbers in their own rows (reservoir.h,
     * reservoir_buffer_keep_pss), so a sample copied from one buffer into another takes its
     * numbers along when the stage that wrote it is done. */
    real *pss;
} path_sample;

/* An empty sample: technique NONE, length 0, no reconnection, all lobes NONE, zeros. */
void path_sample_clear(path_sample *s);
/* Starts a path of the given identity: like path_sample_clear plus seed/pixel/sample. */
void path_sample_begin(path_sample *s, uint32_t seed, uint32_t pixel, uint32_t sample);
/* The base key of the path's addressed random numbers. */
rng_key path_sample_key(const path_sample *s);
/* 1 unless the sample is empty. */
int path_sample_is_valid(const path_sample *s);
/* Lobe ell_k at the reconnection vertex (PATH_LOBE_NONE if k = d or no reconnection). */
unsigned path_sample_rc_lobe(const path_sample *s);
/* Sets F and the target p̂ = luminance(F) together (the one place they are paired). */
void path_sample_set_contribution(path_sample *s, rgb F);
/* to[0..PATH_MAX_PSS-1] = the sample's explicit numbers (zeros where s->pss is NULL). */
void path_sample_copy_pss(const path_sample *s, real *to);
/* Moves the numbers into `home` (PATH_MAX_PSS numbers owned by whoever holds the sample,
 * e.g. a reservoir buffer's row): copies them unless they are there already, and points
 * s->pss at home. A sample without numbers (pss NULL) stays NULL. */
void path_sample_keep_pss(path_sample *s, real *home);

/* Structural consistency (enum ranges, 2 <= d <= 16, 2 <= k <= d, lobes present exactly
 * on x1..x_{d-1}, PATH_LOBE_NEE exactly at x_{d-1} of NEE paths, n_pss <= PATH_MAX_PSS with
 * each number in [0,1), finite non-negative pdfs/radiance/contribution, unit normal and
 * direction at x_k, pss set if n_pss > 0). `what` prefixes the message (e.g. "file: record 17"). Returns 0 if
 * consistent. */
int path_sample_check(const path_sample *s, const char *what, rerror *e);

#endif
