/* Building generated scenes from closed solids (src/scene/generate_rooms.c,
 * generate_atrium.c; docs/scenes.md): a scene_builder with a sticky failure flag, and the
 * solids the generators are written in (prisms, boxes, UV spheres, quads). */
#ifndef RESTIR_MESH_WRITER_H
#define RESTIR_MESH_WRITER_H

#include <stdint.h>
#include "restir/core/error.h"
#include "restir/scene/scene.h"
#include "restir/scene/scene_builder.h"
#include "restir/scene/triangulate.h"

#define MESH_PI 3.14159265358979323846
#define MESH_MAX_PRISM_CORNERS 256 /* the atrium's arcade walls have 229 */

/* Appends geometry to a scene. The first failure is remembered (m->failed, message in
 * *m->e) and every later call does nothing, so the scene descriptions read as
 * plain lists of solids with one check at the end. */
typedef struct {
    scene_builder b;
    triangulator tri;
    uint32_t material, object;
    rerror *e;
    int failed;
} mesh_writer;

typedef struct {
    const char *name;
    enum material_type type;
    double kd[3], ks[3], ke[3];
    double roughness, ior;
} material_spec;

/* A new vertex; its index. */
uint32_t mesh_vertex(mesh_writer *m, double x, double y, double z);

/* A point given by its coordinate w along `axis` and (u, v) on the two following axes
 * (cyclically: u = axis+1, v = axis+2, so that u x v = +axis). */
uint32_t mesh_axis_vertex(mesh_writer *m, int axis, double w, double u, double v);

/* Triangle a, b, c: the front face is the side of (b - a) x (c - a). */
void mesh_face(mesh_writer *m, uint32_t a, uint32_t b, uint32_t c);

/* Quad a, b, c, d (counter-clockwise seen from its front) as triangles abc and acd. */
void mesh_quad(mesh_writer *m, uint32_t a, uint32_t b, uint32_t c, uint32_t d);

/* Defines each material of specs[0..count) under its name. */
void mesh_define_materials(mesh_writer *m, const material_spec *specs, int count);

/* The material and object of the faces that follow (the material must be defined). */
void mesh_use(mesh_writer *m, const char *material_name, const char *object_name);

/* A polygon cap: the corners (vertex indices) in counter-clockwise order seen from the
 * side the cap faces, triangulated by ear clipping (which keeps the winding). */
void mesh_cap(mesh_writer *m, const uint32_t *ring, int n, int reversed);

/* A closed prism: the simple polygon of n corners uv[2i], uv[2i+1], given as (u, v)
 * coordinates on the two axes after `axis` (see mesh_axis_vertex), swept along `axis` from lo to hi (lo < hi). Faces
 * point outward whatever the polygon's winding: a counter-clockwise polygon in (u, v)
 * has its area normal along +axis, so the top cap keeps the order, the bottom cap
 * reverses it, and the side quad over edge e (from corner i to i+1) has normal
 * e x (+axis), which points out of a counter-clockwise polygon. */
void mesh_prism(mesh_writer *m, const double *uv, int n, int axis, double lo, double hi);

/* An axis-aligned box [x0, x1] x [y0, y1] x [z0, z1] with outward faces. */
void mesh_box(mesh_writer *m, double x0, double y0, double z0, double x1, double y1, double z1);

/* A box standing on the y axis whose footprint, the rectangle [0, size_x] x [-size_z, 0]
 * in local coordinates (a, b), is turned about the vertical axis through (pivot_x,
 * pivot_z) so that the local +a direction becomes (cos t, -sin t) in (x, z) and +b
 * becomes (sin t, cos t): a proper rotation, which keeps the faces outward. */
void mesh_turned_box(mesh_writer *m, double pivot_x, double pivot_z, double size_x, double size_z, double turn_degrees,
                     double y0, double y1);

/* A UV sphere (outward faces): `rings` bands in the polar angle from +y, `segments`
 * sectors in azimuth; the poles are single shared vertices. 2 * segments * (rings - 1)
 * triangles, closed. */
void mesh_uv_sphere(mesh_writer *m, double cx, double cy, double cz, double r, int segments, int rings);

/* Starts a scene named `name` in *s (zeroed and overwritten). */
int mesh_writer_begin(mesh_writer *m, scene *s, const char *name, rerror *e);

/* Checks the result (no failure, no triangle dropped as degenerate), frees the
 * builder's tables and, on failure, the scene. */
int mesh_writer_end(mesh_writer *m);

/* The camera (up +y, fov_y in degrees) and a 512 x 512 image. */
void mesh_set_camera(scene *s, double ex, double ey, double ez, double tx, double ty, double tz, double fov);

#endif
