/* BVH, watertight triangle test, ray-origin offsets, scene ray queries, generated scene.
 *
 * The reference for every BVH answer is a loop over all triangles with the same
 * watertight test: the BVH must return the very same triangle, t and barycentrics
 * (bit for bit), and the same any-hit answer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "restir/scene/bvh.h"
#include "restir/scene/generate.h"
#include "restir/core/rng.h"
#include "restir/scene/scene.h"
#include "restir/core/warp.h"
#include "mesh_util.h"
#include "test.h"
#include "restir/scene/scene_trace.h"

/* ------------------------------------------------------------------------------- */
/* Helpers                                                                          */

/* A triangle soup: 3 consecutive vertices per triangle. */
typedef struct {
    vec3f *v;
    size_t count, cap;
} soup;

static void soup_add(soup *m, vec3f a, vec3f b, vec3f c)
{
    if (m->count == m->cap) {
        m->cap = m->cap ? 2 * m->cap : 256;
        m->v = realloc(m->v, 3 * m->cap * sizeof *m->v);
    }
    m->v[3 * m->count] = a;
    m->v[3 * m->count + 1] = b;
    m->v[3 * m->count + 2] = c;
    m->count++;
}

static void soup_free(soup *m)
{
    free(m->v);
    memset(m, 0, sizeof *m);
}

/* Uniform [0,1) from the test stream; `tag` separates the uses within a test. */
static float urand(uint32_t tag, uint32_t i, uint32_t slot)
{
    return rng_uniform_float(rng_key_at(rng_key_make(test_seed(), i, tag), RNG_TEST, 0, slot));
}

static vec3f urand_box(uint32_t tag, uint32_t i, float lo, float hi)
{
    return v3f(lo + (hi - lo) * urand(tag, i, 0), lo + (hi - lo) * urand(tag, i, 1), lo + (hi - lo) * urand(tag, i, 2));
}

static vec3f urand_direction(uint32_t tag, uint32_t i)
{
    return v3f_from(warp_uniform_sphere(v2(urand(tag, i, 3), urand(tag, i, 4))));
}

static ray make_ray(vec3f o, vec3f d)
{
    ray r;
    r.origin = o;
    r.dir = d;
    r.tmin = 0;
    r.tmax = INFINITY;
    return r;
}

static int brute_intersect(const soup *m, const ray *r, bvh_hit *h)
{
    size_t i;
    h->tri = BVH_NO_HIT;
    for (i = 0; i < m->count; ++i) {
        float t, b1, b2;
        if (!ray_triangle_watertight(r, m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2], &t, &b1, &b2)) continue;
        if (h->tri == BVH_NO_HIT || t < h->t) {
            h->t = t;
            h->b1 = b1;
            h->b2 = b2;
            h->tri = (uint32_t)i;
        }
    }
    return h->tri != BVH_NO_HIT;
}

static int brute_occluded(const soup *m, const ray *r)
{
    size_t i;
    for (i = 0; i < m->count; ++i) {
        float t, b1, b2;
        if (ray_triangle_watertight(r, m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2], &t, &b1, &b2)) return 1;
    }
    return 0;
}

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Compares BVH and brute force on one ray; returns 0 and describes the first
 * difference in `why`. Counts hits so that callers can insist on non-trivial cases. */
static int agrees_with_brute_force(const soup *m, const bvh *b, const ray *r, long *hits, char *why, size_t why_size)
{
    bvh_hit hb, hr;
    int fb = bvh_intersect(b, r, &hb), fr = brute_intersect(m, r, &hr);
    int ob = bvh_occluded(b, r), orf = brute_occluded(m, r);
    if (fb != fr || (fb && (hb.tri != hr.tri || !same_bits(hb.t, hr.t) || !same_bits(hb.b1, hr.b1) ||
                            !same_bits(hb.b2, hr.b2)))) {
        snprintf(why, why_size, "closest: bvh %d tri %u t %.9g, brute %d tri %u t %.9g", fb, hb.tri,
                 fb ? (double)hb.t : 0.0, fr, hr.tri, fr ? (double)hr.t : 0.0);
        return 0;
    }
    if (ob != orf || ob != fr) {
        snprintf(why, why_size, "any-hit: bvh %d brute %d closest %d", ob, orf, fr);
        return 0;
    }
    if (fb && !(isfinite(hb.t) && isfinite(hb.b1) && isfinite(hb.b2))) {
        snprintf(why, why_size, "non-finite hit t %g b %g %g", (double)hb.t, (double)hb.b1, (double)hb.b2);
        return 0;
    }
    *hits += fb;
    return 1;
}

/* A random soup: triangles of log-uniform size in [-1,1]^3. */
static void random_soup(soup *m, uint32_t tag, int count)
{
    int i;
    for (i = 0; i < count; ++i) {
        vec3f c = urand_box(tag, (uint32_t)i, -1, 1);
        float size = 0.01f * powf(50.0f, urand(tag, (uint32_t)i, 5));
        vec3f a = v3f_add(c, v3f_scale(urand_box(tag + 1, (uint32_t)i, -1, 1), size));
        vec3f b = v3f_add(c, v3f_scale(urand_box(tag + 2, (uint32_t)i, -1, 1), size));
        vec3f d = v3f_add(c, v3f_scale(urand_box(tag + 3, (uint32_t)i, -1, 1), size));
        soup_add(m, a, b, d);
    }
}

/* Closed meshes over the lattice of a cube's surface, n cells per edge. Every vertex
 * is a function of its lattice point only, so shared vertices are bit-identical and
 * the mesh is closed. shape 0: the cube [-1,1]^3; shape 1: projected to the unit
 * sphere. Then scaled and shifted. Outward winding. */
static vec3f lattice_point(const int p[3], int n, int shape, float scale, vec3f shift)
{
    float c[3];
    int a;
    for (a = 0; a < 3; ++a) c[a] = 2.0f * (float)p[a] / (float)n - 1.0f;
    if (shape == 1) {
        float len = sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for (a = 0; a < 3; ++a) c[a] /= len;
    }
    return v3f(c[0] * scale + shift.x, c[1] * scale + shift.y, c[2] * scale + shift.z);
}

static void closed_mesh(soup *m, int n, int shape, float scale, vec3f shift)
{
    int axis, side, iu, iv, q;
    for (axis = 0; axis < 3; ++axis) {
        int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (side = 0; side < 2; ++side) {
            for (iv = 0; iv < n; ++iv) {
                for (iu = 0; iu < n; ++iu) {
                    vec3f c[4];
                    for (q = 0; q < 4; ++q) {
                        int p[3];
                        p[axis] = side ? n : 0;
                        p[u] = iu + (q == 1 || q == 2);
                        p[v] = iv + (q >= 2);
                        c[q] = lattice_point(p, n, shape, scale, shift);
                    }
                    if (side) {
                        soup_add(m, c[0], c[1], c[2]);
                        soup_add(m, c[0], c[2], c[3]);
                    } else {
                        soup_add(m, c[0], c[2], c[1]);
                        soup_add(m, c[0], c[3], c[2]);
                    }
                }
            }
        }
    }
}

/* A scene over a soup (unshared vertices): one material, one object. */
static int scene_from_soup(scene *s, const soup *m, rerror *e)
{
    size_t i;
    int k;
    memset(s, 0, sizeof *s);
    strcpy(s->path, "test-soup");
    s->positions = malloc(3 * m->count * sizeof *s->positions);
    s->triangles = malloc(m->count * sizeof *s->triangles);
    memcpy(s->positions, m->v, 3 * m->count * sizeof *s->positions);
    s->position_count = 3 * m->count;
    s->triangle_count = m->count;
    for (i = 0; i < m->count; ++i) {
        for (k = 0; k < 3; ++k) {
            s->triangles[i].v[k] = (uint32_t)(3 * i + (size_t)k);
            s->triangles[i].n[k] = -1;
        }
        s->triangles[i].material = 0;
        s->triangles[i].object = 0;
    }
    return scene_prepare(s, e);
}

/* Frees what the tests allocate by hand (scene_free belongs to the scene loader). */
static void free_test_scene(scene *s)
{
    free(s->positions);
    free(s->normals);
    free(s->triangles);
    bvh_free(&s->accel);
    free(s->face_normals);
    memset(s, 0, sizeof *s);
}

static void free_generated_scene(scene *s)
{
    size_t i;
    for (i = 0; i < s->object_count; ++i) free(s->object_names[i]);
    free(s->object_names);
    free(s->materials);
    free_test_scene(s);
}

/* ------------------------------------------------------------------------------- */
/* Structure                                                                         */

/* Every node bounds its subtree, leaves hold 1..8 triangles, every valid triangle
 * is in exactly one leaf; stats are recorded. (The wide tree's leaf blocks:
 * bvh_wide_tree_covers_every_leaf_slot_once.) */
