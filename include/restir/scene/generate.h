/* Generated scenes: deterministic geometry from our own code, for benchmarks and
 * for tests that need a large, closed mesh. */
#ifndef RESTIR_GENERATE_H
#define RESTIR_GENERATE_H

#include "restir/core/error.h"
#include "restir/scene/scene.h"

/* Fills a zeroed scene with a closed, displaced sphere (radius about 1, centred at the
 * origin) and a 1 x 1 emissive quad light above it, facing down, plus a camera.
 * The sphere is a cube whose six faces carry an n x n grid (n = subdivisions), mapped
 * to the sphere equi-angularly and displaced radially: 12 n^2 triangles, vertices
 * shared (the mesh is closed and watertight). n = 92 gives >= 100k triangles, n = 289
 * about 1M. Materials: 0 "white" (Lambert, albedo 0.8), 1 "light" (emission 10).
 * Objects: 0 "sphere", 1 "light". Does not build the BVH (call scene_prepare).
 * The scene's arrays are malloc'ed as scene_free() expects. */
int generate_displaced_sphere(scene *s, int subdivisions, rerror *e);

/* Progress of the long generators (`restir generate sphere --subdivisions 2000`: 48M
 * triangles, about a minute to build and write): step(ctx, phase, done, total) is called
 * often (every grid row, every few thousand OBJ lines; the caller rate-limits its output)
 * with done = total at the end of each phase. phase names what runs ("building the mesh",
 * "writing OBJ"). The library prints nothing: the CLI shows it (progress.h). A nonzero
 * return stops the work (`restir bench` on SIGINT): the function fails ("cancelled"),
 * leaving nothing (the scene freed, no OBJ or MTL written). */
typedef struct {
    int (*step)(void *ctx, const char *phase, long done, long total);
    void *ctx;
} generate_progress;

/* generate_displaced_sphere reporting its progress (p may be NULL). */
int generate_displaced_sphere_progress(scene *s, int subdivisions, const generate_progress *p, rerror *e);

/* Writes the scene's triangles as OBJ at `path` and its materials as MTL next to it
 * (same name with the extension .mtl), both atomically. The MTL statements are chosen
 * so that loading the files gives back each material's type, colours, roughness and
 * ior (the few exceptions are listed at write_mtl_material in generate.c). */
int generate_write_obj(const scene *s, const char *path, rerror *e);
/* generate_write_obj reporting its progress in OBJ lines (p may be NULL). */
int generate_write_obj_progress(const scene *s, const char *path, const generate_progress *p, rerror *e);

#endif
