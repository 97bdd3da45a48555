/* Growing a scene while its files are parsed (see scene_builder.h). */
#include "restir/scene/scene_builder.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

material material_default(const char *name)
{
    material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.type = MAT_LAMBERT;
    m.diffuse = rgb_gray((real)0.8);
    m.specular = rgb_gray(0);
    m.emission = rgb_gray(0);
    m.roughness = (real)0.5;
    m.ior = (real)1.5;
    return m;
}

int builder_reserve(void **array, size_t *capacity, size_t need, size_t elem_size, rerror *e)
{
    size_t cap = *capacity ? *capacity : 16;
    void *p;
    if (need <= *capacity) return 0;
    while (cap < need) {
        if (cap > ((size_t)-1) / 2 / elem_size) return rerror_set(e, "out of memory (array of %zu elements)", need);
        cap *= 2;
    }
    p = realloc(*array, cap * elem_size);
    if (!p) return rerror_set(e, "out of memory (%zu bytes)", cap * elem_size);
    *array = p;
    *capacity = cap;
    return 0;
}

int builder_init(scene_builder *b, scene *s, const scene_load_options *options, rerror *e)
{
    (void)e;
    memset(b, 0, sizeof *b);
    b->s = s;
    if (options) b->options = *options;
    return 0;
}

void builder_finish(scene_builder *b)
{
    size_t i;
    name_table_free(&b->material_names);
    name_table_free(&b->object_names);
    name_table_free(&b->libraries);
    if (b->material_first_use)
        for (i = 0; i < b->s->material_count; ++i) free(b->material_first_use[i]);
    free(b->material_first_use);
    free(b->material_origin);
    b->material_first_use = NULL;
    b->material_origin = NULL;
}

static char *format_line(const char *file, long line, const char *fmt, va_list ap)
{
    char msg[1024];
    int n = line > 0 ? snprintf(msg, sizeof msg, "%s:%ld: ", file, line) : snprintf(msg, sizeof msg, "%s: ", file);
    size_t len;
    char *copy;
    if (n < 0 || (size_t)n >= sizeof msg) n = 0;
    vsnprintf(msg + n, sizeof msg - (size_t)n, fmt, ap);
    len = strlen(msg);
    copy = malloc(len + 1);
    if (copy) memcpy(copy, msg, len + 1);
    return copy;
}

int builder_warn(scene_builder *b, const char *file, long line, const char *fmt, ...)
{
    scene *s = b->s;
    va_list ap;
    char *msg;
    if (s->warning_count >= SCENE_MAX_WARNINGS) {
        b->suppressed_warnings++;
        return 0;
    }
    if (builder_reserve((void **)&s->warnings, &b->warning_capacity, s->warning_count + 1, sizeof *s->warnings, NULL))
        return -1;
    va_start(ap, fmt);
    msg = format_line(file, line, fmt, ap);
    va_end(ap);
    if (!msg) return -1;
    s->warnings[s->warning_count++] = msg;
    return 0;
}

int builder_material(scene_builder *b, const char *name, uint32_t *index, rerror *e)
{
    scene *s = b->s;
    long found = name_table_find(&b->material_names, name);
    size_t cap_origin, cap_use;
    if (found >= 0) {
        *index = (uint32_t)found;
        return 0;
    }
    if (strlen(name) >= MATERIAL_NAME_MAX)
        return rerror_set(e, "material name longer than %d bytes: '%.40s...'", MATERIAL_NAME_MAX - 1, name);
    cap_origin = cap_use = b->material_capacity;
    if (builder_reserve((void **)&s->materials, &b->material_capacity, s->material_count + 1, sizeof *s->materials, e) ||
        builder_reserve((void **)&b->material_origin, &cap_origin, b->material_capacity, 1, e) ||
        builder_reserve((void **)&b->material_first_use, &cap_use, b->material_capacity, sizeof(char *), e))
        return -1;
    if (name_table_insert(&b->material_names, name, (uint32_t)s->material_count, e)) return -1;
    s->materials[s->material_count] = material_default(name);
    b->material_origin[s->material_count] = MATERIAL_UNDEFINED;
    b->material_first_use[s->material_count] = NULL;
    *index = (uint32_t)s->material_count++;
    return 0;
}

