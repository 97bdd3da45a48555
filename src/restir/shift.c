/* The shift mappings of ReSTIR PT (include/restir/restir/shift.h, docs/restir-pt.md). */
#include "restir/restir/shift.h"

#include "restir/restir/footprint.h"

#include <math.h>
#include <string.h>

static int rgb_finite(rgb c) { return isfinite(c.r) && isfinite(c.g) && isfinite(c.b); }

static enum shift_failure fail(path_sample *y, real *jacobian, enum shift_failure why)
{
    path_sample_clear(y);
    *jacobian = 0;
    return why;
}

/* An offset path without reconnection vertex carries no x_k data. */
static void clear_reconnection(path_sample *s)
{
    s->rc_k = PATH_RC_NONE;
    s->rc_flags = 0;
    s->rc_triangle = 0;
    s->rc_bary[0] = s->rc_bary[1] = 0;
    s->rc_position = s->rc_normal = v3f(0, 0, 0);
    s->rc_wo = v3(0, 0, 0);
    s->rc_pdf_prev = s->rc_geom = s->rc_pdf = 0;
    s->rc_radiance = rgb_gray(0);
}

static void info_clear(shift_info *info)
{
    if (info) memset(info, 0, sizeof *info);
}

/* --ablate footprint-base-only: the footprint criterion tested on the base path alone. */
static int footprint_base_only(const restir_context *c)
{
    return c->rc.mode == RC_MODE_FOOTPRINT && c->ablation == RESTIR_ABLATE_FOOTPRINT_BASE;
}

/* Full random replay (GRIS §7.2; J = 1 in PSS, GRIS §8.1). With `require_no_reconnection`
 * (the hybrid shift of a base path without k) the offset must not have a connectable
 * pair either, or T^{-1} would reconnect and not return to x. */
static enum shift_failure replay_whole_path(const restir_context *c, const path_vertex *y1, const path_sample *x,
                                            path_sample *y, real *jacobian, shift_info *info,
                                            int require_no_reconnection)
{
    path_trunk t;
    path_end end;
    path_sample r = *x;
    int d = x->length;
    enum shift_failure why;
    t.n = 0;
    why = path_replay(&t, c, y1, x, &end);
    if (info) info->replayed = t.n;
    if (why != SHIFT_OK) return fail(y, jacobian, why);
    trunk_lobes(&t, d, x->technique, r.lobe);
    if (require_no_reconnection && !footprint_base_only(c)) {
        rc_vertex v[PATH_MAX_LENGTH + 1];
        trunk_rc_vertices(&t, c, r.lobe, d, &end, x->technique, v);
        if (rc_select(c, v, d) != PATH_RC_NONE) return fail(y, jacobian, SHIFT_FAIL_RC_OFFSET_RECONNECTS);
    }
    clear_reconnection(&r);
    r.light_pdf = end.light_pdf;
    path_sample_set_contribution(&r, end.F);
    if (!rgb_finite(r.F)) return fail(y, jacobian, SHIFT_FAIL_NONFINITE);
    *y = r;
    *jacobian = 1;
    return SHIFT_OK;
}

enum shift_failure hybrid_same_reconnection(const restir_context *c, const path_trunk *t, const path_sample *x)
{
    const scene *s = c->path.scene;
    rc_vertex v[PATH_MAX_LENGTH + 1];
    path_vertex xk;
    int k = x->rc_k, j;
    real threshold = c->rc.roughness_threshold, primary = 0;
    for (j = 1; j < k; ++j) {
        /* y_{k-1} uses the base lobe ell_{k-1} (copied by the reconnection); earlier
         * vertices use the lobes their replayed numbers picked. */
        unsigned lobe = j < k - 1 ? (unsigned)t->b[j].lobe : x->lobe[k - 1];
        v[j].position = t->v[j].position;
        v[j].at_infinity = 0;
        v[j].rough = rc_vertex_is_rough(&t->v[j].b, lobe, threshold);
        v[j].ng = t->v[j].ng;
        v[j].surface = &t->v[j];
        v[j].lobe = lobe;
        v[j].wi = j < k - 1 ? t->b[j].wi
                  : (x->rc_flags & PATH_RC_FLAG_DISTANT) ? light_distant_direction(x->rc_position)
                                                         : v3_normalize(v3_sub(v3_from_f(x->rc_position), t->v[j].position));
    }
    /* x_k with its own lobe ell_k and w_k; the footprint test sees it from y_{k-1}. */
    if (!rc_vertex_of_xk(s, x, threshold, &xk, &v[k])) return SHIFT_FAIL_ZERO;
    if (c->rc.mode == RC_MODE_FOOTPRINT) primary = rc_primary_footprint(&t->v[1]);
    for (j = 2; j < k; ++j)
        if (rc_pair_test(&c->rc, &v[j - 1], &v[j], primary) == SHIFT_OK)
            return j < k - 1 ? SHIFT_FAIL_RC_EARLIER : SHIFT_FAIL_RC_PREV;
    if (rc_forced_nee(&c->rc, v, k, x->length)) return SHIFT_OK; /* Enhanced §6.2.3, as rc_select */
    return rc_pair_test(&c->rc, &v[k - 1], &v[k], primary);
}

