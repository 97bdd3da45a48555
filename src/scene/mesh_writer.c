/* The solids of the scene generators (include/restir/scene/mesh_writer.h).
 *
 * Building blocks: closed solids (prisms over a polygon, UV spheres) whose faces share
 * their vertices, so each solid is watertight under the BVH's watertight ray/triangle
 * test, and whose faces point outward. */
#include "restir/scene/mesh_writer.h"

#include <math.h>
#include <stdio.h>
#include <string.h>



uint32_t mesh_vertex(mesh_writer *m, double x, double y, double z)
{
    uint32_t index = (uint32_t)m->b.s->position_count;
    if (m->failed) return 0;
    if (builder_add_position(&m->b, v3f((float)x, (float)y, (float)z), m->e)) m->failed = 1;
    return index;
}

/* A point given by its coordinate w along `axis` and (u, v) on the two following axes
 * (cyclically: u = axis+1, v = axis+2, so that u x v = +axis). */
uint32_t mesh_axis_vertex(mesh_writer *m, int axis, double w, double u, double v)
{
    double c[3];
    c[axis] = w;
    c[(axis + 1) % 3] = u;
    c[(axis + 2) % 3] = v;
    return mesh_vertex(m, c[0], c[1], c[2]);
}

/* Triangle a, b, c: the front face is the side of (b - a) x (c - a). */
void mesh_face(mesh_writer *m, uint32_t a, uint32_t b, uint32_t c)
{
    triangle t;
    if (m->failed) return;
    t.v[0] = a, t.v[1] = b, t.v[2] = c;
    t.n[0] = t.n[1] = t.n[2] = -1;
    t.t[0] = t.t[1] = t.t[2] = -1;
    t.material = m->material;
    t.object = m->object;
    if (builder_add_triangle(&m->b, &t, m->e)) m->failed = 1;
}

void mesh_quad(mesh_writer *m, uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    mesh_face(m, a, b, c);
    mesh_face(m, a, c, d);
}

void mesh_define_materials(mesh_writer *m, const material_spec *specs, int count)
{
    int i;
    for (i = 0; i < count && !m->failed; ++i) {
        const material_spec *p = &specs[i];
        uint32_t index;
        material *mat;
        if (builder_material(&m->b, p->name, &index, m->e)) {
            m->failed = 1;
            return;
        }
        mat = &m->b.s->materials[index];
        mat->type = p->type;
        mat->diffuse = rgb_make((real)p->kd[0], (real)p->kd[1], (real)p->kd[2]);
        mat->specular = rgb_make((real)p->ks[0], (real)p->ks[1], (real)p->ks[2]);
        mat->emission = rgb_make((real)p->ke[0], (real)p->ke[1], (real)p->ke[2]);
        mat->roughness = (real)p->roughness;
        mat->ior = (real)p->ior;
    }
}

/* The material and object of the faces that follow (the material must be defined). */
void mesh_use(mesh_writer *m, const char *material_name, const char *object_name)
{
    if (m->failed) return;
    if (builder_material(&m->b, material_name, &m->material, m->e) ||
        builder_object(&m->b, object_name, &m->object, m->e))
        m->failed = 1;
}

/* A polygon cap: the corners (vertex indices) in counter-clockwise order seen from the
 * side the cap faces, triangulated by ear clipping (which keeps the winding). */
void mesh_cap(mesh_writer *m, const uint32_t *ring, int n, int reversed)
{
    vec3f corners[MESH_MAX_PRISM_CORNERS];
    uint32_t order[MESH_MAX_PRISM_CORNERS], tri[3 * MESH_MAX_PRISM_CORNERS];
    size_t count, k;
    int i;
    if (m->failed) return;
    for (i = 0; i < n; ++i) {
        order[i] = ring[reversed ? n - 1 - i : i];
        corners[i] = m->b.s->positions[order[i]];
    }
    if (triangulate_polygon(&m->tri, corners, (size_t)n, tri, &count, m->e)) {
        m->failed = 1;
        return;
    }
    for (k = 0; k < count; ++k) mesh_face(m, order[tri[3 * k]], order[tri[3 * k + 1]], order[tri[3 * k + 2]]);
}

/* A closed prism: the simple polygon of n corners uv[2i], uv[2i+1], given as (u, v)
 * coordinates on the two axes after `axis` (see mesh_axis_vertex), swept along `axis` from lo to hi (lo < hi). Faces
 * point outward whatever the polygon's winding: a counter-clockwise polygon in (u, v)
 * has its area normal along +axis, so the top cap keeps the order, the bottom cap
 * reverses it, and the side quad over edge e (from corner i to i+1) has normal
 * e x (+axis), which points out of a counter-clockwise polygon. */