int builder_object(scene_builder *b, const char *name, uint32_t *index, rerror *e)
{
    scene *s = b->s;
    long found = name_table_find(&b->object_names, name);
    size_t len = strlen(name);
    char *copy;
    if (found >= 0) {
        *index = (uint32_t)found;
        return 0;
    }
    if (builder_reserve((void **)&s->object_names, &b->object_capacity, s->object_count + 1, sizeof(char *), e))
        return -1;
    copy = rmalloc(len + 1, 1, e);
    if (!copy) return -1;
    memcpy(copy, name, len + 1);
    if (name_table_insert(&b->object_names, name, (uint32_t)s->object_count, e)) {
        free(copy);
        return -1;
    }
    s->object_names[s->object_count] = copy;
    *index = (uint32_t)s->object_count++;
    return 0;
}

int builder_add_position(scene_builder *b, vec3f p, rerror *e)
{
    scene *s = b->s;
    if (s->position_count >= UINT32_MAX) return rerror_set(e, "more than 2^32 - 1 vertices");
    if (s->position_count == b->position_capacity &&
        builder_reserve((void **)&s->positions, &b->position_capacity, s->position_count + 1, sizeof(vec3f), e))
        return -1;
    s->positions[s->position_count++] = p;
    return 0;
}

int builder_add_normal(scene_builder *b, vec3f n, rerror *e)
{
    scene *s = b->s;
    if (s->normal_count >= INT32_MAX) return rerror_set(e, "more than 2^31 - 1 normals");
    if (s->normal_count == b->normal_capacity &&
        builder_reserve((void **)&s->normals, &b->normal_capacity, s->normal_count + 1, sizeof(vec3f), e))
        return -1;
    s->normals[s->normal_count++] = n;
    return 0;
}

int builder_add_texcoord(scene_builder *b, float u, float v, rerror *e)
{
    scene *s = b->s;
    if (s->texcoord_count >= INT32_MAX) return rerror_set(e, "more than 2^31 - 1 texture coordinates");
    if (s->texcoord_count == b->texcoord_capacity &&
        builder_reserve((void **)&s->texcoords, &b->texcoord_capacity, s->texcoord_count + 1, sizeof *s->texcoords, e))
        return -1;
    s->texcoords[s->texcoord_count][0] = u;
    s->texcoords[s->texcoord_count][1] = v;
    s->texcoord_count++;
    return 0;
}

int builder_texture(scene_builder *b, const char *path, enum texture_kind kind, uint32_t *map, rerror *e)
{
    scene *s = b->s;
    size_t i;
    for (i = 0; i < s->texture_count; ++i)
        if (s->textures[i].kind == kind && !strcmp(s->textures[i].path, path)) {
            *map = (uint32_t)i + 1;
            return 0;
        }
    if (s->texture_count == b->texture_capacity &&
        builder_reserve((void **)&s->textures, &b->texture_capacity, s->texture_count + 1, sizeof *s->textures, e))
        return -1;
    if (texture_load(&s->textures[s->texture_count], path, kind, e)) return -1;
    *map = (uint32_t)++s->texture_count;
    return 0;
}

int builder_add_triangle(scene_builder *b, const triangle *t, rerror *e)
{
    scene *s = b->s;
    vec3f p0 = s->positions[t->v[0]], p1 = s->positions[t->v[1]], p2 = s->positions[t->v[2]];
    /* The face normal (v1-v0)x(v2-v0) in double (as the ray queries compute it): if it is
     * zero the triangle has no front face, no area to hit and none to sample. Tiny but
     * nonzero triangles stay. */
    double ax = (double)p1.x - p0.x, ay = (double)p1.y - p0.y, az = (double)p1.z - p0.z;
    double bx = (double)p2.x - p0.x, by = (double)p2.y - p0.y, bz = (double)p2.z - p0.z;
    double nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    double len2 = nx * nx + ny * ny + nz * nz;
    if (!(len2 > 0) || !isfinite(len2)) {
        b->degenerate_triangles++;
        return 0;
    }
    if (s->triangle_count >= UINT32_MAX) return rerror_set(e, "more than 2^32 - 1 triangles");
    if (s->triangle_count == b->triangle_capacity &&
        builder_reserve((void **)&s->triangles, &b->triangle_capacity, s->triangle_count + 1, sizeof(triangle), e))
        return -1;
    s->triangles[s->triangle_count++] = *t;
    return 0;
}
