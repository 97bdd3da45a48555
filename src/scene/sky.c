/* Distant lights: environment and sun (include/restir/scene/sky.h, docs/environment.md). */
#include "restir/scene/sky.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image.h"
#include "restir/core/pfm.h"
#include "restir/scene/bvh.h"
#include "restir/scene/scene_trace.h"
#include "restir/core/image_io.h"

void sky_init(scene_sky *k)
{
    memset(k, 0, sizeof *k);
    k->scale = 1;
    k->rotate_cos = 1; /* no rotation until sky_prepare */
}

static void sky_free_derived(scene_sky *k)
{
    free(k->marginal_cdf);
    free(k->conditional_cdf);
    free(k->row_weight);
    k->marginal_cdf = k->conditional_cdf = k->row_weight = NULL;
}

void sky_free(scene_sky *k)
{
    if (!k) return;
    sky_free_derived(k);
    free(k->texels);
    sky_init(k);
}

static int copy_reals(real **dst, const real *src, size_t n, rerror *e)
{
    *dst = NULL;
    if (!src) return 0;
    *dst = rmalloc(n, sizeof **dst, e);
    if (!*dst) return -1;
    memcpy(*dst, src, n * sizeof **dst);
    return 0;
}

int sky_clone(scene_sky **dst, const scene_sky *src, rerror *e)
{
    scene_sky *k;
    size_t texels, h;
    *dst = NULL;
    if (!src) return 0;
    k = rmalloc(1, sizeof *k, e);
    if (!k) return -1;
    *k = *src;
    k->texels = NULL;
    k->marginal_cdf = k->conditional_cdf = k->row_weight = NULL;
    texels = (size_t)src->width * (size_t)src->height;
    h = (size_t)src->height;
    if (src->texels) {
        k->texels = rmalloc(3 * texels, sizeof *k->texels, e);
        if (!k->texels) goto fail;
        memcpy(k->texels, src->texels, 3 * texels * sizeof *k->texels);
    }
    if (copy_reals(&k->marginal_cdf, src->marginal_cdf, h + 1, e) ||
        copy_reals(&k->conditional_cdf, src->conditional_cdf, h * ((size_t)src->width + 1), e) ||
        copy_reals(&k->row_weight, src->row_weight, h, e))
        goto fail;
    *dst = k;
    return 0;
fail:
    sky_free(k);
    free(k);
    return -1;
}

int sky_set_map(scene_sky *k, int width, int height, const float *rgb_texels, real scale, rerror *e)
{
    size_t n, i;
    if (width < 1 || height < 1) return rerror_set(e, "environment map: size %dx%d", width, height);
    if (!(scale >= 0) || !isfinite(scale)) return rerror_set(e, "environment map: scale %g", (double)scale);
    n = 3 * (size_t)width * (size_t)height;
    for (i = 0; i < n; ++i)
        if (!(rgb_texels[i] >= 0) || !isfinite(rgb_texels[i]))
            return rerror_set(e, "environment map: texel (%lu, %lu) has the value %g (must be finite and >= 0)",
                              (unsigned long)(i / 3 % (size_t)width), (unsigned long)(i / 3 / (size_t)width),
                              (double)rgb_texels[i]);
    free(k->texels);
    k->texels = rmalloc(n, sizeof *k->texels, e);
    if (!k->texels) return -1;
    for (i = 0; i < n; ++i) k->texels[i] = (float)(rgb_texels[i] * scale);
    k->width = width;
    k->height = height;
    k->scale = scale;
    k->has_env = 1;
    k->env_is_map = 1;
    return 0;
}

static int has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext), i;
    if (n < m) return 0;
    for (i = 0; i < m; ++i) {
        char c = path[n - m + i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != ext[i]) return 0;
    }
    return 1;
}

int sky_load_map(scene_sky *k, const char *path, real scale, rerror *e)
{
    image img;
    int status;
    /* Radiance maps: PFM and EXR (linear); a PNG is taken as an sRGB-encoded picture
     * (image_read's rule). Rows top first. */
    if (!has_extension(path, ".pfm") && !has_extension(path, ".exr") && !has_extension(path, ".png"))
        return rerror_set(e, "%s: environment maps are read from .pfm, .exr or .png files", path);
    if (image_read(path, &img, NULL, e)) return -1;
    status = sky_set_map(k, img.width, img.height, img.px, scale, e);
    image_free(&img);
    if (status && e) {
        char what[sizeof e->msg];
        memcpy(what, e->msg, sizeof what);
        return rerror_set(e, "%s: %s", path, what);
    }
    if (status) return -1;
    strncpy(k->env_path, path, sizeof k->env_path - 1);
    k->env_path[sizeof k->env_path - 1] = '\0';
    return 0;
}

