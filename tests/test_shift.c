/* Shift mappings (include/restir/restir/shift.h) on random paths of the Cornell scenes, the glass
 * room (delta lobes) and the mirror corridor (long replayed prefixes, late reconnection,
 * rough transmission):
 *   - T to the own pixel is the identity with J = 1 (exactly: the source terms are
 *     computed by the code every shift runs);
 *   - every successful T_{a->b}(x) = y shifts back: T_{b->a}(y) = x (same length,
 *     technique, lobes, k, x_k and source terms), F(x) recovered, and
 *     J(a->b) J(b->a) = 1;
 *   - shifts of shifted samples (what spatial pass 2+ does): y is the identity at b,
 *     T_{b->c}(y) = w shifts back to y (J(b->c) J(c->b) = 1) and on to a: T_{c->a}(w) = x
 *     with J(a->b) J(b->c) J(c->a) = 1; under random replay y equals the sample that
 *     path_record builds afresh at b from x's numbers (every stored field), and under
 *     the other shifts y's prefix lobes and stored source terms equal the ones
 *     evaluated afresh at b;
 *   - zero logic failures (a successful shift whose inverse fails or differs).
 * 10^4 paths per scene and shift here; 10^5 in the TEST_LONG version. */
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"

#ifdef RESTIR_REAL_FLOAT
#define F_RTOL 1e-2
#define JJ_RTOL 1e-4
#else
#define F_RTOL 1e-4 /* F of the tree (sampled directions) vs F from the vertices: ill_conditioned() */
#define JJ_RTOL 1e-12
#endif

typedef struct {
    long paths;            /* base paths drawn */
    long identity_ok;      /* identity shifts that succeeded */
    long forward_ok;       /* successful shifts a -> b (each was shifted back) */
    long logic_failures;   /* inverse failed or differed, or the identity was not one */
    long outcome[SHIFT_FAILURE_COUNT]; /* forward shifts a -> b by result */
    long by_k[PATH_MAX_LENGTH + 1], by_k_ok[PATH_MAX_LENGTH + 1];
    long by_replay_ok[PATH_MAX_LENGTH + 1]; /* successful a -> b by replayed bounces (info.replayed - 1) */
    long delta_ok, rough_transmission_ok;   /* successful a -> b of paths with such a lobe */
    long chain_ok, fresh_compared;          /* T_{b->c}(y) succeeded; replay: y compared with path_record */
    double max_f_err, max_jj_err, max_identity_f_err; /* F errors over well-conditioned paths */
    char first_failure[512];
} shift_tally;

static double rel_err(rgb a, rgb b)
{
    double la = luminance(a), lb = luminance(b);
    double d = fmax(fabs(a.r - b.r), fmax(fabs(a.g - b.g), fabs(a.b - b.b)));
    return d / fmax(fmax(la, lb), 1e-300);
}

/* The parts of a path sample that identify the path in the lobe-extended path space. */
static int same_path(const path_sample *a, const path_sample *b)
{
    int j;
    if (a->length != b->length || a->technique != b->technique || a->rc_k != b->rc_k) return 0;
    if (a->seed != b->seed || a->pixel != b->pixel || a->sample != b->sample) return 0;
    for (j = 0; j < PATH_MAX_LENGTH; ++j)
        if (a->lobe[j] != b->lobe[j]) return 0;
    if (a->rc_k == PATH_RC_NONE) return 1;
    return a->rc_triangle == b->rc_triangle && a->rc_position.x == b->rc_position.x &&
           a->rc_position.y == b->rc_position.y && a->rc_position.z == b->rc_position.z &&
           a->rc_wo.x == b->rc_wo.x && a->rc_wo.y == b->rc_wo.y && a->rc_wo.z == b->rc_wo.z &&
           a->rc_pdf_prev == b->rc_pdf_prev && a->rc_geom == b->rc_geom && a->rc_pdf == b->rc_pdf;
}

