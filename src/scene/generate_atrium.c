/* The atrium (generate_rooms.h, docs/scenes.md §11): a generated stand-in for a
 * Sponza-like interior, the third scene of the traversal yardstick (issue 17) and a
 * heavier scene for the path tracer. ../shared/data holds no such interior, so this one
 * is built from the solids of mesh_writer.h to have what makes Sponza hard for a BVH:
 * about a quarter of a million triangles of very different sizes (floor and walls of a
 * few triangles each, fluted columns, arcades with arches, thin draped curtains,
 * balusters, vases with plants), a camera inside the geometry, and light that reaches the
 * galleries only past the arcades.
 *
 * Metres; x along the courtyard, y up. Courtyard x in [-15, 15], z in [-6, 6]; on both
 * long sides a two-storey gallery to z = +-9.5 behind an arcade of ten columns; the
 * courtyard is open to a sky panel 16 m up, and a small "sun" hangs under it. Every solid
 * is closed with outward faces. Unlike the smaller rooms, solids here may touch in a
 * plane where it cannot be seen (a capital on its column); the scene is a benchmark, not
 * a light-leak test. */
#include "restir/scene/generate_atrium.h"

#include "restir/scene/generate_rooms.h"
#include "restir/scene/mesh_writer.h"

#include <math.h>

#define AT_X 15.0          /* courtyard half-length */
#define AT_Z 6.0           /* arcade line (column axes) */
#define AT_GALLERY 9.5     /* the galleries' outer walls start here */
#define AT_WALL_T 0.3      /* wall thickness */
#define AT_TOP 16.0        /* outer walls reach here; the sky panel sits on them */
#define AT_COLUMNS 10      /* columns per arcade, 3 m apart */
#define AT_SPACING 3.0
#define AT_FLOOR1 6.0      /* the first floor's slab: [AT_FLOOR1 - 0.2, AT_FLOOR1 + 0.2] */
#define AT_ROOF 11.2       /* the galleries' roof slab: [AT_ROOF - 0.2, AT_ROOF + 0.2] */
#define AT_ARCH_SEGMENTS 24 /* corners per arch intrados */
#define AT_COLUMN_SEGMENTS 40
#define AT_COLUMN_RINGS 24
#define AT_FLUTES 20

static const material_spec atrium_materials[] = {
    {"stone", MAT_LAMBERT, {0.62, 0.57, 0.48}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"column", MAT_LAMBERT, {0.70, 0.66, 0.58}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"floor", MAT_PLASTIC, {0.45, 0.42, 0.38}, {1, 1, 1}, {0, 0, 0}, 0.3, 1.5},
    {"curtain_red", MAT_LAMBERT, {0.55, 0.08, 0.06}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"curtain_green", MAT_LAMBERT, {0.10, 0.40, 0.12}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"curtain_blue", MAT_LAMBERT, {0.08, 0.15, 0.50}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"vase", MAT_PLASTIC, {0.45, 0.20, 0.10}, {1, 1, 1}, {0, 0, 0}, 0.2, 1.5},
    {"plant", MAT_LAMBERT, {0.10, 0.30, 0.08}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"bronze", MAT_CONDUCTOR, {0, 0, 0}, {0.80, 0.55, 0.35}, {0, 0, 0}, 0.25, 1.5},
    {"sky", MAT_LAMBERT, {0, 0, 0}, {0, 0, 0}, {0.6, 0.7, 0.85}, 1, 1.5},
    {"sun", MAT_LAMBERT, {0, 0, 0}, {0, 0, 0}, {3000, 2800, 2400}, 1, 1.5},
};

/* A solid of revolution about the vertical axis through (cx, cz): radius radius[k] at
 * height y[k] (k = 0..n-1, increasing y), `segments` sectors, closed by a pole vertex at
 * each end. With flutes > 0 the radius is modulated by 1 + depth cos(flutes phi) (a
 * fluted column). Faces point outward: increasing phi runs clockwise seen from +y, so a
 * band's quad lists its lower corner at phi before the upper one (see mesh_uv_sphere). */