TEST(bvh_structure_valid)
{
    soup m = {0};
    bvh b;
    rerror e;
    size_t i, seen_slots = 0;
    unsigned char *seen;
    random_soup(&m, 10, 20000);
    CHECKF(bvh_build(&b, m.v, m.count, &e) == 0, "%s", e.msg);
    CHECK(sizeof(bvh_node) == 32);
    CHECK(b.prim_count == m.count);
    CHECK(b.node_count >= 1 && b.node_count <= 2 * m.count - 1);
    CHECKF(b.depth > 5 && b.depth < 64, "depth %d", b.depth);
    CHECKF(b.sah_cost > 1 && b.sah_cost < 1000, "sah %g", b.sah_cost);
    seen = calloc(m.count, 1);
    for (i = 0; i < b.node_count; ++i) {
        const bvh_node *n = &b.nodes[i];
        uint32_t count = n->count_axis & 0xffffffu;
        int k;
        if (count == 0) {
            const bvh_node *kids[2];
            int c;
            CHECK(n->offset > i + 1 && n->offset < b.node_count && (n->count_axis >> 24) < 3);
            kids[0] = &b.nodes[i + 1];
            kids[1] = &b.nodes[n->offset];
            for (c = 0; c < 2; ++c)
                for (k = 0; k < 3; ++k) CHECK(kids[c]->min[k] >= n->min[k] && kids[c]->max[k] <= n->max[k]);
        } else {
            uint32_t slot;
            CHECK(count <= 8 && n->offset + count <= b.prim_count);
            for (slot = n->offset; slot < n->offset + count; ++slot) {
                uint32_t tri = b.prim_order[slot];
                CHECK(tri < m.count && !seen[tri]);
                seen[tri] = 1;
                seen_slots++;
                for (k = 0; k < 3; ++k) {
                    vec3f v = m.v[3 * tri + (size_t)k];
                    CHECK(v.x >= n->min[0] && v.x <= n->max[0] && v.y >= n->min[1] && v.y <= n->max[1] &&
                          v.z >= n->min[2] && v.z <= n->max[2]);
                }
            }
        }
    }
    CHECK(seen_slots == m.count);
    free(seen);
    bvh_free(&b);
    soup_free(&m);
}

/* ------------------------------------------------------------------------------- */
/* The collapse to wide nodes is SAH-optimal                                        */

/* bvh.c's collapse cost: a wide node costs WIDE_COST times its box's area, a leaf of n
 * triangles ceil(n / 4) times its box's area, and a subtree of at most MAX_LEAF
 * triangles may be one leaf (bvh.c: WIDE_NODE_COST, sah_blocks, BVH_MAX_LEAF). */
enum { WIDE_COST = 2, MAX_LEAF = 8, MAX_CUTS = 1 << 16 };

static double node_box_area(const bvh_node *n)
{
    double dx = (double)n->max[0] - n->min[0], dy = (double)n->max[1] - n->min[1];
    double dz = (double)n->max[2] - n->min[2];
    return dx < 0 || dy < 0 || dz < 0 ? 0 : 2 * (dx * dy + dy * dz + dz * dx);
}

static double box_rows_area(const bvh_wide_node *n, int k)
{
    double dx = (double)n->bounds[3][k] - n->bounds[0][k], dy = (double)n->bounds[4][k] - n->bounds[1][k];
    double dz = (double)n->bounds[5][k] - n->bounds[2][k];
    return 2 * (dx * dy + dy * dz + dz * dx);
}

/* The cost of the wide tree as built, walked independently of bvh_wide_sah_cost. */
static double walk_wide_cost(const bvh *b, uint32_t at, double area)
{
    const bvh_wide_node *n = &b->wide[at];
    double cost = WIDE_COST * area;
    int k;
    for (k = 0; k < BVH_WIDTH; ++k) {
        if (n->count[k] == 0 && n->child[k] == BVH_WIDE_EMPTY) continue;
        cost += n->count[k] ? (double)((n->count[k] + 3) / 4) * box_rows_area(n, k)
                            : walk_wide_cost(b, n->child[k], box_rows_area(n, k));
    }
    return cost;
}

/* Brute force: every cut of binary subtree x with at most BVH_WIDTH nodes (as lists of
 * node indices), enumerated explicitly (no dynamic programme), once per node. */
typedef struct {
    uint32_t node[BVH_WIDTH];
    int n;
} cut;

typedef struct {
    cut *cuts;
    int count; /* -1: more than MAX_CUTS (the tree is too large for the brute force) */
    int done;
} cut_list;

static int cuts_of(const bvh *b, uint32_t x, cut_list *memo)
{
    const bvh_node *n = &b->nodes[x];
    cut_list *c = &memo[x];
    int i, j, count = 1;
    if (c->done) return c->count;
    c->done = 1;
    if ((n->count_axis & 0xffffffu) == 0) {
        const cut_list *l = &memo[x + 1], *r = &memo[n->offset];
        if (cuts_of(b, x + 1, memo) < 0 || cuts_of(b, n->offset, memo) < 0) return c->count = -1;
        for (i = 0; i < l->count; ++i)
            for (j = 0; j < r->count; ++j) count += l->cuts[i].n + r->cuts[j].n <= BVH_WIDTH;
        if (count > MAX_CUTS) return c->count = -1;
    }
    c->cuts = malloc((size_t)count * sizeof *c->cuts);
    c->cuts[0].node[0] = x;
    c->cuts[0].n = 1;
    c->count = 1;
    if ((n->count_axis & 0xffffffu) == 0) {
        const cut_list *l = &memo[x + 1], *r = &memo[n->offset];
        for (i = 0; i < l->count; ++i)
            for (j = 0; j < r->count; ++j) {
                cut *u = &c->cuts[c->count];
                if (l->cuts[i].n + r->cuts[j].n > BVH_WIDTH) continue;
                *u = l->cuts[i];
                memcpy(u->node + u->n, r->cuts[j].node, (size_t)r->cuts[j].n * sizeof u->node[0]);
                u->n += r->cuts[j].n;
                c->count++;
            }
    }
    return c->count;
}

static uint32_t subtree_triangles(const bvh *b, uint32_t x)
{
    const bvh_node *n = &b->nodes[x];
    if (n->count_axis & 0xffffffu) return n->count_axis & 0xffffffu;
    return subtree_triangles(b, x + 1) + subtree_triangles(b, n->offset);
}

/* The least cost of subtree x as one child (a leaf, or a wide node over the best cut of
 * its two children), by brute force over the cuts; memoised in best[] (< 0: unknown).
 * As the root (as_root), x is a wide node. NAN if the tree is too large. */
static double best_one(const bvh *b, uint32_t x, cut_list *memo, double *best, int as_root)
{
    const bvh_node *n = &b->nodes[x];
    uint32_t count = n->count_axis & 0xffffffu;
    double leaf = INFINITY, wide = INFINITY;
    if (!as_root && best[x] >= 0) return best[x];
    if (count) {
        leaf = (double)((count + 3) / 4) * node_box_area(n);
        wide = WIDE_COST * node_box_area(n) + leaf; /* only the root of a one-leaf tree */
    } else {
        const cut_list *l = &memo[x + 1], *r = &memo[n->offset];
        uint32_t below = subtree_triangles(b, x);
        int i, j, k;
        if (cuts_of(b, x + 1, memo) < 0 || cuts_of(b, n->offset, memo) < 0) return NAN;
        if (below <= MAX_LEAF) leaf = (double)((below + 3) / 4) * node_box_area(n);
        for (i = 0; i < l->count; ++i)
            for (j = 0; j < r->count; ++j) {
                double c = WIDE_COST * node_box_area(n);
                if (l->cuts[i].n + r->cuts[j].n > BVH_WIDTH) continue;
                for (k = 0; k < l->cuts[i].n; ++k) c += best_one(b, l->cuts[i].node[k], memo, best, 0);
                for (k = 0; k < r->cuts[j].n; ++k) c += best_one(b, r->cuts[j].node[k], memo, best, 0);
                wide = c < wide ? c : wide;
            }
    }
    if (as_root) return wide;
    best[x] = leaf < wide ? leaf : wide;
    return best[x];
}

/* The collapse (bvh.c collapse_costs, gather_kids) builds a wide tree whose cost is the
 * minimum over every way of cutting the binary tree into wide nodes and leaves, found
 * here by brute force on small random soups; and bvh_wide_sah_cost reports that cost. */
TEST(bvh_collapse_is_sah_optimal)
{
    int trial, checked = 0;
    for (trial = 0; trial < 400; ++trial) {
        soup m = {0};
        bvh b;
        rerror e;
        double *best, want, got, walked, root;
        cut_list *memo;
        size_t i;
        random_soup(&m, 200 + 4 * (uint32_t)trial, 8 + 6 * (trial % 100));
        CHECKF(bvh_build(&b, m.v, m.count, &e) == 0, "%s", e.msg);
        best = malloc(b.node_count * sizeof *best);
        memo = calloc(b.node_count, sizeof *memo);
        for (i = 0; i < b.node_count; ++i) best[i] = -1;
        root = node_box_area(&b.nodes[0]);
        want = best_one(&b, 0, memo, best, 1) / root;
        walked = walk_wide_cost(&b, 0, root) / root;
        got = bvh_wide_sah_cost(&b);
        if (want == want) {
            checked++;
            CHECKF(fabs(walked - want) <= 1e-5 * want, "trial %d (%zu triangles): wide tree cost %.7g, optimum %.7g",
                   trial, m.count, walked, want);
        }
        CHECKF(fabs(got - walked) <= 1e-9 * walked, "trial %d: bvh_wide_sah_cost %.9g, walked %.9g", trial, got, walked);
        for (i = 0; i < b.node_count; ++i) free(memo[i].cuts);
        free(memo);
        free(best);
        bvh_free(&b);
        soup_free(&m);
    }
    CHECKF(checked >= 360, "only %d of 400 trees small enough for the brute force", checked);
}

/* ------------------------------------------------------------------------------- */
/* BVH == brute force                                                                */

/* Ray i of a brute-force comparison on the soup m (which rays may aim at). */
typedef ray (*ray_maker)(const soup *m, long i);

/* A BVH over m against brute force for the rays make(m, 0..n-1): the same first hit for
 * every ray; *hits counts the rays that hit. 0 if all agree (a test failure names the
 * first ray that does not). */
static int expect_brute_force(const soup *m, long n, ray_maker make, long *hits)
{
    bvh b;
    rerror e;
    char why[256];
    long i;
    if (bvh_build(&b, m->v, m->count, &e)) {
        test_fail(__FILE__, __LINE__, "%s", e.msg);
        return -1;
    }
    for (i = 0; i < n; ++i) {
        ray r = make(m, i);
        if (!agrees_with_brute_force(m, &b, &r, hits, why, sizeof why)) {
            test_fail(__FILE__, __LINE__, "ray %ld: %s", i, why);
            bvh_free(&b);
            return -1;
        }
    }
    bvh_free(&b);
    return 0;
}

