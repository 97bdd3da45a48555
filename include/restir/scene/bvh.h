/* Bounding volume hierarchy over triangles: binned-SAH build, 32-byte flattened
 * nodes collapsed (SAH-optimally) to 8-wide nodes with 4-triangle leaf blocks, ordered
 * stack traversal, watertight ray/triangle test (Woop et al. 2013), four triangles at a
 * time.
 * Geometry is float (docs/design.md, Conventions). */
#ifndef RESTIR_BVH_H
#define RESTIR_BVH_H

#include <stddef.h>
#include <stdint.h>
#include "restir/core/error.h"
#include "restir/core/vec.h"

typedef struct {
    vec3f origin, dir;
    float tmin, tmax;
} ray;

#define BVH_NO_HIT UINT32_MAX

typedef struct {
    float t;
    float b1, b2;  /* barycentric coordinates of vertices 1 and 2 */
    uint32_t tri;  /* original triangle index, or BVH_NO_HIT */
} bvh_hit;

/* 32 bytes: bounds, then either the right child's index (interior; the left child
 * is the next node) or the first primitive (leaf), and the primitive count (0 = interior)
 * with the split axis packed in. */
typedef struct {
    float min[3];
    uint32_t offset;  /* leaf: first index into prim_order; interior: right child */
    float max[3];
    uint32_t count_axis; /* leaf: primitive count (>0) in the low 24 bits; interior: axis << 24 */
} bvh_node;

/* The traversal's node: the binary tree above collapsed to BVH_WIDTH = 8 children per
 * node (BVH8; docs/performance.md), 256 bytes = four cache lines (allocated on a 64-byte
 * boundary). Structure of arrays, so the eight slab tests are one loop the compiler can
 * vectorise. The child boxes are exactly
 * the binary tree's node boxes. Per child k: bounds[0..2][k] = min x, y, z and
 * bounds[3..5][k] = max x, y, z; count[k] > 0: a leaf of count[k] triangles stored in
 * the (count[k] + 3) / 4 leaf blocks from block child[k]; count[k] == 0: the wide node
 * child[k], or no child if child[k] is BVH_WIDE_EMPTY (its box is empty too). */
#define BVH_WIDTH 8
#define BVH_WIDE_EMPTY UINT32_MAX
typedef struct {
    float bounds[6][BVH_WIDTH];
    uint32_t child[BVH_WIDTH];
    uint32_t count[BVH_WIDTH];
} bvh_wide_node;

/* Four triangles of a leaf, structure of arrays, so that the watertight test runs on
 * them as four lanes of one loop (160 bytes). v[3 * j + axis][lane] = coordinate `axis`
 * of vertex j; tri[lane] = the original triangle index. A leaf whose count is not a
 * multiple of 4 repeats its last triangle in the unused lanes (a repeated triangle
 * cannot change the closest hit or its tie-break). */
#define BVH_LANES 4
typedef struct {
    float v[9][BVH_LANES];
    uint32_t tri[BVH_LANES];
} bvh_leaf_block;

typedef struct {
    bvh_node *nodes;        /* the binary SAH tree (the build's output) */
    size_t node_count;
    bvh_wide_node *wide;    /* the same tree, BVH_WIDTH wide, what the queries traverse */
    size_t wide_count;
    uint32_t *prim_order;   /* leaf slots of the binary tree -> original triangle index */
    bvh_leaf_block *blocks; /* the wide tree's leaves: triangles inline, in traversal order */
    size_t block_count;
    size_t prim_count;
    int depth;
    double sah_cost;
    int simd; /* 1: the queries run their AVX2 build (x86-64, chosen at run time by bvh_build;
               * bit-identical hits); 0: the portable build. Either may be set by hand. */
} bvh;

/* Builds over tri_count triangles given as 3 consecutive vertices each. */
int bvh_build(bvh *b, const vec3f *tri_vertices, size_t tri_count, rerror *e);
void bvh_free(bvh *b);
/* Bytes of every array the BVH holds (binary nodes, wide nodes, leaf blocks, leaf order). */
size_t bvh_memory_bytes(const bvh *b);

/* The SAH cost of the wide tree as the collapse counts it (a wide node 2, a leaf block 1,
 * each times its box's area), relative to the root's area. */
double bvh_wide_sah_cost(const bvh *b);

/* Closest hit with t in (r->tmin, r->tmax). Returns 1 on a hit. */
int bvh_intersect(const bvh *b, const ray *r, bvh_hit *h);
/* Any hit with t in (r->tmin, r->tmax). Returns 1 if occluded. */
int bvh_occluded(const bvh *b, const ray *r);

/* A hit filter: 1 keeps the hit of triangle `tri` at barycentrics (b1, b2), 0 makes the
 * queries below act as if that triangle were not there at that point (alpha cut-outs). */
typedef int (*bvh_hit_filter)(const void *ctx, uint32_t tri, float b1, float b2);
/* bvh_intersect and bvh_occluded counting only the hits `accept` keeps. The closest kept
 * hit; among kept hits at exactly equal t the lowest triangle index, as without a filter. */
int bvh_intersect_filtered(const bvh *b, const ray *r, bvh_hit *h, bvh_hit_filter accept, const void *ctx);
int bvh_occluded_filtered(const bvh *b, const ray *r, bvh_hit_filter accept, const void *ctx);

/* Watertight ray/triangle test (Woop, Benthin, Wald 2013). 1 on a hit in range.
 * Degenerate triangles (zero area, non-finite vertices) are never hit; the BVH leaves
 * them out, so bvh_intersect == the loop over all triangles with this test. */
int ray_triangle_watertight(const ray *r, vec3f v0, vec3f v1, vec3f v2, float *t, float *b1, float *b2);
/* The same test on four triangles at once (v[lane][vertex]), as the traversal runs it on
 * a leaf block: returns the mask of the lanes hit in range, and for those lanes t, b1, b2
 * bit-identical to ray_triangle_watertight on that triangle alone. */
unsigned ray_triangle4_watertight(const ray *r, const vec3f v[BVH_LANES][3], float t[BVH_LANES],
                                  float b1[BVH_LANES], float b2[BVH_LANES]);

/* Robust, scale-invariant ray-origin offset along the (geometric) normal n
 * (Wächter & Binder, Ray Tracing Gems ch. 6): 256 ULPs of the point's largest
 * coordinate (the paper counts ULPs per coordinate; see bvh.c for why not). */
vec3f offset_ray_origin(vec3f p, vec3f n);

#endif