static void lathe(mesh_writer *m, double cx, double cz, const double *y, const double *radius, int n, int segments,
                  int flutes, double depth)
{
    uint32_t first, bottom, top;
    int k, j;
    for (k = 0; k < n; ++k)
        for (j = 0; j < segments; ++j) {
            double phi = 2 * MESH_PI * j / segments, r = radius[k] * (1 + depth * cos(flutes * phi));
            mesh_vertex(m, cx + r * cos(phi), y[k], cz + r * sin(phi));
        }
    first = (uint32_t)m->b.s->position_count - (uint32_t)(n * segments);
    bottom = mesh_vertex(m, cx, y[0], cz);
    top = mesh_vertex(m, cx, y[n - 1], cz);
#define LATHE_VERTEX(k, j) (first + (uint32_t)((k) * segments + ((j) % segments)))
    for (j = 0; j < segments; ++j) {
        mesh_face(m, bottom, LATHE_VERTEX(0, j), LATHE_VERTEX(0, j + 1));
        for (k = 0; k + 1 < n; ++k)
            mesh_quad(m, LATHE_VERTEX(k, j), LATHE_VERTEX(k + 1, j), LATHE_VERTEX(k + 1, j + 1), LATHE_VERTEX(k, j + 1));
        mesh_face(m, top, LATHE_VERTEX(n - 1, j + 1), LATHE_VERTEX(n - 1, j));
    }
#undef LATHE_VERTEX
}

/* A fluted column from y0 to y1 with a slight entasis (widest a third of the way up),
 * standing on a square base and carrying a square capital. */
static void column(mesh_writer *m, double x, double z, double y0, double y1, double r)
{
    double y[AT_COLUMN_RINGS + 1], radius[AT_COLUMN_RINGS + 1];
    int k;
    for (k = 0; k <= AT_COLUMN_RINGS; ++k) {
        double t = (double)k / AT_COLUMN_RINGS;
        y[k] = y0 + t * (y1 - y0);
        radius[k] = r * (1 + 0.04 * sin(MESH_PI * fmin(1.5 * t, 1.0)) - 0.08 * t);
    }
    mesh_use(m, "column", "columns");
    lathe(m, x, z, y, radius, AT_COLUMN_RINGS + 1, AT_COLUMN_SEGMENTS, AT_FLUTES, 0.05);
    mesh_use(m, "stone", "capitals");
    mesh_box(m, x - 1.4 * r, y0 - 0.05, z - 1.4 * r, x + 1.4 * r, y0 + 0.25, z + 1.4 * r);
    mesh_box(m, x - 1.3 * r, y1 - 0.05, z - 1.3 * r, x + 1.3 * r, y1 + 0.3, z + 1.3 * r);
}

/* One storey of an arcade at z = zc: a wall from y_spring to y_top along the whole
 * courtyard, pierced by a semicircular arch of radius `inner` between each pair of
 * neighbouring columns (centres on y_spring). The wall is one prism along z, its (x, y)
 * outline a single polygon that dips under every arch. */
static void arcade_wall(mesh_writer *m, double zc, double y_spring, double y_top, double inner, double depth)
{
    double outline[2 * (4 + (AT_COLUMNS - 1) * (AT_ARCH_SEGMENTS + 1))];
    int n = 0, a, j;
    const double x0 = -(AT_COLUMNS - 1) * AT_SPACING / 2;
    /* (u, v) = (x, y) for axis z: start at the left end, walk the underside left to right
     * (down into every arch), then back along the top. */
    outline[n++] = -AT_X - 0.1, outline[n++] = y_spring;
    for (a = 0; a + 1 < AT_COLUMNS; ++a) {
        double xc = x0 + (a + 0.5) * AT_SPACING;
        for (j = 0; j <= AT_ARCH_SEGMENTS; ++j) {
            double theta = MESH_PI * (1 - (double)j / AT_ARCH_SEGMENTS);
            outline[n++] = xc + inner * cos(theta);
            outline[n++] = y_spring + inner * sin(theta);
        }
    }
    outline[n++] = AT_X + 0.1, outline[n++] = y_spring;
    outline[n++] = AT_X + 0.1, outline[n++] = y_top;
    outline[n++] = -AT_X - 0.1, outline[n++] = y_top;
    mesh_use(m, "stone", "arcades");
    mesh_prism(m, outline, n / 2, 2, zc - depth / 2, zc + depth / 2);
}

/* A curtain: a 3 cm thick sheet hanging in the plane z = z0 from y1 down to y0 over
 * x in [x0, x1], draped in vertical folds that flatten towards the top. The sheet is a
 * closed slab: front grid, back grid (+3 cm in z) and four edge strips. */