static rgb texel(const scene_sky *k, int col, int row)
{
    const float *t = k->texels + 3 * ((size_t)row * (size_t)k->width + (size_t)col);
    return rgb_make(t[0], t[1], t[2]);
}

/* The 2-D distribution: weight of texel (col, row) = luminance x its solid angle
 * (2 pi / W)(cos theta_row - cos theta_row+1); marginal CDF over rows, conditional CDF
 * over columns (the piecewise-constant 2-D sampling of Pharr, Jakob & Humphreys,
 * PBR 3rd ed. §13.6.7, written out in docs/environment.md). */
static int build_distribution(scene_sky *k, rerror *e)
{
    int w = k->width, h = k->height, row, col;
    real acc = 0;
    k->marginal_cdf = rmalloc((size_t)h + 1, sizeof *k->marginal_cdf, e);
    k->conditional_cdf = rmalloc((size_t)h * ((size_t)w + 1), sizeof *k->conditional_cdf, e);
    k->row_weight = rmalloc((size_t)h, sizeof *k->row_weight, e);
    if (!k->marginal_cdf || !k->conditional_cdf || !k->row_weight) return -1;
    k->env_power = 0;
    for (row = 0; row < h; ++row) {
        real *cdf = k->conditional_cdf + (size_t)row * ((size_t)w + 1), sum = 0;
        real band = (real)(cos(PI_R * row / h) - cos(PI_R * (row + 1) / h)) * 2 * PI_R / (real)w;
        cdf[0] = 0;
        for (col = 0; col < w; ++col) {
            sum += luminance(texel(k, col, row)) * band;
            cdf[col + 1] = sum;
        }
        for (col = 1; col <= w; ++col) cdf[col] = sum > 0 ? cdf[col] / sum : (real)col / (real)w;
        cdf[w] = 1;
        k->row_weight[row] = sum;
        k->marginal_cdf[row] = acc;
        acc += sum;
    }
    k->marginal_cdf[h] = acc;
    for (row = 1; row <= h; ++row) k->marginal_cdf[row] = acc > 0 ? k->marginal_cdf[row] / acc : (real)row / (real)h;
    k->marginal_cdf[h] = 1;
    k->weight_sum = acc;
    k->env_power = acc; /* the weights are luminance x solid angle: their sum is the integral */
    return 0;
}

int sky_prepare(scene_sky *k, rerror *e)
{
    real rad = k->rotate_degrees * PI_R / 180;
    sky_free_derived(k);
    k->rotate_cos = (real)cos(rad);
    k->rotate_sin = (real)sin(rad);
    k->env_power = 0;
    k->sun_power = 0;
    if (k->has_env && k->env_is_map && build_distribution(k, e)) return -1;
    if (k->has_env && !k->env_is_map) k->env_power = 4 * PI_R * luminance(k->env_constant);
    if (k->has_sun) {
        real half = k->sun_angle_degrees * PI_R / 360, s = (real)sin(half);
        k->sun_direction = v3_normalize(k->sun_direction);
        k->sun_cos_max = (real)cos(k->sun_angle_degrees * PI_R / 180);
        k->sun_solid_angle = 4 * PI_R * s * s; /* 2 pi (1 - cos alpha) without cancellation */
        k->sun_power = luminance(k->sun_radiance) * k->sun_solid_angle;
        v3_basis(k->sun_direction, &k->sun_t, &k->sun_b);
    }
    return 0;
}

/* ---- the map's parametrisation --------------------------------------------------- */

vec2 sky_env_uv(const scene_sky *k, vec3 w)
{
    real y = w.y > 1 ? 1 : w.y < -1 ? -1 : w.y;
    real phi = (real)atan2(w.x, w.z); /* world azimuth, 0 along +z, pi/2 along +x */
    /* undo the rotation: phi_map = phi - rotation, as an angle difference in [0, 2 pi) */
    real pm = (real)atan2(sin(phi) * k->rotate_cos - cos(phi) * k->rotate_sin,
                          cos(phi) * k->rotate_cos + sin(phi) * k->rotate_sin);
    real u = pm / (2 * PI_R);
    if (u < 0) u += 1;
    if (u >= 1) u = 0;
    return v2(u, (real)acos(y) / PI_R);
}

vec3 sky_env_direction(const scene_sky *k, vec2 uv)
{
    real theta = PI_R * uv.y, phi_map = 2 * PI_R * uv.x;
    real st = (real)sin(theta), sp = (real)sin(phi_map), cp = (real)cos(phi_map);
    /* phi = phi_map + rotation */
    real s = sp * k->rotate_cos + cp * k->rotate_sin, c = cp * k->rotate_cos - sp * k->rotate_sin;
    return v3(st * s, (real)cos(theta), st * c);
}

