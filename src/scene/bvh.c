/* Bounding volume hierarchy over triangles.
 *
 * Build: top-down binned SAH (Wald 2007, "On fast construction of SAH-based bounding
 * volume hierarchies"): BVH_BINS = 16 centroid bins per axis, all three axes tried at
 * every node, leaves of at most BVH_MAX_LEAF = 8 triangles, a node becomes a leaf when
 * the SAH says splitting does not pay; the SAH counts a leaf's cost in blocks of 4
 * triangles (sah_blocks). Nodes are stored depth-first: the left child of an interior
 * node is the next node, the right child is at `offset`.
 *
 * Collapse: the binary tree is then collapsed to BVH_WIDTH = 8 wide nodes (BVH8) with the
 * very same boxes, which binary nodes become wide nodes and leaves chosen by the SAH-optimal
 * dynamic programme of Ylitie et al. 2017 (collapse_costs), and each leaf's triangles are
 * copied into leaf blocks of 4 (vertices inline, structure of arrays); queries traverse
 * those (fewer, larger nodes: fewer dependent cache misses for incoherent rays;
 * docs/performance.md has the measurements).
 *
 * Traversal: one stack of wide nodes; of the inner children a ray enters, the nearest is
 * visited first (by entry distance); the leaf children it enters are tested where they
 * are found, without a push and a pop. A leaf block's four triangles are tested as four
 * lanes of one loop (watertight_lanes), bit-identical to the scalar test. The box test is made conservative with respect to the
 * rounding of both the slab test and the watertight triangle test (see ray_setup),
 * so the BVH finds exactly what a loop over all triangles finds. On x86-64 (GCC, Clang)
 * the two queries are also compiled for AVX2 and chosen at run time (b->simd; the same C,
 * bit-identical answers; see bvh_intersect).
 *
 * Triangle test: Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection"
 * (JCGT 2(1)): translate to the ray origin, permute so the dominant direction axis is
 * z, shear so the ray is the z axis, then 2D edge functions with a double-precision
 * re-evaluation when one is exactly zero. Watertight along shared edges and vertices. */
#include "restir/scene/bvh.h"

#include <float.h>
#include <stddef.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The node layout is part of the interface (two nodes per 64-byte cache line). */
typedef char bvh_node_must_be_32_bytes[(sizeof(bvh_node) == 32) ? 1 : -1];
/* Vertices are read as float[9] per triangle. */
typedef char vec3f_must_be_12_bytes[(sizeof(vec3f) == 12) ? 1 : -1];

enum {
    BVH_BINS = 16,
    BVH_MAX_LEAF = 8,
    /* Below this depth the SAH decides; deeper nodes are halved by count, which keeps
     * the depth (and the traversal stack) bounded even for adversarial inputs. */
    BVH_SAH_DEPTH_LIMIT = 48,
    /* Depth <= 48 + log2(2^32) < 96; a wide level is at least one binary level, and the
     * stack grows by at most BVH_WIDTH - 1 entries per wide level. */
    BVH_STACK_SIZE = (BVH_WIDTH - 1) * 96 + 1
};

/* SAH constants: cost of one node traversal and one leaf block test (4 triangles as
 * lanes), in the same unit. 2 : 1 measured best of 0.5, 1, 2, 3, 4 on the bunny's rays
 * (docs/performance.md); the tree shape never changes a hit (ties go to the lowest index). */
static const double SAH_TRAVERSAL_COST = 2.0;
static const double SAH_TRIANGLE_COST = 1.0;

#define COUNT_MASK 0xffffffu

/* The traversal's per-node and per-leaf steps, inlined into both queries (gcc inlines
 * them into neither on its own: each has two callers; measured 3-5% faster inlined,
 * docs/performance.md). Only a hint: other compilers get plain inline. */
#ifdef __GNUC__
#define HOT_INLINE inline __attribute__((always_inline))
#else
#define HOT_INLINE inline
#endif

/* The traversal tests a leaf's triangles BVH_LANES at a time (leaf blocks, bvh.h), so the
 * SAH counts a leaf's cost in blocks: ceil(n / BVH_LANES) (as Embree does for its
 * 4-triangle leaves). */
static double sah_blocks(uint32_t n) { return (double)((n + BVH_LANES - 1) / BVH_LANES); }

/* ------------------------------------------------------------------------------- */
/* Boxes                                                                            */

typedef struct {
    float lo[3], hi[3];
} box3;

static box3 box_empty(void)
{
    box3 b;
    int i;
    for (i = 0; i < 3; ++i) {
        b.lo[i] = FLT_MAX;
        b.hi[i] = -FLT_MAX;
    }
    return b;
}

/* (Selects rather than branches: the build spends most of its time here.) */
static inline void box_grow(box3 *b, const box3 *o)
{
    int i;
    for (i = 0; i < 3; ++i) {
        b->lo[i] = o->lo[i] < b->lo[i] ? o->lo[i] : b->lo[i];
        b->hi[i] = o->hi[i] > b->hi[i] ? o->hi[i] : b->hi[i];
    }
}

static inline void box_grow_point(box3 *b, const float p[3])
{
    int i;
    for (i = 0; i < 3; ++i) {
        b->lo[i] = p[i] < b->lo[i] ? p[i] : b->lo[i];
        b->hi[i] = p[i] > b->hi[i] ? p[i] : b->hi[i];
    }
}

/* Surface area (in double: the SAH sums many of them). 0 for an empty box. */
static inline double box_area(const box3 *b)
{
    double dx = (double)b->hi[0] - b->lo[0], dy = (double)b->hi[1] - b->lo[1];
    double dz = (double)b->hi[2] - b->lo[2];
    if (dx < 0 || dy < 0 || dz < 0) return 0;
    return 2 * (dx * dy + dy * dz + dz * dx);
}

/* ------------------------------------------------------------------------------- */
/* Degenerate triangles                                                             */