#define CURTAIN_NX 60
#define CURTAIN_NY 40
static void curtain(mesh_writer *m, double x0, double x1, double y0, double y1, double z0)
{
    uint32_t front = (uint32_t)m->b.s->position_count, back;
    int i, j, side;
    for (side = 0; side < 2; ++side)
        for (j = 0; j <= CURTAIN_NY; ++j)
            for (i = 0; i <= CURTAIN_NX; ++i) {
                double u = (double)i / CURTAIN_NX, v = (double)j / CURTAIN_NY;
                double fold = 0.12 * (1 - 0.7 * v) * sin(2 * MESH_PI * 7 * u + 1.3 * v);
                mesh_vertex(m, x0 + u * (x1 - x0), y0 + v * (y1 - y0), z0 + fold + 0.03 * side);
            }
    back = front + (uint32_t)((CURTAIN_NX + 1) * (CURTAIN_NY + 1));
#define F(i, j) (front + (uint32_t)((j) * (CURTAIN_NX + 1) + (i)))
#define K(i, j) (back + (uint32_t)((j) * (CURTAIN_NX + 1) + (i)))
    for (j = 0; j < CURTAIN_NY; ++j)
        for (i = 0; i < CURTAIN_NX; ++i) {
            mesh_quad(m, F(i, j), F(i, j + 1), F(i + 1, j + 1), F(i + 1, j)); /* faces -z */
            mesh_quad(m, K(i, j), K(i + 1, j), K(i + 1, j + 1), K(i, j + 1)); /* faces +z */
        }
    for (i = 0; i < CURTAIN_NX; ++i) {
        mesh_quad(m, F(i, 0), F(i + 1, 0), K(i + 1, 0), K(i, 0));                                     /* -y */
        mesh_quad(m, F(i, CURTAIN_NY), K(i, CURTAIN_NY), K(i + 1, CURTAIN_NY), F(i + 1, CURTAIN_NY)); /* +y */
    }
    for (j = 0; j < CURTAIN_NY; ++j) {
        mesh_quad(m, F(0, j), K(0, j), K(0, j + 1), F(0, j + 1));                                     /* -x */
        mesh_quad(m, F(CURTAIN_NX, j), F(CURTAIN_NX, j + 1), K(CURTAIN_NX, j + 1), K(CURTAIN_NX, j)); /* +x */
    }
#undef F
#undef K
}

/* A terracotta vase (a lathe profile) holding a plant of seven overlapping spheres. */
static void planter(mesh_writer *m, double x, double z)
{
    static const double y[] = {0.0, 0.05, 0.3, 0.6, 0.8, 0.9, 0.95};
    static const double r[] = {0.22, 0.3, 0.42, 0.4, 0.3, 0.32, 0.35};
    int k;
    mesh_use(m, "vase", "vases");
    lathe(m, x, z, y, r, 7, 64, 0, 0);
    mesh_use(m, "plant", "plants");
    for (k = 0; k < 7; ++k) {
        double phi = 2 * MESH_PI * k / 7, d = k ? 0.25 : 0;
        mesh_uv_sphere(m, x + d * cos(phi), 1.2 + 0.15 * (k % 3), z + d * sin(phi), 0.3, 32, 16);
    }
}

/* The first floor's balustrade along one arcade: eight turned balusters per bay on a
 * plinth, under a rail. */
static void balustrade(mesh_writer *m, double zc)
{
    static const double y[] = {0.0, 0.08, 0.25, 0.45, 0.6, 0.7, 0.78, 0.85};
    static const double r[] = {0.05, 0.06, 0.045, 0.075, 0.05, 0.035, 0.055, 0.05};
    const double x0 = -(AT_COLUMNS - 1) * AT_SPACING / 2, base = AT_FLOOR1 + 0.2;
    double yk[8];
    int a, b, k;
    for (k = 0; k < 8; ++k) yk[k] = base + 0.1 + y[k];
    mesh_use(m, "stone", "balustrades");
    for (a = 0; a + 1 < AT_COLUMNS; ++a) {
        double left = x0 + a * AT_SPACING + 0.45, right = x0 + (a + 1) * AT_SPACING - 0.45;
        mesh_box(m, left, base - 0.05, zc - 0.12, right, base + 0.12, zc + 0.12);
        mesh_box(m, left, base + 0.93, zc - 0.1, right, base + 1.03, zc + 0.1);
        for (b = 0; b < 8; ++b) lathe(m, left + (b + 0.5) * (right - left) / 8, zc, yk, r, 8, 12, 0, 0);
    }
}

