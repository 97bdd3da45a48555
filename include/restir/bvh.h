/* Bounding volume hierarchy over triangles: binned-SAH build, 32-byte flattened
 * nodes collapsed to 4-wide nodes, ordered stack traversal, watertight ray/triangle test (Woop et al. 2013).
 * Geometry is float (docs/design.md, Conventions). */
#ifndef RESTIR_BVH_H
#define RESTIR_BVH_H

#include <stddef.h>
#include <stdint.h>
#include "restir/error.h"
#include "restir/vec.h"

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

/* The traversal's node: the binary tree above collapsed to 4 children per node
 * (BVH4; docs/performance.md), 128 bytes = two cache lines. Structure of arrays, so the
 * four slab tests are one loop the compiler can vectorise. The child boxes are exactly
 * the binary tree's node boxes. Per child k: bounds[0..2][k] = min x, y, z and
 * bounds[3..5][k] = max x, y, z; count[k] > 0: a leaf of count[k] triangles from leaf
 * slot child[k]; count[k] == 0: the wide node child[k], or no child if child[k] is
 * BVH_WIDE_EMPTY (its box is empty too). */
#define BVH_WIDTH 4
#define BVH_WIDE_EMPTY UINT32_MAX
typedef struct {
    float bounds[6][BVH_WIDTH];
    uint32_t child[BVH_WIDTH];
    uint32_t count[BVH_WIDTH];
} bvh_wide_node;

typedef struct {
    bvh_node *nodes;        /* the binary SAH tree (the build's output) */
    size_t node_count;
    bvh_wide_node *wide;    /* the same tree, 4-wide, what the queries traverse */
    size_t wide_count;
    uint32_t *prim_order;   /* leaf slots -> original triangle index */
    vec3f *leaf_vertices;   /* 3 vertices per leaf slot, in prim_order order */
    size_t prim_count;
    int depth;
    double sah_cost;
} bvh;

/* Builds over tri_count triangles given as 3 consecutive vertices each. */
int bvh_build(bvh *b, const vec3f *tri_vertices, size_t tri_count, rerror *e);
void bvh_free(bvh *b);

/* Closest hit with t in (r->tmin, r->tmax). Returns 1 on a hit. */
int bvh_intersect(const bvh *b, const ray *r, bvh_hit *h);
/* Any hit with t in (r->tmin, r->tmax). Returns 1 if occluded. */
int bvh_occluded(const bvh *b, const ray *r);

/* Watertight ray/triangle test (Woop, Benthin, Wald 2013). 1 on a hit in range.
 * Degenerate triangles (zero area, non-finite vertices) are never hit; the BVH leaves
 * them out, so bvh_intersect == the loop over all triangles with this test. */
int ray_triangle_watertight(const ray *r, vec3f v0, vec3f v1, vec3f v2, float *t, float *b1, float *b2);

/* Robust, scale-invariant ray-origin offset along the (geometric) normal n
 * (Wächter & Binder, Ray Tracing Gems ch. 6): 256 ULPs of the point's largest
 * coordinate (the paper counts ULPs per coordinate; see bvh.c for why not). */
vec3f offset_ray_origin(vec3f p, vec3f n);

#endif
