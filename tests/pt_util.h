/* Helpers shared by the light and path-tracer tests: small statistics (chi-square test,
 * normal tail probability; the chi-square tail is chi2.h's), in-memory scene construction,
 * path-tracer options and runs, run images written as files. */
#ifndef RESTIR_TESTS_PT_UTIL_H
#define RESTIR_TESTS_PT_UTIL_H

#include <stddef.h>
#include "restir/core/image.h"
#include "restir/render/pt.h"
#include "restir/scene/scene.h"
#include "restir/render/vertex_sampling.h"
#include "bench.h"

/* Two-sided normal tail P(|Z| >= |z|). */
double normal_two_sided_p(double z);

/* Pearson chi-square of observed counts against expected counts; cells with expected
 * count below 5 are pooled into one (pbrt/Mitsuba practice). Cells with expected 0
 * must have observed 0, else the p-value is 0. Returns the p-value; *chi2 and *dof
 * (may be NULL) receive the statistic and the degrees of freedom. */
double chi2_test(const double *observed, const double *expected, size_t n, double *chi2, int *dof);

/* In-memory scenes. test_scene_begin allocates room for max_triangles triangles
 * (3 fresh vertices each) and max_materials materials; the scene is freed by scene_free. */
int test_scene_begin(scene *s, size_t max_triangles, size_t max_materials);
uint32_t test_scene_material(scene *s, enum material_type type, rgb diffuse, rgb emission);
/* A material with a glossy lobe (conductor, plastic): specular colour and GGX roughness. */
uint32_t test_scene_glossy(scene *s, enum material_type type, rgb diffuse, rgb specular, real roughness);
void test_scene_triangle(scene *s, vec3f a, vec3f b, vec3f c, uint32_t material);
/* Parallelogram p, p+e1, p+e1+e2, p+e2 as two triangles; front normal along e1 x e2. */
void test_scene_quad(scene *s, vec3f p, vec3f e1, vec3f e2, uint32_t material);
/* An axis-aligned box [lo, hi] whose 12 triangles face INWARD (front face towards the
 * inside), all with `material`; test_scene_outward_box faces outward. */
void test_scene_inward_box(scene *s, vec3f lo, vec3f hi, uint32_t material);
void test_scene_outward_box(scene *s, vec3f lo, vec3f hi, uint32_t material);
/* Sets the fields of the last added material. */
material *test_scene_last_material(scene *s);
/* A camera at eye looking at target, square image of size res. */
void test_scene_camera(scene *s, vec3 eye, vec3 target, vec3 up, real fov_y, int res);
/* Multiplies every position and the camera eye/target by k (a change of units). */
void test_scene_scale(scene *s, float k);
/* The analytic furnace of the path-tracer and ReSTIR tests (docs/path-tracer.md "Furnace"):
 * the inside of a closed, tessellated sphere (12 rings x 24 segments, radius 1.5) whose
 * every triangle emits Le and reflects with Lambertian albedo rho, so the radiance is
 * L_D = Le (1 - rho^D) / (1 - rho) everywhere for paths of at most D segments; the camera
 * sits inside. Unprepared. */
int test_scene_furnace_sphere(scene *s, rgb le, rgb rho, int res);
/* pt_options_default with the given seed, samples per pixel, longest path and 2 threads. */
void test_pt_options(pt_options *o, uint32_t seed, uint32_t spp, int max_depth);
/* pt_render, recording a test failure with its message; 0 on success. */
int test_pt_render(const scene *s, const pt_options *o, pt_result *r);
/* Makes run k of a side (img is allocated at the side's size). */
typedef void (*test_run_image_fn)(void *user, int k, image *img);
/* Writes `runs` images make(user, k, img) of width x height as scratch files STEMk.pfm and
 * lists their paths, separated by spaces, in list (of `size` bytes). 0 on success. */
int test_write_runs(char *list, size_t size, int width, int height, int runs, const char *stem,
                    test_run_image_fn make, void *user);
/* The sums over every pixel of R, G and B (in pixel order). */
void test_image_sums(const image *img, double sum[3]);
/* The largest relative difference |a - b| / max(|a|, 1e-30) over every pixel and channel
 * (a and b of the same size). */
double test_image_max_rel_diff(const image *a, const image *b);
/* Writes NAME.mtl, NAME.obj and NAME.scene (the given texts) in the scratch directory, loads
 * the scene and prepares it, recording a test failure with its message; 0 on success. */
int test_scene_from_text(scene *s, const char *name, const char *mtl, const char *obj, const char *scene_text);
/* scene_prepare, recording a test failure with its message; returns nonzero on failure. */
int test_scene_prepare(scene *s);

/* One sample of the direct light at x_1 = v (key: the path), NEE + BSDF with MIS, through the
 * library's calls as the path tracer makes them at x_1 (the light-RIS evidence and power tests). */
rgb test_direct_mis_sample(const path_context *c, const path_vertex *v, const rng_key *key);

/* The paired light-RIS bench at single shading points: `batches` batches of `per_batch` samples
 * at each of the nv points v, sample j of point i keyed rng_key_make(key_seed, point_id[i], j)
 * for both A (context a) and B (context b), each batch's per-channel means added to p. */
void test_direct_mis_paired_batches(bench_paired *p, const path_context *a, const path_context *b,
                                    const path_vertex *v, const uint32_t *point_id, int nv, uint32_t key_seed,
                                    int batches, int per_batch);

#endif