void mesh_prism(mesh_writer *m, const double *uv, int n, int axis, double lo, double hi)
{
    uint32_t bottom[MESH_MAX_PRISM_CORNERS], top[MESH_MAX_PRISM_CORNERS];
    double twice_area = 0;
    int i;
    if (n < 3 || n > MESH_MAX_PRISM_CORNERS) {
        if (!m->failed) rerror_set(m->e, "generate: prism with %d corners", n);
        m->failed = 1;
        return;
    }
    for (i = 0; i < n; ++i)
        twice_area += uv[2 * i] * uv[2 * ((i + 1) % n) + 1] - uv[2 * ((i + 1) % n)] * uv[2 * i + 1];
    for (i = 0; i < n; ++i) {
        const double *p = uv + 2 * (twice_area < 0 ? n - 1 - i : i);
        bottom[i] = mesh_axis_vertex(m, axis, lo, p[0], p[1]);
        top[i] = mesh_axis_vertex(m, axis, hi, p[0], p[1]);
    }
    for (i = 0; i < n; ++i) mesh_quad(m, bottom[i], bottom[(i + 1) % n], top[(i + 1) % n], top[i]);
    mesh_cap(m, top, n, 0);
    mesh_cap(m, bottom, n, 1);
}

/* An axis-aligned box [x0, x1] x [y0, y1] x [z0, z1] with outward faces. */
void mesh_box(mesh_writer *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    /* Footprint in the (u, v) = (z, x) plane of axis y. */
    const double footprint[4][2] = {{z0, x0}, {z1, x0}, {z1, x1}, {z0, x1}};
    mesh_prism(m, footprint[0], 4, 1, y0, y1);
}

/* A box standing on the y axis whose footprint, the rectangle [0, size_x] x [-size_z, 0]
 * in local coordinates (a, b), is turned about the vertical axis through (pivot_x,
 * pivot_z) so that the local +a direction becomes (cos t, -sin t) in (x, z) and +b
 * becomes (sin t, cos t): a proper rotation, which keeps the faces outward. */
void mesh_turned_box(mesh_writer *m, double pivot_x, double pivot_z, double size_x, double size_z, double turn_degrees,
                     double y0, double y1)
{
    const double local[4][2] = {{0, -size_z}, {size_x, -size_z}, {size_x, 0}, {0, 0}};
    double footprint[4][2], c = cos(turn_degrees * MESH_PI / 180), s = sin(turn_degrees * MESH_PI / 180);
    int i;
    for (i = 0; i < 4; ++i) {
        double a = local[i][0], b = local[i][1];
        double x = pivot_x + a * c + b * s, z = pivot_z - a * s + b * c;
        footprint[i][0] = z; /* (u, v) = (z, x) for axis y */
        footprint[i][1] = x;
    }
    mesh_prism(m, footprint[0], 4, 1, y0, y1);
}

/* A UV sphere (outward faces): `rings` bands in the polar angle from +y, `segments`
 * sectors in azimuth; the poles are single shared vertices. 2 * segments * (rings - 1)
 * triangles, closed. */
void mesh_uv_sphere(mesh_writer *m, double cx, double cy, double cz, double r, int segments, int rings)
{
    uint32_t north = mesh_vertex(m, cx, cy + r, cz), south = mesh_vertex(m, cx, cy - r, cz), first = north + 2;
    int k, j;
    for (k = 1; k < rings; ++k) {
        double theta = MESH_PI * k / rings;
        for (j = 0; j < segments; ++j) {
            double phi = 2 * MESH_PI * j / segments;
            mesh_vertex(m, cx + r * sin(theta) * cos(phi), cy + r * cos(theta), cz + r * sin(theta) * sin(phi));
        }
    }
#define RING_VERTEX(k, j) (first + (uint32_t)(((k) - 1) * segments + ((j) % segments)))
    for (j = 0; j < segments; ++j) {
        /* Going around +y with increasing azimuth is clockwise seen from outside at the
         * north pole, so the caps and bands list j + 1 before j there (and after j at the
         * south pole). */
        mesh_face(m, north, RING_VERTEX(1, j + 1), RING_VERTEX(1, j));
        for (k = 1; k + 1 < rings; ++k)
            mesh_quad(m, RING_VERTEX(k, j), RING_VERTEX(k, j + 1), RING_VERTEX(k + 1, j + 1), RING_VERTEX(k + 1, j));
        mesh_face(m, south, RING_VERTEX(rings - 1, j), RING_VERTEX(rings - 1, j + 1));
    }
#undef RING_VERTEX
}

int mesh_writer_begin(mesh_writer *m, scene *s, const char *name, rerror *e)
{
    memset(s, 0, sizeof *s);
    memset(m, 0, sizeof *m);
    m->e = e;
    snprintf(s->path, sizeof s->path, "%s", name);
    return builder_init(&m->b, s, NULL, e);
}

/* Checks the result (no failure, no triangle dropped as degenerate), frees the
 * builder's tables and, on failure, the scene. */
int mesh_writer_end(mesh_writer *m)
{
    scene *s = m->b.s;
    if (!m->failed && m->b.degenerate_triangles)
        m->failed = rerror_set(m->e, "%s: %zu degenerate triangles", s->path, m->b.degenerate_triangles) != 0;
    builder_finish(&m->b);
    triangulator_free(&m->tri);
    if (m->failed) {
        scene_free(s);
        return -1;
    }
    return 0;
}

void mesh_set_camera(scene *s, double ex, double ey, double ez, double tx, double ty, double tz, double fov)
{
    s->has_camera = 1;
    s->camera.eye = v3((real)ex, (real)ey, (real)ez);
    s->camera.target = v3((real)tx, (real)ty, (real)tz);
    s->camera.up = v3(0, 1, 0);
    s->camera.fov_y_degrees = (real)fov;
    s->width = 512;
    s->height = 512;
}
