/* Reuse textures for paired spatial reuse (include/restir/restir/pairing.h; Enhanced §3). */
#include "restir/restir/pairing.h"

#include <math.h>
#include <stdlib.h>
#include "restir/core/rng.h"

/* Enhanced Eq. 3. The extracted paper text shows all correction terms with a plus sign and
 * a ceiling; that gives n = 7 passes at sigma = 0.8, contradicting footnote 1 (sigma = 0.8
 * is ONE pass). Of the readings that keep footnote 1, the port's floor(s^2/2 + 1.46/s -
 * 1.76/s^2 + 0.656/s^3 + 0.5) reaches sigma best where the paper says the deltas have
 * standard deviation sigma (measured, docs/results/eq3.md; docs/enhanced.md §2). */
int pairing_shuffle_count(double sigma) { return pairing_shuffle_count_as(sigma, PAIRING_EQ3_DEFAULT); }

const char *const pairing_eq3_names[] = {"signed-ceil", "port-round", "signed-round", "literal-ceil", "leading-ceil",
                                          NULL};

/* Enhanced Eq. 3 under reading r (pairing.h lists them; docs/enhanced.md §2). */
int pairing_shuffle_count_as(double sigma, enum pairing_eq3 r)
{
    double s1 = 1.46 / sigma, s2 = 1.76 / (sigma * sigma), s3 = 0.656 / (sigma * sigma * sigma);
    double lead = sigma * sigma / 2 + 0.5, n;
    switch (r) {
    case PAIRING_EQ3_PORT_ROUND: n = floor(lead + s1 - s2 + s3); break;
    case PAIRING_EQ3_SIGNED_ROUND: n = floor(lead - s1 + s2 - s3); break;
    case PAIRING_EQ3_LITERAL_CEIL: n = ceil(lead + s1 + s2 + s3); break;
    case PAIRING_EQ3_LEADING_CEIL: n = ceil(lead); break;
    default: n = ceil(lead - s1 + s2 - s3); break;
    }
    return n < 1 ? 1 : (int)n;
}

static int wrap(int v, int w) { return ((v % w) + w) % w; }

/* A uniformly random permutation of the four link indices of one 2x2 block. */
static void shuffle_block(uint32_t *link, const int idx[4], rng_key key, uint32_t pass)
{
    int i;
    for (i = 3; i > 0; --i) { /* Fisher-Yates: slot 2 + i for step i (+ 4 per 256 passes) */
        int j = (int)(rng_u(key, RNG_NEIGHBOR, pass & 255u, (uint32_t)(2 + i) + 4u * (pass >> 8)) * (real)(i + 1));
        uint32_t tmp;
        if (j > i) j = i;
        tmp = link[idx[i]];
        link[idx[i]] = link[idx[j]];
        link[idx[j]] = tmp;
    }
}

/* The tileable offset a -> b on a torus of width w: into [-w/2, w/2]. */
static int tile_delta(int d, int w)
{
    if (d > w / 2) d -= w;
    if (d < -w / 2) d += w;
    return d;
}

/* Enhanced §3: an involution texture from pairing_shuffle_count(sigma) 2x2 shuffle passes
 * (Enhanced Eq. 3), so its offsets have standard deviation sigma. */
int reuse_texture_build(reuse_texture *t, int w, double sigma, uint32_t seed, uint32_t id, rerror *e)
{
    return reuse_texture_build_as(t, w, sigma, PAIRING_EQ3_DEFAULT, seed, id, e);
}

int reuse_texture_build_as(reuse_texture *t, int w, double sigma, enum pairing_eq3 r, uint32_t seed, uint32_t id,
                           rerror *e)
{
    t->dx = t->dy = NULL;
    if (!(sigma >= PAIRING_MIN_SIGMA && sigma <= PAIRING_MAX_SIGMA))
        return rerror_set(e, "reuse texture: sigma %g outside [%g, %g]", sigma, PAIRING_MIN_SIGMA, PAIRING_MAX_SIGMA);
    if ((int)r < 0 || (int)r >= PAIRING_EQ3_COUNT) return rerror_set(e, "reuse texture: unknown Eq. 3 reading %d", (int)r);
    return reuse_texture_build_passes(t, w, sigma, pairing_shuffle_count_as(sigma, r), seed, id, e);
}