/* F of a recorded path comes from the sampled directions, F after a shift from the float
 * vertex positions; the two differ by the rounding of the vertices (~1e-7 of their
 * coordinates), which a glossy lobe amplifies near the horizon and on short segments
 * (observed: up to 1.3e-3 at cos 4e-4, 3.5e-4 on a 15 mm segment at cos 0.012). F is
 * compared only on well-conditioned reconnections: both cosines (at x_{k-1}, shading
 * normal, and at x_k) at least 0.02 and the segment at least 2% of the scene diagonal.
 * Structure, J and the success of the inverse shift are checked on every path. */
static int ill_conditioned(const restir_context *c, const path_vertex *x1, const path_sample *x)
{
    path_trunk t;
    vec3 d, w;
    real length;
    int k = x->rc_k;
    if (k == PATH_RC_NONE) return 0;
    if (trunk_replay(&t, c, x1, x, k - 1) != SHIFT_OK) return 1;
    d = v3_sub(v3_from_f(x->rc_position), t.v[k - 1].position);
    length = v3_length(d);
    w = v3_scale(d, 1 / length);
    return fabs(v3_dot(t.v[k - 1].ns, w)) < 0.02 || fabs(v3_dot(v3_from_f(x->rc_normal), w)) < 0.02 ||
           length < rc_min_distance_for_scene(c->path.scene, (real)0.02);
}

/* How much F of x (at its own pixel, vertex x1) moves when x_k moves by one float ulp along
 * an axis: F after a shift is computed from float vertex positions, so this is the scale
 * of the rounding error of any F comparison. Nearly all paths have ~1e-7; refraction
 * through the corridor's rough glass near the critical angle reaches ~1e-2 (observed F
 * errors 6.2e-4 and 2.2e-2 on such paths). */
static double f_sensitivity(const restir_context *c, const path_vertex *x1, const path_sample *x)
{
    path_sample y0, y1;
    real J;
    double worst = 0;
    int axis, sign;
    if (x->rc_k == PATH_RC_NONE || shift_path(c, x1, x, &y0, &J, NULL) != SHIFT_OK) return 0;
    for (axis = 0; axis < 3; ++axis)
        for (sign = -1; sign <= 1; sign += 2) {
            path_sample moved = *x;
            float *p = axis == 0 ? &moved.rc_position.x : axis == 1 ? &moved.rc_position.y : &moved.rc_position.z;
            *p = nextafterf(*p, (float)sign * HUGE_VALF);
            if (shift_path(c, x1, &moved, &y1, &J, NULL) == SHIFT_OK && rel_err(y1.F, y0.F) > worst)
                worst = rel_err(y1.F, y0.F);
        }
    return worst;
}

/* F of x recovered to e: within F_RTOL, or on an ill-conditioned reconnection, or within
 * 8 times the measured rounding sensitivity (one ulp on each of x_{k-1} and x_k, both
 * directions, a factor 2 to spare). */
static int f_close(const restir_context *c, const path_vertex *x1, const path_sample *x, double e)
{
    if (e <= F_RTOL || ill_conditioned(c, x1, x)) return 1;
    return e <= F_RTOL + 8 * f_sensitivity(c, x1, x);
}

/* The reconnection index the offset path y = T_{a->b}(x) selects under its OWN criterion
 * (rc_select on y's vertices: its replayed prefix y_1..y_{k-1}, then x_k..x_d of x), computed
 * independently of the shift's invertibility check. T is a bijection between paths carrying
 * their own k only if this is y.rc_k (GRIS §7.4; Enhanced §4). -1 if a replay fails. */