static ray soup_ray(const soup *m, long i)
{
    ray r = make_ray(urand_box(30, (uint32_t)i, -1.5f, 1.5f), urand_direction(30, (uint32_t)i));
    /* Every third ray gets a finite, random range: the range must be honoured. */
    if (i % 3 == 1) {
        r.tmin = urand(31, (uint32_t)i, 0) * 0.5f;
        r.tmax = r.tmin + urand(31, (uint32_t)i, 1) * 2.0f;
    }
    /* Every third ray is aimed at a vertex exactly (shared-nothing soup, but it exercises
     * the exactly-zero edge functions and the double fallback). */
    if (i % 3 == 2) r.dir = v3f_sub(m->v[(size_t)i % (3 * m->count)], r.origin);
    return r;
}

TEST(bvh_matches_brute_force_random_soup)
{
    soup m = {0};
    long hits = 0;
    random_soup(&m, 20, 3000);
    if (expect_brute_force(&m, 3000, soup_ray, &hits) == 0) CHECKF(hits > 1000, "only %ld hits", hits);
    soup_free(&m);
}

static ray sphere_ray(const soup *m, long i)
{
    if (i % 2) { /* from outside toward a point near the sphere */
        vec3f o = v3f_scale(urand_direction(40, (uint32_t)i), 4.0f);
        return make_ray(o, v3f_sub(urand_box(41, (uint32_t)i, -1.1f, 1.1f), o));
    } else { /* from inside: aimed exactly at a mesh vertex half of the time */
        vec3f o = urand_box(42, (uint32_t)i, -0.5f, 0.5f);
        return make_ray(o, i % 4 ? urand_direction(42, (uint32_t)i) : v3f_sub(m->v[(size_t)i % (3 * m->count)], o));
    }
}

TEST(bvh_matches_brute_force_sphere)
{
    scene s;
    soup m = {0};
    rerror e;
    long hits = 0;
    size_t t;
    CHECKF(generate_displaced_sphere(&s, 14, &e) == 0, "%s", e.msg);
    for (t = 0; t < s.triangle_count; ++t)
        soup_add(&m, s.positions[s.triangles[t].v[0]], s.positions[s.triangles[t].v[1]],
                 s.positions[s.triangles[t].v[2]]);
    if (expect_brute_force(&m, 3000, sphere_ray, &hits) == 0) CHECKF(hits > 2000, "only %ld hits", hits);
    soup_free(&m);
    free_generated_scene(&s);
}

/* Degenerate triangles (repeated vertices, zero area, exactly collinear) are never hit;
 * axis-aligned triangles and axis-parallel rays (zero direction components, rays lying
 * in a triangle's plane) give no NaN and the same answers as brute force. */
/* One ray through both builds of the queries (bvh.c: b->simd selects the AVX2 build of the
 * same C, the portable build otherwise): the same answer, bit for bit. */
static int simd_agrees(bvh *b, const ray *r, long *hits)
{
    bvh_hit hs, hp;
    int ds, dp, os, op, simd = b->simd;
    memset(&hs, 0, sizeof hs);
    memset(&hp, 0, sizeof hp);
    ds = bvh_intersect(b, r, &hs);
    os = bvh_occluded(b, r);
    b->simd = 0;
    dp = bvh_intersect(b, r, &hp);
    op = bvh_occluded(b, r);
    b->simd = simd;
    *hits += ds;
    return ds == dp && os == op && hs.tri == hp.tri &&
           (!ds || (memcmp(&hs.t, &hp.t, sizeof hs.t) == 0 && memcmp(&hs.b1, &hp.b1, sizeof hs.b1) == 0 &&
                    memcmp(&hs.b2, &hp.b2, sizeof hs.b2) == 0));
}

/* The AVX2 build of the queries (runtime dispatch, bvh.c) returns exactly what the portable
 * build returns: closest hits (triangle, t, barycentrics bit for bit) and any-hit answers,
 * on a displaced sphere and a random soup, for random rays, rays aimed at vertices, axis-
 * parallel rays and rays with a finite range ending near a hit. Where the CPU has no AVX2
 * (or the build has no second path) both runs take the portable path. */
TEST(bvh_simd_path_equals_portable_path)
{
    scene s;
    soup m = {0};
    bvh b;
    rerror e;
    long i, hits = 0;
    size_t t;
    int simd;
    CHECKF(generate_displaced_sphere(&s, 14, &e) == 0, "%s", e.msg);
    for (t = 0; t < s.triangle_count; ++t)
        soup_add(&m, s.positions[s.triangles[t].v[0]], s.positions[s.triangles[t].v[1]],
                 s.positions[s.triangles[t].v[2]]);
    random_soup(&m, 50, 2000);
    CHECKF(bvh_build(&b, m.v, m.count, &e) == 0, "%s", e.msg);
    simd = b.simd;
    for (i = 0; i < 20000; ++i) {
        vec3f o = urand_box(51, (uint32_t)i, -2.0f, 2.0f), d = urand_direction(52, (uint32_t)i);
        ray r;
        if (i % 4 == 1) d = v3f_sub(m.v[(size_t)i % (3 * m.count)], o); /* at a vertex */
        if (i % 8 == 2) { /* axis-parallel: two zero components */
            float c = urand(53, (uint32_t)i, 0) < 0.5f ? -1.0f : 1.0f;
            d = i % 3 == 0 ? v3f(c, 0, 0) : (i % 3 == 1 ? v3f(0, c, 0) : v3f(0, 0, c));
        }
        r = make_ray(o, d);
        if (i % 3 == 2) { /* a range that ends near the closest hit */
            bvh_hit h;
            if (bvh_intersect(&b, &r, &h)) r.tmax = h.t * (i % 2 ? 1.0f : 0.999999f);
        }
        CHECKF(simd_agrees(&b, &r, &hits), "ray %ld: AVX2 and portable builds disagree", i);
    }
    CHECKF(hits > 5000, "only %ld hits", hits);
    if (!simd) printf("     (no AVX2 build of the queries here: both runs took the portable one)\n");
    bvh_free(&b);
    soup_free(&m);
    free_generated_scene(&s);
}

TEST(bvh_degenerate_and_axis_aligned)
{
    soup m = {0};
    bvh b;
    rerror e;
    char why[256];
    long i, hits = 0;
    size_t first_degenerate, degenerate_count, t;
    random_soup(&m, 50, 300);
    first_degenerate = m.count;
    for (i = 0; i < 100; ++i) {
        /* Integer-valued coordinates keep collinear points exactly collinear in float. */
        vec3f a = v3f(floorf(urand(51, (uint32_t)i, 0) * 8 - 4) * 0.25f, floorf(urand(51, (uint32_t)i, 1) * 8 - 4) * 0.25f,
                      floorf(urand(51, (uint32_t)i, 2) * 8 - 4) * 0.25f);
        vec3f d = v3f(floorf(urand(52, (uint32_t)i, 0) * 5 - 2) * 0.125f, floorf(urand(52, (uint32_t)i, 1) * 5 - 2) * 0.125f,
                      floorf(urand(52, (uint32_t)i, 2) * 5 - 2) * 0.125f);
        soup_add(&m, a, a, a);                                            /* a point */
        soup_add(&m, a, v3f_add(a, d), a);                                /* repeated vertex */
        soup_add(&m, a, v3f_add(a, d), v3f_add(a, v3f_scale(d, 2.0f)));  /* collinear */
        soup_add(&m, v3f_add(a, v3f_scale(d, 3.0f)), a, v3f_add(a, d));  /* collinear, other order */
    }
    degenerate_count = m.count - first_degenerate;
    for (i = 0; i < 150; ++i) { /* axis-aligned triangles in the planes x, y or z = const */
        int axis = i % 3;
        float c = floorf(urand(53, (uint32_t)i, 0) * 8 - 4) * 0.25f;
        vec3f p[3];
        int k;
        for (k = 0; k < 3; ++k) {
            float q[3];
            q[axis] = c;
            q[(axis + 1) % 3] = urand(54, (uint32_t)i, (uint32_t)(2 * k)) * 2 - 1;
            q[(axis + 2) % 3] = urand(54, (uint32_t)i, (uint32_t)(2 * k + 1)) * 2 - 1;
            p[k] = v3f(q[0], q[1], q[2]);
        }
        soup_add(&m, p[0], p[1], p[2]);
    }
    CHECKF(bvh_build(&b, m.v, m.count, &e) == 0, "%s", e.msg);
    CHECKF(b.prim_count == m.count - degenerate_count, "prims %zu of %zu, %zu degenerate", b.prim_count, m.count,
           degenerate_count);
    for (i = 0; i < 6000; ++i) {
        ray r = make_ray(urand_box(55, (uint32_t)i, -1.2f, 1.2f), urand_direction(55, (uint32_t)i));
        bvh_hit h;
        switch (i % 4) {
        case 0: /* axis-parallel: two zero components */
            r.dir = v3f(0, 0, 0);
            if (i % 8 == 0) r.dir.x = -1; else r.dir.z = 1;
            break;
        case 1: /* one zero component, origin on a plane of the axis-aligned triangles */
            r.origin.y = floorf(urand(56, (uint32_t)i, 0) * 8 - 4) * 0.25f;
            r.dir.y = 0;
            break;
        case 2: /* aimed exactly at a vertex of a degenerate triangle */
            r.dir = v3f_sub(m.v[3 * (first_degenerate + (size_t)i % degenerate_count) + (size_t)i % 3], r.origin);
            break;
        default:
            break;
        }
        CHECKF(agrees_with_brute_force(&m, &b, &r, &hits, why, sizeof why), "ray %ld: %s", i, why);
        if (bvh_intersect(&b, &r, &h))
            CHECKF(h.tri < first_degenerate || h.tri >= first_degenerate + degenerate_count, "ray %ld hit degenerate %u",
                   i, h.tri);
    }
    CHECKF(hits > 1000, "only %ld hits", hits);
    /* The public test alone also rejects them. */
    for (t = first_degenerate; t < first_degenerate + degenerate_count; ++t) {
        float tt, b1, b2;
        ray r = make_ray(v3f(0.01f, 0.02f, 3), v3f_sub(m.v[3 * t], v3f(0.01f, 0.02f, 3)));
        CHECK(!ray_triangle_watertight(&r, m.v[3 * t], m.v[3 * t + 1], m.v[3 * t + 2], &tt, &b1, &b2));
    }
    /* Rays with zero or non-finite direction, or an empty range, hit nothing. */
    {
        ray r = make_ray(v3f(0, 0, 0), v3f(0, 0, 0));
        bvh_hit h;
        CHECK(!bvh_intersect(&b, &r, &h) && !bvh_occluded(&b, &r) && h.tri == BVH_NO_HIT);
        r.dir = v3f(NAN, 0, 1);
        CHECK(!bvh_intersect(&b, &r, &h) && !bvh_occluded(&b, &r));
        r.dir = v3f(0, 0, 1);
        r.tmin = 1;
        r.tmax = 1;
        CHECK(!bvh_intersect(&b, &r, &h) && !bvh_occluded(&b, &r));
    }
    bvh_free(&b);
    soup_free(&m);
}