static int vec3f_is_finite(vec3f v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* A triangle with a non-finite vertex, or whose edge cross product is exactly zero
 * (repeated vertices, collinear vertices), has no area: it can never be hit. The
 * cross product is evaluated in double, where differences of floats of similar
 * magnitude and all products of them are exact, so exactly collinear float vertices
 * give exactly zero. Such triangles are left out of the BVH, and the public
 * ray_triangle_watertight() rejects them too, so both agree. */
static int triangle_is_degenerate(vec3f a, vec3f b, vec3f c)
{
    double e1x, e1y, e1z, e2x, e2y, e2z;
    if (!vec3f_is_finite(a) || !vec3f_is_finite(b) || !vec3f_is_finite(c)) return 1;
    e1x = (double)b.x - a.x, e1y = (double)b.y - a.y, e1z = (double)b.z - a.z;
    e2x = (double)c.x - a.x, e2y = (double)c.y - a.y, e2z = (double)c.z - a.z;
    return e1y * e2z - e1z * e2y == 0 && e1z * e2x - e1x * e2z == 0 && e1x * e2y - e1y * e2x == 0;
}

/* ------------------------------------------------------------------------------- */
/* Build                                                                            */

typedef struct {
    const box3 *prim_box;   /* per valid primitive */
    const float (*centroid)[3];
    uint32_t *index;        /* valid-primitive ids, partitioned in place */
    bvh_node *nodes;
    size_t node_count;
    int depth;
    double sah_cost;        /* unnormalised: sum of cost * area */
} builder;

typedef struct {
    box3 bounds;
    uint32_t count;
} bin;

/* Bin of a centroid coordinate; used for both binning and partitioning so that the
 * two always agree. Clamped as a float before the conversion: a centroid extent below
 * about 1e-37 makes scale infinite, and (int) of inf or NaN is undefined (the fuzzer's
 * finding, tests/data/fuzz/scene/crash-bvh-bin-inf.scene: a light disk of radius 2e-28). */
static int bin_of(float c, float lo, float scale)
{
    float t = (c - lo) * scale;
    if (!(t >= 0)) return 0; /* negative, or NaN (0 * inf) */
    return t >= (float)BVH_BINS ? BVH_BINS - 1 : (int)t;
}

typedef struct {
    int axis;      /* -1: no useful split found */
    int split;     /* primitives with bin < split go left */
    double cost;   /* SAH cost relative to the node's area */
} split_choice;

/* SAH over BVH_BINS bins on each axis with a non-flat centroid extent:
 * cost(split) = C_trav + C_tri * (A_L N_L + A_R N_R) / A_node. */
static split_choice find_sah_split(const builder *b, uint32_t begin, uint32_t end,
                                   const box3 *node_box, const box3 *centroid_box)
{
    split_choice best;
    double node_area = box_area(node_box);
    int axis;
    best.axis = -1;
    best.split = 0;
    best.cost = INFINITY;
    if (node_area <= 0) return best;
    for (axis = 0; axis < 3; ++axis) {
        bin bins[BVH_BINS];
        double right_cost[BVH_BINS];
        float lo = centroid_box->lo[axis], extent = centroid_box->hi[axis] - lo;
        float scale;
        box3 acc;
        uint32_t i, n;
        int k;
        if (!(extent > 0)) continue;
        scale = (float)BVH_BINS / extent;
        for (k = 0; k < BVH_BINS; ++k) {
            bins[k].bounds = box_empty();
            bins[k].count = 0;
        }
        for (i = begin; i < end; ++i) {
            uint32_t p = b->index[i];
            k = bin_of(b->centroid[p][axis], lo, scale);
            box_grow(&bins[k].bounds, &b->prim_box[p]);
            bins[k].count++;
        }
        /* Sweep from the right: right_cost[k] = A(bins k..) * N(bins k..). */
        acc = box_empty();
        n = 0;
        for (k = BVH_BINS - 1; k > 0; --k) {
            box_grow(&acc, &bins[k].bounds);
            n += bins[k].count;
            right_cost[k] = box_area(&acc) * sah_blocks(n);
        }
        /* Sweep from the left and combine. */
        acc = box_empty();
        n = 0;
        for (k = 1; k < BVH_BINS; ++k) {
            double cost;
            box_grow(&acc, &bins[k - 1].bounds);
            n += bins[k - 1].count;
            if (n == 0 || n == end - begin) continue;
            cost = SAH_TRAVERSAL_COST + SAH_TRIANGLE_COST * (box_area(&acc) * sah_blocks(n) + right_cost[k]) / node_area;
            if (cost < best.cost) {
                best.cost = cost;
                best.axis = axis;
                best.split = k;
            }
        }
    }
    return best;
}

/* Moves primitives whose centroid bin is < split to the front; returns the middle. */
static uint32_t partition_by_bin(builder *b, uint32_t begin, uint32_t end, const box3 *centroid_box,
                                 split_choice s)
{
    float lo = centroid_box->lo[s.axis];
    float scale = (float)BVH_BINS / (centroid_box->hi[s.axis] - lo);
    uint32_t i = begin, j = end;
    while (i < j) {
        if (bin_of(b->centroid[b->index[i]][s.axis], lo, scale) < s.split) {
            i++;
        } else {
            uint32_t t = b->index[--j];
            b->index[j] = b->index[i];
            b->index[i] = t;
        }
    }
    return i;
}

static int largest_axis(const box3 *bx)
{
    float dx = bx->hi[0] - bx->lo[0], dy = bx->hi[1] - bx->lo[1], dz = bx->hi[2] - bx->lo[2];
    return dx >= dy && dx >= dz ? 0 : (dy >= dz ? 1 : 2);
}

static void make_leaf(builder *b, bvh_node *node, uint32_t begin, uint32_t end, double area)
{
    node->offset = begin;
    node->count_axis = end - begin;
    b->sah_cost += SAH_TRIANGLE_COST * sah_blocks(end - begin) * area;
}

/* Builds the subtree of index[begin, end) at node `at`; its nodes follow `at`. */
static void build_node(builder *b, size_t at, uint32_t begin, uint32_t end, int depth)
{
    bvh_node *node = &b->nodes[at];
    box3 bounds = box_empty(), centroid_box = box_empty();
    uint32_t i, count = end - begin, mid;
    split_choice s;
    double area;
    size_t left;

    for (i = begin; i < end; ++i) {
        box_grow(&bounds, &b->prim_box[b->index[i]]);
        box_grow_point(&centroid_box, b->centroid[b->index[i]]);
    }
    memcpy(node->min, bounds.lo, sizeof node->min);
    memcpy(node->max, bounds.hi, sizeof node->max);
    area = box_area(&bounds);
    if (depth > b->depth) b->depth = depth;

    if (count == 1) {
        make_leaf(b, node, begin, end, area);
        return;
    }
    s.axis = -1;
    if (depth < BVH_SAH_DEPTH_LIMIT) s = find_sah_split(b, begin, end, &bounds, &centroid_box);
    if (count <= BVH_MAX_LEAF && (s.axis < 0 || s.cost >= SAH_TRIANGLE_COST * sah_blocks(count))) {
        make_leaf(b, node, begin, end, area);
        return;
    }
    if (s.axis >= 0) {
        mid = partition_by_bin(b, begin, end, &centroid_box, s);
    } else {
        /* No SAH split (all centroids coincide, or too deep): halve by count. Any
         * partition is a correct BVH; this one bounds the depth by log2(count). */
        s.axis = largest_axis(&centroid_box);
        mid = begin + count / 2;
    }
    node->count_axis = (uint32_t)s.axis << 24;
    b->sah_cost += SAH_TRAVERSAL_COST * area;

    left = b->node_count++;
    build_node(b, left, begin, mid, depth + 1);
    node = &b->nodes[at];
    node->offset = (uint32_t)b->node_count++;
    build_node(b, node->offset, mid, end, depth + 1);
}

static void triangle_box(const vec3f *v, box3 *bx, float centroid[3])
{
    int k;
    *bx = box_empty();
    for (k = 0; k < 3; ++k) {
        float p[3];
        p[0] = v[k].x;
        p[1] = v[k].y;
        p[2] = v[k].z;
        box_grow_point(bx, p);
    }
    for (k = 0; k < 3; ++k) centroid[k] = 0.5f * bx->lo[k] + 0.5f * bx->hi[k];
}

static int simd_available(void);

/* ------------------------------------------------------------------------------- */
/* Collapse to wide nodes and leaf blocks                                           */

static double node_area(const bvh_node *n)
{
    box3 bx;
    memcpy(bx.lo, n->min, sizeof bx.lo);
    memcpy(bx.hi, n->max, sizeof bx.hi);
    return box_area(&bx);
}

/* The leaf blocks of the binary leaf of `count` slots from `slot`: the triangles' vertices
 * copied inline, four per block, the last triangle repeated in unused lanes. Returns the
 * index of the first block. */
static uint32_t make_leaf_blocks(bvh *b, const vec3f *tri_vertices, uint32_t slot, uint32_t count)
{
    uint32_t first = (uint32_t)b->block_count, i;
    for (i = 0; i < count; i += BVH_LANES) {
        bvh_leaf_block *q = &b->blocks[b->block_count++];
        int lane, j;
        for (lane = 0; lane < BVH_LANES; ++lane) {
            uint32_t s = slot + (i + (uint32_t)lane < count ? i + (uint32_t)lane : count - 1);
            const vec3f *v = &tri_vertices[3 * (size_t)b->prim_order[s]];
            q->tri[lane] = b->prim_order[s];
            for (j = 0; j < 3; ++j) {
                q->v[3 * j][lane] = v[j].x;
                q->v[3 * j + 1][lane] = v[j].y;
                q->v[3 * j + 2][lane] = v[j].z;
            }
        }
    }
    return first;
}

/* SAH-optimal collapse (Ylitie, Karras, Laine 2017, "Efficient incoherent ray traversal
 * on GPUs through compressed wide BVHs", Sec. 4.1): which binary nodes become the wide
 * nodes and the leaves is chosen by dynamic programming over the binary tree, minimising
 *     sum over wide nodes of WIDE_NODE_COST * area + sum over leaves of blocks * area.
 * Per binary node, cost[j - 1] is the least cost of its subtree as at most j children of
 * a wide node (j = 1..BVH_WIDTH); one child is a leaf (the subtree's triangles are
 * contiguous leaf slots, so any subtree of at most BVH_MAX_LEAF triangles can be one) or
 * a wide node whose BVH_WIDTH children are distributed over the two binary children.
 * The boxes are still the binary nodes' own boxes; only which of them are tested changes. */
static const float WIDE_NODE_COST = 2.0f;

typedef struct {
    float cost[BVH_WIDTH];
    uint32_t first, count; /* the subtree's leaf slots */
    int as_leaf;           /* cost[0] is the subtree as one leaf (else one wide node) */
} collapse_cost;

/* The least cost of subtree i as at most j children, split between its binary children
 * l and r (Ylitie et al.'s distribute); *left = the children given to l. */
static float distribute(const collapse_cost *cc, uint32_t l, uint32_t r, int j, int *left)
{
    float best = INFINITY;
    int k;
    *left = 1;
    for (k = 1; k < j; ++k) {
        float c = cc[l].cost[k - 1] + cc[r].cost[j - k - 1];
        if (c < best) {
            best = c;
            *left = k;
        }
    }
    return best;
}

/* Children before parents: node i's children have larger indices (depth-first order). */
static void collapse_costs(const bvh *b, collapse_cost *cc)
{
    size_t i = b->node_count;
    while (i-- > 0) {
        const bvh_node *n = &b->nodes[i];
        collapse_cost *c = &cc[i];
        float area = (float)node_area(n), leaf;
        int j, k;
        if (n->count_axis & COUNT_MASK) {
            c->first = n->offset;
            c->count = n->count_axis & COUNT_MASK;
            for (j = 0; j < BVH_WIDTH; ++j) c->cost[j] = (float)sah_blocks(c->count) * area;
            c->as_leaf = 1;
            continue;
        }
        c->first = cc[i + 1].first;
        c->count = cc[i + 1].count + cc[n->offset].count;
        leaf = c->count <= BVH_MAX_LEAF ? (float)sah_blocks(c->count) * area : INFINITY;
        c->cost[0] = WIDE_NODE_COST * area + distribute(cc, (uint32_t)i + 1, n->offset, BVH_WIDTH, &k);
        c->as_leaf = leaf <= c->cost[0];
        if (c->as_leaf) c->cost[0] = leaf;
        for (j = 2; j <= BVH_WIDTH; ++j) {
            float d = distribute(cc, (uint32_t)i + 1, n->offset, j, &k);
            c->cost[j - 1] = d < c->cost[j - 2] ? d : c->cost[j - 2];
        }
    }
}

/* A child of a wide node: binary node `node`, as a leaf or as a wide node. */
typedef struct {
    uint32_t node;
    int leaf;
} wide_kid;

/* Appends the children of subtree i's best form as at most j children. */
static int gather_kids(const bvh *b, const collapse_cost *cc, uint32_t i, int j, wide_kid *kids, int n)
{
    int k = 0;
    /* The fewest children with the same cost (cost[] does not increase with j). */
    while (j > 1 && cc[i].cost[j - 2] == cc[i].cost[j - 1]) --j;
    if (j == 1 || (b->nodes[i].count_axis & COUNT_MASK)) {
        kids[n].node = i;
        kids[n].leaf = cc[i].as_leaf;
        return n + 1;
    }
    distribute(cc, i + 1, b->nodes[i].offset, j, &k);
    n = gather_kids(b, cc, i + 1, k, kids, n);
    return gather_kids(b, cc, b->nodes[i].offset, j - k, kids, n);
}

/* Wide node `at` for binary node i (a leaf only at the root of a one-leaf tree). */
static void collapse_node(bvh *b, const vec3f *tri_vertices, const collapse_cost *cc, size_t at, uint32_t i)
{
    wide_kid kids[BVH_WIDTH];
    int n = 0, k;
    if (b->nodes[i].count_axis & COUNT_MASK) {
        kids[0].node = i;
        kids[0].leaf = 1;
        n = 1;
    } else {
        distribute(cc, i + 1, b->nodes[i].offset, BVH_WIDTH, &k);
        n = gather_kids(b, cc, i + 1, k, kids, 0);
        n = gather_kids(b, cc, b->nodes[i].offset, BVH_WIDTH - k, kids, n);
    }
    for (k = 0; k < BVH_WIDTH; ++k) {
        bvh_wide_node *w = &b->wide[at];
        const bvh_node *c = &b->nodes[kids[k].node];
        int axis;
        if (k >= n) {
            for (axis = 0; axis < 3; ++axis) {
                w->bounds[axis][k] = FLT_MAX;
                w->bounds[3 + axis][k] = -FLT_MAX;
            }
            w->child[k] = BVH_WIDE_EMPTY;
            w->count[k] = 0;
            continue;
        }
        for (axis = 0; axis < 3; ++axis) {
            w->bounds[axis][k] = c->min[axis];
            w->bounds[3 + axis][k] = c->max[axis];
        }
        if (kids[k].leaf) {
            w->count[k] = cc[kids[k].node].count;
            w->child[k] = make_leaf_blocks(b, tri_vertices, cc[kids[k].node].first, w->count[k]);
        } else {
            size_t child = b->wide_count++;
            w->count[k] = 0;
            w->child[k] = (uint32_t)child;
            collapse_node(b, tri_vertices, cc, child, kids[k].node);
        }
    }
}

/* A copy of count elements of the given size at a 64-byte boundary (free() frees it). */
static void *aligned_copy(const void *from, size_t count, size_t size, rerror *e)
{
    void *p = NULL;
    if (posix_memalign(&p, 64, count * size + (count == 0)) != 0) {
        rerror_set(e, "bvh: out of memory (%zu bytes)", count * size);
        return NULL;
    }
    memcpy(p, from, count * size);
    return p;
}

/* b->wide and b->blocks from b->nodes (at most one wide node per binary interior node,
 * and one for a root that is a leaf; at most one block per triangle). */
static int collapse(bvh *b, const vec3f *tri_vertices, rerror *e)
{
    bvh_wide_node *shrunk;
    bvh_leaf_block *fewer;
    collapse_cost *cc = rmalloc(b->node_count, sizeof *cc, e);
    b->wide = rmalloc(b->node_count, sizeof *b->wide, e);
    b->blocks = rmalloc(b->prim_count, sizeof *b->blocks, e);
    if (!cc || !b->wide || !b->blocks) {
        free(cc);
        return -1;
    }
    collapse_costs(b, cc);
    b->wide_count = 1;
    b->block_count = 0;
    collapse_node(b, tri_vertices, cc, 0, 0);
    free(cc);
    /* Exact-size copies on cache-line boundaries: a wide node is then exactly two
     * lines, and a leaf block never straddles more lines than its size needs. */
    shrunk = aligned_copy(b->wide, b->wide_count, sizeof *b->wide, e);
    fewer = aligned_copy(b->blocks, b->block_count, sizeof *b->blocks, e);
    free(b->wide);
    free(b->blocks);
    b->wide = shrunk;
    b->blocks = fewer;
    return shrunk && fewer ? 0 : -1;
}

int bvh_build(bvh *b, const vec3f *tri_vertices, size_t tri_count, rerror *e)
{
    builder bd;
    box3 *prim_box = NULL;
    float (*centroid)[3] = NULL;
    uint32_t *original = NULL;
    size_t i, valid = 0;
    double root_area;

    memset(b, 0, sizeof *b);
    if (tri_count >= UINT32_MAX / 2) /* node indices are 32-bit; there are < 2n nodes */
        return rerror_set(e, "bvh: %zu triangles are more than the 32-bit node format holds", tri_count);

    prim_box = rmalloc(tri_count, sizeof *prim_box, e);
    centroid = rmalloc(tri_count, sizeof *centroid, e);
    original = rmalloc(tri_count, sizeof *original, e);
    if (!prim_box || !centroid || !original) goto fail;
    for (i = 0; i < tri_count; ++i) {
        const vec3f *v = &tri_vertices[3 * i];
        if (triangle_is_degenerate(v[0], v[1], v[2])) continue;
        triangle_box(v, &prim_box[valid], centroid[valid]);
        original[valid++] = (uint32_t)i;
    }
    b->prim_count = valid;
    if (valid == 0) goto done; /* nothing can be hit; queries return "no hit" */

    memset(&bd, 0, sizeof bd);
    bd.prim_box = prim_box;
    bd.centroid = (const float(*)[3])centroid;
    bd.index = rmalloc(valid, sizeof *bd.index, e);
    bd.nodes = rmalloc(2 * valid - 1, sizeof *bd.nodes, e);
    if (!bd.index || !bd.nodes) {
        free(bd.index);
        free(bd.nodes);
        goto fail;
    }
    for (i = 0; i < valid; ++i) bd.index[i] = (uint32_t)i;
    bd.node_count = 1;
    build_node(&bd, 0, 0, (uint32_t)valid, 0);

    /* Leaf slots -> original triangles. */
    b->prim_order = bd.index;
    for (i = 0; i < valid; ++i) b->prim_order[i] = original[bd.index[i]];
    b->nodes = realloc(bd.nodes, bd.node_count * sizeof *bd.nodes);
    if (!b->nodes) b->nodes = bd.nodes;
    b->node_count = bd.node_count;
    b->depth = bd.depth;
    {
        box3 root;
        memcpy(root.lo, b->nodes[0].min, sizeof root.lo);
        memcpy(root.hi, b->nodes[0].max, sizeof root.hi);
        root_area = box_area(&root);
    }
    b->sah_cost = root_area > 0 ? bd.sah_cost / root_area : 0;
    if (collapse(b, tri_vertices, e)) goto fail;
    b->simd = simd_available();
done:
    free(prim_box);
    free(centroid);
    free(original);
    return 0;
fail:
    free(prim_box);
    free(centroid);
    free(original);
    bvh_free(b);
    return -1;
}

void bvh_free(bvh *b)
{
    free(b->nodes);
    free(b->wide);
    free(b->prim_order);
    free(b->blocks);
    memset(b, 0, sizeof *b);
}

size_t bvh_memory_bytes(const bvh *b)
{
    return b->node_count * sizeof *b->nodes + b->wide_count * sizeof *b->wide + b->block_count * sizeof *b->blocks +
           b->prim_count * sizeof *b->prim_order;
}

/* The cost the collapse minimises (collapse_costs), of the wide subtree `at` whose box has
 * the given area. */
static double wide_cost(const bvh *b, uint32_t at, double area)
{
    const bvh_wide_node *n = &b->wide[at];
    double cost = WIDE_NODE_COST * area;
    int k;
    for (k = 0; k < BVH_WIDTH; ++k) {
        box3 bx;
        int axis;
        if (n->count[k] == 0 && n->child[k] == BVH_WIDE_EMPTY) continue;
        for (axis = 0; axis < 3; ++axis) {
            bx.lo[axis] = n->bounds[axis][k];
            bx.hi[axis] = n->bounds[3 + axis][k];
        }
        if (n->count[k] > 0) cost += sah_blocks(n->count[k]) * box_area(&bx);
        else cost += wide_cost(b, n->child[k], box_area(&bx));
    }
    return cost;
}

double bvh_wide_sah_cost(const bvh *b)
{
    double root = b->node_count ? node_area(&b->nodes[0]) : 0;
    return b->wide_count && root > 0 ? wide_cost(b, 0, root) / root : 0;
}

/* ------------------------------------------------------------------------------- */
/* Per-ray precomputation                                                            */

typedef struct {
    float org[3], dir[3];
    /* Woop et al. 2013: kz = axis of the largest |dir| component, kx and ky the
     * other two (swapped when dir[kz] < 0 to keep the winding), shear sx, sy, sz. */
    int kx, ky, kz;
    float sx, sy, sz;
    /* Slab test, t = face * inv + c: the inverse direction, per axis the rows of the
     * near and the far face in bvh_wide_node.bounds (chosen by the direction's sign),
     * and the constants c = -org * inv -+ slack / |dir| (see setup_box_test). */
    float inv[3];
    int near_row[3], far_row[3];
    float near_c[3], far_c[3];
    float tmin, tmax;
} ray_setup;

static int largest_abs_axis(const float d[3])
{
    float ax = fabsf(d[0]), ay = fabsf(d[1]), az = fabsf(d[2]);
    return ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
}

/* The ray, its checks and the axes of the triangle test. Returns 0 for a ray that
 * cannot hit anything (zero or non-finite direction, non-finite origin, empty range). */
static HOT_INLINE int setup_axes(ray_setup *s, const ray *r)
{
    s->org[0] = r->origin.x, s->org[1] = r->origin.y, s->org[2] = r->origin.z;
    s->dir[0] = r->dir.x, s->dir[1] = r->dir.y, s->dir[2] = r->dir.z;
    s->tmin = r->tmin;
    s->tmax = r->tmax;
    if (!vec3f_is_finite(r->origin) || !vec3f_is_finite(r->dir)) return 0;
    if (r->dir.x == 0 && r->dir.y == 0 && r->dir.z == 0) return 0;
    if (!(r->tmin < r->tmax)) return 0; /* also rejects NaN bounds */
    s->kz = largest_abs_axis(s->dir);
    s->kx = s->kz == 2 ? 0 : s->kz + 1;
    s->ky = s->kx == 2 ? 0 : s->kx + 1;
    if (s->dir[s->kz] < 0) {
        int t = s->kx;
        s->kx = s->ky;
        s->ky = t;
    }
    return 1;
}

/* The shear of the triangle test; inv_kz = 1 / dir[kz]. */
static HOT_INLINE void setup_shear(ray_setup *s, float inv_kz)
{
    s->sx = s->dir[s->kx] / s->dir[s->kz];
    s->sy = s->dir[s->ky] / s->dir[s->kz];
    s->sz = inv_kz;
}

/* Triangle part of the setup (the scalar test's). Returns 0 as setup_axes. */
static int setup_triangle_test(ray_setup *s, const ray *r)
{
    if (!setup_axes(s, r)) return 0;
    setup_shear(s, 1.0f / s->dir[s->kz]);
    return 1;
}

static float larger(float a, float b) { return a > b ? a : b; }

/* Box part of the setup. The slab distance of a face is evaluated as
 *     t = face * inv + c,   c = -org * inv,
 * two roundings fewer than (face - org) * inv, and every box is enlarged by
 *     slack = 2^-20 (R + M)
 * (R: largest distance from the origin to the scene box along an axis; M: largest
 * coordinate magnitude of the origin and the scene box), applied as -+ slack / |dir_i|
 * folded into c. The slack exceeds the rounding of the slab distances (a few ulps of
 * M) and the displacement of a triangle's vertices by the translation and shear of
 * the triangle test (< 6 ulps of R; Woop et al. 2013 note that their test needs bounds
 * enlarged in the traversal for this reason), so the traversal never skips a box whose triangle the triangle
 * test would hit: the BVH finds exactly what a loop over all triangles finds. The
 * price is boxes larger by ~1e-6 of the scene's extent plus its distance from the
 * coordinate origin. (A NaN can only come from overflow at absurd coordinates; the
 * slab test then keeps the interval unchanged, which is conservative too.)
 * recip[i] = 1 / dir[i] where |dir[i]| > 1e-30 (setup_traversal divides). */
static void setup_box_test(ray_setup *s, const bvh_node *root, const float recip[3])
{
    float reach = 0, magnitude = 0, slack;
    int i;
    for (i = 0; i < 3; ++i) {
        reach = larger(reach, larger(fabsf(root->min[i] - s->org[i]), fabsf(root->max[i] - s->org[i])));
        magnitude = larger(magnitude, larger(fabsf(s->org[i]), larger(fabsf(root->min[i]), fabsf(root->max[i]))));
    }
    slack = (reach + magnitude) * (1.0f / 1048576.0f);
    for (i = 0; i < 3; ++i) {
        /* A zero component gets a huge finite inverse instead of infinity, so that
         * 0 * inv never makes a NaN and a parallel ray outside the slab is culled. */
        float d = s->dir[i];
        float inv = fabsf(d) > 1e-30f ? recip[i] : copysignf(1e30f, d);
        float slack_t = slack * fabsf(inv);
        int negative = inv < 0;
        s->inv[i] = inv;
        s->near_c[i] = -s->org[i] * inv - slack_t;
        s->far_c[i] = -s->org[i] * inv + slack_t;
        s->near_row[i] = i + 3 * negative;
        s->far_row[i] = i + 3 - 3 * negative;
    }
}

/* The whole per-ray setup of a query: setup_triangle_test and setup_box_test sharing
 * the reciprocal of the dominant direction component (the same division, so the same
 * bits). Returns 0 as setup_axes. */
static int setup_traversal(ray_setup *s, const ray *r, const bvh_node *root)
{
    float recip[3];
    int i;
    if (!setup_axes(s, r)) return 0;
    for (i = 0; i < 3; ++i) recip[i] = 1.0f / (fabsf(s->dir[i]) > 1e-30f ? s->dir[i] : 1.0f);
    setup_shear(s, fabsf(s->dir[s->kz]) > 1e-30f ? recip[s->kz] : 1.0f / s->dir[s->kz]);
    setup_box_test(s, root, recip);
    return 1;
}

/* ------------------------------------------------------------------------------- */
/* Watertight ray/triangle test (Woop, Benthin, Wald 2013)                          */

/* p: the 9 floats of the triangle. On a hit of the (infinite) line with the closed
 * triangle, writes t and the barycentrics of vertices 1 and 2 and returns 1. The caller
 * checks the t range. */
static inline int watertight_test(const ray_setup *s, const float p[9], float *t, float *b1, float *b2)
{
    const int kx = s->kx, ky = s->ky, kz = s->kz;
    /* Translate to the ray origin; z = the dominant direction axis. */
    const float az = p[kz] - s->org[kz], bz = p[3 + kz] - s->org[kz], cz = p[6 + kz] - s->org[kz];
    /* Shear so that the ray becomes the +z axis through (0,0). */
    const float ax = (p[kx] - s->org[kx]) - s->sx * az, ay = (p[ky] - s->org[ky]) - s->sy * az;
    const float bx = (p[3 + kx] - s->org[kx]) - s->sx * bz, by = (p[3 + ky] - s->org[ky]) - s->sy * bz;
    const float cx = (p[6 + kx] - s->org[kx]) - s->sx * cz, cy = (p[6 + ky] - s->org[ky]) - s->sy * cz;
    /* Scaled barycentrics: 2D edge functions of the edges opposite a, b, c. */
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    float det, tt;
    /* An edge function that is exactly 0 in float may have either sign: re-evaluate
     * all three in double, where the products of floats are exact, so the difference
     * is rounded once and its sign is right (the paper's fallback). */
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = (float)((double)cx * by - (double)cy * bx);
        v = (float)((double)ax * cy - (double)ay * cx);
        w = (float)((double)bx * ay - (double)by * ax);
    }
    /* Mixed signs: the ray passes outside (both windings accepted: no culling). */
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return 0;
    det = u + v + w;
    if (det == 0.0f) return 0; /* the ray lies in the triangle's plane */
    /* Scaled hit distance from the sheared z coordinates. */
    tt = (u * (s->sz * az) + v * (s->sz * bz) + w * (s->sz * cz)) / det;
    *t = tt;
    *b1 = v / det;
    *b2 = w / det;
    return 1;
}