/* Floor, end walls, the galleries' outer walls, their floor and roof slabs. */
static void shell(mesh_writer *m)
{
    const double t = AT_WALL_T, xe = AT_X + 0.2, ze = AT_GALLERY + t;
    int side;
    mesh_use(m, "floor", "floor");
    mesh_box(m, -xe - t, -0.3, -ze - 0.1, xe + t, 0, ze + 0.1);
    mesh_use(m, "stone", "walls");
    mesh_box(m, -xe - t, -0.2, -ze - 0.2, -xe, AT_TOP + 0.1, ze + 0.2);
    mesh_box(m, xe, -0.2, -ze - 0.2, xe + t, AT_TOP + 0.1, ze + 0.2);
    mesh_box(m, -xe - 0.1, -0.1, AT_GALLERY, xe + 0.1, AT_TOP, ze);
    mesh_box(m, -xe - 0.1, -0.1, -ze, xe + 0.1, AT_TOP, -AT_GALLERY);
    mesh_use(m, "stone", "slabs");
    for (side = -1; side <= 1; side += 2) {
        /* From just inside the arcade line to 0.15 into the outer wall. */
        double z_in1 = side * (AT_Z - 0.35), z_in2 = side * (AT_Z - 0.4), z_out = side * (AT_GALLERY + 0.15);
        mesh_box(m, -xe - 0.05, AT_FLOOR1 - 0.2, fmin(z_in1, z_out), xe + 0.05, AT_FLOOR1 + 0.2, fmax(z_in1, z_out));
        mesh_box(m, -xe - 0.05, AT_ROOF - 0.2, fmin(z_in2, z_out), xe + 0.05, AT_ROOF + 0.2, fmax(z_in2, z_out));
    }
}

/* Both arcades: columns, arch walls and, upstairs, the balustrade and the curtains. */
static void arcades(mesh_writer *m)
{
    static const char *const curtains[3] = {"curtain_red", "curtain_green", "curtain_blue"};
    const double x0 = -(AT_COLUMNS - 1) * AT_SPACING / 2;
    int side, c, a;
    for (side = -1; side <= 1; side += 2) {
        double zc = side * AT_Z;
        for (c = 0; c < AT_COLUMNS; ++c) {
            double x = x0 + c * AT_SPACING;
            column(m, x, zc, 0.0, 4.2, 0.35);
            column(m, x, zc, AT_FLOOR1 + 0.2, 9.4, 0.25);
        }
        arcade_wall(m, zc, 4.5, AT_FLOOR1 - 0.1, 1.1, 0.6);
        arcade_wall(m, zc, 9.7, AT_ROOF - 0.1, 1.2, 0.5);
        balustrade(m, zc);
        /* Curtains in every other upper bay, hanging just behind the arches. */
        for (a = side > 0 ? 0 : 1; a + 1 < AT_COLUMNS; a += 2) {
            double xc = x0 + (a + 0.5) * AT_SPACING;
            mesh_use(m, curtains[(a / 2) % 3], "curtains");
            curtain(m, xc - 1.1, xc + 1.1, AT_FLOOR1 + 1.5, 9.6, zc + side * 0.45);
        }
    }
}

int generate_atrium(scene *s, rerror *e)
{
    static const double planters[8][2] = {{-10.5, -3}, {-10.5, 3}, {-4.5, -3}, {-4.5, 3},
                                          {4.5, -3},   {4.5, 3},   {10.5, -3}, {10.5, 3}};
    mesh_writer m;
    int i;
    if (mesh_writer_begin(&m, s, "generated:atrium", e)) return -1;
    mesh_define_materials(&m, atrium_materials, (int)(sizeof atrium_materials / sizeof *atrium_materials));
    shell(&m);
    arcades(&m);
    for (i = 0; i < 8; ++i) planter(&m, planters[i][0], planters[i][1]);
    mesh_use(&m, "bronze", "fountain");
    mesh_uv_sphere(&m, 0, 0.6, 0, 0.6, 48, 24);
    mesh_use(&m, "sky", "sky");
    mesh_box(&m, -AT_X - 1, AT_TOP - 0.05, -AT_GALLERY - 1, AT_X + 1, AT_TOP + 0.2, AT_GALLERY + 1);
    mesh_use(&m, "sun", "sun");
    mesh_box(&m, 7.7, 15.0, 2.7, 8.3, 15.6, 3.3);
    mesh_set_camera(s, -13.0, 1.7, 0.8, 12.0, 5.0, -0.6, 55);
    return mesh_writer_end(&m);
}
