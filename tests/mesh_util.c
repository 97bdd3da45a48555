/* mesh_util.h: closed, outward meshes. */
#include "mesh_util.h"

#include <stdlib.h>

typedef struct {
    uint32_t a, b;
} directed_edge;

static int compare_edges(const void *x, const void *y)
{
    const directed_edge *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

const char *check_closed_outward(const scene *s, uint32_t o, double *volume)
{
    directed_edge *edges = malloc(3 * s->triangle_count * sizeof *edges);
    size_t n = 0, t, i;
    const char *problem = NULL;
    *volume = 0;
    if (!edges) return "out of memory";
    for (t = 0; t < s->triangle_count; ++t) {
        int k;
        vec3 a, b, c;
        if (s->triangles[t].object != o) continue;
        a = v3_from_f(s->positions[s->triangles[t].v[0]]);
        b = v3_from_f(s->positions[s->triangles[t].v[1]]);
        c = v3_from_f(s->positions[s->triangles[t].v[2]]);
        *volume += v3_dot(a, v3_cross(b, c)) / 6;
        for (k = 0; k < 3; ++k) {
            edges[n].a = s->triangles[t].v[k];
            edges[n].b = s->triangles[t].v[(k + 1) % 3];
            n++;
        }
    }
    qsort(edges, n, sizeof *edges, compare_edges);
    for (i = 0; i < n && !problem; ++i) {
        directed_edge rev;
        if (i > 0 && !compare_edges(&edges[i - 1], &edges[i])) problem = "a directed edge is used twice";
        rev.a = edges[i].b;
        rev.b = edges[i].a;
        if (!bsearch(&rev, edges, n, sizeof *edges, compare_edges)) problem = "an edge has no opposite (hole)";
    }
    if (!problem && n == 0) problem = "no triangles";
    if (!problem && !(*volume > 0)) problem = "faces point inward (negative volume)";
    free(edges);
    return problem;
}