int ray_triangle_watertight(const ray *r, vec3f v0, vec3f v1, vec3f v2, float *t, float *b1, float *b2)
{
    ray_setup s;
    float p[9], tt, u1, u2;
    if (triangle_is_degenerate(v0, v1, v2) || !setup_triangle_test(&s, r)) return 0;
    memcpy(p, &v0, sizeof v0);
    memcpy(p + 3, &v1, sizeof v1);
    memcpy(p + 6, &v2, sizeof v2);
    if (!watertight_test(&s, p, &tt, &u1, &u2) || !(tt > s.tmin && tt < s.tmax)) return 0;
    *t = tt;
    *b1 = u1;
    *b2 = u2;
    return 1;
}

/* The hits of the four lanes of a leaf block: t, and the barycentrics as the quotients
 * b1 = v / det, b2 = w / det, divided only for the hit that is kept (dividing here
 * would keep gcc from vectorising the lanes). */
typedef struct {
    float t[BVH_LANES], v[BVH_LANES], w[BVH_LANES], det[BVH_LANES];
} lane_hits;

/* The 9 coordinates of lane `lane` of a leaf block, in watertight_test's order. */
static void lane_triangle(const bvh_leaf_block *q, int lane, float p[9])
{
    int i;
    for (i = 0; i < 9; ++i) p[i] = q->v[i][lane];
}