/* Woop et al. 2013 §3: an edge function that rounds to exactly 0 in float is
 * re-evaluated in double. Fibonacci coordinates make the exact edge function +-1
 * while both float products round to the same value: the ray along +z through the
 * origin passes 1/|BC| outside edge BC of the first triangle (a miss that float
 * alone would call a hit on the edge) and just inside it for the mirrored one. */
TEST(watertight_double_precision_fallback)
{
    const float f23 = 28657, f24 = 46368, f25 = 75025;
    vec3f b = v3f(f25, f24, 1), c = v3f(-f24, -f23, 1);
    vec3f a_outside = v3f(f24 + f23, -(f25 + f24), 1), a_inside = v3f(-(f24 + f23), f25 + f24, 1);
    ray r = make_ray(v3f(0, 0, 0), v3f(0, 0, 1));
    float t, b1, b2;
    bvh tree;
    bvh_hit h;
    vec3f tri[3];
    rerror e;
    CHECK((double)f25 * f23 - (double)f24 * f24 == 1);   /* exact edge function */
    CHECK(f25 * f23 - f24 * f24 == 0);                   /* what float makes of it */
    CHECK(!ray_triangle_watertight(&r, a_outside, b, c, &t, &b1, &b2));
    CHECK(ray_triangle_watertight(&r, a_inside, b, c, &t, &b1, &b2) && t == 1);
    tri[0] = a_outside, tri[1] = b, tri[2] = c;
    CHECKF(bvh_build(&tree, tri, 1, &e) == 0, "%s", e.msg);
    CHECK(!bvh_intersect(&tree, &r, &h) && !bvh_occluded(&tree, &r));
    bvh_free(&tree);
}

/* One call of the four-lane test against four calls of the scalar one: the same lanes
 * hit, with bit-identical t and barycentrics. Returns 0 and says where they differ. */
static int lanes_match_scalar(const ray *r, const vec3f v[BVH_LANES][3], char *why, size_t why_size, long *hits)
{
    float t4[BVH_LANES], b14[BVH_LANES], b24[BVH_LANES];
    unsigned mask = ray_triangle4_watertight(r, v, t4, b14, b24);
    int lane;
    for (lane = 0; lane < BVH_LANES; ++lane) {
        float t, b1, b2;
        int hit = ray_triangle_watertight(r, v[lane][0], v[lane][1], v[lane][2], &t, &b1, &b2);
        if (hit != (int)((mask >> lane) & 1u) ||
            (hit && (!same_bits(t, t4[lane]) || !same_bits(b1, b14[lane]) || !same_bits(b2, b24[lane])))) {
            snprintf(why, why_size, "lane %d: scalar %d t %.9g b %.9g %.9g, lanes %u t %.9g b %.9g %.9g", lane, hit,
                     hit ? (double)t : 0.0, hit ? (double)b1 : 0.0, hit ? (double)b2 : 0.0, (mask >> lane) & 1u,
                     (double)t4[lane], (double)b14[lane], (double)b24[lane]);
            return 0;
        }
        *hits += hit;
    }
    return 1;
}

/* A triangle with vertices on a grid of quarter units (edge functions of rays through
 * grid points are then often exactly 0), axis-aligned when `flat` (in the plane of
 * coordinate flat - 1). */
static void grid_triangle(uint32_t tag, uint32_t i, int flat, vec3f v[3])
{
    int k;
    for (k = 0; k < 3; ++k) {
        float q[3];
        int a;
        for (a = 0; a < 3; ++a) q[a] = floorf(urand(tag, i, (uint32_t)(3 * k + a)) * 8 - 4) * 0.25f;
        if (flat) q[flat - 1] = 0.5f;
        v[k] = v3f(q[0], q[1], q[2]);
    }
}

/* The traversal tests leaf triangles four at a time (bvh.c watertight_lanes); that must
 * be the scalar watertight test exactly, on ordinary rays and on the cases where float
 * rounding decides: rays through vertices and along shared edges (edge functions exactly
 * 0, re-evaluated in double), axis-parallel rays (zero direction components), rays in a
 * triangle's plane, t exactly at the ends of the range, degenerate triangles. */
TEST(ray_triangle4_equals_scalar_test)
{
    const float f23 = 28657, f24 = 46368, f25 = 75025;
    char why[256];
    long i, hits = 0;
    for (i = 0; i < 40000; ++i) {
        vec3f v[BVH_LANES][3];
        ray r = make_ray(urand_box(61, (uint32_t)i, -1.5f, 1.5f), urand_direction(61, (uint32_t)i));
        int lane, kind = (int)(i % 6);
        for (lane = 0; lane < BVH_LANES; ++lane) {
            uint32_t id = (uint32_t)(BVH_LANES * i + lane);
            if ((lane + i) % 3 == 0) {
                v[lane][0] = urand_box(62, id, -1, 1), v[lane][1] = urand_box(63, id, -1, 1);
                v[lane][2] = urand_box(64, id, -1, 1);
            } else {
                grid_triangle(65, id, (int)((lane + i) % 4), v[lane]);
            }
        }
        if (i % 50 == 0) v[3][2] = v[3][0]; /* a degenerate lane */
        switch (kind) {
        case 0: /* through a vertex of lane 1 */
            r.dir = v3f_sub(v[1][i % 3], r.origin);
            break;
        case 1: /* through the midpoint of an edge of lane 2 (exact on the grid) */
            r.dir = v3f_sub(v3f_scale(v3f_add(v[2][0], v[2][1]), 0.5f), r.origin);
            break;
        case 2: /* axis-parallel from a grid point */
            r.origin = v3f(floorf(r.origin.x * 4) * 0.25f, floorf(r.origin.y * 4) * 0.25f, floorf(r.origin.z * 4) * 0.25f);
            r.dir = i % 4 == 2 ? v3f(0, -1, 0) : v3f(0, 0, 1);
            break;
        case 3: /* in the plane z = 0.5 of the axis-aligned lanes */
            r.origin.z = 0.5f;
            r.dir.z = 0;
            break;
        default:
            break;
        }
        if (kind == 5) { /* the range ends exactly at a hit's t */
            float t, b1, b2;
            if (ray_triangle_watertight(&r, v[0][0], v[0][1], v[0][2], &t, &b1, &b2)) {
                if (i % 2) r.tmax = t; else r.tmin = t;
            }
        }
        CHECKF(lanes_match_scalar(&r, (const vec3f(*)[3])v, why, sizeof why, &hits), "ray %ld: %s", i, why);
    }
    CHECKF(hits > 10000, "only %ld lane hits", hits);
    { /* the double-precision fallback (watertight_double_precision_fallback) in lanes 0 and 2 */
        vec3f v[BVH_LANES][3];
        ray r = make_ray(v3f(0, 0, 0), v3f(0, 0, 1));
        int lane;
        for (lane = 0; lane < BVH_LANES; ++lane) {
            v[lane][0] = lane % 2 ? v3f(-(f24 + f23), f25 + f24, 1) : v3f(f24 + f23, -(f25 + f24), 1);
            v[lane][1] = v3f(f25, f24, 1);
            v[lane][2] = v3f(-f24, -f23, 1);
        }
        hits = 0;
        CHECKF(lanes_match_scalar(&r, (const vec3f(*)[3])v, why, sizeof why, &hits), "fallback: %s", why);
        CHECK(hits == 2);
    }
}

/* A BVH over nothing but degenerate triangles is empty and answers "no hit". */
TEST(bvh_all_degenerate_is_empty)
{
    vec3f v[6];
    bvh b;
    rerror e;
    ray r = make_ray(v3f(0, 0, -1), v3f(0, 0, 1));
    bvh_hit h;
    v[0] = v[1] = v[2] = v3f(0, 0, 0);
    v[3] = v3f(0, 0, 0), v[4] = v3f(1, 1, 1), v[5] = v3f(2, 2, 2);
    CHECKF(bvh_build(&b, v, 2, &e) == 0, "%s", e.msg);
    CHECK(b.node_count == 0 && b.prim_count == 0);
    CHECK(!bvh_intersect(&b, &r, &h) && !bvh_occluded(&b, &r));
    bvh_free(&b);
}

/* ------------------------------------------------------------------------------- */
/* Watertightness                                                                    */

