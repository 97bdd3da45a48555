/* Textured surface points (include/restir/scene/surface_maps.h). */
#include "restir/scene/surface_maps.h"

#include <math.h>
#include "restir/scene/mtl.h"

vec2 scene_uv(const scene *s, uint32_t tri, float b1, float b2)
{
    const triangle *t = &s->triangles[tri];
    vec2 uv = {0, 0};
    real w[3];
    int k;
    for (k = 0; k < 3; ++k)
        if (t->t[k] < 0 || (size_t)t->t[k] >= s->texcoord_count) return uv;
    w[0] = 1 - (real)b1 - (real)b2;
    w[1] = (real)b1;
    w[2] = (real)b2;
    for (k = 0; k < 3; ++k) {
        uv.x += w[k] * (real)s->texcoords[t->t[k]][0];
        uv.y += w[k] * (real)s->texcoords[t->t[k]][1];
    }
    return uv;
}

int material_has_bsdf_maps(const material *m) { return m->map_kd != 0 || m->map_roughness != 0; }

static const scene_texture *map_of(const scene *s, uint32_t map)
{
    return map && map <= s->texture_count ? &s->textures[map - 1] : NULL;
}

material scene_material_at(const scene *s, uint32_t tri, float b1, float b2)
{
    material m = s->materials[s->triangles[tri].material];
    const scene_texture *kd = map_of(s, m.map_kd), *rough = map_of(s, m.map_roughness);
    vec2 uv;
    if (!kd && !rough) return m;
    uv = scene_uv(s, tri, b1, b2);
    if (kd) {
        rgb c = texture_rgb(kd, uv);
        if (m.map_kd_is_f0) m.specular = rgb_mul(m.specular, c);
        else m.diffuse = rgb_mul(m.diffuse, c);
    }
    if (rough) {
        real t = texture_scalar(rough, uv);
        m.roughness = m.roughness_from_ns ? roughness_from_phong_exponent((double)(m.roughness_map_scale * t))
                                          : m.roughness_map_scale * t;
    }
    return m;
}

bsdf scene_bsdf_at(const scene *s, const surface_hit *h)
{
    const material *m = &s->materials[h->material];
    material textured;
    if (!material_has_bsdf_maps(m)) return bsdf_from_material(m);
    textured = scene_material_at(s, h->triangle, h->b1, h->b2);
    return bsdf_from_material(&textured);
}

int scene_alpha_keeps(const scene *s, uint32_t tri, float b1, float b2)
{
    const scene_texture *a = map_of(s, s->materials[s->triangles[tri].material].map_alpha);
    return !a || texture_scalar(a, scene_uv(s, tri, b1, b2)) >= (real)SCENE_ALPHA_CUTOFF;
}

rgb scene_emission_at(const scene *s, uint32_t tri, float b1, float b2, rgb ke)
{
    const scene_texture *map = map_of(s, s->materials[s->triangles[tri].material].map_ke);
    return map ? rgb_mul(ke, texture_rgb(map, scene_uv(s, tri, b1, b2))) : ke;
}

void scene_barycentrics(const scene *s, uint32_t tri, vec3 p, float *b1, float *b2)
{
    const triangle *t = &s->triangles[tri];
    vec3 a = v3_from_f(s->positions[t->v[0]]);
    vec3 e1 = v3_sub(v3_from_f(s->positions[t->v[1]]), a), e2 = v3_sub(v3_from_f(s->positions[t->v[2]]), a);
    vec3 d = v3_sub(p, a);
    double d11 = v3_dot(e1, e1), d12 = v3_dot(e1, e2), d22 = v3_dot(e2, e2);
    double p1 = v3_dot(d, e1), p2 = v3_dot(d, e2), det = d11 * d22 - d12 * d12;
    *b1 = det != 0 ? (float)((d22 * p1 - d12 * p2) / det) : 0;
    *b2 = det != 0 ? (float)((d11 * p2 - d12 * p1) / det) : 0;
}

int scene_has_emission_maps(const scene *s)
{
    size_t i;
    for (i = 0; i < s->material_count; ++i)
        if (s->materials[i].map_ke) return 1;
    return 0;
}