static int own_reconnection_index(const restir_context *c, const path_vertex *xa, const path_sample *x,
                                  const path_vertex *xb, const path_sample *y)
{
    path_trunk tx, ty;
    path_end ex, ey;
    rc_vertex v[PATH_MAX_LENGTH + 1], vy[PATH_MAX_LENGTH + 1];
    int d = x->length, k = y->rc_k, j;
    if (k == PATH_RC_NONE) { /* y is a full replay: all of it from its own numbers */
        if (path_replay(&ty, c, xb, y, &ey) != SHIFT_OK) return -1;
        trunk_rc_vertices(&ty, c, y->lobe, d, &ey, y->technique, v);
        return rc_select(c, v, d);
    }
    if (path_replay(&tx, c, xa, x, &ex) != SHIFT_OK || trunk_replay(&ty, c, xb, y, k - 1) != SHIFT_OK) return -1;
    trunk_rc_vertices(&tx, c, x->lobe, d, &ex, x->technique, v);
    for (j = 1; j < k; ++j) { /* the offset prefix, its lobes as T assigned them */
        vy[j].position = ty.v[j].position;
        vy[j].at_infinity = 0;
        vy[j].rough = rc_vertex_is_rough(&ty.v[j].b, y->lobe[j], c->rc.roughness_threshold);
        vy[j].ng = ty.v[j].ng;
        vy[j].surface = &ty.v[j];
        vy[j].lobe = y->lobe[j];
        vy[j].wi = j < k - 1 ? ty.b[j].wi : v3_normalize(v3_sub(v[k].position, ty.v[j].position));
    }
    for (j = k; j <= d; ++j) vy[j] = v[j];
    return rc_select(c, vy, d);
}

static void logic_failure(shift_tally *t, const char *fmt, long i, int reason, double value)
{
    if (!t->logic_failures)
        snprintf(t->first_failure, sizeof t->first_failure, fmt, i, shift_failure_names[reason], value);
    t->logic_failures++;
}

/* Whether x has a delta lobe / a rough (GGX) transmission lobe on x_1..x_{d-1}. */
static void lobe_kinds(const restir_context *c, const path_vertex *x1, const path_sample *x, int *delta, int *rough_t)
{
    path_trunk t;
    int j;
    *delta = *rough_t = 0;
    if (trunk_replay(&t, c, x1, x, x->length - 1) != SHIFT_OK) return;
    for (j = 1; j < x->length; ++j) {
        if (x->lobe[j] == PATH_LOBE_NEE) continue;
        *delta |= bsdf_lobe_is_delta(&t.v[j].b, x->lobe[j]);
        *rough_t |= bsdf_lobe_kind_of(&t.v[j].b, x->lobe[j]) == BSDF_LOBE_GLOSSY_TRANSMISSION;
    }
}

/* Every stored field of two samples of the same path (F to F_RTOL, the rest exactly). */
static int same_fields(const path_sample *a, const path_sample *b)
{
    return same_path(a, b) && a->rc_flags == b->rc_flags && a->light_pdf == b->light_pdf &&
           a->rc_radiance.r == b->rc_radiance.r && a->rc_radiance.g == b->rc_radiance.g &&
           a->rc_radiance.b == b->rc_radiance.b && rel_err(a->F, b->F) <= F_RTOL && a->n_pss == b->n_pss;
}

static uint32_t draw(rng_key key, uint32_t slot, uint32_t n) { return (uint32_t)(rng_u(key, RNG_TEST, 1, slot) * n); }

/* The prefix lobes and the source terms of Enhanced Eq. 2 that a shifted sample y
 * stores must be the ones of y's own domain b: the lobes of y_1..y_{k-2} as replayed at
 * b, and p_{k-1}, G, p_k and the light pdf evaluated from y_{k-1} (bit for bit: the
 * same code computes both). */
static int stored_terms_fresh(const restir_context *c, const path_vertex *xb, const path_sample *y)
{
    path_trunk t;
    rc_terms terms;
    int k = y->rc_k, j;
    if (trunk_replay(&t, c, xb, y, k - 1) != SHIFT_OK) return 0;
    for (j = 1; j < k - 1; ++j)
        if (y->lobe[j] != t.b[j].lobe) return 0;
    if (rc_evaluate(c, &t.v[k - 1], y, &terms) != SHIFT_OK) return 0;
    return terms.pdf_prev == y->rc_pdf_prev && terms.geom == y->rc_geom && terms.pdf_k == y->rc_pdf &&
           terms.light_pdf == y->light_pdf;
}

/* Shifts of the shifted sample y = T_{a->b}(x) (spatial pass 2+): the identity at b,
 * y -> c -> b and y -> c -> a, with the Jacobians multiplying to 1 along the chains;
 * under random replay y must equal the sample recorded afresh at b from x's numbers. */
