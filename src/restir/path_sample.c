/* Path samples: construction and the structural invariants of include/restir/restir/path_sample.h. */
#include "restir/restir/path_sample.h"

#include <math.h>
#include <string.h>

void path_sample_clear(path_sample *s)
{
    memset(s, 0, sizeof *s);
    memset(s->lobe, PATH_LOBE_NONE, sizeof s->lobe);
    s->technique = PATH_TECH_NONE;
    s->rc_k = PATH_RC_NONE;
    s->pss = NULL; /* no explicit numbers: a vector of zeros (path_sample.h) */
}

void path_sample_begin(path_sample *s, uint32_t seed, uint32_t pixel, uint32_t sample)
{
    path_sample_clear(s);
    s->seed = seed;
    s->pixel = pixel;
    s->sample = sample;
}

rng_key path_sample_key(const path_sample *s) { return rng_key_make(s->seed, s->pixel, s->sample); }

int path_sample_is_valid(const path_sample *s) { return s->technique != PATH_TECH_NONE; }

unsigned path_sample_rc_lobe(const path_sample *s)
{
    if (s->rc_k == PATH_RC_NONE || s->rc_k >= s->length) return PATH_LOBE_NONE;
    return s->lobe[s->rc_k];
}

void path_sample_set_contribution(path_sample *s, rgb F)
{
    s->F = F;
    s->target = luminance(F);
}

void path_sample_copy_pss(const path_sample *s, real *to)
{
    int i;
    for (i = 0; i < PATH_MAX_PSS; ++i) to[i] = s->pss ? s->pss[i] : 0;
}

void path_sample_keep_pss(path_sample *s, real *home)
{
    if (!s->pss || s->pss == home) return;
    memcpy(home, s->pss, PATH_MAX_PSS * sizeof *home);
    s->pss = home;
}

static int finite_nonneg(real v) { return isfinite(v) && v >= 0; }
static int rgb_finite_nonneg(rgb c) { return finite_nonneg(c.r) && finite_nonneg(c.g) && finite_nonneg(c.b); }

/* Unit length within what float storage of a normalised vector can lose. */
static int is_unit(real x, real y, real z)
{
    real len2 = x * x + y * y + z * z;
    return isfinite(len2) && fabs(len2 - 1) <= 1e-4;
}

static int check_lobes(const path_sample *s, const char *what, rerror *e)
{
    int j, d = s->length;
    for (j = 0; j < PATH_MAX_LENGTH; ++j) {
        unsigned l = s->lobe[j];
        int scattering = j >= 1 && j <= d - 1;
        int nee_vertex = scattering && j == d - 1 && s->technique == PATH_TECH_NEE;
        if (!scattering && l != PATH_LOBE_NONE)
            return rerror_set(e, "%s: lobe[%d] = %u but x%d is not a scattering vertex of a length-%d path", what,
                              j, l, j, d);
        if (nee_vertex && l != PATH_LOBE_NEE)
            return rerror_set(e, "%s: NEE path must have lobe[%d] = NEE (0x%X), found %u", what, j, PATH_LOBE_NEE,
                              l);
        if (scattering && !nee_vertex && l >= PATH_LOBE_NEE)
            return rerror_set(e, "%s: lobe[%d] = %u is not a lobe index", what, j, l);
    }
    return 0;
}

static int check_reconnection(const path_sample *s, const char *what, rerror *e)
{
    int k = s->rc_k, d = s->length;
    if (k == PATH_RC_NONE) {
        if (s->rc_flags) return rerror_set(e, "%s: rc_flags = %u without a reconnection vertex", what, s->rc_flags);
        return 0;
    }
    if (s->rc_flags & ~(PATH_RC_FLAG_UNSHIFTABLE | PATH_RC_FLAG_DISTANT))
        return rerror_set(e, "%s: unknown rc_flags bits 0x%X", what,
                          s->rc_flags & ~(PATH_RC_FLAG_UNSHIFTABLE | PATH_RC_FLAG_DISTANT));
    if (k < 2 || k > d) return rerror_set(e, "%s: reconnection index k = %d outside [2, d = %d]", what, k, d);
    if ((s->rc_flags & PATH_RC_FLAG_DISTANT) && k != d)
        return rerror_set(e, "%s: x_k at infinity must be the last vertex (k = %d, d = %d)", what, k, d);
    if ((s->rc_flags & PATH_RC_FLAG_DISTANT) && !is_unit(s->rc_position.x, s->rc_position.y, s->rc_position.z))
        return rerror_set(e, "%s: the direction of x_k at infinity is not a unit vector", what);
    if (!isfinite(s->rc_bary[0]) || !isfinite(s->rc_bary[1]) || !isfinite(s->rc_position.x) ||
        !isfinite(s->rc_position.y) || !isfinite(s->rc_position.z))
        return rerror_set(e, "%s: reconnection vertex position is not finite", what);
    if (!is_unit(s->rc_normal.x, s->rc_normal.y, s->rc_normal.z))
        return rerror_set(e, "%s: geometric normal at x_k is not a unit vector", what);
    if (k < d && !is_unit(s->rc_wo.x, s->rc_wo.y, s->rc_wo.z))
        return rerror_set(e, "%s: omega_k is not a unit vector", what);
    if (k == d && (s->rc_wo.x != 0 || s->rc_wo.y != 0 || s->rc_wo.z != 0))
        return rerror_set(e, "%s: omega_k must be zero when x_k is the last vertex", what);
    if (!finite_nonneg(s->rc_pdf_prev) || !finite_nonneg(s->rc_geom) || !finite_nonneg(s->rc_pdf))
        return rerror_set(e, "%s: Jacobian source pdfs must be finite and >= 0", what);
    if (!rgb_finite_nonneg(s->rc_radiance))
        return rerror_set(e, "%s: suffix radiance must be finite and >= 0", what);
    return 0;
}

static int check_pss(const path_sample *s, const char *what, rerror *e)
{
    int i;
    if (s->n_pss > PATH_MAX_PSS) return rerror_set(e, "%s: n_pss = %d > %d", what, s->n_pss, PATH_MAX_PSS);
    if (s->n_pss > 0 && !s->pss) return rerror_set(e, "%s: n_pss = %d without numbers", what, s->n_pss);
    for (i = 0; i < s->n_pss; ++i)
        if (!(s->pss[i] >= 0 && s->pss[i] < 1))
            return rerror_set(e, "%s: pss[%d] = %g is not in [0, 1)", what, i, (double)s->pss[i]);
    return 0;
}

int path_sample_check(const path_sample *s, const char *what, rerror *e)
{
    if (s->technique == PATH_TECH_NONE) {
        if (s->length != 0 || s->rc_k != PATH_RC_NONE)
            return rerror_set(e, "%s: an empty sample must have length 0 and no reconnection vertex", what);
        return 0;
    }
    if (s->technique != PATH_TECH_NEE && s->technique != PATH_TECH_BSDF)
        return rerror_set(e, "%s: technique %d is not NEE (1) or BSDF (2)", what, s->technique);
    if (s->length < 2 || s->length > PATH_MAX_LENGTH)
        return rerror_set(e, "%s: path length d = %d outside [2, %d]", what, s->length, PATH_MAX_LENGTH);
    if (check_lobes(s, what, e) || check_reconnection(s, what, e) || check_pss(s, what, e)) return -1;
    if (!finite_nonneg(s->light_pdf)) return rerror_set(e, "%s: light pdf must be finite and >= 0", what);
    if (!rgb_finite_nonneg(s->F) || !finite_nonneg(s->target))
        return rerror_set(e, "%s: contribution F and target must be finite and >= 0", what);
    return 0;
}
