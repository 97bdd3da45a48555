/* Wavefront OBJ reader: the polygonal subset (v, vn, vt, f, o, g, usemtl, mtllib),
 * with every statement of the OBJ specification either read, explicitly ignored, or
 * rejected with "file:line: what is wrong". See docs/scene-format.md. */
#include "restir/scene/obj.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/camera_path.h"
#include "restir/scene/mtl.h"
#include "restir/scene/scene_builder.h"
#include "restir/scene/text.h"
#include "restir/scene/triangulate.h"

#define OBJ_MAX_FACE_CORNERS 16384

typedef struct {
    scene_builder *b;
    text_reader text;
    const char *path;
    char dir[4096];
    size_t position_base, normal_base, texcoord_base;

    char *object_name;       /* current o/g name (owned), "default" before any */
    int object_resolved;     /* object_id is valid for object_name */
    uint32_t object_id;
    char material_name[MATERIAL_NAME_MAX];
    int material_explicit;   /* set by a usemtl (not the implicit "default") */
    long material_line;      /* line of that usemtl */
    int material_resolved;
    uint32_t material_id;

    /* One face: position index, normal and texture coordinate index (-1 = none) and
     * position per corner. */
    uint32_t *face_position;
    int32_t *face_normal;
    int32_t *face_texcoord;
    vec3f *face_corner;
    uint32_t *face_triangles;
    size_t face_capacity;
    triangulator triangulator;
    size_t zero_normal_triangles;
    long first_zero_normal_line;
} obj_parser;

/* Statements of the OBJ specification that describe nothing we render: display and
 * render attributes, points and lines (no area), free-form curves and their
 * parameters. They are accepted and skipped. */
static const char *const ignored_statements[] = {
    "s", "l", "p", "mg", "lod", "bevel", "c_interp", "d_interp", "shadow_obj", "trace_obj", "maplib", "usemap",
    "ctech", "stech", "vp", "cstype", "deg", "bmat", "step", "curv", "curv2", "parm", "trim", "hole", "scrv", "sp",
    "end", "con", NULL};

static int is_ignored_statement(const char *keyword)
{
    const char *const *k;
    for (k = ignored_statements; *k; ++k)
        if (!strcmp(*k, keyword)) return 1;
    return 0;
}

/* Prefixes the message already in e (from a helper that knows no line) with file:line. */
static int at_line(obj_parser *o, rerror *e)
{
    char msg[sizeof e->msg];
    memcpy(msg, e->msg, sizeof msg);
    return rerror_at(e, o->path, o->text.line, "%s", msg);
}

/* Reads count_min..count_max numbers; the first `keep` go to out (as float). */
static int parse_numbers(obj_parser *o, char *rest, const char *keyword, int count_min, int count_max, float *out,
                         int keep, rerror *e)
{
    int n = 0;
    char *tok;
    while ((tok = text_next_token(&rest)) != NULL) {
        float v;
        enum number_status st = text_parse_float(tok, &v);
        if (st != NUMBER_OK)
            return rerror_at(e, o->path, o->text.line, "%s: %s '%s'", keyword, text_number_problem(st), tok);
        if (n >= count_max)
            return rerror_at(e, o->path, o->text.line, "%s: more than %d numbers", keyword, count_max);
        if (n < keep) out[n] = v;
        n++;
    }
    if (n < count_min)
        return rerror_at(e, o->path, o->text.line, "%s: expected at least %d numbers, found %d", keyword, count_min, n);
    return 0;
}

static int read_vertex(obj_parser *o, char *rest, rerror *e)
{
    float xyz[3];
    /* x y z, optionally w (rational curves) or r g b [a] (a common vertex-colour extension). */
    int i;
    if (parse_numbers(o, rest, "v", 3, 7, xyz, 3, e)) return -1;
    for (i = 0; i < 3; ++i) /* float geometry multiplies three coordinates (camera_path.h) */
        if (!(fabs(xyz[i]) <= SCENE_COORD_MAX))
            return rerror_at(e, o->path, o->text.line, "v: %g is out of range (|coordinate| <= %g: float geometry)",
                             (double)xyz[i], SCENE_COORD_MAX);
    return builder_add_position(o->b, v3f(xyz[0], xyz[1], xyz[2]), e) ? at_line(o, e) : 0;
}

static int read_normal(obj_parser *o, char *rest, rerror *e)
{
    float xyz[3];
    double x, y, z, len;
    if (parse_numbers(o, rest, "vn", 3, 3, xyz, 3, e)) return -1;
    /* Stored unit length (in double, so huge components do not overflow); a zero
     * normal stays zero and the triangles that use it fall back to the face normal. */
    x = xyz[0];
    y = xyz[1];
    z = xyz[2];
    len = sqrt(x * x + y * y + z * z);
    if (len > 0) x /= len, y /= len, z /= len;
    return builder_add_normal(o->b, v3f((float)x, (float)y, (float)z), e) ? at_line(o, e) : 0;
}

