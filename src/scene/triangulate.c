/* Ear clipping in the plane of the polygon (see triangulate.h).
 *
 * An "ear" is a corner b, with neighbours a and c on the remaining polygon, that turns
 * counter-clockwise (orient(a, b, c) > 0) and whose triangle abc contains no other
 * remaining corner, boundary included. Clipping an ear leaves a simple polygon with one
 * corner fewer, and every simple polygon with more than three corners has at least two
 * ears (Meisters 1975, "Polygons have ears"), so for valid input the loop below always
 * finds one. Corners that coincide with a, b or c (the two ends of a bridge edge that
 * joins a hole to the outline) do not block an ear. */
#include "restir/scene/triangulate.h"

#include <math.h>
#include <stdlib.h>

/* Newell's normal of corners[order[0..m-1]] (order NULL: 0..m-1), relative to the first
 * corner: the sum is translation invariant, the rounding is not. */
static void newell(const vec3f *corners, const uint32_t *order, size_t m, double normal[3])
{
    double nx = 0, ny = 0, nz = 0;
    vec3f o = corners[order ? order[0] : 0];
    size_t i;
    for (i = 0; i < m; ++i) {
        vec3f p = corners[order ? order[i] : i], q = corners[order ? order[(i + 1) % m] : (i + 1) % m];
        double px = (double)p.x - o.x, py = (double)p.y - o.y, pz = (double)p.z - o.z;
        double qx = (double)q.x - o.x, qy = (double)q.y - o.y, qz = (double)q.z - o.z;
        nx += (py - qy) * (pz + qz);
        ny += (pz - qz) * (px + qx);
        nz += (px - qx) * (py + qy);
    }
    normal[0] = nx;
    normal[1] = ny;
    normal[2] = nz;
}

vec3 polygon_newell_normal(const vec3f *corners, size_t n)
{
    double normal[3];
    newell(corners, NULL, n, normal);
    return v3((real)normal[0], (real)normal[1], (real)normal[2]);
}

static int reserve(triangulator *t, size_t n, rerror *e)
{
    if (n <= t->capacity) return 0;
    triangulator_free(t);
    t->x = rmalloc(n, sizeof *t->x, e);
    t->y = rmalloc(n, sizeof *t->y, e);
    t->corner = rmalloc(n, sizeof *t->corner, e);
    t->prev = rmalloc(n, sizeof *t->prev, e);
    t->next = rmalloc(n, sizeof *t->next, e);
    t->convex = rmalloc(n, sizeof *t->convex, e);
    if (!t->x || !t->y || !t->corner || !t->prev || !t->next || !t->convex) {
        triangulator_free(t);
        return -1;
    }
    t->capacity = n;
    return 0;
}

void triangulator_free(triangulator *t)
{
    free(t->x);
    free(t->y);
    free(t->corner);
    free(t->prev);
    free(t->next);
    free(t->convex);
    t->convex = NULL;
    t->x = t->y = NULL;
    t->corner = t->prev = t->next = NULL;
    t->capacity = 0;
}

