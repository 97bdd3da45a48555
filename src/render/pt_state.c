/* Path-tracer accumulation state: allocation, mean and variance images, merging of
 * runs over disjoint sample ranges, and the scene/options fingerprint. */
#include "restir/render/pt_state.h"

#include "restir/render/pt.h"

#include <stdlib.h>
#include <string.h>
#include "restir/scene/sky.h"

int pt_state_alloc(pt_state *st, int width, int height, rerror *e)
{
    size_t n = 3 * (size_t)width * (size_t)height;
    memset(st, 0, sizeof *st);
    if (width < 1 || height < 1) return rerror_set(e, "pt: image size %dx%d", width, height);
    st->width = width;
    st->height = height;
    st->sum = rcalloc(n, sizeof *st->sum, e);
    st->sum_sq = st->sum ? rcalloc(n, sizeof *st->sum_sq, e) : NULL;
    if (!st->sum_sq) {
        pt_state_free(st);
        return -1;
    }
    return 0;
}

void pt_state_free(pt_state *st)
{
    free(st->sum);
    free(st->sum_sq);
    memset(st, 0, sizeof *st);
}

int pt_state_mean(const pt_state *st, image *out, rerror *e)
{
    size_t i, n = 3 * (size_t)st->width * (size_t)st->height;
    if (image_alloc(out, st->width, st->height, e)) return -1;
    if (st->spp == 0) return 0;
    for (i = 0; i < n; ++i) out->px[i] = (float)(st->sum[i] / (double)st->spp);
    return 0;
}

int pt_state_merge(pt_state *acc, const pt_state *add, rerror *e)
{
    size_t i, n = 3 * (size_t)acc->width * (size_t)acc->height;
    uint64_t acc_end = (uint64_t)acc->sample_offset + acc->spp, add_end = (uint64_t)add->sample_offset + add->spp;
    if (add->width != acc->width || add->height != acc->height)
        return rerror_set(e, "merge: image sizes %dx%d and %dx%d differ", acc->width, acc->height, add->width,
                          add->height);
    if (add->seed != acc->seed || add->fingerprint != acc->fingerprint)
        return rerror_set(e, "merge: runs of different scenes, options or seeds (seed %u vs %u, fingerprint %016llx vs %016llx)",
                          acc->seed, add->seed, (unsigned long long)acc->fingerprint,
                          (unsigned long long)add->fingerprint);
    if (add->sample_offset != acc_end && add_end != acc->sample_offset)
        return rerror_set(e, "merge: sample ranges [%u, %llu) and [%u, %llu) are not adjacent", acc->sample_offset,
                          (unsigned long long)acc_end, add->sample_offset, (unsigned long long)add_end);
    for (i = 0; i < n; ++i) {
        acc->sum[i] += add->sum[i];
        acc->sum_sq[i] += add->sum_sq[i];
    }
    if (add->nonfinite) {
        uint64_t a = ((uint64_t)acc->first_nonfinite_sample << 32) | acc->first_nonfinite_pixel;
        uint64_t b = ((uint64_t)add->first_nonfinite_sample << 32) | add->first_nonfinite_pixel;
        if (acc->nonfinite == 0 || b < a) {
            acc->first_nonfinite_sample = add->first_nonfinite_sample;
            acc->first_nonfinite_pixel = add->first_nonfinite_pixel;
        }
    }
    acc->nonfinite += add->nonfinite;
    if (add->sample_offset < acc->sample_offset) acc->sample_offset = add->sample_offset;
    acc->spp += add->spp;
    return 0;
}

int pt_merge_means(const image *images, const double *counts, int n, image *out, rerror *e)
{
    double total = 0, *acc;
    size_t i, len;
    int k;
    if (n < 1) return rerror_set(e, "merge: no images");
    for (k = 0; k < n; ++k) {
        if (images[k].width != images[0].width || images[k].height != images[0].height)
            return rerror_set(e, "merge: image %d is %dx%d, image 0 is %dx%d", k, images[k].width, images[k].height,
                              images[0].width, images[0].height);
        if (!(counts[k] >= 0) || !isfinite(counts[k])) return rerror_set(e, "merge: count %d is %g", k, counts[k]);
        total += counts[k];
    }
    if (!(total > 0)) return rerror_set(e, "merge: the sample counts sum to 0");
    len = 3 * (size_t)images[0].width * (size_t)images[0].height;
    acc = rcalloc(len, sizeof *acc, e);
    if (!acc) return -1;
    if (image_alloc(out, images[0].width, images[0].height, e)) {
        free(acc);
        return -1;
    }
    for (k = 0; k < n; ++k)
        for (i = 0; i < len; ++i) acc[i] += counts[k] * (double)images[k].px[i];
    for (i = 0; i < len; ++i) out->px[i] = (float)(acc[i] / total);
    free(acc);
    return 0;
}

/* ---- fingerprint: FNV-1a 64 over a canonical little-endian byte stream ---- */

typedef struct {
    uint64_t h;
} fnv;

static void fnv_bytes(fnv *f, const unsigned char *p, size_t n)
{
    size_t i;
    for (i = 0; i < n; ++i) {
        f->h ^= p[i];
        f->h *= 1099511628211ull;
    }
}

static void fnv_u64(fnv *f, uint64_t v)
{
    unsigned char b[8];
    int i;
    for (i = 0; i < 8; ++i) b[i] = (unsigned char)(v >> (8 * i));
    fnv_bytes(f, b, 8);
}

static void fnv_f64(fnv *f, double d)
{
    uint64_t bits;
    memcpy(&bits, &d, sizeof bits);
    fnv_u64(f, bits);
}