/* watertight_test plus the caller's range check on the four lanes of a leaf block:
 * lane by lane the very same float operations in the same order (the loops have no
 * branches, so compilers vectorise them; -ffp-contract=off keeps every product rounded
 * as in the scalar code). A lane with an edge function exactly 0 goes to watertight_test
 * itself, which re-evaluates it in double. Returns the mask of the lanes hit in
 * (tmin, tmax), with their t and barycentrics in h (the unit test
 * ray_triangle4_equals_scalar_test checks bit equality). */
static HOT_INLINE unsigned watertight_lanes(const ray_setup *s, const bvh_leaf_block *q, lane_hits *h)
{
    const int kx = s->kx, ky = s->ky, kz = s->kz;
    const float *pax = q->v[kx], *pay = q->v[ky], *paz = q->v[kz];
    const float *pbx = q->v[3 + kx], *pby = q->v[3 + ky], *pbz = q->v[3 + kz];
    const float *pcx = q->v[6 + kx], *pcy = q->v[6 + ky], *pcz = q->v[6 + kz];
    const float ox = s->org[kx], oy = s->org[ky], oz = s->org[kz];
    const float sx = s->sx, sy = s->sy, sz = s->sz, tmin = s->tmin, tmax = s->tmax;
    float u[BVH_LANES], v[BVH_LANES], w[BVH_LANES], az[BVH_LANES], bz[BVH_LANES], cz[BVH_LANES];
    int is_zero[BVH_LANES], is_hit[BVH_LANES];
    unsigned zero = 0, mask = 0;
    int k;
    for (k = 0; k < BVH_LANES; ++k) {
        const float a_z = paz[k] - oz, b_z = pbz[k] - oz, c_z = pcz[k] - oz;
        const float a_x = (pax[k] - ox) - sx * a_z, a_y = (pay[k] - oy) - sy * a_z;
        const float b_x = (pbx[k] - ox) - sx * b_z, b_y = (pby[k] - oy) - sy * b_z;
        const float c_x = (pcx[k] - ox) - sx * c_z, c_y = (pcy[k] - oy) - sy * c_z;
        u[k] = c_x * b_y - c_y * b_x;
        v[k] = a_x * c_y - a_y * c_x;
        w[k] = b_x * a_y - b_y * a_x;
        az[k] = a_z;
        bz[k] = b_z;
        cz[k] = c_z;
    }
    for (k = 0; k < BVH_LANES; ++k) {
        const float det = u[k] + v[k] + w[k], safe = det != 0.0f ? det : 1.0f;
        const int mixed = ((u[k] < 0) | (v[k] < 0) | (w[k] < 0)) & ((u[k] > 0) | (v[k] > 0) | (w[k] > 0));
        const float tt = (u[k] * (sz * az[k]) + v[k] * (sz * bz[k]) + w[k] * (sz * cz[k])) / safe;
        h->t[k] = tt;
        h->v[k] = v[k];
        h->w[k] = w[k];
        h->det[k] = det;
        is_zero[k] = (u[k] == 0.0f) | (v[k] == 0.0f) | (w[k] == 0.0f);
        is_hit[k] = !mixed & (det != 0.0f) & (tt > tmin) & (tt < tmax);
    }
    for (k = 0; k < BVH_LANES; ++k) {
        zero |= (unsigned)is_zero[k] << k;
        mask |= (unsigned)is_hit[k] << k;
    }
    if (zero) {
        for (k = 0; k < BVH_LANES; ++k) {
            float p[9];
            if (!((zero >> k) & 1u)) continue;
            lane_triangle(q, k, p);
            mask &= ~(1u << k);
            /* b1 / 1 and b2 / 1 are b1 and b2 exactly. */
            h->det[k] = 1.0f;
            if (watertight_test(s, p, &h->t[k], &h->v[k], &h->w[k]) && h->t[k] > tmin && h->t[k] < tmax)
                mask |= 1u << k;
        }
    }
    return mask;
}

