/* A generated benchmark scene: a finely tessellated, radially displaced sphere under a
 * quad light. Everything is a pure function of the integer grid coordinates, so the
 * output is the same on every run. */
#include "restir/scene/generate.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/scene/mtl.h"

enum { MAX_SUBDIVISIONS = 8192 };

/* Radial displacement of the unit direction d: a few products of sines at unrelated
 * frequencies (smooth, bumpy, no visible pattern at the benchmark's resolution). */
static double displacement(double x, double y, double z)
{
    return 0.08 * sin(9.1 * x + 1.3) * sin(7.3 * y + 0.4) * sin(8.7 * z + 2.1) +
           0.04 * sin(23.0 * x * y + 17.0 * z) + 0.02 * sin(41.0 * (x + z) + 29.0 * y);
}

/* The surface point of cube lattice point (i, j, k), 0 <= i, j, k <= n. The lattice
 * coordinate is warped with tan (an equi-angular cube map: cells of similar size on the
 * sphere), normalised and displaced. */
static vec3f sphere_point(const int lattice[3], int n)
{
    double c[3], len, r;
    int a;
    for (a = 0; a < 3; ++a) c[a] = tan(0.78539816339744831 * (2.0 * lattice[a] / n - 1.0));
    len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (a = 0; a < 3; ++a) c[a] /= len;
    r = 1.0 + displacement(c[0], c[1], c[2]);
    return v3f((float)(c[0] * r), (float)(c[1] * r), (float)(c[2] * r));
}

/* Open-addressing map from lattice points to vertex indices (each surface lattice
 * point becomes one shared vertex, so the six faces are stitched). */
typedef struct {
    uint64_t *keys; /* key + 1; 0 = empty */
    uint32_t *values;
    size_t mask;
} lattice_map;

static uint32_t lattice_vertex(lattice_map *m, scene *s, const int p[3], int n)
{
    uint64_t key = ((uint64_t)p[0] * (uint64_t)(n + 1) + (uint64_t)p[1]) * (uint64_t)(n + 1) + (uint64_t)p[2];
    size_t slot = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & m->mask;
    while (m->keys[slot] && m->keys[slot] != key + 1) slot = (slot + 1) & m->mask;
    if (!m->keys[slot]) {
        m->keys[slot] = key + 1;
        m->values[slot] = (uint32_t)s->position_count;
        s->positions[s->position_count++] = sphere_point(p, n);
    }
    return m->values[slot];
}

static triangle make_triangle(uint32_t a, uint32_t b, uint32_t c, uint32_t material, uint32_t object)
{
    triangle t;
    t.v[0] = a, t.v[1] = b, t.v[2] = c;
    t.n[0] = t.n[1] = t.n[2] = -1;
    t.t[0] = t.t[1] = t.t[2] = -1;
    t.material = material;
    t.object = object;
    return t;
}

/* Face (axis, side) of the cube: the grid spans the two other axes u = axis+1,
 * v = axis+2 (cyclic), whose cross product is +axis; the winding is reversed on the
 * negative side so that every face normal points outward. */
/* Nonzero: the caller asks to stop (generate_progress). */
static int report(const generate_progress *p, const char *phase, long done, long total)
{
    return p && p->step ? p->step(p->ctx, phase, done, total) : 0;
}

/* face: 0..5, the faces before this one (for the progress in grid rows, 6 n in all).
 * Returns nonzero if the progress callback asked to stop. */
static int add_cube_face(scene *s, lattice_map *m, int n, int axis, int positive, int face,
                         const generate_progress *p)
{
    int iu, iv, u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (iv = 0; iv < n; ++iv) {
        if (report(p, "building the mesh", (long)face * n + iv, 6L * n)) return 1;
        for (iu = 0; iu < n; ++iu) {
            int p[4][3], q;
            uint32_t id[4];
            for (q = 0; q < 4; ++q) {
                p[q][axis] = positive ? n : 0;
                p[q][u] = iu + (q == 1 || q == 2);
                p[q][v] = iv + (q >= 2);
                id[q] = lattice_vertex(m, s, p[q], n);
            }
            /* Quad corners 0:(u,v) 1:(u+1,v) 2:(u+1,v+1) 3:(u,v+1). */
            if (positive) {
                s->triangles[s->triangle_count++] = make_triangle(id[0], id[1], id[2], 0, 0);
                s->triangles[s->triangle_count++] = make_triangle(id[0], id[2], id[3], 0, 0);
            } else {
                s->triangles[s->triangle_count++] = make_triangle(id[0], id[2], id[1], 0, 0);
                s->triangles[s->triangle_count++] = make_triangle(id[0], id[3], id[2], 0, 0);
            }
        }
    }
    return 0;
}

static material make_material(const char *name, real albedo, real emission)
{
    material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.type = MAT_LAMBERT;
    m.diffuse = rgb_gray(albedo);
    m.specular = rgb_gray(0);
    m.emission = rgb_gray(emission);
    m.roughness = 1;
    m.ior = (real)1.5;
    return m;
}

