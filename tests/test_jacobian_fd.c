/* The analytic PSS Jacobian of a reconnection (Enhanced Eq. 2 = GRIS Eq. 52 converted by
 * GRIS Eq. 54, with the lobe-selection probabilities of the lobe-extended PSS) against a
 * finite-difference Jacobian of the map u^x -> u^y of the random numbers themselves:
 *
 *   u^x = (lobe, u1, u2) at x_{k-1} and (lobe, u1, u2) at x_k  --(path sampler)-->  x_k, w_k
 *   u^y = the numbers with which the OFFSET path would sample the same x_k and w_k:
 *         direction numbers by the inverse sampling routines (bsdf_lobe_sample_inverse) at
 *         y_{k-1} and at x_k seen from y_{k-1}; the lobe number mapped affinely from the
 *         base lobe's interval [lo, hi) onto the offset's (bsdf_lobe_interval).
 *
 * det(du^y/du^x) is taken by central differences (steps 1e-3 and 5e-4, Richardson
 * extrapolation), with x_k and w_k computed in double precision from the sampled
 * directions; it must equal the J the shift returns to 1e-4 (observed: <= 2e-5; the
 * analytic J works from float vertex positions). The finite differences do not call the
 * shift code: they only sample, intersect a plane and invert the samplers. With the lobe
 * selection probabilities left out of the pdfs the test fails (0.3% off on the plastic). Cases: reconnection at k = 2 (mid-path), at k > 2 (hybrid shift after a
 * replayed glossy vertex), and at the light vertex (k = d, BSDF-hit emitter, and the NEE
 * light vertex whose Jacobian is exactly 1: NEE numbers map to themselves).
 *
 * Issue 9 cases: k = d-1 with NEE (x_k samples x_d by NEE: omega_k comes from the light
 * numbers, which map to themselves, so only the three numbers at x_{k-1} move and the
 * map is 3 x 3. It was excluded because the 6-variable map sampled a BSDF lobe at x_k,
 * which an NEE vertex does not have: no path was ever accepted); a delta lobe in the
 * replayed prefix (glass room); rough transmission at x_{k-1} or x_k and k >= 5 (the
 * mirror corridor). A delta lobe can only sit in the replayed prefix (PSS Jacobian 1
 * there) or after x_k (inside the stored suffix radiance): x_{k-1} and x_k themselves
 * are never delta (a Dirac cannot reach a fixed x_k: SHIFT_FAIL_DELTA_LOBE). */
#include <stdlib.h>
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/scene/scene_trace.h"

#define FD_STEP 1e-3
#ifdef RESTIR_REAL_FLOAT
#define FD_RTOL 1e-2 /* the differences themselves are taken in float */
#else
#define FD_RTOL 1e-4 /* stated tolerance: the analytic J uses the float vertex positions */
#endif

typedef struct {
    const restir_context *c;
    const path_sample *x; /* the recorded base path (rc_k = k) */
    path_trunk ta;        /* base prefix x_1..x_{k-1} (pixel a) */
    path_trunk tb;        /* offset prefix y_1..y_{k-1} (pixel b) */
    int k, nvars;         /* nvars = 3 (x_k = x_d) or 6 */
} fd_setup;

static void to_local_u(const path_vertex *v, int lobe, vec3 w, real *u1, real *u2, int *ok)
{
    vec2 u;
    if (!bsdf_lobe_sample_inverse(&v->b, lobe, v->wo_local, shading_frame_to_local(&v->frame, w), &u)) *ok = 0;
    *u1 = u.x;
    *u2 = u.y;
}

/* The offset's lobe number: the affine map of [lo_x, hi_x) onto [lo_y, hi_y). */
static real map_lobe_number(const path_vertex *vx, const path_vertex *vy, int lobe, real u)
{
    real lo_x, hi_x, lo_y, hi_y;
    bsdf_lobe_interval(&vx->b, vx->wo_local, lobe, &lo_x, &hi_x);
    bsdf_lobe_interval(&vy->b, vy->wo_local, lobe, &lo_y, &hi_y);
    return lo_y + (u - lo_x) * (hi_y - lo_y) / (hi_x - lo_x);
}

/* The point where the ray (o, w) meets the plane of triangle `tri`, in double precision,
 * if it lies inside the triangle. The finite differences need positions that are smooth
 * in u; float hit points would add noise of ~1e-7 of the coordinates to each difference. */
