/* Scene-file area lights (sphere, quad, disk) as emissive triangle meshes
 * (include/restir/scene/light_shapes.h, docs/scene-format.md "Lights"). */
#include "restir/scene/light_shapes.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI_D 3.14159265358979323846

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double length3(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

double light_shape_area(const light_shape *l)
{
    double c[3];
    switch (l->kind) {
    case LIGHT_SPHERE: return 4 * PI_D * l->radius * l->radius;
    case LIGHT_DISK: return PI_D * l->radius * l->radius;
    case LIGHT_QUAD: break;
    }
    cross3(l->u, l->v, c);
    return 4 * length3(c);
}

/* Finite and at most LIGHT_MAX_COORDINATE in magnitude, so that every corner (a sum of
 * three such values) is a finite float. */
#define LIGHT_MAX_COORDINATE 1e18
static int all_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; ++i)
        if (!(fabs(v[i]) <= LIGHT_MAX_COORDINATE)) return 0;
    return 1;
}

int light_shape_check(const light_shape *l, rerror *e)
{
    double c[3];
    if (!all_finite(l->centre, 3) || !all_finite(l->u, 3) || !all_finite(l->v, 3) || !all_finite(l->normal, 3) ||
        !isfinite(l->radius))
        return rerror_set(e, "a coordinate or radius beyond +-1e18");
    if (l->kind != LIGHT_QUAD && !(l->radius > 0)) return rerror_set(e, "radius %g is not > 0", l->radius);
    if (l->kind == LIGHT_QUAD) {
        cross3(l->u, l->v, c);
        if (!(length3(c) > 1e-12 * length3(l->u) * length3(l->v)) || !(length3(c) > 0))
            return rerror_set(e, "u and v are zero or parallel (the quad has no area)");
    }
    if (l->kind == LIGHT_DISK && !(length3(l->normal) > 0)) return rerror_set(e, "the normal is zero");
    if (!(l->radiance.r >= 0 && l->radiance.g >= 0 && l->radiance.b >= 0 && l->radiance.r <= 1e30 &&
          l->radiance.g <= 1e30 && l->radiance.b <= 1e30))
        return rerror_set(e, "radiance outside [0, 1e30]");
    if (rgb_is_black(l->radiance)) return rerror_set(e, "radiance 0 0 0 (the light emits nothing)");
    return 0;
}

/* The triangles' shared state while a shape is built. */
typedef struct {
    scene_builder *b;
    uint32_t material, object;
} shape_out;

static int add_point(shape_out *o, const double p[3], uint32_t *index, rerror *e)
{
    *index = (uint32_t)o->b->s->position_count;
    return builder_add_position(o->b, v3f((float)p[0], (float)p[1], (float)p[2]), e);
}

/* Front face (emitting side): the counter-clockwise side of a, b, c. */
static int add_triangle(shape_out *o, uint32_t a, uint32_t b, uint32_t c, rerror *e)
{
    triangle t;
    t.v[0] = a;
    t.v[1] = b;
    t.v[2] = c;
    t.n[0] = t.n[1] = t.n[2] = -1;
    t.t[0] = t.t[1] = t.t[2] = -1;
    t.material = o->material;
    t.object = o->object;
    return builder_add_triangle(o->b, &t, e);
}

static int build_quad(shape_out *o, const light_shape *l, rerror *e)
{
    static const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    uint32_t idx[4];
    int i, k;
    for (i = 0; i < 4; ++i) { /* counter-clockwise seen from the side of u x v */
        double p[3];
        for (k = 0; k < 3; ++k) p[k] = l->centre[k] + su[i] * l->u[k] + sv[i] * l->v[k];
        if (add_point(o, p, &idx[i], e)) return -1;
    }
    return add_triangle(o, idx[0], idx[1], idx[2], e) || add_triangle(o, idx[0], idx[2], idx[3], e) ? -1 : 0;
}

/* An orthonormal pair (t, s) with t x s = n (n unit). */
static void tangent_frame(const double n[3], double t[3], double s[3])
{
    double a[3] = {0, 0, 0}, len;
    a[fabs(n[0]) < 0.5 ? 0 : fabs(n[1]) < 0.5 ? 1 : 2] = 1;
    cross3(a, n, t);
    len = length3(t);
    t[0] /= len, t[1] /= len, t[2] /= len;
    cross3(n, t, s);
}

static int build_disk(shape_out *o, const light_shape *l, rerror *e)
{
    double n[3], t[3], s[3], len = length3(l->normal);
    uint32_t centre, first = 0, prev = 0;
    int i, k;
    for (k = 0; k < 3; ++k) n[k] = l->normal[k] / len;
    tangent_frame(n, t, s);
    if (add_point(o, l->centre, &centre, e)) return -1;
    for (i = 0; i <= LIGHT_DISK_SEGMENTS; ++i) {
        uint32_t cur;
        double angle = 2 * PI_D * (i % LIGHT_DISK_SEGMENTS) / LIGHT_DISK_SEGMENTS, p[3];
        if (i == LIGHT_DISK_SEGMENTS) {
            cur = first; /* the rim closes on its first point, bit for bit */
        } else {
            for (k = 0; k < 3; ++k) p[k] = l->centre[k] + l->radius * (cos(angle) * t[k] + sin(angle) * s[k]);
            if (add_point(o, p, &cur, e)) return -1;
        }
        if (i == 0) first = cur;
        else if (add_triangle(o, centre, prev, cur, e)) return -1; /* counter-clockwise about n = t x s */
        prev = cur;
    }
    return 0;
}