unsigned ray_triangle4_watertight(const ray *r, const vec3f v[BVH_LANES][3], float t[BVH_LANES],
                                  float b1[BVH_LANES], float b2[BVH_LANES])
{
    ray_setup s;
    bvh_leaf_block q;
    lane_hits h;
    unsigned mask, valid = 0;
    int lane, j;
    if (!setup_triangle_test(&s, r)) return 0;
    for (lane = 0; lane < BVH_LANES; ++lane) {
        valid |= (unsigned)!triangle_is_degenerate(v[lane][0], v[lane][1], v[lane][2]) << lane;
        q.tri[lane] = (uint32_t)lane;
        for (j = 0; j < 3; ++j) {
            q.v[3 * j][lane] = v[lane][j].x;
            q.v[3 * j + 1][lane] = v[lane][j].y;
            q.v[3 * j + 2][lane] = v[lane][j].z;
        }
    }
    mask = watertight_lanes(&s, &q, &h) & valid;
    for (lane = 0; lane < BVH_LANES; ++lane) {
        if (!((mask >> lane) & 1u)) continue;
        t[lane] = h.t[lane];
        b1[lane] = h.v[lane] / h.det[lane];
        b2[lane] = h.w[lane] / h.det[lane];
    }
    return mask;
}

/* ------------------------------------------------------------------------------- */
/* Traversal                                                                        */