static int hit_triangle_exactly(const scene *s, uint32_t tri, vec3 o, vec3 w, vec3 *p)
{
    const triangle *t = &s->triangles[tri];
    vec3 a = v3_from_f(s->positions[t->v[0]]), b = v3_from_f(s->positions[t->v[1]]),
         c = v3_from_f(s->positions[t->v[2]]);
    vec3 e1 = v3_sub(b, a), e2 = v3_sub(c, a), n = v3_cross(e1, e2), q;
    real denom = v3_dot(n, w), dist, b1, b2, nn = v3_dot(n, n);
    if (denom == 0) return 0;
    dist = v3_dot(n, v3_sub(a, o)) / denom;
    if (!(dist > 0)) return 0;
    *p = v3_add(o, v3_scale(w, dist));
    q = v3_sub(*p, a);
    b1 = v3_dot(v3_cross(q, e2), n) / nn;
    b2 = v3_dot(v3_cross(e1, q), n) / nn;
    return b1 >= 0 && b2 >= 0 && b1 + b2 <= 1;
}

/* Phi(u^x) = u^y; 0 if the perturbed base path leaves the structure (another lobe or
 * triangle, or a sampling failure). Everything after the fixed prefixes is computed in
 * double precision from the sampled directions. */
static int phi(const fd_setup *f, const real *ux, real *uy)
{
    const scene *s = f->c->path.scene;
    path_trunk t = f->ta;
    const path_vertex *xprev, *yprev = &f->tb.v[f->k - 1];
    int lobe_prev = f->x->lobe[f->k - 1], ok = 1;
    vec3 origin, xk, w;
    path_vertex vk;
    surface_hit h;
    if (trunk_sample(&t, ux) != SHIFT_OK || t.b[f->k - 1].lobe != lobe_prev) return 0;
    xprev = &t.v[f->k - 1];
    origin = v3_from_f(
        scene_spawn_ray(xprev->hit.position, xprev->hit.ng, v3f_from(t.b[f->k - 1].wi), v3f_from(xprev->wo)).origin);
    if (!hit_triangle_exactly(s, f->x->rc_triangle, origin, t.b[f->k - 1].wi, &xk)) return 0;
    /* x_k as the base path arrives at it (for the sampling at x_k). */
    scene_surface_point(s, f->x->rc_triangle, f->x->rc_bary[0], f->x->rc_bary[1], &h);
    path_vertex_make(&vk, s, &h, t.b[f->k - 1].wi);
    /* The offset's direction to x_k from its ray origin (as the path sampler would trace it). */
    origin = v3_from_f(scene_spawn_ray(yprev->hit.position, yprev->hit.ng, v3f_sub(v3f_from(xk), yprev->hit.position),
                                       v3f_from(yprev->wo))
                           .origin);
    w = v3_normalize(v3_sub(xk, origin));
    uy[0] = map_lobe_number(xprev, yprev, lobe_prev, ux[0]);
    to_local_u(yprev, lobe_prev, w, &uy[1], &uy[2], &ok);
    if (f->nvars == 6) {
        int lobe_k = f->x->lobe[f->k];
        path_vertex seen_from_y;
        bsdf_bounce b;
        if (!vertex_sample_bsdf_numbers(&vk, ux[3], v2(ux[4], ux[5]), &b) || b.lobe != lobe_k) return 0;
        path_vertex_make(&seen_from_y, s, &h, w);
        uy[3] = map_lobe_number(&vk, &seen_from_y, lobe_k, ux[3]);
        to_local_u(&seen_from_y, lobe_k, b.wi, &uy[4], &uy[5], &ok);
    }
    return ok;
}

/* Column i of dPhi/du by a central difference with step h; 0 if a perturbation leaves
 * the structure. */
static int fd_column(const fd_setup *f, const real *u0, int i, double h, double *col)
{
    real up[6], um[6], yp[6], ym[6];
    int r;
    memcpy(up, u0, sizeof up);
    memcpy(um, u0, sizeof um);
    up[i] += (real)h;
    um[i] -= (real)h;
    if (!phi(f, up, yp) || !phi(f, um, ym)) return 0;
    for (r = 0; r < f->nvars; ++r) col[r] = ((double)yp[r] - (double)ym[r]) / (2 * h);
    return 1;
}

/* |det dPhi/du| at u0: central differences with steps h and h/2 combined by Richardson
 * extrapolation (error O(h^4)); 0 if a perturbation leaves the structure. */
static double fd_jacobian(const fd_setup *f, const real *u0)
{
    double m[6][6], coarse[6], fine[6];
    int i, r;
    for (i = 0; i < f->nvars; ++i) {
        if (!fd_column(f, u0, i, FD_STEP, coarse) || !fd_column(f, u0, i, FD_STEP / 2, fine)) return 0;
        for (r = 0; r < f->nvars; ++r) m[r][i] = (4 * fine[r] - coarse[r]) / 3;
    }
    return fabs(rt_determinant(m, f->nvars));
}

