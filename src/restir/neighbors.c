/* Spatial neighbour selection (see neighbors.h and docs/spatial-reuse.md). */
#include "restir/restir/neighbors.h"

#include <math.h>

const char *const neighbor_pattern_names[] = {"uniform", "r2", "box", "paired", NULL};
const char *const neighbor_verdict_names[] = {"accepted", "centre", "outside", "repeat", "no_hit", "normal", "depth", NULL};

/* The R2 sequence (Roberts 2018, "The unreasonable effectiveness of quasirandom
 * sequences"): t_k = frac(s + k alpha) with alpha = (1/g, 1/g^2), g = 1.3247179572...
 * the plastic number (the real root of x^3 = x + 1). */
#define R2_ALPHA_X 0.75487766624669276005
#define R2_ALPHA_Y 0.56984029099805326591

void neighbor_options_default(neighbor_options *o)
{
    o->pattern = NEIGHBOR_R2;
    o->count = 6;
    o->radius = 10;
    o->reject_geometry = 1;
    o->min_normal_cos = NEIGHBOR_DEFAULT_MIN_NORMAL_COS;
    o->max_relative_depth = NEIGHBOR_DEFAULT_MAX_RELATIVE_DEPTH;
    o->textures = NULL;
    o->placements = NULL;
}

int neighbor_options_validate(const neighbor_options *o, rerror *e)
{
    if (o->pattern != NEIGHBOR_UNIFORM && o->pattern != NEIGHBOR_R2 && o->pattern != NEIGHBOR_BOX &&
        o->pattern != NEIGHBOR_PAIRED)
        return rerror_set(e, "neighbours: unknown pattern %d", (int)o->pattern);
    if (!(o->radius > 0) || !isfinite(o->radius))
        return rerror_set(e, "neighbours: radius must be a positive number of pixels, not %g", o->radius);
    if (o->pattern == NEIGHBOR_BOX && (o->radius < 1 || o->radius >= NEIGHBOR_MAX_BOX_RADIUS + 1))
        return rerror_set(e, "neighbours: box radius floor(%g) must be in [1, %d]", o->radius, NEIGHBOR_MAX_BOX_RADIUS);
    if (o->pattern != NEIGHBOR_BOX && (o->count < 1 || o->count > NEIGHBOR_MAX_COUNT))
        return rerror_set(e, "neighbours: count %d not in [1, %d]", o->count, NEIGHBOR_MAX_COUNT);
    if (o->pattern == NEIGHBOR_PAIRED && o->count > PAIRING_MAX_TEXTURES)
        return rerror_set(e, "neighbours: paired reuse takes at most %d neighbours, not %d", PAIRING_MAX_TEXTURES,
                          o->count);
    if (!(o->min_normal_cos >= -1 && o->min_normal_cos <= 1))
        return rerror_set(e, "neighbours: normal threshold %g not in [-1, 1]", (double)o->min_normal_cos);
    if (!(o->max_relative_depth >= 0) || !isfinite(o->max_relative_depth))
        return rerror_set(e, "neighbours: depth threshold %g must be >= 0", (double)o->max_relative_depth);
    return 0;
}

int neighbor_candidate_count(const neighbor_options *o)
{
    int r = (int)floor(o->radius);
    return o->pattern == NEIGHBOR_BOX ? (2 * r + 1) * (2 * r + 1) - 1 : o->count;
}

/* Shirley & Chiu 1997 concentric map of [0,1)^2 onto the unit disk (area-preserving up
 * to the factor pi, so a uniform square point gives a uniform disk point). warp.h has
 * it in `real`; here it is in double so that the float and double builds choose the
 * same neighbours. */
static void concentric_disk(double u, double v, double *px, double *py)
{
    double a = 2 * u - 1, b = 2 * v - 1, r, phi;
    const double quarter_pi = 0.78539816339744830962;
    if (a == 0 && b == 0) {
        *px = *py = 0;
        return;
    }
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = quarter_pi * (b / a);
    } else {
        r = b;
        phi = 2 * quarter_pi - quarter_pi * (a / b);
    }
    *px = r * cos(phi);
    *py = r * sin(phi);
}

static double frac(double x) { return x - floor(x); }

void neighbor_disk_point(enum neighbor_pattern pattern, rng_key key, int k, double *px, double *py)
{
    double u, v;
    if (pattern == NEIGHBOR_R2) {
        /* A uniform shift s makes frac(s + k alpha) uniform on the torus for every k,
         * while the differences between the n points stay those of the R2 sequence. */
        double sx = rng_uniform_double(rng_key_at(key, RNG_NEIGHBOR, NEIGHBOR_SHIFT_VERTEX, 0));
        double sy = rng_uniform_double(rng_key_at(key, RNG_NEIGHBOR, NEIGHBOR_SHIFT_VERTEX, 1));
        u = frac(sx + k * R2_ALPHA_X);
        v = frac(sy + k * R2_ALPHA_Y);
    } else {
        u = rng_uniform_double(rng_key_at(key, RNG_NEIGHBOR, (uint32_t)k, 0));
        v = rng_uniform_double(rng_key_at(key, RNG_NEIGHBOR, (uint32_t)k, 1));
    }
    concentric_disk(u, v, px, py);
}