static void shift_chain(const restir_context *c, const scene *s, const path_vertex *xa, const path_vertex *xb,
                        const path_sample *x, const path_sample *y, real j_ab, rng_key key, long i, int radius, int bx,
                        int by, shift_tally *t)
{
    int cx = bx + (int)draw(key, 4, 2u * radius + 1) - radius, cy = by + (int)draw(key, 5, 2u * radius + 1) - radius;
    path_vertex xc;
    path_sample w, v, back;
    real j_bb, j_bc, j_cb, j_ca;
    enum shift_failure why = shift_path(c, xb, y, &v, &j_bb, NULL);
    if (why != SHIFT_OK || !same_path(&v, y) || j_bb != 1 ||
        !f_close(c, xb, y, rel_err(v.F, y->F))) {
        logic_failure(t, "path %ld: the identity shift of a shifted sample is not the identity (%s, %g)", i, why, 0);
        return;
    }
    if (c->shift == RESTIR_SHIFT_REPLAY) {
        path_sample fresh;
        path_sample_begin(&fresh, x->seed, x->pixel, x->sample);
        fresh.length = x->length;
        fresh.technique = x->technique;
        why = path_record(c, xb, &fresh);
        t->fresh_compared++;
        if (why != SHIFT_OK || !same_fields(&fresh, y)) {
            logic_failure(t, "path %ld: the replayed sample differs from the one recorded at b (%s, F rel %g)", i, why,
                          rel_err(fresh.F, y->F));
            return;
        }
    }
    if (y->rc_k != PATH_RC_NONE && !stored_terms_fresh(c, xb, y)) {
        logic_failure(t, "path %ld: a shifted sample's stored prefix lobes or source terms differ from the ones "
                         "evaluated afresh at b (%s, %g)", i, SHIFT_OK, 0);
        return;
    }
    if (cx < 0 || cy < 0 || cx >= s->width || cy >= s->height || (cx == bx && cy == by)) return;
    if (!rt_primary_vertex(s, cx, cy, &xc)) return;
    if (shift_path(c, &xc, y, &w, &j_bc, NULL) != SHIFT_OK) return;
    t->chain_ok++;
    why = shift_path(c, xb, &w, &v, &j_cb, NULL);
    if (why != SHIFT_OK || !same_path(&v, y)) {
        logic_failure(t, "path %ld: T_{c->b}(T_{b->c}(y)) is not y (%s, %g)", i, why, 0);
        return;
    }
    if (!(fabs((double)j_bc * (double)j_cb - 1) <= JJ_RTOL) ||
        !f_close(c, xb, y, rel_err(v.F, y->F))) {
        logic_failure(t, "path %ld: chain b->c->b: J J - 1 = %2$s%3$g", i, 0, (double)j_bc * (double)j_cb - 1);
        return;
    }
    why = shift_path(c, xa, &w, &back, &j_ca, NULL);
    if (why != SHIFT_OK || !same_path(&back, x)) {
        logic_failure(t, "path %ld: T_{c->a}(T_{b->c}(T_{a->b}(x))) is not x (%s, %g)", i, why, 0);
        return;
    }
    if (!(fabs((double)j_ab * (double)j_bc * (double)j_ca - 1) <= JJ_RTOL) ||
        !f_close(c, xa, x, rel_err(back.F, x->F)))
        logic_failure(t, "path %ld: chain a->b->c->a: J J J - 1 = %2$s%3$g", i, 0,
                      (double)j_ab * (double)j_bc * (double)j_ca - 1);
}