enum fd_case {
    FD_K2 = 0, FD_K_GT_2 = 1, FD_LIGHT_BSDF = 2, FD_LIGHT_NEE = 3,
    FD_K_NEE = 4,       /* k = d-1 with x_k the NEE vertex: omega_k is the NEE direction */
    FD_DELTA_PREFIX = 5, /* a delta lobe in the replayed prefix x_1..x_{k-2} */
    FD_ROUGH_T = 6,     /* rough transmission at x_{k-1}, or x_k on a rough dielectric */
    FD_LATE = 7         /* k >= 5 (the corridor: 3+ replayed glossy bounces) */
};
static const char *const fd_case_names[] = {"k = 2", "k > 2", "light vertex (BSDF hit)", "light vertex (NEE)",
                                            "k = d-1 (NEE)", "delta lobe in the prefix", "rough transmission",
                                            "k >= 5"};

static int wanted(enum fd_case which, const path_sample *x)
{
    int k = x->rc_k, d = x->length;
    if (k == PATH_RC_NONE || (x->rc_flags & PATH_RC_FLAG_UNSHIFTABLE)) return 0;
    switch (which) {
    case FD_K2: return k == 2 && d >= 4 && x->lobe[2] != PATH_LOBE_NEE;
    case FD_K_GT_2: return k >= 3 && k < d && x->lobe[k] != PATH_LOBE_NEE;
    case FD_LIGHT_BSDF: return k == d && x->technique == PATH_TECH_BSDF;
    case FD_LIGHT_NEE: return k == d && x->technique == PATH_TECH_NEE;
    case FD_K_NEE: return k == d - 1 && x->lobe[k] == PATH_LOBE_NEE;
    case FD_DELTA_PREFIX: return k >= 3 && !(k == d && x->technique == PATH_TECH_NEE);
    case FD_LATE: return k >= 5 && !(k == d && x->technique == PATH_TECH_NEE);
    default: return !(k == d && x->technique == PATH_TECH_NEE);
    }
}

/* The cases that need the replayed prefix (f->ta) to decide. */
static int wanted_prefix(enum fd_case which, const fd_setup *f)
{
    const scene *s = f->c->path.scene;
    int j;
    switch (which) {
    case FD_DELTA_PREFIX:
        for (j = 1; j < f->k - 1; ++j)
            if (bsdf_lobe_is_delta(&f->ta.v[j].b, f->x->lobe[j])) return 1;
        return 0;
    case FD_ROUGH_T:
        return bsdf_lobe_kind_of(&f->ta.v[f->k - 1].b, f->x->lobe[f->k - 1]) == BSDF_LOBE_GLOSSY_TRANSMISSION ||
               s->materials[s->triangles[f->x->rc_triangle].material].type == MAT_ROUGH_DIELECTRIC;
    default: return 1;
    }
}

/* The base numbers at x_{k-1} (and x_k), with the lobe numbers moved to the middle of
 * their intervals (the same path: only the interval matters) so +-h stays inside.
 * 0 if a direction number lies within 5h of 0 or 1. */
static int base_numbers(const fd_setup *f, real *u)
{
    int j, v;
    for (v = 0; v < f->nvars / 3; ++v) {
        int vertex = f->k - 1 + v;
        const path_vertex *pv;
        real lo, hi;
        path_bsdf_numbers(f->x, vertex, u + 3 * v);
        for (j = 1; j < 3; ++j)
            if (u[3 * v + j] < 5 * FD_STEP || u[3 * v + j] > 1 - 5 * FD_STEP) return 0;
        if (v == 0) pv = &f->ta.v[vertex];
        else {
            path_trunk t = f->ta;
            if (trunk_sample(&t, u) != SHIFT_OK || trunk_trace(&t, f->c->path.scene) != SHIFT_OK) return 0;
            pv = &t.v[vertex];
            bsdf_lobe_interval(&pv->b, pv->wo_local, f->x->lobe[vertex], &lo, &hi);
            u[3 * v] = (lo + hi) / 2;
            if (hi - lo < 20 * FD_STEP) return 0;
            continue;
        }
        bsdf_lobe_interval(&pv->b, pv->wo_local, f->x->lobe[vertex], &lo, &hi);
        if (hi - lo < 20 * FD_STEP) return 0;
        u[3 * v] = (lo + hi) / 2;
    }
    return 1;
}