/* The regular icosahedron: 12 vertices (±1, ±phi, 0) and cyclic permutations; 20 faces. */
static const signed char ico_vertex[12][3] = {{-1, 2, 0}, {1, 2, 0}, {-1, -2, 0}, {1, -2, 0}, {0, -1, 2}, {0, 1, 2},
                                              {0, -1, -2}, {0, 1, -2}, {2, 0, -1}, {2, 0, 1}, {-2, 0, -1}, {-2, 0, 1}};
static const unsigned char ico_face[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                              {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                              {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                              {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};

static void ico_corner(int i, double out[3])
{
    const double phi = 0.5 * (1 + sqrt(5.0));
    int k;
    for (k = 0; k < 3; ++k) {
        int c = ico_vertex[i][k];
        out[k] = c == 2 ? phi : c == -2 ? -phi : (double)c;
    }
}

/* Point (i, j) of a face's grid: the barycentric mix of the corners, pushed onto the sphere.
 * The mix is a*wa + b*wb + c*wc with one weight 0 on an edge, so the two faces sharing an
 * edge compute the same sums and their vertices coincide bit for bit (no cracks). */
static void sphere_point(const light_shape *l, const double a[3], const double b[3], const double c[3], int i, int j,
                         double out[3])
{
    const int m = LIGHT_SPHERE_DIVISIONS;
    double wa = (double)(m - i - j) / m, wb = (double)i / m, wc = (double)j / m, q[3], len;
    int k;
    for (k = 0; k < 3; ++k) q[k] = a[k] * wa + b[k] * wb + c[k] * wc;
    len = length3(q);
    for (k = 0; k < 3; ++k) out[k] = l->centre[k] + l->radius * q[k] / len;
}

static int build_sphere_face(shape_out *o, const light_shape *l, int face, rerror *e)
{
    const int m = LIGHT_SPHERE_DIVISIONS;
    double a[3], b[3], c[3], ab[3], ac[3], nrm[3];
    uint32_t base = (uint32_t)o->b->s->position_count, unused;
    int i, j;
    ico_corner(ico_face[face][0], a);
    ico_corner(ico_face[face][1], b);
    ico_corner(ico_face[face][2], c);
    for (i = 0; i < 3; ++i) ab[i] = b[i] - a[i], ac[i] = c[i] - a[i];
    cross3(ab, ac, nrm);
    if (nrm[0] * a[0] + nrm[1] * a[1] + nrm[2] * a[2] < 0) { /* make the front face point outwards */
        double tmp[3];
        memcpy(tmp, b, sizeof tmp);
        memcpy(b, c, sizeof tmp);
        memcpy(c, tmp, sizeof tmp);
    }
    for (i = 0; i <= m; ++i)
        for (j = 0; j <= m - i; ++j) {
            double p[3];
            sphere_point(l, a, b, c, i, j, p);
            if (add_point(o, p, &unused, e)) return -1;
        }
    /* Row i holds m - i + 1 points and starts at i (m + 1) - i (i - 1) / 2. */
#define GRID(i, j) (base + (uint32_t)((i) * (m + 1) - (i) * ((i)-1) / 2 + (j)))
    for (i = 0; i < m; ++i)
        for (j = 0; j < m - i; ++j) {
            if (add_triangle(o, GRID(i, j), GRID(i + 1, j), GRID(i, j + 1), e)) return -1;
            if (i + j < m - 1 && add_triangle(o, GRID(i + 1, j), GRID(i + 1, j + 1), GRID(i, j + 1), e)) return -1;
        }
#undef GRID
    return 0;
}

int light_shape_add(scene_builder *b, const light_shape *l, const char *name, rerror *e)
{
    shape_out o;
    material *m;
    int face;
    if (light_shape_check(l, e)) return -1;
    o.b = b;
    if (builder_material(b, name, &o.material, e) || builder_object(b, name, &o.object, e)) return -1;
    m = &b->s->materials[o.material];
    b->material_origin[o.material] = MATERIAL_FROM_SCENE;
    m->type = MAT_LAMBERT;
    m->diffuse = rgb_make(0, 0, 0);
    m->specular = rgb_make(0, 0, 0);
    m->emission = l->radiance;
    switch (l->kind) {
    case LIGHT_QUAD: return build_quad(&o, l, e);
    case LIGHT_DISK: return build_disk(&o, l, e);
    case LIGHT_SPHERE: break;
    }
    for (face = 0; face < 20; ++face)
        if (build_sphere_face(&o, l, face, e)) return -1;
    return 0;
}