static char *copy_string(const char *text, rerror *e)
{
    char *c = rmalloc(strlen(text) + 1, 1, e);
    if (c) strcpy(c, text);
    return c;
}

/* The light: a 1 x 1 quad at height 2.2, front face (v1-v0)x(v2-v0) pointing down. */
static void add_light(scene *s)
{
    uint32_t base = (uint32_t)s->position_count;
    s->positions[s->position_count++] = v3f(-0.5f, 2.2f, -0.5f);
    s->positions[s->position_count++] = v3f(0.5f, 2.2f, -0.5f);
    s->positions[s->position_count++] = v3f(0.5f, 2.2f, 0.5f);
    s->positions[s->position_count++] = v3f(-0.5f, 2.2f, 0.5f);
    s->triangles[s->triangle_count++] = make_triangle(base, base + 1, base + 2, 1, 1);
    s->triangles[s->triangle_count++] = make_triangle(base, base + 2, base + 3, 1, 1);
}

int generate_displaced_sphere(scene *s, int subdivisions, rerror *e)
{
    return generate_displaced_sphere_progress(s, subdivisions, NULL, e);
}

int generate_displaced_sphere_progress(scene *s, int subdivisions, const generate_progress *p, rerror *e)
{
    int n = subdivisions, axis;
    size_t max_vertices, max_triangles;
    lattice_map m;

    memset(s, 0, sizeof *s);
    snprintf(s->path, sizeof s->path, "generated:displaced_sphere(%d)", n);
    if (n < 1 || n > MAX_SUBDIVISIONS)
        return rerror_at(e, s->path, 0, "subdivisions must be in [1, %d]", MAX_SUBDIVISIONS);
    max_vertices = 6 * (size_t)n * n + 2 + 4;
    max_triangles = 12 * (size_t)n * n + 2;
    m.mask = 1;
    while (m.mask < 2 * max_vertices) m.mask <<= 1;
    m.keys = rcalloc(m.mask, sizeof *m.keys, e);
    m.values = rmalloc(m.mask, sizeof *m.values, e);
    m.mask -= 1;
    s->positions = rmalloc(max_vertices, sizeof *s->positions, e);
    s->triangles = rmalloc(max_triangles, sizeof *s->triangles, e);
    s->materials = rmalloc(2, sizeof *s->materials, e);
    s->object_names = rcalloc(2, sizeof *s->object_names, e);
    if (!m.keys || !m.values || !s->positions || !s->triangles || !s->materials || !s->object_names) goto fail;

    for (axis = 0; axis < 3; ++axis)
        if (add_cube_face(s, &m, n, axis, 1, 2 * axis, p) || add_cube_face(s, &m, n, axis, 0, 2 * axis + 1, p)) {
            rerror_at(e, s->path, 0, "cancelled");
            goto fail;
        }
    report(p, "building the mesh", 6L * n, 6L * n);
    add_light(s);

    s->materials[0] = make_material("white", (real)0.8, 0);
    s->materials[1] = make_material("light", 0, 10);
    s->material_count = 2;
    s->object_names[0] = copy_string("sphere", e);
    s->object_names[1] = copy_string("light", e);
    s->object_count = 2;
    if (!s->object_names[0] || !s->object_names[1]) goto fail;

    s->has_camera = 1;
    s->camera.eye = v3(0, 1, 4);
    s->camera.target = v3(0, 0, 0);
    s->camera.up = v3(0, 1, 0);
    s->camera.fov_y_degrees = 40;
    s->width = 512;
    s->height = 512;
    free(m.keys);
    free(m.values);
    return 0;
fail:
    free(m.keys);
    free(m.values);
    free(s->positions);
    free(s->triangles);
    free(s->materials);
    if (s->object_names) {
        free(s->object_names[0]);
        free(s->object_names[1]);
    }
    free(s->object_names);
    memset(s, 0, sizeof *s);
    return -1;
}

/* ------------------------------------------------------------------------------- */
/* OBJ + MTL output                                                                  */

static void mtl_path_for(const char *obj_path, char *out, size_t size)
{
    size_t len = strlen(obj_path);
    if (len >= 4 && !strcmp(obj_path + len - 4, ".obj"))
        snprintf(out, size, "%.*s.mtl", (int)(len - 4), obj_path);
    else
        snprintf(out, size, "%s.mtl", obj_path);
}

/* The MTL statements that make mtl_to_material (docs/scene-format.md, "MTL mapping")
 * give back the material's type and values: Lambert = illum 1 (rule 4); conductor =
 * Pm 1 with F0 as Kd (rule 1); plastic = Pm 0, Pr (rule 5); dielectrics = illum 7, Ni,
 * and Pr for the rough one (rule 3). Not representable (and then changed on reading):
 * a plastic with Ks = 0 (read as Ks 1), a plastic coat ior <= 1 (read as 1.5), a tinted
 * dielectric (read as untinted). Every type keeps Ke. */