/* Central differences with a step of 1e-3 need the map to be close to linear over the
 * step: both reconnection segments at least 5% of the scene's diagonal long (near a
 * corner, where a segment is millimetres long, the step moves x_k by more than the
 * segment and the difference quotient is meaningless). */
static int well_conditioned(const fd_setup *f, const scene *s)
{
    real min_length = rc_min_distance_for_scene(s, (real)0.05);
    vec3 xk = v3_from_f(f->x->rc_position);
    int lobe = f->x->lobe[f->k - 1];
    /* The reconnection shift reconnects from whatever x_1 is; from a sharp glossy lobe
     * (the corridor's 0.05 walls) the pdf towards x_k changes by ~1e-4 relative with the
     * float rounding of the vertices (observed: 2e-4 on a J of 8e-4), which the analytic
     * J sees and the exact finite differences do not. Both ends at x_{k-1} must be rough
     * under the default threshold (as the hybrid shift requires anyway). */
    if (!bsdf_lobe_is_rough(&f->ta.v[f->k - 1].b, lobe, (real)0.2) ||
        !bsdf_lobe_is_rough(&f->tb.v[f->k - 1].b, lobe, (real)0.2))
        return 0;
    return v3_length(v3_sub(xk, f->ta.v[f->k - 1].position)) >= min_length &&
           v3_length(v3_sub(xk, f->tb.v[f->k - 1].position)) >= min_length;
}

/* The samplers are smooth inside [0,1)^2 except on a few lines: the concentric disk map
 * of the cosine lobe (Shirley & Chiu 1997) has kinks on the diagonals u1 = u2 and
 * u1 + u2 = 1 and, like any disk map, derivatives ~1/r near its centre (the pole of the
 * hemisphere); the polar map of the GGX lobe wraps at u2 = 0 / 1. A central difference
 * straddling a kink, or taken where the second derivatives are ~1/r^2, measures
 * nothing; skip numbers (base and offset) within 4 steps of a kink or with disk radius
 * max(|2u1 - 1|, |2u2 - 1|) < 0.25. */
static int pair_clear(real u1, real u2)
{
    real margin = 4 * (real)FD_STEP;
    return u1 > margin && u1 < 1 - margin && u2 > margin && u2 < 1 - margin && fabs(u1 - u2) > margin &&
           fabs(u1 + u2 - 1) > margin && fmax(fabs(2 * u1 - 1), fabs(2 * u2 - 1)) >= 0.25;
}

static int away_from_kinks(const fd_setup *f, const real *u0)
{
    real uy[6];
    int v;
    if (!phi(f, u0, uy)) return 0;
    for (v = 0; v < f->nvars / 3; ++v)
        if (!pair_clear(u0[3 * v + 1], u0[3 * v + 2]) || !pair_clear(uy[3 * v + 1], uy[3 * v + 2])) return 0;
    return 1;
}

/* Finds base paths of the wanted case whose shift to a nearby pixel succeeds and compares
 * the Jacobians on `count` of them. */