/* A stack entry: a wide node still to visit and where the ray enters its box, so that a
 * closest hit found meanwhile can cull it without touching it again. (Leaves never go on
 * the stack: they are tested where they are found, push_children_*.) */
typedef struct {
    uint32_t node;
    float tnear;
} stack_entry;

/* Conservative slab tests (Kay & Kajiya 1986, t = face * inv + c with the slack of
 * setup_box_test) of the eight children of a wide node against [tmin, tfar_limit],
 * inclusive so that hits tied in t with the current closest hit are still found; a NaN
 * slab distance leaves the interval unchanged. Returns the bit mask of the children the
 * ray enters and their entry distances. One loop over the children without branches,
 * which compilers vectorise. */
static HOT_INLINE unsigned wide_overlaps(const ray_setup *s, const bvh_wide_node *n, float tfar_limit,
                                         float entry[BVH_WIDTH])
{
    const float *near_x = n->bounds[s->near_row[0]], *near_y = n->bounds[s->near_row[1]];
    const float *near_z = n->bounds[s->near_row[2]], *far_x = n->bounds[s->far_row[0]];
    const float *far_y = n->bounds[s->far_row[1]], *far_z = n->bounds[s->far_row[2]];
    /* Local copies: nothing the loop writes can alias them, so it vectorises. */
    const float ix = s->inv[0], iy = s->inv[1], iz = s->inv[2], tmin = s->tmin;
    const float ncx = s->near_c[0], ncy = s->near_c[1], ncz = s->near_c[2];
    const float fcx = s->far_c[0], fcy = s->far_c[1], fcz = s->far_c[2];
    static const unsigned lane_bit[BVH_WIDTH] = {1, 2, 4, 8, 16, 32, 64, 128}; /* BVH_WIDTH = 8 */
    float tnear[BVH_WIDTH], tfar[BVH_WIDTH];
    unsigned mask = 0;
    int k;
    for (k = 0; k < BVH_WIDTH; ++k) {
        float t, tn = tmin, tf = tfar_limit;
        t = near_x[k] * ix + ncx;
        tn = t > tn ? t : tn;
        t = near_y[k] * iy + ncy;
        tn = t > tn ? t : tn;
        t = near_z[k] * iz + ncz;
        tn = t > tn ? t : tn;
        t = far_x[k] * ix + fcx;
        tf = t < tf ? t : tf;
        t = far_y[k] * iy + fcy;
        tf = t < tf ? t : tf;
        t = far_z[k] * iz + fcz;
        tf = t < tf ? t : tf;
        tnear[k] = tn;
        tfar[k] = tf;
    }
    /* The mask as an OR of per-lane bits (vectorised too: compare, and, reduce). */
    for (k = 0; k < BVH_WIDTH; ++k) {
        entry[k] = tnear[k];
        mask |= lane_bit[k] & (0u - (unsigned)(tnear[k] <= tfar[k]));
    }
    return mask;
}