/* Rays from inside a closed mesh aimed exactly at its vertices and at points on its
 * shared edges must all hit something. Returns the number of leaks. */
static long count_leaks(const soup *m, const bvh *b, long rays, uint32_t tag)
{
    long i, leaks = 0;
    for (i = 0; i < rays; ++i) {
        size_t tri = (size_t)(urand(tag, (uint32_t)i, 0) * (float)m->count) % m->count;
        int corner = (int)(urand(tag, (uint32_t)i, 1) * 3) % 3;
        vec3f a = m->v[3 * tri + (size_t)corner], c = m->v[3 * tri + (size_t)(corner + 1) % 3];
        vec3f o = urand_box(tag + 1, (uint32_t)i, -0.4f, 0.4f), target;
        bvh_hit h;
        ray r;
        if (i % 4 == 0)
            target = a; /* a vertex */
        else            /* a point on the edge a-c */
            target = v3f_add(a, v3f_scale(v3f_sub(c, a), urand(tag, (uint32_t)i, 2)));
        r = make_ray(o, v3f_sub(target, o));
        if (!bvh_intersect(b, &r, &h)) leaks++;
    }
    return leaks;
}

/* A closed cube (cells per edge: n_cube) and a closed sphere (n_sphere), offset by `offset`:
 * none of `rays` rays aimed at their edges and vertices from inside leaks (tags tag0 and
 * tag0 + 2). */
static void expect_watertight(int n_cube, int n_sphere, vec3f offset, long rays, uint32_t tag0)
{
    int shape;
    for (shape = 0; shape < 2; ++shape) {
        soup m = {0};
        bvh b;
        rerror e;
        long leaks;
        closed_mesh(&m, shape ? n_sphere : n_cube, shape, 1.0f, offset);
        CHECKF(bvh_build(&b, m.v, m.count, &e) == 0, "%s", e.msg);
        leaks = count_leaks(&m, &b, rays, tag0 + 2u * (uint32_t)shape);
        bvh_free(&b);
        soup_free(&m);
        CHECKF(leaks == 0, "%s: %ld of %ld rays aimed at edges/vertices leaked", shape ? "sphere" : "cube", leaks, rays);
    }
}

TEST(bvh_watertight_closed_meshes)
{
    expect_watertight(5, 9, v3f(0.0f, 0.0f, 0.0f), 50000, 60);
}

/* ------------------------------------------------------------------------------- */
/* Ray-origin offsets: no self-intersection at any scale                             */

/* For each hit point on the mesh (from rays out of the interior and from outside),
 * spawns rays into both hemispheres. A self-intersection is a hit on the triangle the
 * ray starts on (sphere) or on any triangle of the same face plane (cube). Returns
 * the number of self-intersections out of `*rays`. */
static long count_self_intersections(const scene *s, int is_cube, float scale, vec3f shift, long points, uint32_t tag,
                                     long *rays)
{
    long i, bad = 0;
    int side;
    for (i = 0; i < points; ++i) {
        vec3f dir = urand_direction(tag, (uint32_t)i), o;
        surface_hit h, g;
        ray r;
        if (i % 2) {
            o = v3f_add(v3f_scale(urand_box(tag, (uint32_t)i, -0.5f, 0.5f), scale), shift);
        } else {
            o = v3f_add(v3f_scale(dir, -4.0f * scale), shift);
            dir = v3f_sub(v3f_add(v3f_scale(urand_box(tag + 1, (uint32_t)i, -0.9f, 0.9f), scale), shift), o);
        }
        r = make_ray(o, dir);
        if (!scene_intersect(s, &r, &h)) continue;
        for (side = 0; side < 2; ++side) {
            /* Uniform in the hemisphere about +-ng: grazing directions included. */
            vec3 t, bb, n = v3_from_f(side ? v3f_scale(h.ng, -1.0f) : h.ng);
            vec3 l = warp_uniform_hemisphere(v2(urand(tag + 2, (uint32_t)i, (uint32_t)side), urand(tag + 3, (uint32_t)i, (uint32_t)side)));
            vec3f d;
            v3_basis(n, &t, &bb);
            d = v3f_from(v3_add(v3_add(v3_scale(t, l.x), v3_scale(bb, l.y)), v3_scale(n, l.z)));
            r = scene_spawn_ray(h.position, h.ng, d, v3f(0, 0, 0));
            (*rays)++;
            if (!scene_intersect(s, &r, &g)) continue;
            if (is_cube ? (g.ng.x == h.ng.x && g.ng.y == h.ng.y && g.ng.z == h.ng.z) : g.triangle == h.triangle) bad++;
        }
    }
    return bad;
}

TEST(offset_ray_origin_no_self_intersection_at_any_scale)
{
    static const float scales[4] = {1e-3f, 1.0f, 1e3f, 1e4f};
    int k, shape;
    for (k = 0; k < 4; ++k) {
        for (shape = 0; shape < 2; ++shape) {
            float sc = scales[k];
            vec3f shift = v3f_scale(shape ? v3f(0.3f, -0.2f, 0.45f) : v3f(0.25f, 0.5f, -0.75f), sc);
            soup m = {0};
            scene s;
            rerror e;
            long rays = 0, bad;
            closed_mesh(&m, shape ? 10 : 4, shape, sc, shift);
            CHECKF(scene_from_soup(&s, &m, &e) == 0, "%s", e.msg);
            bad = count_self_intersections(&s, !shape, sc, shift, 2000, 70 + 4u * (uint32_t)k, &rays);
            CHECKF(rays > 3000, "only %ld rays", rays);
            CHECKF(bad == 0, "scale %g %s: %ld of %ld spawned rays re-hit their own surface", (double)sc,
                   shape ? "sphere" : "cube", bad, rays);
            free_test_scene(&s);
            soup_free(&m);
        }
    }
}

/* The paper's rule, literally (Wächter & Binder 2019, constants int_scale = 256,
 * float_scale = 1/65536, origin = 1/32): per-coordinate ulps, a fixed offset near 0.
 * Kept here only to show why offset_ray_origin deviates from it. */
static vec3f offset_wachter_binder_literal(vec3f p, vec3f n)
{
    float pin[3], nin[3], out[3];
    int i;
    memcpy(pin, &p, sizeof pin);
    memcpy(nin, &n, sizeof nin);
    for (i = 0; i < 3; ++i) {
        if (fabsf(pin[i]) < 1.0f / 32.0f) {
            out[i] = pin[i] + nin[i] / 65536.0f;
        } else {
            int32_t ulps = (int32_t)(256.0f * nin[i]);
            uint32_t bits;
            memcpy(&bits, &pin[i], sizeof bits);
            bits += (uint32_t)(pin[i] < 0 ? -ulps : ulps);
            memcpy(&out[i], &bits, sizeof bits);
        }
    }
    return v3f(out[0], out[1], out[2]);
}

/* Rays spawned from a floor at y = 0 spanning [-S, S]^2, in both hemispheres; returns
 * how many re-hit the floor. Hit points closer to the coordinate origin than S/64 are
 * skipped (there the offset, 256 ulps of the point's largest coordinate, is too small
 * for a triangle of size S: the documented residual of offset_ray_origin). */
static long floor_rehits(float scale, int literal, uint32_t tag, long *rays)
{
    soup m = {0};
    scene s;
    rerror e;
    long i, bad = 0;
    vec3f c[4];
    c[0] = v3f(-scale, 0, -scale), c[1] = v3f(scale, 0, -scale), c[2] = v3f(scale, 0, scale), c[3] = v3f(-scale, 0, scale);
    soup_add(&m, c[0], c[2], c[1]);
    soup_add(&m, c[0], c[3], c[2]);
    if (scene_from_soup(&s, &m, &e)) return -1;
    for (i = 0; i < 5000; ++i) {
        vec3f target = v3f((urand(tag, (uint32_t)i, 0) * 1.8f - 0.9f) * scale, 0,
                           (urand(tag, (uint32_t)i, 1) * 1.8f - 0.9f) * scale);
        vec3f o = v3f_add(target, v3f_scale(v3f(0.3f, 0.5f, -0.2f), scale));
        ray r = make_ray(o, v3f_sub(target, o));
        surface_hit h, g;
        int side;
        if (fmaxf(fabsf(target.x), fabsf(target.z)) < scale / 64 || !scene_intersect(&s, &r, &h)) continue;
        for (side = 0; side < 2; ++side) {
            vec3f n = side ? v3f_scale(h.ng, -1.0f) : h.ng;
            vec3 t, b, nn = v3_from_f(n);
            vec3 l = warp_uniform_hemisphere(v2(urand(tag + 1, (uint32_t)i, (uint32_t)side), urand(tag + 2, (uint32_t)i, (uint32_t)side)));
            vec3f d;
            v3_basis(nn, &t, &b);
            d = v3f_from(v3_add(v3_add(v3_scale(t, l.x), v3_scale(b, l.y)), v3_scale(nn, l.z)));
            r = scene_spawn_ray(h.position, h.ng, d, v3f(0, 0, 0));
            if (literal) r.origin = offset_wachter_binder_literal(h.position, n);
            (*rays)++;
            bad += scene_intersect(&s, &r, &g);
        }
    }
    free_test_scene(&s);
    soup_free(&m);
    return bad;
}

/* A floor at y = 0 (the common case) at every scale: no spawned ray re-hits it. The
 * paper's literal rule fails here once the scene is large (mm units), which is why
 * offset_ray_origin counts ulps of the largest coordinate. */
TEST(offset_ray_origin_floor_at_zero_any_scale)
{
    static const float scales[5] = {1e-3f, 1.0f, 1e3f, 1e4f, 1e5f};
    long rays, bad, literal_bad;
    int k;
    for (k = 0; k < 5; ++k) {
        rays = 0;
        bad = floor_rehits(scales[k], 0, 110, &rays);
        CHECKF(rays > 9000 && bad == 0, "scale %g: %ld of %ld spawned rays re-hit the floor", (double)scales[k], bad,
               rays);
    }
    rays = 0;
    literal_bad = floor_rehits(1e3f, 1, 110, &rays);
    CHECKF(literal_bad > rays / 100, "the literal rule was expected to fail at scale 1e3: %ld of %ld", literal_bad, rays);
}