static void fd_case(const char *path, int shift, enum fd_case which, int count, int max_depth)
{
    scene s;
    light_set lights;
    restir_context c;
    initial_options io;
    rerror e;
    int found = 0;
    long i;
    double worst = 0;
    if (rt_load_scene(path, 48, &s)) return;
    if (lights_build(&lights, &s, &e)) {
        scene_free(&s);
        CHECKF(0, "%s", e.msg);
    }
    rt_context(&c, &s, &lights, shift);
    memset(&io, 0, sizeof io);
    io.trees = 1;
    io.max_depth = max_depth;
    for (i = 0; i < 200000 && found < count && !test_has_failed(); ++i) {
        rng_key key = rng_key_make(test_seed() * 31u + (uint32_t)which, (uint32_t)i, 1);
        int ax = (int)(rng_u(key, RNG_TEST, 0, 0) * s.width), ay = (int)(rng_u(key, RNG_TEST, 0, 1) * s.height);
        int bx = ax + 1 + (int)(rng_u(key, RNG_TEST, 0, 2) * 3), by = ay - 1 + (int)(rng_u(key, RNG_TEST, 0, 3) * 3);
        path_vertex xa, xb;
        reservoir r;
        initial_stats st;
        path_sample y;
        real J;
        fd_setup f;
        real u0[6];
        double fd;
        memset(&st, 0, sizeof st);
        if (bx >= s.width || by < 0 || by >= s.height) continue;
        if (!rt_primary_vertex(&s, ax, ay, &xa) || !rt_primary_vertex(&s, bx, by, &xb)) continue;
        initial_sample_pixel(&c, &io, &xa, key.seed, (uint32_t)(ay * s.width + ax), (uint32_t)i, &r, &st);
        if (!path_sample_is_valid(&r.y) || !wanted(which, &r.y)) continue;
        if (shift_path(&c, &xb, &r.y, &y, &J, NULL) != SHIFT_OK) continue;
        if (which == FD_LIGHT_NEE) {
            /* p_light G is the light's area pdf from any receiver: J = 1 up to rounding. */
            CHECKF(fabs(J - 1) < 64 * REAL_EPSILON, "%s %s: NEE light vertex J = %.17g", path, fd_case_names[which],
                   (double)J);
            found++;
            continue;
        }
        f.c = &c;
        f.x = &r.y;
        f.k = r.y.rc_k;
        /* x_k = x_d, or x_k the NEE vertex (k = d-1): the numbers after x_{k-1} map to
         * themselves (light numbers), only x_{k-1}'s three move. */
        f.nvars = f.k == r.y.length || r.y.lobe[f.k] == PATH_LOBE_NEE ? 3 : 6;
        if (trunk_replay(&f.ta, &c, &xa, &r.y, f.k - 1) != SHIFT_OK) continue;
        if (trunk_replay(&f.tb, &c, &xb, &r.y, f.k - 1) != SHIFT_OK) continue;
        if (!wanted_prefix(which, &f)) continue;
        if (!base_numbers(&f, u0) || !well_conditioned(&f, &s) || !away_from_kinks(&f, u0)) continue;
        fd = fd_jacobian(&f, u0);
        if (fd == 0) continue; /* a perturbation crossed a triangle edge or changed the lobe */
        found++;
        if (fabs(fd / J - 1) > worst) worst = fabs(fd / J - 1);
        CHECKF(fabs(fd / J - 1) <= FD_RTOL, "%s %s (k = %d, d = %d, lobes %d %d): analytic J = %.9g, finite differences %.9g",
               path, fd_case_names[which], f.k, r.y.length, r.y.lobe[f.k - 1], r.y.lobe[f.k], (double)J, fd);
    }
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s %s %s: %d paths, max |J_fd / J - 1| = %.2g\n", path, restir_shift_names[shift],
                fd_case_names[which], found, worst);
    lights_free(&lights);
    scene_free(&s);
    CHECKF(found == count, "%s %s: found only %d of %d suitable paths", path, fd_case_names[which], found, count);
}

TEST(shift_jacobian_matches_finite_differences)
{
    fd_case("scenes/cornell.scene", RESTIR_SHIFT_RECONNECTION, FD_K2, 40, 6);
    if (!test_has_failed()) fd_case("scenes/cornell-glossy.scene", RESTIR_SHIFT_HYBRID, FD_K_GT_2, 25, 6);
    if (!test_has_failed()) fd_case("scenes/cornell.scene", RESTIR_SHIFT_RECONNECTION, FD_LIGHT_BSDF, 25, 6);
    if (!test_has_failed()) fd_case("scenes/cornell.scene", RESTIR_SHIFT_RECONNECTION, FD_LIGHT_NEE, 25, 6);
}

/* The cases issue 9 found missing: k = d-1 with NEE (on the plastic blocks: the NEE
 * vertex's all-lobe BSDF; on the corridor after replayed glossy bounces), a delta lobe in the replayed prefix (glass room, hybrid),
 * rough transmission at x_{k-1} or x_k and reconnections after 3+ replayed glossy
 * bounces (the corridor). */
TEST(shift_jacobian_fd_nee_delta_transmission_late)
{
    fd_case("scenes/cornell.scene", RESTIR_SHIFT_RECONNECTION, FD_K_NEE, 25, 6);
    if (!test_has_failed()) fd_case(RT_CORRIDOR, RESTIR_SHIFT_HYBRID, FD_K_NEE, 20, 8); /* after replayed bounces */
    if (!test_has_failed()) fd_case("scenes/glass.scene", RESTIR_SHIFT_HYBRID, FD_DELTA_PREFIX, 20, 8);
#ifndef RESTIR_REAL_FLOAT
    /* In float the differences through the rough glass are off by up to 7.5% (refraction
     * amplifies the float rounding of the differences): no information at 1e-2. */
    if (!test_has_failed()) fd_case(RT_CORRIDOR, RESTIR_SHIFT_HYBRID, FD_ROUGH_T, 20, 8);
#endif
    if (!test_has_failed()) fd_case(RT_CORRIDOR, RESTIR_SHIFT_HYBRID, FD_LATE, 20, 8);
}
