/* Ear-clipping triangulation of a polygon given by its 3D corners (OBJ faces with more
 * than three vertices). The polygon is projected onto the plane of its Newell normal,
 * where it winds counter-clockwise; ears are clipped there, so concave polygons and
 * polygons with a hole joined by a bridge edge (corners visited twice) are correct.
 * Every output triangle keeps the polygon's winding. */
#ifndef RESTIR_TRIANGULATE_H
#define RESTIR_TRIANGULATE_H

#include <stddef.h>
#include <stdint.h>
#include "restir/core/error.h"
#include "restir/core/vec.h"

typedef struct {
    double *x, *y;          /* corners in the plane */
    uint32_t *corner;       /* slot -> corner number */
    uint32_t *prev, *next;  /* the remaining polygon as a doubly linked cycle of slots */
    unsigned char *convex;  /* per slot: the corner turns strictly counter-clockwise */
    size_t capacity;
} triangulator;

/* Triangulates the n corners; writes up to n - 2 triangles as corner numbers (0..n-1)
 * to tri (3 per triangle) and their count to *count. For a convex polygon the result
 * is the fan from corner 0. Consecutive repeated corners are skipped; a polygon whose
 * Newell normal is zero (all corners collinear) gives no triangles. Never loops forever:
 * when no proper ear exists (degenerate or self-intersecting input) a fallback clips
 * one corner per step anyway; after 16 such passes the remaining corners are clipped
 * in order without a search, so no input costs more than 16 quadratic passes. */
int triangulate_polygon(triangulator *t, const vec3f *corners, size_t n, uint32_t *tri, size_t *count, rerror *e);
void triangulator_free(triangulator *t);

/* Newell's normal of the polygon: its length is twice the area of the polygon
 * projected onto the plane it defines (Newell's method, e.g. Sutherland et al. 1974;
 * Filippo Tampieri, "Newell's Method for Computing the Plane Equation", Graphics Gems III). */
vec3 polygon_newell_normal(const vec3f *corners, size_t n);

#endif