/* One base path of pixel a, shifted to itself and to a random pixel b within `radius`. */
static void one_path(const restir_context *c, const initial_options *io, const scene *s, uint32_t seed, long i,
                     int radius, shift_tally *t)
{
    rng_key key = rng_key_make(seed, (uint32_t)i, 0);
    int ax = (int)draw(key, 0, (uint32_t)s->width), ay = (int)draw(key, 1, (uint32_t)s->height);
    int bx = ax + (int)draw(key, 2, 2u * radius + 1) - radius, by = ay + (int)draw(key, 3, 2u * radius + 1) - radius;
    path_vertex xa, xb;
    reservoir r;
    initial_stats st;
    path_sample y, z;
    real j_ab, j_ba, j_id;
    enum shift_failure why;
    shift_info info;
    memset(&st, 0, sizeof st);
    if (!rt_primary_vertex(s, ax, ay, &xa)) return;
    initial_sample_pixel(c, io, &xa, seed, (uint32_t)(ay * s->width + ax), (uint32_t)i, &r, &st);
    if (!path_sample_is_valid(&r.y)) return;
    t->paths++;
    /* Identity: T_{a->a}(x) = x with J = 1. */
    why = shift_path(c, &xa, &r.y, &y, &j_id, NULL);
    if (why == SHIFT_OK) {
        double e = rel_err(y.F, r.y.F);
        t->identity_ok++;
        if (e > t->max_identity_f_err && !ill_conditioned(c, &xa, &r.y)) t->max_identity_f_err = e;
        if (!same_path(&y, &r.y) || j_id != 1 || !f_close(c, &xa, &r.y, e))
            logic_failure(t, "path %ld: the identity shift is not the identity (%s, F error %g)", i, why, e);
    } else if (!(r.y.rc_flags & PATH_RC_FLAG_UNSHIFTABLE)) {
        logic_failure(t, "path %ld: the identity shift failed: %s (%g)", i, why, 0);
    }
    if (bx < 0 || by < 0 || bx >= s->width || by >= s->height || (bx == ax && by == ay)) return;
    if (!rt_primary_vertex(s, bx, by, &xb)) return;
    t->by_k[r.y.rc_k]++;
    memset(&info, 0, sizeof info);
    why = shift_path(c, &xb, &r.y, &y, &j_ab, &info);
    t->outcome[why]++;
    if (why != SHIFT_OK) return;
    t->forward_ok++;
    t->by_k_ok[r.y.rc_k]++;
    {
        int own = own_reconnection_index(c, &xa, &r.y, &xb, &y);
        if (own >= 0 && own != y.rc_k)
            logic_failure(t, "path %ld (%s): the offset path selects its own k = %g, not T's", i, SHIFT_OK, own);
    }
    why = shift_path(c, &xa, &y, &z, &j_ba, NULL);
    if (why != SHIFT_OK) {
        logic_failure(t, "path %ld: the inverse shift failed: %s (J(a->b) = %g)", i, why, (double)j_ab);
        return;
    }
    {
        double fe = rel_err(z.F, r.y.F), jj = fabs((double)j_ab * (double)j_ba - 1);
        if (fe > t->max_f_err && !ill_conditioned(c, &xa, &r.y)) t->max_f_err = fe;
        if (jj > t->max_jj_err) t->max_jj_err = jj;
        if (!same_path(&z, &r.y)) logic_failure(t, "path %ld: T^-1(T(x)) is another path (%s, %g)", i, SHIFT_OK, 0);
        else if (!f_close(c, &xa, &r.y, fe)) logic_failure(t, "path %ld: F(T^-1(T(x))) differs from F(x) (%s, rel %g)", i, SHIFT_OK, fe);
        else if (!(jj <= JJ_RTOL)) logic_failure(t, "path %ld: J(a->b) J(b->a) - 1 = %2$s%3$g", i, 0, jj);
    }
    {
        int delta, rough_t;
        if (info.replayed >= 1) t->by_replay_ok[info.replayed - 1]++;
        lobe_kinds(c, &xa, &r.y, &delta, &rough_t);
        t->delta_ok += delta;
        t->rough_transmission_ok += rough_t;
    }
    shift_chain(c, s, &xa, &xb, &r.y, &y, j_ab, key, i, radius, bx, by, t);
}

