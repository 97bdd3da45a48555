/* The scene: what the papers' scenes require and nothing more (docs/scenes.md).
 * Triangles with optional per-vertex shading normals, materials from MTL (or
 * scene-file overrides), object ids from OBJ o/g, a pinhole camera with optional
 * per-frame keyframes, and an image size. */
#ifndef RESTIR_SCENE_H
#define RESTIR_SCENE_H

#include <stddef.h>
#include <stdint.h>
#include "restir/core/error.h"
#include "restir/core/vec.h"
#include "restir/scene/bvh.h"
#include "restir/scene/texture.h"

enum material_type {
    MAT_LAMBERT = 0,         /* diffuse Kd */
    MAT_CONDUCTOR = 1,       /* GGX conductor, F0 = Ks */
    MAT_PLASTIC = 2,         /* diffuse Kd + GGX dielectric coat (ior Ni), two lobes */
    MAT_DIELECTRIC = 3,      /* smooth glass: delta reflection + delta refraction (ior Ni) */
    MAT_ROUGH_DIELECTRIC = 4 /* Walter et al. 2007 rough glass (ior Ni) */
};
#define MATERIAL_TYPE_COUNT 5
/* The scene file's names, index = enum material_type: "lambert", "conductor", "plastic",
 * "dielectric", "rough-dielectric"; NULL-terminated (src/scene/scene_file.c). */
extern const char *const material_type_names[];

#define MATERIAL_NAME_MAX 128

typedef struct {
    char name[MATERIAL_NAME_MAX];
    enum material_type type;
    rgb diffuse;    /* Kd: Lambertian albedo (Lambert, plastic base) */
    rgb specular;   /* Ks: conductor F0, or plastic/dielectric specular tint */
    rgb emission;   /* Ke: radiance emitted from the front face */
    real roughness; /* linear (perceptual) roughness r in [0,1]; GGX alpha = r*r */
    real ior;       /* Ni: index of refraction (dielectric, plastic coat) */
    /* Image maps (docs/materials.md, "Textures"): 1 + an index into scene.textures, 0 = none
     * (so a zeroed material is untextured). */
    uint32_t map_kd;          /* multiplies Kd (or Ks where the base colour is F0: map_kd_is_f0) */
    uint32_t map_roughness;   /* map_Pr (r = roughness_map_scale * t) or map_Ns (see roughness_from_ns) */
    uint32_t map_alpha;       /* map_d: a cut-out, the surface is absent where alpha < 0.5 */
    uint32_t map_ke;          /* multiplies Ke */
    int map_kd_is_f0;         /* the PBR metal rule: the base colour map tints Ks */
    int roughness_from_ns;    /* map_roughness is map_Ns: r = roughness_from_phong_exponent(scale * t) */
    real roughness_map_scale; /* Pr or Ns multiplying the map's value */
} material;

typedef struct {
    uint32_t v[3];     /* indices into scene.positions (front face: counter-clockwise) */
    int32_t n[3];      /* indices into scene.normals, or -1 (then the face normal is used) */
    int32_t t[3];      /* indices into scene.texcoords, or -1 (then the UV is (0, 0)) */
    uint32_t material; /* index into scene.materials */
    uint32_t object;   /* index into scene.object_names */
} triangle;

typedef struct {
    vec3 eye, target, up;
    real fov_y_degrees; /* vertical field of view */
} camera_pose;

typedef struct {
    int frame;          /* frame index at which this pose holds exactly */
    camera_pose pose;   /* poses between keyframes are linearly interpolated */
} camera_keyframe;

typedef struct {
    char path[4096]; /* the file the scene came from (scene file or bare OBJ) */

    vec3f *positions;
    size_t position_count;
    vec3f *normals;
    size_t normal_count;
    float (*texcoords)[2]; /* OBJ vt: (u, v) */
    size_t texcoord_count;
    triangle *triangles;
    size_t triangle_count;
    material *materials;
    size_t material_count;
    char **object_names;
    size_t object_count;

    camera_pose camera;
    int has_camera;      /* 0: frame the bounding box (bare OBJ) */
    camera_keyframe *keyframes;
    size_t keyframe_count;
    int width, height;

    /* Rigid per-object animation and the rest pose (restir/scene/animation.h); NULL: static. */
    struct scene_animation *animation;

    /* The image maps materials refer to (restir/scene/texture.h). has_cutouts: some
     * material has map_d, so ray queries run the alpha test (scene_trace.c). */
    scene_texture *textures;
    size_t texture_count;
    int has_cutouts;

    /* Distant lights: environment and sun (restir/scene/sky.h); NULL: none. */
    struct scene_sky *sky;

    /* Load-time warnings, each one line "file:line: what" (undefined materials, ignored
     * transparency, dropped degenerate triangles, ...). The library never prints them. */
    char **warnings;
    size_t warning_count;

    /* Built by scene_prepare(): */
    bvh accel;
    vec3f bounds_min, bounds_max;
    vec3f *face_normals; /* per triangle: its unit face normal, so hits need not recompute it */
} scene;

/* Loads a .scene file or a bare .obj (then the camera frames the bounding box
 * and the image is 512x512). All errors are "file:line: what is wrong". */
int scene_load(scene *s, const char *path, rerror *e);

typedef struct {
    int allow_missing_mtl; /* a material library, or a map file of one (map_Kd ...), that cannot be
                            * opened or decoded is a warning (the map is then ignored), not an error */
} scene_load_options;

/* scene_load with options (NULL = defaults, which is what scene_load uses). */
int scene_load_with_options(scene *s, const char *path, const scene_load_options *options, rerror *e);
/* Number of triangles whose material has nonzero emission. */
size_t scene_emitter_count(const scene *s);

/* Builds the BVH and bounds; fails on an empty scene. */
int scene_prepare(scene *s, rerror *e);
void scene_free(scene *s);

/* Camera pose at a frame (keyframes interpolated; the static camera otherwise). */
camera_pose scene_camera_at(const scene *s, int frame);
/* Places the camera to see the whole bounding box (used for bare OBJ files): looks at
 * the centre of the triangles' bounding box from the +z side, up +y, vertical fov 40
 * degrees, at the distance where the bounding sphere fits the narrower field of view. */
camera_pose scene_frame_bounds(const scene *s);

/* A surface point found by a ray. Normals are unit length. ng is the true face
 * normal (v1-v0)x(v2-v0) normalised: it decides the front face (emission). ns is
 * the interpolated shading normal (= ng when the mesh has none). */
typedef struct {
    vec3f position;
    vec3f ng;
    vec3f ns;
    float t;
    float b1, b2;       /* barycentrics of v1 and v2 */
    uint32_t triangle;  /* index into scene.triangles */
    uint32_t material;
    uint32_t object;
} surface_hit;

#endif