static void texel_of(const scene_sky *k, vec2 uv, int *col, int *row)
{
    *col = (int)(uv.x * (real)k->width);
    *row = (int)(uv.y * (real)k->height);
    if (*col >= k->width) *col = k->width - 1;
    if (*row >= k->height) *row = k->height - 1;
    if (*col < 0) *col = 0;
    if (*row < 0) *row = 0;
}

rgb sky_env_radiance(const scene_sky *k, vec3 w)
{
    int col, row;
    if (!k->has_env) return rgb_gray(0);
    if (!k->env_is_map) return k->env_constant;
    texel_of(k, sky_env_uv(k, w), &col, &row);
    return texel(k, col, row);
}

/* The index i with cdf[i] <= u < cdf[i+1] among n intervals, skipping empty ones. */
static int find_interval(const real *cdf, int n, real u)
{
    int lo = 0, hi = n; /* invariant: cdf[lo] <= u < cdf[hi] (cdf[n] = 1 > u) */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (cdf[mid] <= u) lo = mid;
        else hi = mid;
    }
    return lo;
}

vec3 sky_env_sample(const scene_sky *k, vec2 u)
{
    if (!k->env_is_map) { /* uniform on the sphere */
        real y = 1 - 2 * u.x, r = (real)sqrt(fmax(0, 1 - y * y)), phi = 2 * PI_R * u.y;
        return v3(r * (real)sin(phi), y, r * (real)cos(phi));
    }
    {
        int row = find_interval(k->marginal_cdf, k->height, u.x);
        const real *cdf = k->conditional_cdf + (size_t)row * ((size_t)k->width + 1);
        int col = find_interval(cdf, k->width, u.y);
        real m0 = k->marginal_cdf[row], m1 = k->marginal_cdf[row + 1], c0 = cdf[col], c1 = cdf[col + 1];
        real fv = m1 > m0 ? (u.x - m0) / (m1 - m0) : (real)0.5, fu = c1 > c0 ? (u.y - c0) / (c1 - c0) : (real)0.5;
        vec2 uv = v2(((real)col + fu) / (real)k->width, ((real)row + fv) / (real)k->height);
        return sky_env_direction(k, uv);
    }
}

/* p(w) = p_uv / (2 pi^2 sin theta), p_uv = weight / weight_sum x W H (texel area 1/(W H)). */
real sky_env_pdf(const scene_sky *k, vec3 w)
{
    int col, row;
    real sin_theta, weight, band;
    if (!k->has_env) return 0;
    if (!k->env_is_map) return 1 / (4 * PI_R);
    if (!(k->weight_sum > 0)) return 0;
    texel_of(k, sky_env_uv(k, w), &col, &row);
    band = (k->conditional_cdf[(size_t)row * ((size_t)k->width + 1) + col + 1] -
            k->conditional_cdf[(size_t)row * ((size_t)k->width + 1) + col]) * k->row_weight[row];
    weight = band / k->weight_sum; /* probability of the texel */
    sin_theta = (real)sqrt(w.x * w.x + w.z * w.z);
    if (!(sin_theta > 0) || !(weight > 0)) return 0;
    return weight * (real)k->width * (real)k->height / (2 * PI_R * PI_R * sin_theta);
}

/* ---- the sun ------------------------------------------------------------------------ */

rgb sky_sun_radiance(const scene_sky *k, vec3 w)
{
    if (!k->has_sun || !(v3_dot(w, k->sun_direction) >= k->sun_cos_max)) return rgb_gray(0);
    return k->sun_radiance;
}

/* Uniform in the cone: 1 - cos theta = u0 (1 - cos alpha), phi = 2 pi u1. */
vec3 sky_sun_sample(const scene_sky *k, vec2 u)
{
    real omc = u.x * k->sun_solid_angle / (2 * PI_R), cos_t = 1 - omc;
    real sin_t = (real)sqrt(fmax(0, omc * (2 - omc))), phi = 2 * PI_R * u.y;
    vec3 w = v3_add(v3_add(v3_scale(k->sun_t, sin_t * (real)cos(phi)), v3_scale(k->sun_b, sin_t * (real)sin(phi))),
                    v3_scale(k->sun_direction, cos_t));
    return v3_normalize(w);
}

real sky_sun_pdf(const scene_sky *k, vec3 w)
{
    if (!k->has_sun || !(v3_dot(w, k->sun_direction) >= k->sun_cos_max)) return 0;
    return 1 / k->sun_solid_angle;
}

int sky_visible(const scene *s, vec3f p, vec3f ng, vec3 w)
{
    ray r;
    vec3f d = v3f_from(w);
    vec3f n = v3f_dot(ng, d) < 0 ? v3f_scale(ng, -1.0f) : ng;
    r.origin = offset_ray_origin(p, n);
    r.dir = d;
    r.tmin = 0;
    r.tmax = INFINITY;
    return !scene_occluded(s, &r);
}