static void print_tally(const char *what, const shift_tally *t)
{
    int i;
    if (!getenv("RESTIR_TEST_VERBOSE")) return;
    fprintf(stderr, "  %s: %ld paths, identity ok %ld, forward ok %ld, logic failures %ld, max |JJ-1| %.2g, max F err "
                    "%.2g (identity %.2g)\n    k:",
            what, t->paths, t->identity_ok, t->forward_ok, t->logic_failures, t->max_jj_err, t->max_f_err,
            t->max_identity_f_err);
    for (i = 0; i <= PATH_MAX_LENGTH; ++i)
        if (t->by_k[i]) fprintf(stderr, " %d: %ld/%ld", i, t->by_k_ok[i], t->by_k[i]);
    fprintf(stderr, "\n    replayed bounces (successful a -> b):");
    for (i = 0; i <= PATH_MAX_LENGTH; ++i)
        if (t->by_replay_ok[i]) fprintf(stderr, " %d: %ld", i, t->by_replay_ok[i]);
    fprintf(stderr, "\n    delta-lobe paths shifted %ld, rough-transmission paths shifted %ld, chains b->c ok %ld, "
                    "replay compared with path_record %ld",
            t->delta_ok, t->rough_transmission_ok, t->chain_ok, t->fresh_compared);
    fprintf(stderr, "\n    failures:");
    for (i = 1; i < SHIFT_FAILURE_COUNT; ++i)
        if (t->outcome[i]) fprintf(stderr, " %s %ld", shift_failure_names[i], t->outcome[i]);
    fprintf(stderr, "\n");
}

/* n_paths base paths of the scene shifted with `shift` under criterion rc_mode (and an
 * ablation) into *t. Returns 0 if the scene could not be set up. */
static int force_nee; /* Enhanced §6.2.3 in the next tally_shifts */

static int tally_shifts(const char *path, int shift, int rc_mode, real footprint_c, int ablation, long n_paths,
                        shift_tally *t)
{
    scene s;
    light_set lights;
    restir_context c;
    initial_options io;
    rerror e;
    long i;
    char what[256];
    if (path) {
        if (rt_load_scene(path, 48, &s)) return 0;
    } else { /* the spot scene with its floor below the roughness threshold (0.1) */
        size_t mi;
        if (rt_make_spot(&s, 48)) return 0;
        for (mi = 0; mi < s.material_count; ++mi)
            if (s.materials[mi].type == MAT_CONDUCTOR) s.materials[mi].roughness = (real)0.1;
        if (scene_prepare(&s, &e)) {
            scene_free(&s);
            test_fail(__FILE__, __LINE__, "%s", e.msg);
            return 0;
        }
    }
    if (lights_build(&lights, &s, &e)) {
        scene_free(&s);
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return 0;
    }
    rt_context(&c, &s, &lights, shift);
    c.rc.mode = rc_mode;
    if (footprint_c > 0) c.rc.footprint_c = footprint_c;
    c.rc.force_nee = force_nee;
    c.ablation = ablation;
    memset(&io, 0, sizeof io);
    io.trees = 1;
    io.max_depth = 8;
    memset(t, 0, sizeof *t);
    for (i = 0; t->paths < n_paths && i < 4 * n_paths; ++i)
        one_path(&c, &io, &s, test_seed() * 2654435761u + (uint32_t)shift, i, 6, t);
    snprintf(what, sizeof what, "%s %s %s c %g %s", path ? path : "spot-0.1", restir_shift_names[shift], rc_mode_names[rc_mode],
             (double)c.rc.footprint_c, restir_ablation_names[ablation]);
    print_tally(what, t);
    lights_free(&lights);
    scene_free(&s);
    return 1;
}

