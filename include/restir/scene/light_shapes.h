/* Area lights written in a scene file (`light sphere|quad|disk ...`, docs/scene-format.md),
 * built as emissive triangle meshes: the oracle's emitters are triangles, so a light shape
 * is nothing but triangles with a pure-emitter material (Kd 0, Ke = the radiance), emitting
 * from their front faces like any OBJ emitter. */
#ifndef RESTIR_SCENE_LIGHT_SHAPES_H
#define RESTIR_SCENE_LIGHT_SHAPES_H

#include "restir/scene/scene_builder.h"

enum light_shape_kind { LIGHT_SPHERE, LIGHT_QUAD, LIGHT_DISK };

typedef struct {
    enum light_shape_kind kind;
    double centre[3];
    double radius;    /* sphere, disk */
    double u[3], v[3]; /* quad: half-edge vectors; corners centre +- u +- v; emits on the side of u x v */
    double normal[3]; /* disk: emits on this side (need not be unit length) */
    rgb radiance;     /* emitted radiance L, constant over the surface */
} light_shape;

/* Tessellation: a sphere is an icosahedron whose faces are cut into
 * LIGHT_SPHERE_DIVISIONS^2 triangles each, with the vertices on the sphere (20 * 400 = 8000
 * triangles, area 7.7e-4 below 4 pi r^2); a disk is a fan of LIGHT_DISK_SEGMENTS triangles
 * (area 4.0e-4 below pi r^2). A quad is two triangles of exactly its area. */
#define LIGHT_SPHERE_DIVISIONS 20
#define LIGHT_DISK_SEGMENTS 128
/* At most this many light triangles per scene file (524 spheres, or 2^21 quads). */
#define LIGHT_MAX_TRIANGLES (1 << 22)

/* The area of the exact shape (4 pi r^2, 4 |u x v|, pi r^2). */
double light_shape_area(const light_shape *l);

/* Checks the shape: finite values, radius > 0, u x v and the disk normal not zero, radiance
 * >= 0 and not all zero. Returns 0, or -1 with e set to "what is wrong" (no file:line). */
int light_shape_check(const light_shape *l, rerror *e);

/* Appends the shape's triangles to the scene under the material and object named name (a
 * new pure emitter: Lambertian, Kd 0, Ke = radiance). Returns 0 or -1 (e set). */
int light_shape_add(scene_builder *b, const light_shape *l, const char *name, rerror *e);

#endif
