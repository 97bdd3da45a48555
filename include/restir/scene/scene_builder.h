/* The state shared by the OBJ, MTL and scene-file parsers while one scene is loaded:
 * growable arrays of the scene, the name tables for materials and objects, and the
 * warning list. Internal to src/scene (tests use it too). */
#ifndef RESTIR_SCENE_BUILDER_H
#define RESTIR_SCENE_BUILDER_H

#include "restir/scene/name_table.h"
#include "restir/scene/scene.h"

/* Where a material's values came from. */
enum material_origin {
    MATERIAL_UNDEFINED = 0, /* referenced by usemtl (or implicitly) but not defined yet */
    MATERIAL_FROM_MTL = 1,  /* newmtl in a material library */
    MATERIAL_FROM_SCENE = 2 /* created by a `material` line of the scene file */
};

#define SCENE_MAX_WARNINGS 100

typedef struct {
    scene *s;
    size_t position_capacity, normal_capacity, texcoord_capacity, triangle_capacity, texture_capacity;
    size_t material_capacity, object_capacity, warning_capacity;
    name_table material_names, object_names, libraries;
    unsigned char *material_origin;  /* per material: enum material_origin */
    char **material_first_use;       /* per material: "file:line" of the first usemtl naming it, or NULL */
    size_t suppressed_warnings;
    size_t degenerate_triangles;     /* dropped: zero face normal */
    scene_load_options options;
} scene_builder;

/* The material used when none is defined: Lambertian, Kd 0.8. */
material material_default(const char *name);

int builder_init(scene_builder *b, scene *s, const scene_load_options *options, rerror *e);
/* Frees the builder's own tables (not the scene). */
void builder_finish(scene_builder *b);

/* Appends "file:line: message" (line <= 0: "file: message") to s->warnings; after
 * SCENE_MAX_WARNINGS only a count is kept. Returns 0, or -1 when out of memory. */
int builder_warn(scene_builder *b, const char *file, long line, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* Index of the material with this name, created (undefined, default values) if new. */
int builder_material(scene_builder *b, const char *name, uint32_t *index, rerror *e);
/* Index of the object with this name, created if new. */
int builder_object(scene_builder *b, const char *name, uint32_t *index, rerror *e);

int builder_add_position(scene_builder *b, vec3f p, rerror *e);
int builder_add_normal(scene_builder *b, vec3f n, rerror *e);
int builder_add_texcoord(scene_builder *b, float u, float v, rerror *e);
/* The map (1 + index into s->textures) of the image at path read as `kind`; an image
 * already loaded as that kind is shared. Errors "path: what". */
int builder_texture(scene_builder *b, const char *path, enum texture_kind kind, uint32_t *map, rerror *e);
/* Appends the triangle unless its geometric normal (v1-v0)x(v2-v0), computed in double,
 * is zero (collinear or repeated corners), which only counts it as dropped. */
int builder_add_triangle(scene_builder *b, const triangle *t, rerror *e);

/* Grows *array (of elem_size elements, capacity *capacity) to hold at least need. */
int builder_reserve(void **array, size_t *capacity, size_t need, size_t elem_size, rerror *e);

#endif
