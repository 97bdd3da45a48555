/* Helpers for the ReSTIR PT tests: scenes, K-run comparisons through the `restir check`
 * library, and per-pixel primary vertices. */
#ifndef RESTIR_TESTS_RESTIR_UTIL_H
#define RESTIR_TESTS_RESTIR_UTIL_H

#include "restir/core/json_text.h"
#include "restir/metrics/check.h"
#include "restir/render/pt.h"
#include "restir/frame/offline.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"
#include "restir/restir/initial.h"
#include "restir/restir/reservoir_dump.h"
#include "restir/restir/shift.h"
#include "sequence_util.h"

/* The name rt_load_scene takes for the generated mirror corridor (generate_corridor). */
#define RT_CORRIDOR "generated:corridor"

/* Loads and prepares a scene file (or RT_CORRIDOR; NULL: the spot scene of rt_make_spot),
 * then sets the image size to res x res.
 * 0 on success (a test failure is recorded otherwise). */
int rt_load_scene(const char *path, int res, scene *s);

/* A scene with a panning camera: cornell-glossy seen from eye x = 278 - pan/2 at frame 0 to
 * 278 + pan/2 at frame 16 (target moves with it); pan 0: the still camera. 0 on success. */
int rt_load_glossy_pan(scene *s, int res, double pan);
/* The same pan on any scene file with a still camera (its own animation, if any, stays). */
int rt_load_scene_pan(const char *path, scene *s, int res, double pan);
/* rt_load_scene, then the scene's light set into *ls (lights_free it). 0 on success (a test
 * failure is recorded otherwise). */
int rt_load_scene_lights(const char *path, int res, scene *s, light_set *ls);

/* One side of a comparison (block: the block edge of the per-block tests): K runs of restir_render with disjoint frame ranges
 * [k * frames, (k+1) * frames), images as the runs. */
int rt_restir_side(const scene *s, const restir_options *o, int runs, int block, check_side *side);
/* Run k of restir_render with the options `base`: frames [first + k frames, first + (k+1) frames)
 * (a test failure is recorded if it fails). 0 on success. */
int rt_restir_run(const scene *s, const restir_options *base, int k, restir_result *r);
/* K runs of the reference path tracer (disjoint sample ranges of spp each); with
 * indirect_only the run image is PT(max_depth) - PT(2) of the same samples: exactly the
 * paths of length >= 3. */
int rt_pt_side(const scene *s, uint32_t seed, int runs, uint32_t spp, int max_depth, int indirect_only, int block,
               check_side *side);
/* K runs of the path tracer with the options `base` (its seed, spp per run, depth, light RIS,
 * ablations, ...): run k takes the samples [base->sample_offset + k spp, ... + spp). */
int rt_pt_side_options(const scene *s, const pt_options *base, int runs, int block, check_side *side);
/* rt_pt_side with the camera at keyframe time `frame`. */
int rt_pt_side_at(const scene *s, uint32_t seed, int runs, uint32_t spp, int max_depth, int indirect_only, int frame,
                  int block, check_side *side);
/* check_compare at level alpha with block x block pixel blocks (the sides' block size);
 * frees both sides. Returns 0 on success. */
int rt_compare(check_side *a, check_side *b, double alpha, int block, check_result *r);
/* check_options_default with level alpha and, when block > 0, block x block pixel blocks. */
check_options rt_check_options(double alpha, int block);
/* check_compare (paired 0) or check_compare_paired (paired 1) of a and b (kept) at level
 * alpha in block x block blocks; a failure of the comparison itself is recorded as a test
 * failure. Returns 0 on success. */
int rt_compare_sides(const check_side *a, const check_side *b, double alpha, int block, int paired,
                     check_result *r);
/* rt_compare_sides(a, b, alpha, block, 1, r), plus the paired bench per colour channel
 * (tests/bench.h; issue 26) on the same runs: the K per-run image means of R, G and B of A
 * and B (same seeds) give one paired t per channel, and a channel with |z| >=
 * BENCH_Z_CONSISTENT sets r->different too (check_compare_paired's global test is on
 * luminance, which a colour-only bias passes). rt_last_channels() holds the last bench. */
int rt_compare_paired(const check_side *a, const check_side *b, double alpha, int block, check_result *r);
struct bench_paired_s;
const struct bench_paired_s *rt_last_channels(void);
/* The signed normal-equivalent z of the image-mean luminance test of r. */
double rt_mean_z(const check_result *r);

/* The expected verdict of `restir check` on side a (freed here) against ref at level alpha
 * in block x block blocks: records a test failure naming `what` (with the mean z, the worst
 * block z, the rejected blocks) unless the verdict is "different" exactly when `biased`.
 * With RESTIR_TEST_VERBOSE prints the numbers. The result goes to *out (the caller frees
 * it) or is freed when out is NULL. Returns 0 when the verdict is the expected one, 1 when
 * not, -1 when check_compare failed (*out is then untouched). */
int rt_expect_verdict(check_side *a, const check_side *ref, double alpha, int block, const char *what, int biased,
                      check_result *out);

/* A scene and its reference: K path-tracer runs (rt_pt_side with seed `pt_seed`, spp per
 * run, max_depth) in block x block pixel blocks (block 4), shared by the cases of a test. */