static void write_mtl_material(FILE *f, const material *m)
{
    rgb kd = m->type == MAT_CONDUCTOR ? m->specular : m->diffuse;
    fprintf(f, "newmtl %s\nKd %.9g %.9g %.9g\n", m->name, (double)kd.r, (double)kd.g, (double)kd.b);
    if (m->type == MAT_PLASTIC)
        fprintf(f, "Ks %.9g %.9g %.9g\n", (double)m->specular.r, (double)m->specular.g, (double)m->specular.b);
    fprintf(f, "Ke %.9g %.9g %.9g\n", (double)m->emission.r, (double)m->emission.g, (double)m->emission.b);
    switch (m->type) {
    case MAT_LAMBERT: fprintf(f, "illum 1\n"); break;
    case MAT_CONDUCTOR: fprintf(f, "Pm 1\nPr %.9g\n", (double)m->roughness); break;
    case MAT_PLASTIC: fprintf(f, "Pm 0\nPr %.9g\nNi %.9g\n", (double)m->roughness, (double)m->ior); break;
    case MAT_DIELECTRIC: fprintf(f, "illum 7\nNi %.9g\n", (double)m->ior); break;
    case MAT_ROUGH_DIELECTRIC: fprintf(f, "illum 7\nNi %.9g\nPr %.9g\n", (double)m->ior, (double)m->roughness); break;
    }
    fputc('\n', f);
}

static void write_mtl(FILE *f, const scene *s)
{
    size_t i;
    fprintf(f, "# restir generated materials\n");
    for (i = 0; i < s->material_count; ++i) write_mtl_material(f, &s->materials[i]);
}

static void write_vertex_ref(FILE *f, const triangle *t, int k)
{
    if (t->n[0] >= 0 && t->n[1] >= 0 && t->n[2] >= 0)
        fprintf(f, " %u//%d", t->v[k] + 1, t->n[k] + 1);
    else
        fprintf(f, " %u", t->v[k] + 1);
}

/* Every OBJ_PROGRESS_LINES lines of vertices, normals and faces: a progress step. */
#define OBJ_PROGRESS_LINES 4096

/* Returns nonzero if the progress callback asked to stop (the file is then incomplete). */
static int write_obj(FILE *f, const scene *s, const char *mtl_name, const generate_progress *p)
{
    size_t i;
    uint32_t object = UINT32_MAX, mat = UINT32_MAX;
    const long lines = (long)(s->position_count + s->normal_count + s->triangle_count);
    const long before_faces = (long)(s->position_count + s->normal_count);
    fprintf(f, "# restir generated scene: %s\n# %zu vertices, %zu triangles\nmtllib %s\n", s->path,
            s->position_count, s->triangle_count, mtl_name);
    /* %.9g round-trips every float exactly. */
    for (i = 0; i < s->position_count; ++i) {
        if (i % OBJ_PROGRESS_LINES == 0 && report(p, "writing OBJ", (long)i, lines)) return 1;
        fprintf(f, "v %.9g %.9g %.9g\n", (double)s->positions[i].x, (double)s->positions[i].y,
                (double)s->positions[i].z);
    }
    for (i = 0; i < s->normal_count; ++i)
        fprintf(f, "vn %.9g %.9g %.9g\n", (double)s->normals[i].x, (double)s->normals[i].y, (double)s->normals[i].z);
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle *t = &s->triangles[i];
        if (i % OBJ_PROGRESS_LINES == 0 && report(p, "writing OBJ", before_faces + (long)i, lines)) return 1;
        if (t->object != object && t->object < s->object_count) {
            object = t->object;
            fprintf(f, "o %s\n", s->object_names[object]);
        }
        if (t->material != mat && t->material < s->material_count) {
            mat = t->material;
            fprintf(f, "usemtl %s\n", s->materials[mat].name);
        }
        fputc('f', f);
        write_vertex_ref(f, t, 0);
        write_vertex_ref(f, t, 1);
        write_vertex_ref(f, t, 2);
        fputc('\n', f);
    }
    return report(p, "writing OBJ", lines, lines);
}

int generate_write_obj(const scene *s, const char *path, rerror *e) { return generate_write_obj_progress(s, path, NULL, e); }

int generate_write_obj_progress(const scene *s, const char *path, const generate_progress *p, rerror *e)
{
    char mtl_path[4200];
    const char *mtl_name;
    atomic_file obj, mtl;
    mtl_path_for(path, mtl_path, sizeof mtl_path);
    mtl_name = strrchr(mtl_path, '/') ? strrchr(mtl_path, '/') + 1 : mtl_path;
    if (atomic_file_open(&mtl, mtl_path, e)) return -1;
    write_mtl(mtl.fp, s);
    if (atomic_file_open(&obj, path, e)) {
        atomic_file_abort(&mtl);
        return -1;
    }
    if (write_obj(obj.fp, s, mtl_name, p)) {
        atomic_file_abort(&obj);
        atomic_file_abort(&mtl);
        return rerror_at(e, path, 0, "cancelled");
    }
    if (atomic_file_commit(&mtl, e)) {
        atomic_file_abort(&obj);
        return -1;
    }
    return atomic_file_commit(&obj, e);
}