/* The offset is a fixed number of ulps of the point's largest coordinate: multiplying
 * a point by a power of two multiplies its offset by the same power of two, also for
 * points near the coordinate origin. */
TEST(offset_ray_origin_scales_with_the_point)
{
    long i;
    for (i = 0; i < 1000; ++i) {
        vec3f p = urand_box(80, (uint32_t)i, i % 3 ? 0.05f : 1e-4f, i % 3 ? 1.9f : 2e-3f);
        vec3f n = urand_direction(81, (uint32_t)i);
        vec3f a, b, d1, d2;
        if (i % 2) p.x = -p.x;
        a = offset_ray_origin(p, n);
        b = offset_ray_origin(v3f_scale(p, 1024.0f), n);
        d1 = v3f_sub(a, p);
        d2 = v3f_sub(b, v3f_scale(p, 1024.0f));
        CHECKF(same_bits(d1.x * 1024.0f, d2.x) && same_bits(d1.y * 1024.0f, d2.y) && same_bits(d1.z * 1024.0f, d2.z),
               "point %ld: offset not scale-covariant", i);
        /* It moves to the side n points to. */
        CHECKF(v3f_dot(d1, n) > 0, "point %ld: offset against the normal", i);
    }
}

/* ------------------------------------------------------------------------------- */
/* Scene queries                                                                     */

/* Surface points on a closed mesh: hits of rays from the interior region, half of them
 * aimed at points on the mesh's edges (the corners and edges of a box are where
 * offsets go wrong first). */
static long surface_points(const scene *s, const soup *m, float scale, vec3f shift, long count, uint32_t tag,
                           surface_hit *out)
{
    long i, n = 0;
    for (i = 0; i < count; ++i) {
        vec3f o = v3f_add(v3f_scale(urand_box(tag, (uint32_t)i, -0.9f, 0.9f), scale), shift);
        ray r = make_ray(o, urand_direction(tag, (uint32_t)i));
        if (i % 2) {
            size_t tri = (size_t)(urand(tag + 1, (uint32_t)i, 0) * (float)m->count) % m->count;
            vec3f a = m->v[3 * tri], c = m->v[3 * tri + 1];
            r.dir = v3f_sub(v3f_add(a, v3f_scale(v3f_sub(c, a), urand(tag + 1, (uint32_t)i, 1))), o);
        }
        if (scene_intersect(s, &r, &out[n])) n++;
    }
    return n;
}

/* Both points lie (to 1e-5 of the box size) in the plane of one face of the box
 * [-1,1]^3 * scale + shift: the segment between them runs along that face, where
 * occlusion is decided by rounding and is physically meaningless (it grazes the
 * surface). Such pairs are not asked about. */
static int in_common_face_plane(vec3f a, vec3f b, float scale, vec3f shift)
{
    float pa[3], pb[3], c[3];
    int i, side;
    memcpy(pa, &a, sizeof pa);
    memcpy(pb, &b, sizeof pb);
    memcpy(c, &shift, sizeof c);
    for (i = 0; i < 3; ++i)
        for (side = -1; side <= 1; side += 2) {
            float plane = c[i] + (float)side * scale, tol = 1e-5f * scale;
            if (fabsf(pa[i] - plane) < tol && fabsf(pb[i] - plane) < tol) return 1;
        }
    return 0;
}

/* Inside a closed box (convex from inside) every pair of surface points sees each
 * other, at every scale: the offsets never produce a false occlusion, also for points
 * on or next to the box's edges (concave from inside), as long as the segment does
 * not run inside one face's plane. */
TEST(scene_visible_inside_convex_box_at_any_scale)
{
    static const float scales[4] = {1e-3f, 1.0f, 1e3f, 1e4f};
    int k;
    for (k = 0; k < 4; ++k) {
        float sc = scales[k];
        vec3f shift = v3f_scale(v3f(0.25f, 0.5f, -0.75f), sc);
        soup m = {0};
        scene s;
        rerror e;
        surface_hit pts[400];
        long n, i, blocked = 0, pairs = 0, same_face = 0;
        closed_mesh(&m, 4, 0, sc, shift);
        CHECKF(scene_from_soup(&s, &m, &e) == 0, "%s", e.msg);
        n = surface_points(&s, &m, sc, shift, 400, 90 + 2u * (uint32_t)k, pts);
        CHECK(n > 350);
        for (i = 0; i + 1 < n; ++i) {
            long j;
            for (j = i + 1; j < n; j += 7) {
                if (in_common_face_plane(pts[i].position, pts[j].position, sc, shift)) {
                    /* Two points of one flat face: the offsets put both ends on the same
                     * side of the face (not on opposite sides, which would cross it). */
                    if (pts[i].ng.x == pts[j].ng.x && pts[i].ng.y == pts[j].ng.y && pts[i].ng.z == pts[j].ng.z) {
                        same_face++;
                        CHECKF(scene_visible(&s, pts[i].position, pts[i].ng, pts[j].position, &pts[j].ng),
                               "scale %g: points %ld, %ld on one face do not see each other", (double)sc, i, j);
                    }
                    continue;
                }
                pairs++;
                blocked += !scene_visible(&s, pts[i].position, pts[i].ng, pts[j].position, &pts[j].ng);
            }
        }
        CHECKF(pairs > 9000 && same_face > 500, "only %ld pairs, %ld on one face", pairs, same_face);
        CHECKF(blocked == 0, "scale %g: %ld of %ld pairs falsely occluded", (double)sc, blocked, pairs);
        free_test_scene(&s);
        soup_free(&m);
    }
}

/* visible(a, b) == visible(b, a) in a closed box with an occluding cube inside, and
 * both answers occur. */
TEST(scene_visible_symmetric)
{
    soup m = {0};
    scene s;
    rerror e;
    surface_hit pts[600];
    long n, i, visible = 0, occluded = 0;
    closed_mesh(&m, 4, 0, 1.0f, v3f(0, 0, 0));
    closed_mesh(&m, 2, 0, 0.35f, v3f(0.1f, -0.05f, 0.02f)); /* the occluder */
    CHECKF(scene_from_soup(&s, &m, &e) == 0, "%s", e.msg);
    /* Points on the box and on the occluder (origins between the two). */
    n = 0;
    for (i = 0; i < 600; ++i) {
        vec3f o = urand_box(100, (uint32_t)i, -0.95f, 0.95f);
        ray r = make_ray(o, urand_direction(101, (uint32_t)i));
        if (fabsf(o.x - 0.1f) < 0.4f && fabsf(o.y + 0.05f) < 0.4f && fabsf(o.z - 0.02f) < 0.4f) continue;
        if (scene_intersect(&s, &r, &pts[n])) n++;
    }
    CHECK(n > 300);
    for (i = 0; i + 1 < n; ++i) {
        long j;
        for (j = i + 1; j < n; j += 5) {
            int ab = scene_visible(&s, pts[i].position, pts[i].ng, pts[j].position, &pts[j].ng);
            int ba = scene_visible(&s, pts[j].position, pts[j].ng, pts[i].position, &pts[i].ng);
            CHECKF(ab == ba, "pair %ld %ld: visible(a,b) = %d, visible(b,a) = %d", i, j, ab, ba);
            visible += ab;
            occluded += !ab;
        }
    }
    CHECKF(visible > 1000 && occluded > 1000, "visible %ld occluded %ld", visible, occluded);
    /* Segments that graze the occluder: b is where the ray from a through a point on
     * one of the occluder's edges meets the outer box (found in a scene without the
     * occluder). Rounding decides these, and still both directions must agree. */
    {
        soup outer = {0};
        scene box_only;
        long grazing = 0;
        closed_mesh(&outer, 4, 0, 1.0f, v3f(0, 0, 0));
        CHECKF(scene_from_soup(&box_only, &outer, &e) == 0, "%s", e.msg);
        for (i = 0; i < 4000; ++i) {
            const surface_hit *a = &pts[i % n];
            size_t tri = outer.count + (size_t)(urand(102, (uint32_t)i, 0) * 48.0f) % 48; /* occluder triangles */
            int corner = (int)(urand(102, (uint32_t)i, 1) * 3) % 3;
            vec3f p = m.v[3 * tri + (size_t)corner], q = m.v[3 * tri + (size_t)(corner + 1) % 3];
            vec3f target = v3f_add(p, v3f_scale(v3f_sub(q, p), urand(102, (uint32_t)i, 2)));
            surface_hit b;
            ray r = scene_spawn_ray(a->position, a->ng, v3f_sub(target, a->position), v3f(0, 0, 0));
            int ab, ba;
            if (!scene_intersect(&box_only, &r, &b)) continue;
            ab = scene_visible(&s, a->position, a->ng, b.position, &b.ng);
            ba = scene_visible(&s, b.position, b.ng, a->position, &a->ng);
            CHECKF(ab == ba, "grazing pair %ld: visible(a,b) = %d, visible(b,a) = %d", i, ab, ba);
            grazing++;
        }
        CHECK(grazing > 2000);
        free_test_scene(&box_only);
        soup_free(&outer);
    }
    /* A point not on a surface (ng_to = NULL): the occluder's centre is hidden from
     * every point on the outer box. */
    for (i = 0; i < n; ++i) {
        vec3f p = pts[i].position;
        if (fmaxf(fabsf(p.x), fmaxf(fabsf(p.y), fabsf(p.z))) < 0.99f) continue;
        CHECKF(!scene_visible(&s, p, pts[i].ng, v3f(0.1f, -0.05f, 0.02f), NULL), "point %ld sees into the occluder", i);
    }
    free_test_scene(&s);
    soup_free(&m);
}