static int read_texcoord(obj_parser *o, char *rest, rerror *e)
{
    float uvw[3] = {0, 0, 0};
    /* u [v [w]]: v defaults to 0 (OBJ specification); w (3-D textures) is not used. */
    if (parse_numbers(o, rest, "vt", 1, 3, uvw, 2, e)) return -1;
    return builder_add_texcoord(o->b, uvw[0], uvw[1], e) ? at_line(o, e) : 0;
}

/* OBJ index (1-based, or negative = relative to the last defined element) -> 0-based
 * index among the `count` elements this file has defined so far. */
static int resolve_index(obj_parser *o, long index, size_t count, const char *what, size_t *out, rerror *e)
{
    if (index == 0)
        return rerror_at(e, o->path, o->text.line, "%s index 0 is invalid (OBJ indices start at 1)", what);
    if (index > 0) {
        if ((size_t)index > count)
            return rerror_at(e, o->path, o->text.line, "%s index %ld out of range (%zu defined so far)", what, index,
                             count);
        *out = (size_t)index - 1;
        return 0;
    }
    if ((size_t)(-index) > count)
        return rerror_at(e, o->path, o->text.line,
                         "relative %s index %ld reaches before the first one (%zu defined so far)", what, index,
                         count);
    *out = count - (size_t)(-index);
    return 0;
}

static int parse_index(obj_parser *o, const char **p, const char *token, long *index, rerror *e)
{
    enum number_status st = text_parse_long(*p, p, index);
    if (st == NUMBER_OUT_OF_RANGE)
        return rerror_at(e, o->path, o->text.line, "index out of range in face vertex '%s'", token);
    if (st != NUMBER_OK) return rerror_at(e, o->path, o->text.line, "malformed face vertex '%s'", token);
    return 0;
}

/* One face corner: v, v/vt, v//vn or v/vt/vn. */
static int read_face_vertex(obj_parser *o, const char *token, uint32_t *position, int32_t *normal,
                            int32_t *texcoord, rerror *e)
{
    scene *s = o->b->s;
    const char *p = token;
    long index;
    size_t resolved;
    *normal = -1;
    *texcoord = -1;
    if (parse_index(o, &p, token, &index, e) ||
        resolve_index(o, index, s->position_count - o->position_base, "vertex", &resolved, e))
        return -1;
    *position = (uint32_t)(o->position_base + resolved);
    if (*p == '/') {
        p++;
        if (*p != '/') {
            if (parse_index(o, &p, token, &index, e) ||
                resolve_index(o, index, s->texcoord_count - o->texcoord_base, "texture coordinate", &resolved, e))
                return -1;
            *texcoord = (int32_t)(o->texcoord_base + resolved);
        }
        if (*p == '/') {
            p++;
            if (parse_index(o, &p, token, &index, e) ||
                resolve_index(o, index, s->normal_count - o->normal_base, "normal", &resolved, e))
                return -1;
            *normal = (int32_t)(o->normal_base + resolved);
        }
    }
    if (*p) return rerror_at(e, o->path, o->text.line, "malformed face vertex '%s'", token);
    return 0;
}

static int current_ids(obj_parser *o, uint32_t *material, uint32_t *object, rerror *e)
{
    scene_builder *b = o->b;
    if (!o->object_resolved) {
        if (builder_object(b, o->object_name, &o->object_id, e)) return at_line(o, e);
        o->object_resolved = 1;
    }
    if (!o->material_resolved) {
        if (builder_material(b, o->material_name, &o->material_id, e)) return at_line(o, e);
        /* Remember where an undefined material was first used, for the warning. */
        if (o->material_explicit && b->material_origin[o->material_id] == MATERIAL_UNDEFINED &&
            !b->material_first_use[o->material_id]) {
            char where[4200];
            size_t n;
            snprintf(where, sizeof where, "%s:%ld", o->path, o->material_line);
            n = strlen(where);
            b->material_first_use[o->material_id] = rmalloc(n + 1, 1, e);
            if (!b->material_first_use[o->material_id]) return -1;
            memcpy(b->material_first_use[o->material_id], where, n + 1);
        }
        o->material_resolved = 1;
    }
    *material = o->material_id;
    *object = o->object_id;
    return 0;
}