int reuse_texture_build_passes(reuse_texture *t, int w, double sigma, int passes, uint32_t seed, uint32_t id,
                               rerror *e)
{
    size_t n = (size_t)w * (size_t)w, p;
    uint32_t *link = NULL;
    int32_t *table = NULL;
    int pass, bx, by;
    t->dx = t->dy = NULL;
    if (w < 4 || w > 4096 || (w & 1)) return rerror_set(e, "reuse texture: size %d (must be even, 4..4096)", w);
    if (passes < 1 || passes > PAIRING_MAX_PASSES)
        return rerror_set(e, "reuse texture: %d shuffle passes (must be 1..%d)", passes, PAIRING_MAX_PASSES);
    t->size = w;
    t->sigma = sigma;
    t->shuffles = passes;
    link = malloc(n * sizeof *link);
    table = malloc(n * sizeof *table); /* N/2 x 2 */
    t->dx = malloc(n * sizeof *t->dx);
    t->dy = malloc(n * sizeof *t->dy);
    if (!link || !table || !t->dx || !t->dy) {
        free(link);
        free(table);
        reuse_texture_free(t);
        return rerror_set(e, "reuse texture: out of memory");
    }
    for (p = 0; p < n; ++p) link[p] = (uint32_t)(p / 2); /* Fig. 3 left */
    for (pass = 0; pass < t->shuffles; ++pass) {        /* Fig. 3 right */
        int o = pass & 1;
        for (by = 0; by < w / 2; ++by)
            for (bx = 0; bx < w / 2; ++bx) {
                int x0 = 2 * bx + o, y0 = 2 * by + o, idx[4];
                rng_key key = rng_key_make(seed, (uint32_t)(by * (w / 2) + bx), PAIRING_TEXTURE_SAMPLE + id);
                idx[0] = wrap(y0, w) * w + wrap(x0, w);
                idx[1] = wrap(y0, w) * w + wrap(x0 + 1, w);
                idx[2] = wrap(y0 + 1, w) * w + wrap(x0, w);
                idx[3] = wrap(y0 + 1, w) * w + wrap(x0 + 1, w);
                shuffle_block(link, idx, key, (uint32_t)pass);
            }
    }
    /* The link-index table: slot 0 for the first texel (scan order) with a link, slot 1 for the second. */
    for (p = 0; p < n; ++p) table[p] = -1;
    for (p = 0; p < n; ++p) {
        size_t l = link[p];
        if (table[2 * l] < 0) table[2 * l] = (int32_t)p;
        else table[2 * l + 1] = (int32_t)p;
    }
    for (p = 0; p < n; ++p) {
        size_t l = link[p];
        int q = table[2 * l] == (int32_t)p ? table[2 * l + 1] : table[2 * l];
        int px = (int)(p % (size_t)w), py = (int)(p / (size_t)w);
        t->dx[p] = (int16_t)tile_delta(q % w - px, w);
        t->dy[p] = (int16_t)tile_delta(q / w - py, w);
    }
    free(link);
    free(table);
    return 0;
}

double pairing_sigma_for_radius(double radius)
{
    double sigma = 2 * radius / (3 * sqrt(1.5707963267948966));
    return sigma < PAIRING_MIN_SIGMA ? PAIRING_MIN_SIGMA : sigma > PAIRING_MAX_SIGMA ? PAIRING_MAX_SIGMA : sigma;
}

int reuse_textures_build(reuse_texture *tex, int count, double sigma, uint32_t seed, rerror *e)
{
    return reuse_textures_build_as(tex, count, sigma, PAIRING_EQ3_DEFAULT, seed, e);
}

int reuse_textures_build_as(reuse_texture *tex, int count, double sigma, enum pairing_eq3 r, uint32_t seed,
                            rerror *e)
{
    int k;
    if (count < 1 || count > PAIRING_MAX_TEXTURES)
        return rerror_set(e, "paired reuse: %d neighbours (1..%d: one reuse texture each)", count, PAIRING_MAX_TEXTURES);
    for (k = 0; k < count; ++k)
        if (reuse_texture_build_as(&tex[k], 254 - 22 * k, sigma, r, seed, (uint32_t)k, e)) {
            reuse_textures_free(tex, k);
            return -1;
        }
    return 0;
}

void reuse_textures_free(reuse_texture *tex, int count)
{
    int k;
    for (k = 0; k < count; ++k) reuse_texture_free(&tex[k]);
}

void reuse_texture_free(reuse_texture *t)
{
    free(t->dx);
    free(t->dy);
    t->dx = t->dy = NULL;
}

reuse_transform reuse_transform_draw(const reuse_texture *t, uint32_t seed, uint32_t sample, uint32_t id)
{
    rng_key key = rng_key_make(seed, 0, sample);
    uint32_t v = PAIRING_TRANSFORM_VERTEX - id;
    reuse_transform f;
    f.flip = rng_u(key, RNG_NEIGHBOR, v, 2) < (real)0.5;
    f.mirror = rng_u(key, RNG_NEIGHBOR, v, 3) < (real)0.5;
    f.transpose = rng_u(key, RNG_NEIGHBOR, v, 4) < (real)0.5;
    f.ox = (int)(rng_u(key, RNG_NEIGHBOR, v, 5) * (real)t->size) % t->size;
    f.oy = (int)(rng_u(key, RNG_NEIGHBOR, v, 6) * (real)t->size) % t->size;
    return f;
}

/* Screen pixel (x, y) -> texel: offset, then flip / mirror / transpose on the torus. The
 * same signed permutation maps texel offsets back to screen offsets, so partners stay
 * partners: texel(p + d_screen) = texel(p) + d_texel. */
void reuse_partner_offset(const reuse_texture *t, const reuse_transform *f, int x, int y, int *dx, int *dy)
{
    int w = t->size, tx = wrap(x + f->ox, w), ty = wrap(y + f->oy, w), tmp, ddx, ddy;
    size_t p;
    if (f->flip) tx = w - 1 - tx;
    if (f->mirror) ty = w - 1 - ty;
    if (f->transpose) {
        tmp = tx;
        tx = ty;
        ty = tmp;
    }
    p = (size_t)ty * (size_t)w + (size_t)tx;
    ddx = t->dx[p];
    ddy = t->dy[p];
    if (f->transpose) {
        tmp = ddx;
        ddx = ddy;
        ddy = tmp;
    }
    if (f->mirror) ddy = -ddy;
    if (f->flip) ddx = -ddx;
    *dx = ddx;
    *dy = ddy;
}