/* Replays y_1..y_{k-1} with x's numbers and reconnects y_{k-1} to x_k (for k = 2 the
 * prefix is y_1 alone: the reconnection shift). The PSS Jacobian is 1 for the replayed
 * part times Enhanced Eq. 2 for the reconnection (GRIS §8.1: per-vertex Jacobians
 * multiply). */
static enum shift_failure replay_then_reconnect(const restir_context *c, const path_vertex *y1,
                                                const path_sample *x, path_sample *y, real *jacobian,
                                                shift_info *info, int check_invertibility)
{
    path_trunk t;
    rc_terms terms;
    path_sample r = *x;
    int k = x->rc_k, j;
    enum shift_failure why;
    if (x->rc_flags & PATH_RC_FLAG_UNSHIFTABLE) return fail(y, jacobian, SHIFT_FAIL_UNSHIFTABLE);
    why = trunk_replay(&t, c, y1, x, k - 1);
    if (info) info->replayed = t.n;
    if (why != SHIFT_OK) return fail(y, jacobian, why);
    if (check_invertibility && !footprint_base_only(c) && (why = hybrid_same_reconnection(c, &t, x)) != SHIFT_OK)
        return fail(y, jacobian, why);
    why = rc_evaluate(c, &t.v[k - 1], x, &terms);
    if (info) {
        info->terms = terms;
        info->reconnected = 1;
    }
    if (why != SHIFT_OK) return fail(y, jacobian, why);
    for (j = 1; j < k - 1; ++j) r.lobe[j] = (uint8_t)t.b[j].lobe;
    r.rc_pdf_prev = terms.pdf_prev;
    r.rc_geom = terms.geom;
    r.rc_pdf = terms.pdf_k;
    r.rc_radiance = terms.radiance;
    r.light_pdf = terms.light_pdf;
    r.rc_flags = x->rc_flags & PATH_RC_FLAG_DISTANT; /* the same x_k, at infinity or not */
    path_sample_set_contribution(&r, rgb_mul(t.beta[k - 1], terms.factor));
    *jacobian = rc_jacobian(&terms, x);
    if (!rgb_finite(r.F) || !isfinite(*jacobian) || !(*jacobian > 0)) return fail(y, jacobian, SHIFT_FAIL_NONFINITE);
    *y = r;
    return SHIFT_OK;
}

static int sample_usable(const path_sample *x)
{
    return path_sample_is_valid(x) && x->length >= 2 && x->length <= PATH_MAX_LENGTH;
}

enum shift_failure shift_reconnection(const restir_context *c, const path_vertex *y1, const path_sample *x,
                                      path_sample *y, real *jacobian, shift_info *info)
{
    info_clear(info);
    if (!sample_usable(x)) return fail(y, jacobian, SHIFT_FAIL_EMPTY);
    if (x->rc_k != 2) return fail(y, jacobian, SHIFT_FAIL_UNSHIFTABLE); /* not a reconnection-shift sample */
    return replay_then_reconnect(c, y1, x, y, jacobian, info, 0);
}

enum shift_failure shift_random_replay(const restir_context *c, const path_vertex *y1, const path_sample *x,
                                       path_sample *y, real *jacobian, shift_info *info)
{
    info_clear(info);
    if (!sample_usable(x)) return fail(y, jacobian, SHIFT_FAIL_EMPTY);
    return replay_whole_path(c, y1, x, y, jacobian, info, 0);
}

enum shift_failure shift_hybrid(const restir_context *c, const path_vertex *y1, const path_sample *x, path_sample *y,
                                real *jacobian, shift_info *info)
{
    info_clear(info);
    if (!sample_usable(x)) return fail(y, jacobian, SHIFT_FAIL_EMPTY);
    if (x->rc_k == PATH_RC_NONE) return replay_whole_path(c, y1, x, y, jacobian, info, 1);
    return replay_then_reconnect(c, y1, x, y, jacobian, info, 1);
}

/* The shifted input Y_i = T_i(X_i) (Stochastic MIS Eq. 5; GRIS Eq. 48 per vertex) with
 * its PSS Jacobian, for the configured shift mapping. */
enum shift_failure shift_path(const restir_context *c, const path_vertex *y1, const path_sample *x, path_sample *y,
                              real *jacobian, shift_info *info)
{
    switch (c->shift) {
    case RESTIR_SHIFT_RECONNECTION: return shift_reconnection(c, y1, x, y, jacobian, info);
    case RESTIR_SHIFT_REPLAY: return shift_random_replay(c, y1, x, y, jacobian, info);
    default: return shift_hybrid(c, y1, x, y, jacobian, info);
    }
}