/* Room for n corners in the per-face scratch arrays (doubling). */
static int face_reserve(obj_parser *o, size_t n, rerror *e)
{
    size_t cap = o->face_capacity ? o->face_capacity : 16, c1, c2, c3, c4, c5;
    if (n <= o->face_capacity) return 0;
    while (cap < n) cap *= 2;
    c1 = c2 = c3 = c5 = o->face_capacity;
    c4 = 3 * o->face_capacity;
    if (builder_reserve((void **)&o->face_position, &c1, cap, sizeof *o->face_position, e) ||
        builder_reserve((void **)&o->face_normal, &c2, cap, sizeof *o->face_normal, e) ||
        builder_reserve((void **)&o->face_texcoord, &c5, cap, sizeof *o->face_texcoord, e) ||
        builder_reserve((void **)&o->face_corner, &c3, cap, sizeof *o->face_corner, e) ||
        builder_reserve((void **)&o->face_triangles, &c4, 3 * cap, sizeof *o->face_triangles, e))
        return -1;
    o->face_capacity = cap;
    return 0;
}

/* A triangle of face corners i, j, k; its shading normals only if all three have one, and
 * likewise its texture coordinates. */
static int emit_triangle(obj_parser *o, size_t i, size_t j, size_t k, uint32_t material, uint32_t object, rerror *e)
{
    scene *s = o->b->s;
    triangle t;
    size_t c[3];
    int m, has_normals = 1, has_texcoords = 1;
    c[0] = i;
    c[1] = j;
    c[2] = k;
    for (m = 0; m < 3; ++m) {
        int32_t n = o->face_normal[c[m]];
        t.v[m] = o->face_position[c[m]];
        t.n[m] = n;
        t.t[m] = o->face_texcoord[c[m]];
        if (t.t[m] < 0) has_texcoords = 0;
        if (n < 0) has_normals = 0;
        else if (s->normals[n].x == 0 && s->normals[n].y == 0 && s->normals[n].z == 0) {
            if (!o->zero_normal_triangles++) o->first_zero_normal_line = o->text.line;
            has_normals = 0;
        }
    }
    if (!has_normals) t.n[0] = t.n[1] = t.n[2] = -1;
    if (!has_texcoords) t.t[0] = t.t[1] = t.t[2] = -1;
    t.material = material;
    t.object = object;
    return builder_add_triangle(o->b, &t, e) ? at_line(o, e) : 0;
}

static int read_face(obj_parser *o, char *rest, rerror *e)
{
    size_t n = 0, i, tri_count;
    char *tok;
    uint32_t material = 0, object = 0;
    while ((tok = text_next_token(&rest)) != NULL) {
        /* Ear clipping is quadratic in n: a hostile n-gon of 10^5 corners takes 30 s. */
        if (n == OBJ_MAX_FACE_CORNERS)
            return rerror_at(e, o->path, o->text.line, "face with more than %d corners", OBJ_MAX_FACE_CORNERS);
        if (face_reserve(o, n + 1, e)) return at_line(o, e);
        if (read_face_vertex(o, tok, &o->face_position[n], &o->face_normal[n], &o->face_texcoord[n], e)) return -1;
        n++;
    }
    if (n < 3) return rerror_at(e, o->path, o->text.line, "face with %zu vertices (at least 3 are needed)", n);
    if (current_ids(o, &material, &object, e)) return -1;
    if (n == 3) return emit_triangle(o, 0, 1, 2, material, object, e);
    for (i = 0; i < n; ++i) o->face_corner[i] = o->b->s->positions[o->face_position[i]];
    if (triangulate_polygon(&o->triangulator, o->face_corner, n, o->face_triangles, &tri_count, e)) return at_line(o, e);
    for (i = 0; i < tri_count; ++i)
        if (emit_triangle(o, o->face_triangles[3 * i], o->face_triangles[3 * i + 1], o->face_triangles[3 * i + 2],
                          material, object, e))
            return -1;
    /* Corners that triangulation dropped (collinear, repeated) count as degenerate. */
    if (tri_count < n - 2) o->b->degenerate_triangles += n - 2 - tri_count;
    return 0;
}

static int set_object(obj_parser *o, char *rest, rerror *e)
{
    const char *name = text_rest(rest);
    size_t len;
    char *copy;
    if (!*name) name = "default";
    len = strlen(name);
    if (o->object_name && !strcmp(o->object_name, name)) return 0;
    copy = rmalloc(len + 1, 1, e);
    if (!copy) return at_line(o, e);
    memcpy(copy, name, len + 1);
    free(o->object_name);
    o->object_name = copy;
    o->object_resolved = 0;
    return 0;
}

