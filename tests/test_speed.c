/* Speed work without changing a bit (issue 17, docs/performance.md): the images of a few
 * small renders must have the checksums recorded with the code BEFORE the speed changes
 * (main at ea610ee: binary BVH, one hash per random number). Fixed seed 1 on purpose (the
 * recorded checksums are for that seed; SEED= does not apply). Covers the path tracer on
 * the Cornell box (GGX plastic + Lambert), on the glass scene (delta lobes, ~3k
 * triangles) and on a generated displaced sphere (4.8k triangles: the wide BVH), and the
 * ReSTIR PT frame (initial resampling + spatial reuse) on the Cornell box. A deliberate
 * one-ulp change anywhere in these paths changes the checksum. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/scene/bvh.h"
#include "restir/scene/generate.h"
#include "restir/scene/scene.h"
#include "restir/core/vec.h"
#include "test.h"

/* FNV-1a, 64 bits, of a file's bytes; 0 if it cannot be read. */
static unsigned long long file_fnv1a(const char *path)
{
    FILE *f = fopen(path, "rb");
    unsigned long long h = 0xcbf29ce484222325ull;
    int c;
    if (!f) return 0;
    while ((c = getc(f)) != EOF) {
        h ^= (unsigned long long)(unsigned char)c;
        h *= 0x100000001b3ull;
    }
    fclose(f);
    return h;
}

typedef struct {
    const char *name, *args;
    unsigned long long fnv_double, fnv_float; /* recorded before the change, per PRECISION */
} recorded_render;

TEST(speed_images_bit_identical_to_recorded)
{
    static const recorded_render cases[] = {
        {"pt-cornell", "render scenes/cornell.scene --method pt --spp 2 --size 64x64", 0x9608dbe7132d5205ull,
         0xd2d3ebbb73afaa25ull},
        {"pt-glass", "render scenes/glass.scene --method pt --spp 2 --size 64x64", 0xd04b221da808db70ull, 0x79f1c75e9ec11cd8ull},
        {"restir-cornell", "render scenes/cornell.scene --method restir --size 64x64", 0x63ff91161032e47full, 0xb8868900d2c7c8bfull},
        {"pt-sphere", "render @SPHERE --method pt --spp 1 --size 48x48", 0x8dda5a36e14d5486ull, 0x4acc2a07b8accbe6ull},
    };
    char out[4096], obj[1024], scene[1024], args[2048], pfm[1024];
    size_t i;
    snprintf(obj, sizeof obj, "%s", test_tmp_path("speed-sphere.obj"));
    snprintf(scene, sizeof scene, "%s", test_tmp_path("speed-sphere.scene"));
    CHECKF(test_cli(out, sizeof out, "generate sphere --subdivisions 20 -o '%s'", obj) == 0, "%s", out);
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const recorded_render *c = &cases[i];
        unsigned long long want = sizeof(real) == sizeof(double) ? c->fnv_double : c->fnv_float, got;
        const char *at = strstr(c->args, "@SPHERE");
        if (at)
            snprintf(args, sizeof args, "%.*s'%s'%s", (int)(at - c->args), c->args, scene, at + 7);
        else
            snprintf(args, sizeof args, "%s", c->args);
        snprintf(pfm, sizeof pfm, "%s", test_tmp_path("speed-image.pfm"));
        CHECKF(test_cli(out, sizeof out, "%s --seed 1 --threads 2 -o '%s'", args, pfm) == 0, "%s: %s", c->name, out);
        got = file_fnv1a(pfm);
        CHECKF(got == want, "%s: image checksum %016llx, recorded before the speed changes %016llx", c->name, got,
               want);
    }
}

/* The wide tree (bvh.h) covers every triangle exactly once, through leaf blocks that
 * hold its vertices and repeat a leaf's last triangle in unused lanes; its child boxes
 * contain their triangles, and its depth stays within the binary tree's (the traversal
 * stack is sized by that). */
static int wide_leaf_ok(const bvh *b, const scene *s, const bvh_wide_node *n, int k, unsigned char *seen)
{
    uint32_t i, blocks = (n->count[k] + BVH_LANES - 1) / BVH_LANES;
    int ok = n->child[k] + blocks <= b->block_count;
    for (i = 0; ok && i < BVH_LANES * blocks; ++i) {
        const bvh_leaf_block *q = &b->blocks[n->child[k] + i / BVH_LANES];
        int lane = (int)(i % BVH_LANES), c;
        uint32_t tri = q->tri[lane];
        ok &= tri < s->triangle_count;
        if (!ok) break;
        if (i < n->count[k]) seen[tri]++;
        else ok &= tri == q->tri[lane - 1]; /* the last triangle repeated */
        for (c = 0; c < 3; ++c) {
            vec3f v = s->positions[s->triangles[tri].v[c]];
            ok &= v.x == q->v[3 * c][lane] && v.y == q->v[3 * c + 1][lane] && v.z == q->v[3 * c + 2][lane];
            ok &= v.x >= n->bounds[0][k] && v.x <= n->bounds[3][k] && v.y >= n->bounds[1][k] &&
                  v.y <= n->bounds[4][k] && v.z >= n->bounds[2][k] && v.z <= n->bounds[5][k];
        }
    }
    return ok;
}

static int wide_walk(const bvh *b, const scene *s, uint32_t at, int depth, unsigned char *seen, int *max_depth)
{
    const bvh_wide_node *n = &b->wide[at];
    int k, ok = 1;
    if (depth > *max_depth) *max_depth = depth;
    for (k = 0; k < BVH_WIDTH; ++k) {
        if (n->count[k] == 0 && n->child[k] == BVH_WIDE_EMPTY) continue;
        if (n->count[k] == 0) {
            ok &= n->child[k] > at && n->child[k] < b->wide_count;
            if (ok) ok &= wide_walk(b, s, n->child[k], depth + 1, seen, max_depth);
            continue;
        }
        ok &= wide_leaf_ok(b, s, n, k, seen);
    }
    return ok;
}

TEST(bvh_wide_tree_covers_every_leaf_slot_once)
{
    scene s;
    rerror e;
    unsigned char *seen;
    size_t i, once = 0;
    int depth = 0;
    memset(&s, 0, sizeof s);
    CHECKF(generate_displaced_sphere(&s, 24, &e) == 0 && scene_prepare(&s, &e) == 0, "%s", e.msg);
    seen = calloc(s.triangle_count, 1);
    CHECK(seen != NULL && s.accel.wide_count >= 1 && s.accel.wide_count < s.accel.node_count);
    CHECK(s.accel.prim_count == s.triangle_count); /* no degenerate triangles */
    if (seen) {
        CHECK(wide_walk(&s.accel, &s, 0, 0, seen, &depth));
        for (i = 0; i < s.triangle_count; ++i) once += seen[i] == 1;
        CHECKF(once == s.triangle_count, "%zu of %zu triangles reached exactly once", once, s.triangle_count);
        CHECKF(depth <= s.accel.depth, "wide depth %d > binary depth %d", depth, s.accel.depth);
    }
    free(seen);
    scene_free(&s);
}
