/* G-buffer channels as images. */
#include "restir/render/aov.h"

#include <string.h>
#include "restir/core/rng.h"
#include "restir/scene/surface_maps.h"

const char *const aov_names[] = {"normal", "albedo", "depth", "object", "motion", NULL};

static rgb material_albedo(const material *m)
{
    switch (m->type) {
    case MAT_CONDUCTOR:
    case MAT_DIELECTRIC:
    case MAT_ROUGH_DIELECTRIC:
        return m->specular;
    default:
        return m->diffuse;
    }
}

/* A stable colour per object id: three hashed channels, kept away from black. */
static rgb object_colour(uint32_t object)
{
    rng_key k = rng_key_make(0x0b1ec7u, object, 0);
    return rgb_make((real)0.2 + (real)0.8 * rng_u(k, RNG_TEST, 0, 0), (real)0.2 + (real)0.8 * rng_u(k, RNG_TEST, 0, 1),
                    (real)0.2 + (real)0.8 * rng_u(k, RNG_TEST, 0, 2));
}

static rgb texel_value(const gbuffer_texel *t, const scene *s, enum aov_kind kind)
{
    if (!t->valid) return rgb_gray(0);
    switch (kind) {
    case AOV_NORMAL:
        return rgb_make((real)0.5 + (real)0.5 * t->hit.ns.x, (real)0.5 + (real)0.5 * t->hit.ns.y,
                        (real)0.5 + (real)0.5 * t->hit.ns.z);
    case AOV_ALBEDO:
        if (material_has_bsdf_maps(&s->materials[t->hit.material])) { /* map_Kd at the hit */
            material m = scene_material_at(s, t->hit.triangle, t->hit.b1, t->hit.b2);
            return material_albedo(&m);
        }
        return material_albedo(&s->materials[t->hit.material]);
    case AOV_DEPTH:
        return rgb_gray(t->depth);
    case AOV_OBJECT:
        return object_colour(t->hit.object);
    case AOV_MOTION:
        return rgb_make((real)t->motion[0], (real)t->motion[1], (real)t->prev_valid);
    }
    return rgb_gray(0);
}

void aov_render(const gbuffer *g, const scene *s, enum aov_kind kind, image *out)
{
    int x, y;
    for (y = 0; y < g->height; ++y) {
        for (x = 0; x < g->width; ++x) {
            rgb c = texel_value(gbuffer_at(g, x, y), s, kind);
            float *p = image_pixel(out, x, y);
            p[0] = (float)c.r;
            p[1] = (float)c.g;
            p[2] = (float)c.b;
        }
    }
}

int aov_preview(const image *aov, enum aov_kind kind, image *out, rerror *e)
{
    size_t i, n = 3 * (size_t)aov->width * (size_t)aov->height;
    float scale = 1, largest = 0;
    if (image_alloc(out, aov->width, aov->height, e)) return -1;
    if (kind == AOV_DEPTH) {
        for (i = 0; i < n; ++i)
            if (aov->px[i] > largest) largest = aov->px[i];
        if (largest > 0) scale = 1 / largest;
    }
    for (i = 0; i < n; ++i) out->px[i] = aov->px[i] * scale;
    return 0;
}