static int set_material(obj_parser *o, char *rest, rerror *e)
{
    const char *name = text_rest(rest);
    if (strlen(name) >= MATERIAL_NAME_MAX)
        return rerror_at(e, o->path, o->text.line, "usemtl: material name longer than %d bytes",
                         MATERIAL_NAME_MAX - 1);
    if (o->material_explicit && !strcmp(o->material_name, name)) return 0;
    snprintf(o->material_name, sizeof o->material_name, "%s", name);
    o->material_explicit = 1;
    o->material_line = o->text.line;
    o->material_resolved = 0;
    return 0;
}

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    fclose(f);
    return 1;
}

static int load_library(obj_parser *o, const char *name, rerror *e)
{
    char path[4096];
    if (text_join_path(path, sizeof path, o->dir, name))
        return rerror_at(e, o->path, o->text.line, "mtllib: path too long");
    if (!file_exists(path)) {
        if (o->b->options.allow_missing_mtl)
            return builder_warn(o->b, o->path, o->text.line, "cannot open material library '%s' (ignored)", name)
                       ? rerror_set(e, "out of memory")
                       : 0;
        return rerror_at(e, o->path, o->text.line, "cannot open material library '%s' (looked for %s)", name, path);
    }
    return mtl_load(o->b, path, e);
}

/* mtllib names one or more files. A name may contain spaces: if the whole rest of
 * the line names an existing file it is that one file; otherwise the names are split
 * at whitespace, where "\ " is an escaped space. */
static int read_mtllib(obj_parser *o, char *rest, rerror *e)
{
    char *line = text_rest(rest), *name, *out, *p;
    char whole[4096];
    if (!*line) return rerror_at(e, o->path, o->text.line, "mtllib without a file name");
    if (!text_join_path(whole, sizeof whole, o->dir, line) && file_exists(whole)) return load_library(o, line, e);
    p = line;
    while (*p) {
        while (text_is_space((unsigned char)*p)) p++;
        if (!*p) break;
        name = out = p;
        while (*p && !text_is_space((unsigned char)*p)) {
            if (*p == '\\' && p[1] == ' ') p++;
            *out++ = *p++;
        }
        if (*p) p++;
        *out = '\0';
        if (load_library(o, name, e)) return -1;
    }
    return 0;
}

static int read_statement(obj_parser *o, char *line, rerror *e)
{
    char *rest = line, *keyword = text_next_token(&rest);
    if (!keyword) return 0;
    if (keyword[0] == 'v' && keyword[1] == '\0') return read_vertex(o, rest, e);
    if (keyword[0] == 'f' && keyword[1] == '\0') return read_face(o, rest, e);
    if (!strcmp(keyword, "vn")) return read_normal(o, rest, e);
    if (!strcmp(keyword, "vt")) return read_texcoord(o, rest, e);
    if (!strcmp(keyword, "o") || !strcmp(keyword, "g")) return set_object(o, rest, e);
    if (!strcmp(keyword, "usemtl")) return set_material(o, rest, e);
    if (!strcmp(keyword, "mtllib")) return read_mtllib(o, rest, e);
    if (is_ignored_statement(keyword)) return 0;
    if (!strcmp(keyword, "surf"))
        return rerror_at(e, o->path, o->text.line, "free-form surfaces ('surf') are not supported; export polygons");
    if (!strcmp(keyword, "call") || !strcmp(keyword, "csh"))
        return rerror_at(e, o->path, o->text.line, "'%s' (including files, running commands) is not supported", keyword);
    return rerror_at(e, o->path, o->text.line, "unknown OBJ statement '%.60s'", keyword);
}

static void parser_free(obj_parser *o)
{
    text_close(&o->text);
    free(o->object_name);
    free(o->face_position);
    free(o->face_normal);
    free(o->face_texcoord);
    free(o->face_corner);
    free(o->face_triangles);
    triangulator_free(&o->triangulator);
}

int obj_load(scene_builder *b, const char *path, rerror *e)
{
    obj_parser o;
    char *line, no_name[1] = "";
    int status = 0;
    memset(&o, 0, sizeof o);
    o.b = b;
    o.path = path;
    text_directory_of(path, o.dir, sizeof o.dir);
    o.position_base = b->s->position_count;
    o.normal_base = b->s->normal_count;
    o.texcoord_base = b->s->texcoord_count;
    snprintf(o.material_name, sizeof o.material_name, "default");
    if (text_open(&o.text, path, e)) return -1;
    if (set_object(&o, no_name, e)) status = -1;
    while (!status && (line = text_next_line(&o.text)) != NULL) status = read_statement(&o, line, e);
    if (!status && o.zero_normal_triangles &&
        builder_warn(b, path, o.first_zero_normal_line,
                     "%zu triangles use a zero-length normal (vn 0 0 0); they are shaded with the face normal",
                     o.zero_normal_triangles))
        status = rerror_set(e, "out of memory");
    parser_free(&o);
    return status;
}