void neighbor_offset(const neighbor_options *o, rng_key key, int k, int *dx, int *dy)
{
    if (o->pattern == NEIGHBOR_BOX) {
        int r = (int)floor(o->radius), side = 2 * r + 1;
        int cell = k < side * r + r ? k : k + 1; /* skip the centre cell */
        *dx = cell % side - r;
        *dy = cell / side - r;
    } else {
        double px, py;
        neighbor_disk_point(o->pattern, key, k, &px, &py);
        *dx = (int)floor(o->radius * px + 0.5);
        *dy = (int)floor(o->radius * py + 0.5);
    }
}

/* The geometric normal of the side the camera sees. */
static vec3f facing_normal(const gbuffer_texel *t)
{
    return v3f_dot(t->hit.ng, t->view_dir) < 0 ? t->hit.ng : v3f_scale(t->hit.ng, -1);
}

enum neighbor_verdict neighbor_geometry_test(const neighbor_options *o, const gbuffer_texel *a, const gbuffer_texel *b)
{
    if (!a->valid || !b->valid) return NEIGHBOR_NO_HIT;
    if (!o->reject_geometry) return NEIGHBOR_ACCEPTED;
    /* dot and min are symmetric in (a, b), so is the verdict (unlike the authors' code,
     * which scales the depth tolerance by the centre's depth alone). */
    if (v3f_dot(facing_normal(a), facing_normal(b)) < o->min_normal_cos) return NEIGHBOR_NORMAL;
    if (fabsf(a->depth - b->depth) > o->max_relative_depth * fminf(a->depth, b->depth)) return NEIGHBOR_DEPTH;
    return NEIGHBOR_ACCEPTED;
}

static int seen_before(const uint32_t *proposed, int count, uint32_t pixel)
{
    int i;
    for (i = 0; i < count; ++i)
        if (proposed[i] == pixel) return 1;
    return 0;
}

void neighbor_place(const neighbor_options *o, uint32_t seed, uint32_t sample, reuse_transform *out)
{
    int k;
    for (k = 0; k < o->count; ++k) out[k] = reuse_transform_draw(&o->textures[k], seed, sample, (uint32_t)k);
}

int neighbor_select(const neighbor_options *o, const gbuffer *g, uint32_t seed, uint32_t sample, int x, int y,
                    uint32_t *out, int capacity, neighbor_stats *stats, rerror *e)
{
    return neighbor_select_slots(o, g, seed, sample, x, y, out, NULL, capacity, stats, e);
}

int neighbor_select_slots(const neighbor_options *o, const gbuffer *g, uint32_t seed, uint32_t sample, int x, int y,
                          uint32_t *out, int *slot, int capacity, neighbor_stats *stats, rerror *e)
{
    uint32_t centre = (uint32_t)y * (uint32_t)g->width + (uint32_t)x;
    uint32_t proposed[NEIGHBOR_MAX_COUNT]; /* in-image candidates so far (disk patterns) */
    int candidates = neighbor_candidate_count(o), proposed_count = 0, accepted = 0, k;
    rng_key key = rng_key_make(seed, centre, sample);
    const gbuffer_texel *ti = gbuffer_at(g, x, y);
    if (capacity < candidates)
        return rerror_set(e, "neighbours: room for %d, but %d candidates per pixel", capacity, candidates);
    if (o->pattern == NEIGHBOR_PAIRED && !o->textures) return rerror_set(e, "neighbours: paired without reuse textures");
    for (k = 0; k < candidates; ++k) {
        enum neighbor_verdict verdict;
        int dx, dy, nx, ny;
        uint32_t pixel;
        if (o->pattern == NEIGHBOR_PAIRED) { /* Enhanced §3.2: texture k, this frame's placement */
            reuse_transform f = o->placements ? o->placements[k]
                                              : reuse_transform_draw(&o->textures[k], seed, sample, (uint32_t)k);
            reuse_partner_offset(&o->textures[k], &f, x, y, &dx, &dy);
        } else {
            neighbor_offset(o, key, k, &dx, &dy);
        }
        nx = x + dx;
        ny = y + dy;
        pixel = (uint32_t)ny * (uint32_t)g->width + (uint32_t)nx;
        if (dx == 0 && dy == 0)
            verdict = NEIGHBOR_CENTRE;
        else if (nx < 0 || ny < 0 || nx >= g->width || ny >= g->height)
            verdict = NEIGHBOR_OUTSIDE;
        else if (o->pattern != NEIGHBOR_BOX && seen_before(proposed, proposed_count, pixel))
            verdict = NEIGHBOR_REPEAT;
        else
            verdict = neighbor_geometry_test(o, ti, gbuffer_at(g, nx, ny));
        if (o->pattern != NEIGHBOR_BOX && (verdict == NEIGHBOR_ACCEPTED || verdict >= NEIGHBOR_NO_HIT))
            proposed[proposed_count++] = pixel;
        if (verdict == NEIGHBOR_ACCEPTED) {
            if (slot) slot[accepted] = k;
            out[accepted++] = pixel;
        }
        if (stats) stats->verdict[verdict]++;
    }
    if (stats) stats->candidates += (uint64_t)candidates;
    return accepted;
}