static void fnv_vec3f(fnv *f, vec3f v)
{
    fnv_f64(f, v.x);
    fnv_f64(f, v.y);
    fnv_f64(f, v.z);
}

static void fnv_vec3(fnv *f, vec3 v)
{
    fnv_f64(f, (double)v.x);
    fnv_f64(f, (double)v.y);
    fnv_f64(f, (double)v.z);
}

static void fnv_rgb(fnv *f, rgb c)
{
    fnv_f64(f, (double)c.r);
    fnv_f64(f, (double)c.g);
    fnv_f64(f, (double)c.b);
}

/* The distant lights (docs/environment.md): description and every texel. */
static void fingerprint_sky(fnv *f, const scene_sky *k)
{
    size_t i, n = 3 * (size_t)k->width * (size_t)k->height;
    fnv_u64(f, 0x736b79u); /* "sky" */
    fnv_u64(f, (uint64_t)(k->has_env + 2 * k->env_is_map + 4 * k->has_sun));
    fnv_rgb(f, k->env_constant);
    fnv_f64(f, (double)k->rotate_degrees);
    fnv_u64(f, (uint64_t)k->width);
    fnv_u64(f, (uint64_t)k->height);
    for (i = 0; k->texels && i < n; ++i) fnv_f64(f, (double)k->texels[i]);
    fnv_vec3(f, k->sun_direction);
    fnv_f64(f, (double)k->sun_angle_degrees);
    fnv_rgb(f, k->sun_radiance);
}

/* Image maps: which map each material uses, every UV and every texel. */
static void fingerprint_maps(fnv *f, const scene *s)
{
    size_t i, n;
    for (i = 0; i < s->material_count; ++i) {
        const material *m = &s->materials[i];
        fnv_u64(f, m->map_kd);
        fnv_u64(f, m->map_roughness);
        fnv_u64(f, m->map_alpha);
        fnv_u64(f, m->map_ke);
        fnv_u64(f, (uint64_t)m->map_kd_is_f0);
        fnv_u64(f, (uint64_t)m->roughness_from_ns);
        fnv_f64(f, (double)m->roughness_map_scale);
    }
    for (i = 0; i < s->triangle_count; ++i)
        for (n = 0; n < 3; ++n) fnv_u64(f, (uint64_t)(int64_t)s->triangles[i].t[n]);
    fnv_bytes(f, (const unsigned char *)s->texcoords, s->texcoord_count * sizeof *s->texcoords);
    for (i = 0; i < s->texture_count; ++i) {
        const scene_texture *t = &s->textures[i];
        fnv_u64(f, (uint64_t)t->width);
        fnv_u64(f, (uint64_t)t->height);
        fnv_u64(f, (uint64_t)t->kind);
        fnv_bytes(f, (const unsigned char *)t->px, (size_t)t->width * (size_t)t->height * (size_t)t->channels * sizeof *t->px);
    }
}

static void fingerprint_scene(fnv *f, const scene *s, int frame)
{
    size_t i;
    camera_pose pose = scene_camera_at(s, frame);
    fnv_u64(f, s->triangle_count);
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle *t = &s->triangles[i];
        int k;
        for (k = 0; k < 3; ++k) {
            fnv_vec3f(f, s->positions[t->v[k]]);
            fnv_vec3f(f, t->n[k] >= 0 ? s->normals[t->n[k]] : v3f(0, 0, 0));
        }
        fnv_u64(f, t->material);
    }
    fnv_u64(f, s->material_count);
    for (i = 0; i < s->material_count; ++i) {
        const material *m = &s->materials[i];
        fnv_u64(f, (uint64_t)m->type);
        fnv_rgb(f, m->diffuse);
        fnv_rgb(f, m->specular);
        fnv_rgb(f, m->emission);
        fnv_f64(f, (double)m->roughness);
        fnv_f64(f, (double)m->ior);
    }
    fnv_vec3(f, pose.eye);
    fnv_vec3(f, pose.target);
    fnv_vec3(f, pose.up);
    fnv_f64(f, (double)pose.fov_y_degrees);
    fnv_u64(f, (uint64_t)s->width);
    fnv_u64(f, (uint64_t)s->height);
    if (s->sky) fingerprint_sky(f, s->sky); /* scenes without a sky keep their fingerprint */
    if (s->texture_count) fingerprint_maps(f, s); /* untextured scenes keep their fingerprint */
}

uint64_t pt_fingerprint(const scene *s, const pt_options *o)
{
    fnv f;
    f.h = 14695981039346656037ull;
    fnv_bytes(&f, (const unsigned char *)"restir-pt-1", 11);
    fingerprint_scene(&f, s, o->frame);
    fnv_u64(&f, o->seed);
    fnv_u64(&f, (uint64_t)o->max_depth);
    fnv_u64(&f, (uint64_t)o->strategy);
    fnv_u64(&f, (uint64_t)o->russian_roulette);
    fnv_u64(&f, (uint64_t)(o->russian_roulette ? o->rr_min_depth : 0));
    fnv_u64(&f, (uint64_t)o->jitter);
    fnv_u64(&f, (uint64_t)o->ablations);
    fnv_u64(&f, (uint64_t)o->frame);
    if (o->min_depth > 1) fnv_u64(&f, (uint64_t)o->min_depth); /* older checkpoints keep their fingerprint */
    if (o->light_ris.candidates > 0) { /* likewise */
        fnv_u64(&f, (uint64_t)o->light_ris.candidates);
        fnv_u64(&f, (uint64_t)o->light_ris.tiles);
    }
    fnv_u64(&f, (uint64_t)sizeof(real));
    return f.h;
}