static void invertibility_under(const char *path, int shift, int rc_mode, real footprint_c, long n_paths)
{
    shift_tally t;
    const char *what = restir_shift_names[shift];
    if (!tally_shifts(path, shift, rc_mode, footprint_c, RESTIR_ABLATE_NONE, n_paths, &t)) return;
    CHECKF(t.paths >= n_paths, "%s %s: only %ld paths", path, what, t.paths);
    CHECKF(t.logic_failures == 0, "%s %s %s: %ld logic failures in %ld paths; first: %s", path, what,
           rc_mode_names[rc_mode], t.logic_failures, t.paths, t.first_failure);
    CHECKF(t.forward_ok > n_paths / 10, "%s %s: only %ld of %ld shifts succeeded", path, what, t.forward_ok, t.paths);
    CHECKF(t.identity_ok > n_paths / 2, "%s %s: only %ld identity shifts succeeded", path, what, t.identity_ok);
    /* The glossy blocks make the hybrid shift's invertibility checks fire: they are exercised. */
    if (shift == RESTIR_SHIFT_HYBRID && strstr(path, "glossy"))
        CHECKF(t.outcome[SHIFT_FAIL_RC_PREV] > 0 && t.outcome[SHIFT_FAIL_RC_EARLIER] > 0 && t.by_k_ok[3] > 0,
               "%s: invertibility checks not exercised (rc_prev %ld, rc_earlier %ld, k = 3 shifts %ld)", path,
               t.outcome[SHIFT_FAIL_RC_PREV], t.outcome[SHIFT_FAIL_RC_EARLIER], t.by_k_ok[3]);
    CHECKF(t.chain_ok > n_paths / 50, "%s: only %ld shifts of shifted samples succeeded", what, t.chain_ok);
    if (strstr(path, "glass"))
        CHECKF(t.delta_ok >= 10, "%s: only %ld paths with a delta lobe shifted", what, t.delta_ok);
    if (!strcmp(path, RT_CORRIDOR)) {
        long late = 0, long_replay = 0;
        int j;
        for (j = 5; j <= PATH_MAX_LENGTH; ++j) late += t.by_k_ok[j];
        for (j = 3; j <= PATH_MAX_LENGTH; ++j) long_replay += t.by_replay_ok[j];
        CHECKF(t.rough_transmission_ok > n_paths / 100, "%s: only %ld rough-transmission paths shifted", what,
               t.rough_transmission_ok);
        /* measured (seeds 1-5): ~1150 of 10^4 paths reconnect at k >= 5, ~1230 replay 3+ bounces */
        if (shift == RESTIR_SHIFT_HYBRID)
            CHECKF(late > n_paths / 30 && long_replay > n_paths / 30,
                   "%s: only %ld successful shifts at k >= 5 and %ld with 3+ replayed bounces", what, late, long_replay);
    }
    /* Enhanced Eq. 5 on the offset path rejects offsets whose own footprint is too small
     * (at c = 0.02 about once in 6000 paths on cornell: required only of the strict c) */
    if (rc_mode == RC_MODE_FOOTPRINT && footprint_c >= 1)
        CHECKF(t.outcome[SHIFT_FAIL_RC_FOOTPRINT] > 0, "%s: the offset's footprint test never fired", path);
}

static void invertibility(const char *path, int shift, long n_paths)
{
    invertibility_under(path, shift, RC_MODE_GRIS, 0, n_paths);
}

static void all_shifts(long n)
{
    int shift;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift) {
        invertibility("scenes/cornell.scene", shift, n);
        if (!test_has_failed()) invertibility("scenes/cornell-glossy.scene", shift, n);
    }
}

/* Delta lobes (the glass room) and long replayed prefixes with late reconnections and
 * rough transmission (the mirror corridor). */
static void coverage_scenes(long n)
{
    int shift;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift) {
        invertibility("scenes/glass.scene", shift, n);
        if (!test_has_failed()) invertibility(RT_CORRIDOR, shift, n);
    }
}

TEST(shift_identity_and_invertibility) { all_shifts(10000); }
TEST(shift_invertibility_delta_and_corridor) { coverage_scenes(10000); }
TEST_LONG(shift_invertibility_delta_and_corridor_1e5) { coverage_scenes(100000); }
TEST_LONG(shift_identity_and_invertibility_1e5) { all_shifts(100000); }

/* Enhanced §4: the footprint criterion depends on the direction x_{k-1} is seen from and
 * on the pixel's primary footprint, so it differs between base and offset path; testing
 * it on the offset too (hybrid_same_reconnection) keeps the hybrid shift a bijection:
 * every successful T_{a->b} shifts back to x with J J = 1 (zero logic failures). */
static void footprint_shifts(long n)
{
    invertibility_under("scenes/cornell.scene", RESTIR_SHIFT_HYBRID, RC_MODE_FOOTPRINT, 0, n);
    if (!test_has_failed())
        invertibility_under("scenes/cornell-glossy.scene", RESTIR_SHIFT_HYBRID, RC_MODE_FOOTPRINT, 0, n);
    /* a 100x stricter c (any c must keep T bijective): the footprints, the inverse one
     * at glossy x_k included, decide far more pairs */
    if (!test_has_failed())
        invertibility_under("scenes/cornell-glossy.scene", RESTIR_SHIFT_HYBRID, RC_MODE_FOOTPRINT, 2, n);
}
TEST(shift_footprint_invertibility) { footprint_shifts(6000); }
TEST_LONG(shift_footprint_invertibility_1e5) { footprint_shifts(100000); }