static int same_corner3(vec3f a, vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* Twice the signed area of the projected triangle abc (> 0: counter-clockwise). */
static double orient(const triangulator *t, uint32_t a, uint32_t b, uint32_t c)
{
    return (t->x[b] - t->x[a]) * (t->y[c] - t->y[a]) - (t->y[b] - t->y[a]) * (t->x[c] - t->x[a]);
}

static int same_point(const triangulator *t, uint32_t a, uint32_t b) { return t->x[a] == t->x[b] && t->y[a] == t->y[b]; }

static int is_convex(const triangulator *t, uint32_t b) { return orient(t, t->prev[b], b, t->next[b]) > 0; }

/* If a triangle abc of a (weakly) simple polygon contains any other corner, it contains
 * a reflex or flat one, so only those are tested; a polygon without any (convex) needs
 * no scan at all, which keeps large convex faces linear. */
static int is_ear(const triangulator *t, uint32_t b, size_t not_convex)
{
    uint32_t a = t->prev[b], c = t->next[b], p;
    if (!(orient(t, a, b, c) > 0)) return 0;
    if (!not_convex) return 1;
    for (p = t->next[c]; p != a; p = t->next[p]) {
        if (t->convex[p] || same_point(t, p, a) || same_point(t, p, b) || same_point(t, p, c)) continue;
        if (orient(t, a, b, p) >= 0 && orient(t, b, c, p) >= 0 && orient(t, c, a, p) >= 0) return 0;
    }
    return 1;
}

/* Projects the kept corners onto the plane through corner 0 with normal N, in an
 * orthonormal basis (u, v) with u x v = N / |N|, so the polygon winds counter-clockwise. */
static int project(triangulator *t, const vec3f *corners, size_t m)
{
    double n[3], u[3], v[3], len2, len;
    vec3f o = corners[t->corner[0]];
    size_t i;
    int axis;
    newell(corners, t->corner, m, n);
    len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (!(len2 > 0) || !isfinite(len2)) return 0;
    len = sqrt(len2);
    for (i = 0; i < 3; ++i) n[i] /= len;
    /* u = normalize(e_axis x n) with the axis least aligned with n (well conditioned). */
    axis = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : (fabs(n[1]) <= fabs(n[2]) ? 1 : 2);
    if (axis == 0) u[0] = 0, u[1] = -n[2], u[2] = n[1];
    else if (axis == 1) u[0] = n[2], u[1] = 0, u[2] = -n[0];
    else u[0] = -n[1], u[1] = n[0], u[2] = 0;
    len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (i = 0; i < 3; ++i) u[i] /= len;
    v[0] = n[1] * u[2] - n[2] * u[1]; /* v = n x u, so u x v = n */
    v[1] = n[2] * u[0] - n[0] * u[2];
    v[2] = n[0] * u[1] - n[1] * u[0];
    for (i = 0; i < m; ++i) {
        vec3f p = corners[t->corner[i]];
        double dx = (double)p.x - o.x, dy = (double)p.y - o.y, dz = (double)p.z - o.z;
        t->x[i] = dx * u[0] + dy * u[1] + dz * u[2];
        t->y[i] = dx * v[0] + dy * v[1] + dz * v[2];
    }
    return 1;
}

static void emit(const triangulator *t, uint32_t a, uint32_t b, uint32_t c, uint32_t *tri, size_t *count)
{
    tri[3 * *count + 0] = t->corner[a];
    tri[3 * *count + 1] = t->corner[b];
    tri[3 * *count + 2] = t->corner[c];
    (*count)++;
}

/* A clip changes the neighbours, and so the convexity, of the two corners beside it. */
static void update_convex(triangulator *t, uint32_t b, size_t *not_convex)
{
    unsigned char now = (unsigned char)is_convex(t, b);
    if (now != t->convex[b]) *not_convex += now ? (size_t)-1 : 1;
    t->convex[b] = now;
}

static void unlink_slot(triangulator *t, uint32_t b)
{
    t->next[t->prev[b]] = t->next[b];
    t->prev[t->next[b]] = t->prev[b];
}

/* No proper ear in a whole pass (degenerate or self-intersecting polygon): clip a flat
 * corner (zero turn) if there is one, else a convex one, else the current one. Each
 * call removes one corner, so the triangulation always terminates. */
static uint32_t fallback_corner(const triangulator *t, uint32_t start)
{
    uint32_t b = start;
    do {
        if (orient(t, t->prev[b], b, t->next[b]) == 0) return b;
        b = t->next[b];
    } while (b != start);
    do {
        if (orient(t, t->prev[b], b, t->next[b]) > 0) return b;
        b = t->next[b];
    } while (b != start);
    return start;
}

/* Full passes without an ear tolerated before the rest of the polygon is clipped in
 * place. A simple polygon always has an ear, so only a degenerate or self-intersecting
 * one ever gets here; without a bound every corner of such a polygon could cost a
 * whole failed pass, O(n^2) each (a fuzzed face "f 1 2 3 4 1 2 3 4 ..." of a thousand
 * corners took minutes; tests/data/fuzz/obj/crash-ngon-timeout.obj). */
#define TRIANGULATE_MAX_FAILED_PASSES 16

int triangulate_polygon(triangulator *t, const vec3f *corners, size_t n, uint32_t *tri, size_t *count, rerror *e)
{
    size_t m = 0, i, remaining, stall = 0, not_convex, failed_passes = 0;
    uint32_t cur;
    *count = 0;
    if (n < 3) return 0;
    if (reserve(t, n, e)) return -1;
    /* Skip consecutive repeats (they add only zero-area triangles). */
    for (i = 0; i < n; ++i)
        if (m == 0 || !same_corner3(corners[i], corners[t->corner[m - 1]])) t->corner[m++] = (uint32_t)i;
    while (m > 1 && same_corner3(corners[t->corner[m - 1]], corners[t->corner[0]])) m--;
    if (m < 3) return 0;
    if (m == 3) {
        for (i = 0; i < 3; ++i) tri[i] = t->corner[i];
        *count = 1;
        return 0;
    }
    if (!project(t, corners, m)) return 0;
    for (i = 0; i < m; ++i) {
        t->prev[i] = (uint32_t)(i == 0 ? m - 1 : i - 1);
        t->next[i] = (uint32_t)(i + 1 == m ? 0 : i + 1);
    }
    not_convex = 0;
    for (i = 0; i < m; ++i) not_convex += !(t->convex[i] = (unsigned char)is_convex(t, (uint32_t)i));
    remaining = m;
    cur = 1; /* start at corner 1 so that a convex polygon becomes the fan from corner 0 */
    while (remaining > 3) {
        uint32_t after, before;
        /* After TRIANGULATE_MAX_FAILED_PASSES the polygon is not simple: clip each
         * corner as it comes (a fan from where the scan stands), linear in time. */
        if (failed_passes < TRIANGULATE_MAX_FAILED_PASSES && !is_ear(t, cur, not_convex)) {
            cur = t->next[cur];
            if (++stall < remaining) continue;
            cur = fallback_corner(t, cur);
            failed_passes++;
        }
        emit(t, t->prev[cur], cur, t->next[cur], tri, count);
        before = t->prev[cur];
        after = t->next[cur];
        not_convex -= !t->convex[cur];
        unlink_slot(t, cur);
        update_convex(t, before, &not_convex);
        update_convex(t, after, &not_convex);
        remaining--;
        cur = after;
        stall = 0;
    }
    emit(t, t->prev[cur], cur, t->next[cur], tri, count);
    return 0;
}