/* Starts loading a wide node that was just pushed, every cache line of it. Memory latency
 * dominates incoherent rays (docs/performance.md); a cache hint changes no result, and
 * without the GCC/Clang builtin it does nothing. */
static inline void prefetch_node(const bvh *b, uint32_t node)
{
#ifdef __GNUC__
    const char *at = (const char *)&b->wide[node];
    size_t line;
    for (line = 0; line < sizeof(bvh_wide_node); line += 64) __builtin_prefetch(at + line);
#else
    (void)b;
    (void)node;
#endif
}

/* Whether the ray enters child k of n (bit k of the mask of wide_overlaps) and there is
 * a child in that slot. */
static inline int enters(const bvh_wide_node *n, unsigned mask, int k)
{
    return ((mask >> k) & 1u) && !(n->count[k] == 0 && n->child[k] == BVH_WIDE_EMPTY);
}

/* Inserts a wide node into stack[base..top), kept sorted by decreasing entry distance
 * (so that the nearest is visited next; the order only affects the speed: the closest hit
 * and its tie-break do not depend on it), and starts loading it. */
static HOT_INLINE void push_sorted(const bvh *b, stack_entry *stack, int base, int *top, uint32_t node, float tnear)
{
    int j;
    for (j = (*top)++; j > base && stack[j - 1].tnear < tnear; --j) stack[j] = stack[j - 1];
    stack[j].node = node;
    stack[j].tnear = tnear;
    prefetch_node(b, node);
}

/* The caller's hit filter (bvh_intersect_filtered): NULL in the unfiltered queries, where
 * the always-inlined code below then compiles to exactly what it was without filters. */
typedef struct {
    bvh_hit_filter accept;
    const void *ctx;
} hit_filter;

/* 1 if lane k of a block's hits passes the filter (barycentrics as the query reports them). */
static int filter_keeps(const hit_filter *f, const bvh_leaf_block *q, const lane_hits *lh, int k)
{
    return f->accept(f->ctx, q->tri[k], lh->v[k] / lh->det[k], lh->w[k] / lh->det[k]);
}

/* 1 if some lane of `mask` passes the filter (kept out of line: only cut-out scenes call it). */
#ifdef __GNUC__
__attribute__((noinline))
#endif
static int any_lane_kept(const hit_filter *f, const bvh_leaf_block *q, const lane_hits *lh, unsigned mask)
{
    int k;
    for (k = 0; k < BVH_LANES; ++k)
        if (((mask >> k) & 1u) && filter_keeps(f, q, lh, k)) return 1;
    return 0;
}

/* Any hit in the leaf of `count` triangles from block `first` that the filter keeps. */
static HOT_INLINE int leaf_occludes(const ray_setup *s, const bvh *b, uint32_t first, uint32_t count,
                                    const hit_filter *f)
{
    uint32_t block, end;
    for (block = first, end = first + (count + BVH_LANES - 1) / BVH_LANES; block < end; ++block) {
        lane_hits lh;
        unsigned mask = watertight_lanes(s, &b->blocks[block], &lh);
        /* f is a constant NULL in the unfiltered query: then this is `if (mask) return 1`. */
        if (mask && (!f || any_lane_kept(f, &b->blocks[block], &lh, mask))) return 1;
    }
    return 0;
}

/* push_children for any-hit queries: the leaf children the ray enters are tested at once
 * (an occluder ends the query without a push and a pop; docs/performance.md: shadow rays
 * 7-17% faster), the inner ones pushed. Returns 1 if a leaf child occludes. */
static HOT_INLINE int push_children_any_hit(const ray_setup *s, const bvh *b, const bvh_wide_node *n,
                                            stack_entry *stack, int *top, const hit_filter *f)
{
    float entry[BVH_WIDTH];
    unsigned mask = wide_overlaps(s, n, s->tmax, entry);
    int k, base = *top;
    for (k = 0; k < BVH_WIDTH; ++k) {
        if (!enters(n, mask, k)) continue;
        if (n->count[k] == 0)
            push_sorted(b, stack, base, top, n->child[k], entry[k]);
        else if (leaf_occludes(s, b, n->child[k], n->count[k], f))
            return 1;
    }
    return 0;
}

/* The closest hit so far. */
typedef struct {
    int found;
    float t, b1, b2;
    uint32_t tri;
} closest_hit;

/* Tests the leaf of `count` triangles from block `first` against the closest hit c
 * (hits the filter f rejects do not count). */
static HOT_INLINE void leaf_closest(const ray_setup *s, const bvh *b, uint32_t first, uint32_t count, closest_hit *c,
                                    const hit_filter *f)
{
    uint32_t block, end;
    for (block = first, end = first + (count + BVH_LANES - 1) / BVH_LANES; block < end; ++block) {
        lane_hits lh;
        unsigned mask = watertight_lanes(s, &b->blocks[block], &lh);
        int k;
        for (k = 0; mask && k < BVH_LANES; ++k) {
            uint32_t tri = b->blocks[block].tri[k];
            float t = lh.t[k];
            if (!((mask >> k) & 1u)) continue;
            /* Closest t; among exactly equal t the lowest triangle index, so that the
             * answer does not depend on the tree (nor on the lane or visiting order). */
            if (!c->found || t < c->t || (t == c->t && tri < c->tri)) {
                if (f && !filter_keeps(f, &b->blocks[block], &lh, k)) continue;
                c->found = 1;
                c->t = t;
                c->b1 = lh.v[k] / lh.det[k];
                c->b2 = lh.w[k] / lh.det[k];
                c->tri = tri;
            }
        }
    }
}

/* push_children for closest-hit queries, with the leaf children tested where found
 * (as push_children_any_hit). */
static HOT_INLINE void push_children_closest(const ray_setup *s, const bvh *b, const bvh_wide_node *n,
                                             stack_entry *stack, int *top, closest_hit *c, const hit_filter *f)
{
    float entry[BVH_WIDTH];
    unsigned mask = wide_overlaps(s, n, c->t, entry);
    int k, base = *top;
    for (k = 0; k < BVH_WIDTH; ++k) {
        if (!enters(n, mask, k)) continue;
        if (n->count[k] == 0)
            push_sorted(b, stack, base, top, n->child[k], entry[k]);
        else
            leaf_closest(s, b, n->child[k], n->count[k], c, f);
    }
}

/* The queries. Inlined into the public functions below, once as compiled for the
 * build's target and, where available, once more for AVX2 (runtime dispatch). */