/* Enhanced §6.2.3 forced NEE light reconnection, under both criteria, on the spot scene
 * with a 0.1-rough floor (NEE there has no connectable pair unless forced): still a
 * bijection (the offset's own rc_select forces the same k = d only if no earlier pair
 * passes), and forcing adds successful reconnections at k = d = 3. */
TEST(shift_forced_nee_invertibility)
{
    shift_tally t, unforced;
    int mode;
    for (mode = RC_MODE_GRIS; mode <= RC_MODE_FOOTPRINT && !test_has_failed(); ++mode) {
        if (!tally_shifts(NULL, RESTIR_SHIFT_HYBRID, mode, 0, RESTIR_ABLATE_NONE, 4000, &unforced)) return;
        force_nee = 1;
        if (!tally_shifts(NULL, RESTIR_SHIFT_HYBRID, mode, 0, RESTIR_ABLATE_NONE, 4000, &t)) {
            force_nee = 0;
            return;
        }
        force_nee = 0;
        CHECKF(t.logic_failures == 0, "forced NEE (%s): %ld logic failures in %ld paths; first: %s", rc_mode_names[mode],
               t.logic_failures, t.paths, t.first_failure);
        CHECKF(t.by_k_ok[3] > unforced.by_k_ok[3], "forced NEE (%s): k = 3 reconnections %ld, unforced %ld",
               rc_mode_names[mode], t.by_k_ok[3], unforced.by_k_ok[3]);
        if (getenv("RESTIR_TEST_VERBOSE"))
            fprintf(stderr, "  forced NEE (%s): successful k = 3 shifts %ld (unforced %ld), no k %ld (unforced %ld)\n",
                    rc_mode_names[mode], t.by_k_ok[3], unforced.by_k_ok[3], t.by_k_ok[0], unforced.by_k_ok[0]);
    }
}

/* --ablate footprint-base-only (the criterion on the base path alone) breaks the
 * bijection: T^-1(T(x)) reconnects elsewhere or fails. Detected as logic failures. */
TEST(shift_footprint_base_only_not_invertible)
{
    shift_tally t;
    if (!tally_shifts("scenes/cornell-glossy.scene", RESTIR_SHIFT_HYBRID, RC_MODE_FOOTPRINT, 0,
                      RESTIR_ABLATE_FOOTPRINT_BASE, 6000, &t))
        return;
    CHECKF(t.logic_failures > 0, "footprint-base-only: no logic failure in %ld paths (%ld forward shifts)", t.paths,
           t.forward_ok);
    if (getenv("RESTIR_TEST_VERBOSE")) fprintf(stderr, "  base-only: %ld logic failures in %ld forward shifts\n",
                                               t.logic_failures, t.forward_ok);
}

/* Every failure reason has a name (the --stats keys) and the tables are complete. */
TEST(shift_failure_names_complete)
{
    int i;
    for (i = 0; i < SHIFT_FAILURE_COUNT; ++i) CHECKF(shift_failure_names[i] != NULL, "reason %d has no name", i);
    CHECK(shift_failure_names[SHIFT_FAILURE_COUNT] == NULL);
    CHECK(restir_shift_names[RESTIR_SHIFT_COUNT] == NULL && restir_ablation_names[RESTIR_ABLATION_COUNT] == NULL);
    CHECK(!strcmp(shift_failure_names[SHIFT_FAIL_RC_PREV], "rc_prev") && !strcmp(shift_failure_names[SHIFT_FAIL_ZERO], "zero"));
}

/* Textured surfaces and cut-outs (scenes/textured-room.scene, docs/materials.md "Textures"):
 * the identity shift reproduces F exactly only if a reconnection vertex re-evaluates its
 * textured BSDF from its own stored triangle and barycentrics; every shift stays invertible
 * with the alpha test in all of its rays. */
TEST(shift_identity_textured_room)
{
    int shift;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift)
        invertibility("scenes/textured-room.scene", shift, 3000);
}