/* A room (floor at y = 0) with a cube in it, scaled by 2^k, and what the ray queries
 * answer there: for fixed random rays from inside, the hit triangle and t of the
 * primary ray, of one spawned bounce, and the visibility to another hit point. */
typedef struct {
    uint32_t tri, bounce_tri;
    float t, bounce_t;
    int visible;
} room_answer;

static int room_answers(float scale, long count, room_answer *out)
{
    soup m = {0};
    scene s;
    rerror e;
    surface_hit prev;
    long i;
    int have_prev = 0;
    size_t k;
    closed_mesh(&m, 4, 0, 1.0f, v3f(0, 1, 0));                 /* the room: y in [0, 2] */
    closed_mesh(&m, 2, 0, 0.3f, v3f(0.2f, 0.3f, -0.1f));       /* a cube standing near the floor */
    for (k = 0; k < 3 * m.count; ++k) m.v[k] = v3f_scale(m.v[k], scale);
    if (scene_from_soup(&s, &m, &e)) return -1;
    memset(out, 0, (size_t)count * sizeof *out);
    for (i = 0; i < count; ++i) {
        vec3f o = v3f_scale(v3f_add(urand_box(120, (uint32_t)i, -0.9f, 0.9f), v3f(0, 1, 0)), scale);
        ray r = make_ray(o, urand_direction(121, (uint32_t)i));
        surface_hit h, g;
        vec3 t, b, nn;
        vec3 l = warp_cosine_hemisphere(v2(urand(122, (uint32_t)i, 0), urand(122, (uint32_t)i, 1)));
        if (!scene_intersect(&s, &r, &h)) continue;
        out[i].tri = h.triangle;
        out[i].t = h.t;
        nn = v3_from_f(v3f_dot(h.ng, r.dir) > 0 ? v3f_scale(h.ng, -1.0f) : h.ng);
        v3_basis(nn, &t, &b);
        r = scene_spawn_ray(h.position, h.ng, v3f_from(v3_add(v3_add(v3_scale(t, l.x), v3_scale(b, l.y)), v3_scale(nn, l.z))),
                            v3f_scale(r.dir, -1.0f));
        if (scene_intersect(&s, &r, &g)) {
            out[i].bounce_tri = g.triangle + 1;
            out[i].bounce_t = g.t;
        }
        if (have_prev) out[i].visible = 1 + scene_visible(&s, h.position, h.ng, prev.position, &prev.ng);
        prev = h;
        have_prev = 1;
    }
    free_test_scene(&s);
    soup_free(&m);
    return 0;
}

/* Scale invariance, exactly: scaling a scene by a power of two scales every rounding
 * in the watertight test, the BVH and the offsets by the same power of two, so every
 * answer must be bit-identical (a scene in mm and in m differ by 1000, not 1024, and
 * then agree up to rounding). Offsets with an absolute threshold fail this. */
TEST(scene_queries_exactly_scale_covariant)
{
    enum { N = 3000 };
    static room_answer base[N], scaled[N];
    static const float scales[4] = {1.0f / 1024.0f, 1024.0f, 16384.0f, 1048576.0f};
    long i, hits = 0, visible = 0, occluded = 0;
    int k;
    CHECK(room_answers(1.0f, N, base) == 0);
    for (i = 0; i < N; ++i) {
        hits += base[i].bounce_tri != 0;
        visible += base[i].visible == 2;
        occluded += base[i].visible == 1;
    }
    CHECKF(hits > N / 2 && visible > N / 4 && occluded > N / 50, "hits %ld visible %ld occluded %ld", hits, visible,
           occluded);
    for (k = 0; k < 4; ++k) {
        CHECK(room_answers(scales[k], N, scaled) == 0);
        for (i = 0; i < N; ++i) {
            CHECKF(scaled[i].tri == base[i].tri && scaled[i].bounce_tri == base[i].bounce_tri &&
                       same_bits(scaled[i].t, base[i].t * scales[k]) &&
                       same_bits(scaled[i].bounce_t, base[i].bounce_t * scales[k]) && scaled[i].visible == base[i].visible,
                   "scale %g, ray %ld: tri %u/%u bounce %u/%u visible %d/%d", (double)scales[k], i, scaled[i].tri,
                   base[i].tri, scaled[i].bounce_tri, base[i].bounce_tri, scaled[i].visible, base[i].visible);
        }
    }
}

/* scene_intersect: position from barycentrics, the true (unflipped) face normal,
 * interpolated shading normals, material and object ids. */
TEST(scene_intersect_surface_data)
{
    scene s;
    rerror e;
    surface_hit h;
    ray r;
    memset(&s, 0, sizeof s);
    strcpy(s.path, "test");
    s.positions = malloc(6 * sizeof *s.positions);
    s.normals = malloc(3 * sizeof *s.normals);
    s.triangles = malloc(2 * sizeof *s.triangles);
    /* Triangle 0 in z = 0, counter-clockwise seen from +z; triangle 1 in z = 2, clockwise. */
    s.positions[0] = v3f(0, 0, 0), s.positions[1] = v3f(2, 0, 0), s.positions[2] = v3f(0, 2, 0);
    s.positions[3] = v3f(0, 0, 2), s.positions[4] = v3f(0, 2, 2), s.positions[5] = v3f(2, 0, 2);
    s.position_count = 6;
    s.normals[0] = v3f(0, 0, 1), s.normals[1] = v3f(1, 0, 1), s.normals[2] = v3f(0, 1, 1);
    s.normal_count = 3;
    s.triangles[0].v[0] = 0, s.triangles[0].v[1] = 1, s.triangles[0].v[2] = 2;
    s.triangles[0].n[0] = 0, s.triangles[0].n[1] = 1, s.triangles[0].n[2] = 2;
    s.triangles[0].material = 3, s.triangles[0].object = 4;
    s.triangles[1].v[0] = 3, s.triangles[1].v[1] = 4, s.triangles[1].v[2] = 5;
    s.triangles[1].n[0] = 0, s.triangles[1].n[1] = -1, s.triangles[1].n[2] = 2;
    s.triangles[1].material = 5, s.triangles[1].object = 6;
    s.triangle_count = 2;
    CHECKF(scene_prepare(&s, &e) == 0, "%s", e.msg);
    CHECK(s.bounds_min.x == 0 && s.bounds_max.x == 2 && s.bounds_max.z == 2);

    /* From below, through (0.5, 0.5) of triangle 0: b1 = b2 = 0.25. */
    r = make_ray(v3f(0.5f, 0.5f, -1), v3f(0, 0, 1));
    CHECK(scene_intersect(&s, &r, &h));
    CHECK(h.triangle == 0 && h.material == 3 && h.object == 4);
    CHECK_NEAR(h.t, 1, 1e-6);
    CHECK_NEAR(h.b1, 0.25, 1e-6);
    CHECK_NEAR(h.b2, 0.25, 1e-6);
    CHECK_NEAR(h.position.x, 0.5, 1e-6);
    CHECK_NEAR(h.position.y, 0.5, 1e-6);
    CHECK(h.position.z == 0);
    CHECK(h.ng.x == 0 && h.ng.y == 0 && h.ng.z == 1); /* not flipped toward the ray */
    /* ns = normalize(0.5 (0,0,1) + 0.25 (1,0,1) + 0.25 (0,1,1)) */
    CHECK_NEAR(h.ns.x, 0.25 / sqrt(1.125), 1e-6);
    CHECK_NEAR(h.ns.z, 1.0 / sqrt(1.125), 1e-6);

    /* From above after passing triangle 0's range: hits triangle 1 (clockwise, so its
     * normal is -z) and its shading normal falls back to ng (one n[] is -1). */
    r = make_ray(v3f(0.5f, 0.5f, 3), v3f(0, 0, -1));
    CHECK(scene_intersect(&s, &r, &h));
    CHECK(h.triangle == 1 && h.material == 5 && h.object == 6);
    CHECK(h.ng.z == -1 && h.ns.z == -1);
    /* The spawned ray leaves to the side it points to and hits triangle 0 next. */
    r = scene_spawn_ray(h.position, h.ng, v3f(0, 0, -1), v3f(0, 0, 0));
    CHECK(r.tmin == 0 && isinf(r.tmax) && r.origin.z < 2);
    CHECK(scene_intersect(&s, &r, &h) && h.triangle == 0);
    /* The two triangles see each other; a point beyond triangle 0 is hidden. */
    CHECK(scene_visible(&s, v3f(0.5f, 0.5f, 2), v3f(0, 0, -1), v3f(0.5f, 0.5f, 0), &(vec3f){0, 0, 1}));
    CHECK(!scene_visible(&s, v3f(0.5f, 0.5f, 2), v3f(0, 0, -1), v3f(0.5f, 0.5f, -1), NULL));
    free_test_scene(&s);
}

TEST(scene_prepare_empty_scene_fails)
{
    scene s;
    rerror e;
    memset(&s, 0, sizeof s);
    strcpy(s.path, "empty.obj");
    CHECK(scene_prepare(&s, &e) != 0);
    CHECKF(!strcmp(e.msg, "empty.obj: scene has no triangles"), "message: %s", e.msg);
}

/* ------------------------------------------------------------------------------- */
/* Generated scene                                                                   */

/* >= 100k triangles at subdivision 92, and closed: every directed edge of the sphere
 * appears once and its reverse once (consistent outward winding, no holes). */