typedef struct {
    scene s;
    check_side pt;
    int res, block, runs, max_depth;
} rt_bench;
/* path NULL: the spot scene. 0 on success (a test failure is recorded otherwise). */
int rt_bench_open(rt_bench *b, const char *path, int res, int runs, uint32_t spp, int max_depth, uint32_t pt_seed);
void rt_bench_close(rt_bench *b);

#define RT_MAX_TIMES 3
/* Frames times[0..nt) (ascending) of K sequences 0..times[nt-1]: run k of side[i] is frame
 * times[i] of run k. */
typedef struct {
    int times[RT_MAX_TIMES], nt;
    check_side side[RT_MAX_TIMES];
} rt_frame_sides;
/* Fills q (times and nt set by the caller) by rt_sequence_runs in block x block blocks. */
int rt_frame_sides_run(const scene *s, const restir_options *o, int runs, int block, rt_frame_sides *q);
void rt_frame_sides_free(rt_frame_sides *q);

/* Runs `restir render ARGS --quiet --no-png -o IMG --stats STATS` (both in the scratch
 * directory, named after `name`), which must exit 0, and opens the stats in *jr (close it
 * with json_reader_close). 0 on success (a test failure is recorded otherwise). */
int rt_render_stats(const char *args, const char *name, json_reader *jr);

/* Zeroed initial-sampling options and counters with `trees` path trees per pixel, paths of
 * at most max_depth segments and Russian roulette from the 3rd vertex. */
void rt_initial_options(initial_options *io, initial_stats *ist, int trees, int max_depth);

/* restir_options_default, then the spatial-reuse fields the statistical tests vary (seed,
 * shift, MIS family, K passes, neighbours, radius) and 2 threads. */
void rt_spatial_options(restir_options *o, uint32_t seed, int shift, int mis, int passes, int neighbors,
                        double radius);

/* Builds the primary vertex x1 of pixel (x, y) (pixel centre, frame 0). 0 if the ray misses. */
int rt_primary_vertex(const scene *s, int x, int y, path_vertex *v);

/* A restir context for s (lights built by the caller) with the given shift, the default
 * thresholds of restir_options_default otherwise. */
void rt_context(restir_context *c, const scene *s, const light_set *lights, int shift);

/* The "spot" scene (unprepared): a glossy floor, a white back wall and a small quad light
 * 8 cm above the floor, res x res pixels; where the Jacobian and light-pdf ablations show. */
int rt_make_spot(scene *s, int res);

/* A fresh evaluation of sample x as a path of the pixel whose primary hit is y1, by the
 * path-sampling code alone (vertex_sampling.h, path_replay.h), never by the shift code:
 * the prefix y_1..y_{k-1} is replayed from y1 with x's numbers, the suffix x_k..x_d is
 * replayed from x's own pixel (primary hit x1_origin; the shifts keep x_k..x_d), x_k is
 * rebuilt as seen from y_{k-1} and every factor of F = f/p is evaluated again (lobe
 * bounces, the BSDF at x_k, the final NEE/BSDF MIS weight with the light pdf seen from
 * the new x_{d-1}), and the reconnection segment is re-traced. Without a reconnection
 * index the whole path is replayed from y1. Returns F (black if the path does not exist
 * in y1's pixel: a replay fails, the segment is blocked, a factor is 0). */
rgb rt_fresh_contribution(const restir_context *c, const path_vertex *y1, const path_vertex *x1_origin,
                          const path_sample *x);

/* Determinant of the leading n x n block (n <= 6) by Gaussian elimination with partial
 * pivoting (a is overwritten): finite-difference Jacobians of the shift and mutation tests. */
double rt_determinant(double a[6][6], int n);

/* Frame 4's final confidences of a still-camera sequence with M-cap 2.5 in `mode` and
 * `trees` path trees all equal `expect` (restir_util.c). */
void rt_mcap_sequence_exact(int trees, enum temporal_mcap_mode mode, double expect, const char *what);

/* The two-tone scene of the mutation tests: a glossy floor (reconnection at k = 3), a back
 * wall half red, half green, a small light in front of the red half (restir_util.c). */
int rt_make_two_tone(scene *s, int res);

/* One frame's reservoirs on a scene, with the lights and the context to shift or mutate
 * them (the fixture of the mutation tests). */
typedef struct {
    scene s;
    restir_result res;
    light_set lights;
    restir_context c;
} rt_frame;
/* Loads path at res x res and renders one frame (restir_render, reservoirs kept) with the
 * default options but shift, max_depth, seed and 2 threads; the context is that frame's
 * (restir_context_for). 0 on success (a test failure is recorded otherwise). */
int rt_frame_open(rt_frame *f, const char *path, int res, int shift, int max_depth, uint32_t seed);
void rt_frame_close(rt_frame *f);

/* The options of the paired mutation bench: the hybrid shift, pairwise-defensive MIS, 2
 * candidates, paths of at most 4 segments, 2 threads, 20 mutations after the temporal step
 * (the caller sets the strategy, kernel, ...). */
void rt_mutation_options(restir_options *o);
/* Frame 4 of sequences with the options `on` against the same sequences without mutations
 * (the same seeds: the frames share their initial and temporal samples until the first
 * mutation), K = runs pairs from seed0, into p (initialised by the caller). */
void rt_mutation_paired(const scene *s, const restir_options *on, int runs, uint32_t seed0,
                        struct bench_paired_s *p);

#endif
