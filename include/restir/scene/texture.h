/* Image textures of MTL materials (src/scene/texture.c; docs/materials.md, "Textures"):
 * loading through the image readers with the documented decode rule, and the reference
 * lookup (bilinear at full resolution, repeat wrap) that a GPU's LOD/filtering
 * approximates. */
#ifndef RESTIR_SCENE_TEXTURE_H
#define RESTIR_SCENE_TEXTURE_H

#include "restir/core/error.h"
#include "restir/core/vec.h"
#include "restir/core/warp.h"

/* What a map feeds, which decides how its file is decoded and which channels it keeps. */
enum texture_kind {
    TEXTURE_COLOUR = 0,     /* map_Kd, map_Ke: RGB; PNG sRGB-decoded; grey -> R = G = B */
    TEXTURE_SCALAR = 1,     /* map_Pr, map_Ns: the first channel (R or Y); PNG linear */
    TEXTURE_ALPHA = 2       /* map_d: the alpha channel if the file has one, else the first; PNG linear */
};

typedef struct {
    char path[4096];
    enum texture_kind kind;
    int width, height, channels; /* channels: 3 for TEXTURE_COLOUR, 1 otherwise */
    float *px;                   /* linear values, row 0 = the top row (v = 1) */
} scene_texture;

/* Reads path (.png, .exr, else PFM) as a map of the given kind. Errors "path: what". */
int texture_load(scene_texture *t, const char *path, enum texture_kind kind, rerror *e);
void texture_free(scene_texture *t);
/* A deep copy (for scene_clone). */
int texture_copy(scene_texture *dst, const scene_texture *src, rerror *e);

/* The reference lookup: bilinear between the four texels around (u, v) at full
 * resolution, texel (i, j) centred at ((i + 0.5)/W, 1 - (j + 0.5)/H), repeat wrap on both
 * axes (u and u + 1 are the same point); non-finite coordinates read as 0. */
rgb texture_rgb(const scene_texture *t, vec2 uv);
/* The single channel of a scalar or alpha map (the first channel of any map). */
real texture_scalar(const scene_texture *t, vec2 uv);

#endif