TEST(generate_displaced_sphere_closed)
{
    scene s;
    rerror e;
    const char *problem;
    double volume;
    size_t i, sphere_tris = 0;
    CHECKF(generate_displaced_sphere(&s, 92, &e) == 0, "%s", e.msg);
    CHECKF(s.triangle_count >= 100000, "%zu triangles", s.triangle_count);
    CHECK(s.material_count == 2 && s.object_count == 2 && s.has_camera);
    CHECK(!rgb_is_black(s.materials[1].emission) && rgb_is_black(s.materials[0].emission));
    for (i = 0; i < s.triangle_count; ++i) sphere_tris += s.triangles[i].object == 0;
    CHECK(sphere_tris == 12 * 92 * 92);
    CHECK(s.position_count == 6 * 92 * 92 + 2 + 4); /* Euler: V = E - F + 2 */
    problem = check_closed_outward(&s, 0, &volume);
    CHECKF(problem == NULL, "the sphere: %s", problem);
    /* The light faces down, toward the sphere. */
    {
        const triangle *t = &s.triangles[s.triangle_count - 1];
        vec3f a = s.positions[t->v[0]], b = s.positions[t->v[1]], c = s.positions[t->v[2]];
        CHECK(v3f_cross(v3f_sub(b, a), v3f_sub(c, a)).y < 0);
    }
    free_generated_scene(&s);
}

TEST(generate_write_obj_roundtrips_vertices)
{
    scene s;
    rerror e;
    const char *path = test_tmp_path("gen/sphere.obj");
    char line[256], mtl[1024];
    FILE *f;
    size_t v = 0, faces = 0;
    CHECKF(generate_displaced_sphere(&s, 6, &e) == 0, "%s", e.msg);
    CHECKF(generate_write_obj(&s, path, &e) == 0, "%s", e.msg);
    snprintf(mtl, sizeof mtl, "%s", test_tmp_path("gen/sphere.mtl"));
    CHECK(test_file_exists(mtl));
    f = fopen(path, "r");
    CHECK(f != NULL);
    while (fgets(line, sizeof line, f)) {
        float x, y, z;
        if (sscanf(line, "v %f %f %f", &x, &y, &z) == 3) {
            CHECKF(v < s.position_count && same_bits(x, s.positions[v].x) && same_bits(y, s.positions[v].y) &&
                       same_bits(z, s.positions[v].z),
                   "vertex %zu differs", v);
            v++;
        }
        if (line[0] == 'f') faces++;
    }
    fclose(f);
    CHECK(v == s.position_count && faces == s.triangle_count);
    free_generated_scene(&s);
    CHECK(generate_displaced_sphere(&s, 0, &e) != 0 && s.triangles == NULL);
}

/* ------------------------------------------------------------------------------- */
/* Longer versions                                                                    */

static ray long_ray(const soup *m, long i)
{
    ray r = make_ray(urand_box(201, (uint32_t)i, -1.5f, 1.5f), urand_direction(201, (uint32_t)i));
    if (i % 2) r.dir = v3f_sub(m->v[(size_t)(urand(202, (uint32_t)i, 0) * 3 * (float)m->count) % (3 * m->count)], r.origin);
    return r;
}

TEST_LONG(bvh_matches_brute_force_long)
{
    soup m = {0};
    long hits = 0;
    random_soup(&m, 200, 20000);
    closed_mesh(&m, 20, 1, 0.7f, v3f(0.1f, 0.2f, 0.3f));
    expect_brute_force(&m, 15000, long_ray, &hits);
    soup_free(&m);
}

TEST_LONG(bvh_watertight_long)
{
    expect_watertight(16, 40, v3f(0.01f, -0.02f, 0.03f), 1000000, 210);
}

/* A 1M-triangle build: prints the time and the tree statistics. */
TEST_LONG(bvh_build_one_million)
{
    scene s;
    rerror e;
    struct timespec t0, t1;
    CHECKF(generate_displaced_sphere(&s, 289, &e) == 0, "%s", e.msg);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    CHECKF(scene_prepare(&s, &e) == 0, "%s", e.msg);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("     %zu triangles: build %.2f s, %zu nodes, depth %d, SAH cost %.2f\n", s.triangle_count,
           (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec), s.accel.node_count,
           s.accel.depth, s.accel.sah_cost);
    CHECK(s.accel.prim_count == s.triangle_count);
    free_generated_scene(&s);
}

/* A point exactly on the concave edge of a floor (y = 0) and a wall (x = 0) that both
 * face into the room: a ray leaving the floor towards the wall must hit the wall's front
 * face, not pass through it, at every scale (scene_spawn_ray steps along the surface
 * towards wo, then off it). The incoming direction wo comes from inside the room. */
TEST(spawn_ray_concave_edge)
{
    static const float scales[] = {1e-3f, 1.0f, 1e3f, 1e4f};
    int k, i;
    for (k = 0; k < 4; ++k) {
        float L = scales[k];
        scene s;
        rerror e;
        vec3f pos[6];
        triangle tris[2];
        memset(&s, 0, sizeof s);
        memset(tris, 0, sizeof tris);
        /* floor: normal +y; wall: normal +x */
        pos[0] = v3f(0, 0, -L); pos[1] = v3f(0, 0, L); pos[2] = v3f(L, 0, -L);
        pos[3] = v3f(0, -L, -L); pos[4] = v3f(0, L, -L); pos[5] = v3f(0, 0, L);
        tris[0].v[0] = 0; tris[0].v[1] = 1; tris[0].v[2] = 2;
        tris[1].v[0] = 3; tris[1].v[1] = 4; tris[1].v[2] = 5;
        for (i = 0; i < 2; ++i) tris[i].n[0] = tris[i].n[1] = tris[i].n[2] = -1;
        s.positions = pos;
        s.position_count = 6;
        s.triangles = tris;
        s.triangle_count = 2;
        CHECKF(scene_prepare(&s, &e) == 0, "%s", e.msg);
        CHECK(v3f_dot(v3f_normalize(v3f_cross(v3f_sub(pos[1], pos[0]), v3f_sub(pos[2], pos[0]))), v3f(0, 1, 0)) > 0.99f);
        CHECK(v3f_dot(v3f_normalize(v3f_cross(v3f_sub(pos[4], pos[3]), v3f_sub(pos[5], pos[3]))), v3f(1, 0, 0)) > 0.99f);
        for (i = 0; i < 64; ++i) {
            float z = L * (-0.5f + (float)i / 64.0f);
            vec3f p = v3f(0, 0, z), wo = v3f_normalize(v3f(0.6f, 0.7f, 0.1f));
            vec3f dir = v3f_normalize(v3f(-0.8f, 0.5f, 0.3f * (float)(i % 3 - 1)));
            ray r = scene_spawn_ray(p, v3f(0, 1, 0), dir, wo);
            surface_hit h;
            CHECKF(scene_intersect(&s, &r, &h) && h.triangle == 1, "scale %g, sample %d: the ray passed the wall", (double)L, i);
            CHECK(v3f_dot(h.ng, dir) < 0); /* the front face */
        }
        bvh_free(&s.accel);
        free(s.face_normals);
    }
}

/* ------------------------------------------------------------------------------- */
/* Filtered queries (alpha cut-outs, docs/materials.md §7.4) == brute force          */

/* A filter that cuts parts of some triangles away by their barycentrics (as map_d does). */
static int test_cut_filter(const void *ctx, uint32_t tri, float b1, float b2)
{
    (void)ctx;
    if (tri % 3 == 0 && b1 > 0.3f) return 0;
    if (tri % 5 == 1 && b1 + b2 < 0.5f) return 0;
    return 1;
}

/* Closest kept hit (lowest index among equal t: the loop ascends) and any kept hit. */
static int brute_filtered(const soup *m, const ray *r, bvh_hit *h, int *occluded)
{
    size_t i;
    h->tri = BVH_NO_HIT;
    *occluded = 0;
    for (i = 0; i < m->count; ++i) {
        float t, b1, b2;
        if (!ray_triangle_watertight(r, m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2], &t, &b1, &b2)) continue;
        if (!test_cut_filter(NULL, (uint32_t)i, b1, b2)) continue;
        *occluded = 1;
        if (h->tri == BVH_NO_HIT || t < h->t) {
            h->t = t;
            h->tri = (uint32_t)i;
        }
    }
    return h->tri != BVH_NO_HIT;
}

TEST(bvh_filtered_matches_brute_force)
{
    soup m = {0};
    bvh b;
    rerror e;
    long i, hits = 0, rejected_closest = 0;
    int simd;
    random_soup(&m, 21, 3000);
    CHECKF(bvh_build(&b, m.v, m.count, &e) == 0, "%s", e.msg);
    for (simd = b.simd; simd >= 0 && !test_has_failed(); --simd) {
        b.simd = simd; /* the AVX2 build (if any) and the portable one */
        for (i = 0; i < 1500 && !test_has_failed(); ++i) {
            ray r = make_ray(urand_box(32, (uint32_t)i, -1.5f, 1.5f), urand_direction(32, (uint32_t)i));
            bvh_hit hb, hr, plain;
            int fb = bvh_intersect_filtered(&b, &r, &hb, test_cut_filter, NULL), ob, orf;
            int fr = brute_filtered(&m, &r, &hr, &orf);
            ob = bvh_occluded_filtered(&b, &r, test_cut_filter, NULL);
            CHECKF(fb == fr && (!fb || (hb.tri == hr.tri && same_bits(hb.t, hr.t))),
                   "ray %ld: closest kept: bvh %d tri %u, brute %d tri %u", i, fb, hb.tri, fr, hr.tri);
            CHECKF(ob == orf, "ray %ld: any kept hit: bvh %d, brute %d", i, ob, orf);
            hits += fb;
            if (bvh_intersect(&b, &r, &plain) && (!fb || plain.tri != hb.tri)) rejected_closest++;
        }
    }
    CHECKF(hits > 500 && rejected_closest > 50, "only %ld kept hits, %ld rejected closest hits", hits, rejected_closest);
    bvh_free(&b);
    soup_free(&m);
}