static HOT_INLINE int intersect_query(const bvh *b, const ray *r, bvh_hit *h, const hit_filter *f)
{
    ray_setup s;
    stack_entry stack[BVH_STACK_SIZE];
    int top = 0;
    closest_hit c;

    h->tri = BVH_NO_HIT;
    c.found = 0;
    c.t = r->tmax;
    c.b1 = c.b2 = 0;
    c.tri = BVH_NO_HIT;
    if (b->node_count == 0 || !setup_traversal(&s, r, &b->nodes[0])) return 0;
    /* The root's box is not tested (its children's boxes are: measured faster, even
     * for rays that miss the scene; docs/performance.md). */
    stack[top].node = 0;
    stack[top++].tnear = s.tmin;
    while (top > 0) {
        stack_entry at = stack[--top];
        /* Culled: the ray can only enter this box beyond the closest hit so far. */
        if (at.tnear > c.t) continue;
        push_children_closest(&s, b, &b->wide[at.node], stack, &top, &c, f);
    }
    if (!c.found) return 0;
    h->t = c.t;
    h->b1 = c.b1;
    h->b2 = c.b2;
    h->tri = c.tri;
    return 1;
}

static HOT_INLINE int occluded_query(const bvh *b, const ray *r, const hit_filter *f)
{
    ray_setup s;
    stack_entry stack[BVH_STACK_SIZE];
    int top = 0;

    if (b->node_count == 0 || !setup_traversal(&s, r, &b->nodes[0])) return 0;
    /* The root's box is not tested (its children's boxes are: measured faster, even
     * for rays that miss the scene; docs/performance.md). */
    stack[top].node = 0;
    stack[top++].tnear = s.tmin;
    /* Only wide nodes are ever on this stack: leaf children are tested where found. */
    while (top > 0)
        if (push_children_any_hit(&s, b, &b->wide[stack[--top].node], stack, &top, f)) return 1;
    return 0;
}

/* Runtime dispatch (as Embree dispatches to its AVX2 kernels): on x86-64 with GCC or Clang,
 * the very same C of the two queries is compiled a second time for AVX2 (the 8-wide box
 * loop becomes one instruction sequence instead of two SSE iterations; docs/performance.md),
 * and bvh_build sets b->simd when the CPU has AVX2. No intrinsics: the compiler vectorises
 * the same loops. Without FMA (-ffp-contract=off, and the AVX2 target does not enable it)
 * every operation is the same IEEE single-precision operation in the same order, so both
 * paths return bit-identical hits (test bvh_simd_path_equals_portable_path, which clears
 * b->simd to run the portable path). */
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__AVX2__) && !defined(RESTIR_NO_SIMD_DISPATCH)
#define BVH_AVX2_DISPATCH 1
__attribute__((target("avx2"))) static int intersect_avx2(const bvh *b, const ray *r, bvh_hit *h)
{
    return intersect_query(b, r, h, NULL);
}

__attribute__((target("avx2"))) static int occluded_avx2(const bvh *b, const ray *r)
{
    return occluded_query(b, r, NULL);
}

__attribute__((target("avx2"))) static int intersect_filtered_avx2(const bvh *b, const ray *r, bvh_hit *h,
                                                                     const hit_filter *f)
{
    return intersect_query(b, r, h, f);
}

__attribute__((target("avx2"))) static int occluded_filtered_avx2(const bvh *b, const ray *r, const hit_filter *f)
{
    return occluded_query(b, r, f);
}
#endif

/* Whether the queries may run their AVX2 build (this CPU has it, and it was compiled). */
static int simd_available(void)
{
#ifdef BVH_AVX2_DISPATCH
    return __builtin_cpu_supports("avx2") != 0;
#else
    return 0;
#endif
}

int bvh_intersect(const bvh *b, const ray *r, bvh_hit *h)
{
#ifdef BVH_AVX2_DISPATCH
    if (b->simd) return intersect_avx2(b, r, h);
#endif
    return intersect_query(b, r, h, NULL);
}

int bvh_occluded(const bvh *b, const ray *r)
{
#ifdef BVH_AVX2_DISPATCH
    if (b->simd) return occluded_avx2(b, r);
#endif
    return occluded_query(b, r, NULL);
}

/* The filtered queries are separate functions, so that the unfiltered ones above stay
 * exactly the code they were (docs/performance.md: A/B of the alpha test). */
int bvh_intersect_filtered(const bvh *b, const ray *r, bvh_hit *h, bvh_hit_filter accept, const void *ctx)
{
    hit_filter f;
    f.accept = accept;
    f.ctx = ctx;
#ifdef BVH_AVX2_DISPATCH
    if (b->simd) return intersect_filtered_avx2(b, r, h, &f);
#endif
    return intersect_query(b, r, h, &f);
}

int bvh_occluded_filtered(const bvh *b, const ray *r, bvh_hit_filter accept, const void *ctx)
{
    hit_filter f;
    f.accept = accept;
    f.ctx = ctx;
#ifdef BVH_AVX2_DISPATCH
    if (b->simd) return occluded_filtered_avx2(b, r, &f);
#endif
    return occluded_query(b, r, &f);
}

/* ------------------------------------------------------------------------------- */
/* Ray origin offset                                                                */

/* Wächter & Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection"
 * (Ray Tracing Gems, ch. 6): move p along n by int_scale = 256 units in the last place,
 * so that the offset grows with the magnitude of the coordinates, as the rounding
 * errors of the hit point and of the ray/triangle test do. n must point to the side
 * the ray leaves to.
 *
 * One deliberate deviation, for scale invariance. The paper counts the ulps of each
 * coordinate separately and, within origin = 1/32 of zero, adds a fixed
 * float_scale * n_i = 2^-16 n_i instead. A coordinate that is (nearly) zero while the
 * others are large, e.g. every point of a floor at y = 0 in a scene measured in
 * millimetres, then gets an offset far below the rounding error of the ray/triangle
 * test, which grows with the largest coordinates involved: with the paper's rule 7% of
 * the rays spawned from such a floor re-hit it at scale 10^3 and 22% at 10^4 (none at
 * scale 1), see the test offset_ray_origin_floor_at_zero_any_scale. Here the unit is
 * the ulp of the LARGEST coordinate magnitude m = max |p_i|, for every component:
 *     offset = n * 256 ulp(m) = n * 2^(E - 142),   E = biased exponent of m,
 * which is exactly covariant under scaling by powers of two (as the paper's integer
 * offsets are) and has no absolute threshold: a scene at scale 10^-3 is treated as at
 * scale 1. What remains: points much closer to the coordinate origin than the size of
 * their triangle (m < size / 128) still get too small an offset. */
vec3f offset_ray_origin(vec3f p, vec3f n)
{
    const uint32_t int_scale_log2 = 8; /* 256 ulps */
    float m = fmaxf(fabsf(p.x), fmaxf(fabsf(p.y), fabsf(p.z))), unit;
    uint32_t bits, exponent;
    memcpy(&bits, &m, sizeof bits);
    exponent = (bits >> 23) & 0xffu;
    /* ulp(m) = 2^(E - 127 - 23); times 2^8. Kept a normal float: E >= 16 (m >= 2^-111,
     * which also covers m = 0). */
    if (exponent < 16) exponent = 16;
    bits = (exponent - 23 + int_scale_log2) << 23;
    memcpy(&unit, &bits, sizeof unit);
    return v3f(p.x + n.x * unit, p.y + n.y * unit, p.z + n.z * unit);
}
