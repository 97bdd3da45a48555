/* Light RIS for next-event estimation, optionally from light tiles (ReSTIR PT Enhanced §6.1;
 * Wyman & Panteleev, "Rearchitecting spatiotemporal resampling for production", HPG 2021;
 * Talbot et al. 2005, resampled importance sampling). docs/enhanced.md §6 has the derivations.
 *
 * At a vertex x_i (i >= 1) NEE draws M = max(1, N / i^2) candidates z_1..z_M from the base
 * light sampler p_0 (light by power, point uniform on it; lights.h), weighs them with
 *     w_j = p̂(z_j) / (M p_0(z_j)),  p̂(z) = luminance(f(x_i, z)|cos| Le(z -> x_i))
 * (the UNSHADOWED contribution; both in solid angle at x_i, so p̂/p_0 is the luminance of
 * the plain NEE estimate), selects z_s with probability w_s / Σw and traces one shadow ray.
 * The RIS estimate is f(z_s) V Le W with W = Σw / p̂(z_s) (Talbot Eq. 3.8 / GRIS Eq. 3 with
 * the RIS weights of Bitterli et al. 2020 Eq. 5): 1/W = p̃(z_s; Z) is the estimate
 *     p̃(y; Z) = p̂(y) / ((1/M) Σ_j p̂(z_j)/p_0(z_j))
 * of the intractable RIS density, and the MIS weights of NEE and BSDF sampling use it on
 * both sides, each side building Z the same way in distribution (docs/enhanced.md §6).
 *
 * Light tiles (Wyman & Panteleev 2021 §5; Enhanced §7): LIGHT_TILE_COUNT tiles of
 * LIGHT_TILE_SIZE samples of p_0 per frame; every 8×8 block of pixels draws one tile per
 * frame; candidates pick entries of that tile uniformly. The entries are ADDRESSED: entry e
 * of tile t in frame f is the light sample of the numbers U(seed, pixel = t, sample = f,
 * RNG_NEE, vertex 0, slots 16 + 4e .. 19 + 4e), so a table of them is only a cache and any
 * frame's tile can be recomputed. The tile of a path is U(seed, pixel = screen tile,
 * sample = f, RNG_NEE, vertex 0, slot 0) with the screen tile and f taken from the PATH's
 * replay identity (pixel, sample): vertex 0 never does NEE, so these addresses are free.
 *
 * Random numbers of the path at x_i (RNG_NEE, vertex i; docs/rng.md):
 *   slots 4j .. 4j+3     candidate j < M (without tiles: light_sample_point's four numbers,
 *                        so candidate 0 is the plain sampler's light; with tiles slot 4j
 *                        picks the entry)
 *   slot 4096            the selection number
 *   slots 8192 + 4j ..   the BSDF side's M-1 fresh candidates j (same layout; with tiles
 *                        slot 8192 + 4j picks a slot of the virtual tile)
 *   slots 16384 + 4e ..  entry e != 0 of the BSDF side's virtual tile (entry 0 is y). */
#ifndef RESTIR_LIGHT_RIS_H
#define RESTIR_LIGHT_RIS_H

#include "restir/render/vertex_sampling.h"

#define LIGHT_RIS_MAX 1024       /* largest N (slots 4j .. 4j+3 stay below 4096) */
#define LIGHT_TILE_COUNT 128     /* tiles per frame (Enhanced §7) */
#define LIGHT_TILE_SIZE 1024     /* light samples per tile */
#define LIGHT_TILE_SCREEN 8      /* one tile per 8×8 pixels */
#define LIGHT_RIS_SLOT_SELECT 4096u
#define LIGHT_RIS_SLOT_FRESH 8192u
#define LIGHT_RIS_SLOT_VIRTUAL 16384u

/* The light-RIS technique's options (Enhanced §6.1), as both renderers are configured
 * (pt_options.light_ris, restir_options.light_ris). */
typedef struct {
    int candidates; /* N candidates at x1 (0: the plain light sampler, default) */
    int tiles;      /* 1: candidates from light tiles */
} light_ris_options;

void light_ris_options_default(light_ris_options *o);
/* 0, or -1 with "light RIS: what is wrong". */
int light_ris_options_validate(const light_ris_options *o, rerror *e);

/* Candidates at vertex x_i: max(1, N / i^2) (the decay schedule of Enhanced §7), 0 if off. */
int light_ris_count(const path_context *c, uint32_t vertex_index);

/* Entry e of tile t of frame `frame` (addressed; see above). Returns 0 if there are no lights. */
int light_tile_entry(const light_set *ls, uint32_t seed, uint32_t frame, uint32_t tile, uint32_t entry,
                     light_sample *out);
/* The light tile of a path (its pixel's 8×8 screen tile and its frame = key.sample). */
uint32_t light_tile_of(const path_context *c, rng_key path);

/* NEE at x_i by light RIS: fills *out like vertex_sample_light with pdf_light = p̃(z_s; Z)
 * = 1/W and contribution = f|cos| Le W (0 if occluded). Returns 1 if nonzero. */
int light_ris_sample(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                     nee_sample *out);

/* The NEE pdf estimate p̃(y; {y} ∪ Z') at a light point y (scene triangle tri, normal ny)
 * that BSDF sampling from x_i hit: Z' = M-1 fresh candidates from the path's own addresses
 * (with tiles: the virtual tile of docs/enhanced.md §6). Solid angle at x_i. */
real light_ris_pdf_hit(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                       uint32_t tri, vec3 y, vec3 ny);

/* ---- what the ReSTIR PT shifts need (docs/enhanced.md §6, "Shifts") ---- */

/* p̃(y; Z) with Z the NEE candidates of the path at x_i (its own addresses; y must be one of
 * them, which the caller guarantees by construction): the selection probability of y
 * times M p_0(y), so a ratio of two of these at different x_i (or different incoming
 * directions at x_i) is the ratio P'_s/P_s of the selection interval's lengths. */
real light_ris_pdf_nee(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                       uint32_t tri, vec3 y, vec3 ny);
/* The NEE candidate of the path at x_i whose direction from x_i is exactly wi (the selected
 * one, recovered from the stored direction of a reconnection at k = d-1). 0 if none is. */
int light_ris_candidate_towards(const path_context *c, const path_vertex *v, rng_key path, uint32_t vertex_index,
                                vec3 wi, light_sample *out);

#endif
