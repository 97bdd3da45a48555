/* The private directory the fuzz targets write their input into (fuzz.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "fuzz.h"
#include "restir/scene/scene.h"


/* A lit quad: what a fuzzed scene file's `mesh quad.obj` and an OBJ's `mtllib
 * quad.mtl` find (tests/data/quad-light.* in a few lines). */
static const char quad_obj[] = "mtllib quad.mtl\n"
                               "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
                               "v -0.2 1.9 -0.2\nv 0.2 1.9 -0.2\nv 0.2 1.9 0.2\nv -0.2 1.9 0.2\n"
                               "usemtl floor\nf 1 4 3 2\nusemtl light\nf 5 6 7 8\n";
static const char quad_mtl[] = "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 10 10 10\n";
/* A textured quad and a small emitter with an emission map above it (`mesh tex.obj`;
 * object `textured`): every map statement the MTL reader loads, all naming sky.pfm, so a
 * scene reaches texture loading and textured emitters. */
static const char tex_obj[] = "mtllib tex.mtl\no textured\n"
                              "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
                              "v -0.2 1.5 -0.2\nv 0.2 1.5 -0.2\nv 0.2 1.5 0.2\nv -0.2 1.5 0.2\n"
                              "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\nvn 0 -1 0\n"
                              "usemtl textured\nf 1/1/1 4/4/1 3/3/1 2/2/1\n"
                              "o glow\nusemtl glow\nf 5/1/2 6/2/2 7/3/2 8/4/2\n";
static const char tex_mtl[] = "newmtl textured\nKd 1 1 1\nmap_Kd sky.pfm\nmap_Pr sky.pfm\nmap_Ns sky.pfm\n"
                              "map_d sky.pfm\nnewmtl glow\nKd 0 0 0\nKe 5 5 5\nmap_Ke sky.pfm\n";
/* sky.pfm: a 4 x 2 RGB map with one bright texel, for `environment map sky.pfm` (the
 * importance tables of scene_prepare) and the textures above. */
enum { SKY_W = 4, SKY_H = 2 };

static char directory[64];
static const char *const companions[] = {"quad.obj", "quad.mtl", "tex.obj", "tex.mtl"};

static void remove_directory(void)
{
    /* Only the names the targets use: the directory holds nothing else. */
    static const char *const names[] = {"quad.obj",  "quad.mtl",  "tex.obj",   "tex.mtl",    "sky.pfm",
                                        "input.obj", "input.mtl", "input.scene", "input.pfm", "input.rsv",
                                        "input.gbuf", "manifest.json", "input.exr", "input.png", NULL};
    char path[128];
    int i;
    for (i = 0; names[i]; ++i) {
        snprintf(path, sizeof path, "%s/%s", directory, names[i]);
        remove(path);
    }
    rmdir(directory);
}

static int write_bytes(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    int ok;
    if (!f) return -1;
    ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* The PFM's header states the byte order (scale -1: little-endian), so the floats are
 * written as the host stores them. */
static int write_sky(const char *path)
{
    const union {
        uint16_t u;
        unsigned char c[2];
    } probe = {1};
    float px[SKY_W * SKY_H * 3];
    char head[32];
    FILE *f;
    int i, n, ok;
    for (i = 0; i < SKY_W * SKY_H * 3; ++i) px[i] = i < 3 ? 50.0f : 0.25f + 0.05f * (float)(i % 5);
    n = snprintf(head, sizeof head, "PF\n%d %d\n%s\n", SKY_W, SKY_H, probe.c[0] ? "-1.0" : "1.0");
    if (!(f = fopen(path, "wb"))) return -1;
    ok = fwrite(head, 1, (size_t)n, f) == (size_t)n && fwrite(px, sizeof px, 1, f) == 1;
    return fclose(f) == 0 && ok ? 0 : -1;
}

static int make_directory(void)
{
    const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : getenv("TMPDIR");
    const char *const text[] = {quad_obj, quad_mtl, tex_obj, tex_mtl};
    char path[128];
    int i;
    if (!base || strlen(base) > 32) base = "/tmp";
    snprintf(directory, sizeof directory, "%s/restir-fuzz-XXXXXX", base);
    if (!mkdtemp(directory)) return -1;
    atexit(remove_directory);
    for (i = 0; i < 4; ++i) {
        snprintf(path, sizeof path, "%s/%s", directory, companions[i]);
        if (write_bytes(path, text[i], strlen(text[i]))) return -1;
    }
    snprintf(path, sizeof path, "%s/sky.pfm", directory);
    return write_sky(path);
}

const char *fuzz_write_file(const char *name, const uint8_t *data, size_t size)
{
    static char path[128];
    static int state; /* 0: not made yet, 1: ready, -1: cannot be made */
    if (!state) state = make_directory() ? -1 : 1;
    if (state < 0) return NULL;
    snprintf(path, sizeof path, "%s/%s", directory, name);
    return write_bytes(path, data, size) ? NULL : path;
}

void fuzz_load_scene(const char *name, const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file(name, data, size);
    scene s;
    rerror e;
    if (!path || scene_load(&s, path, &e)) return;
    /* The BVH build of a large scene is the same code for every input and took 93 % of
     * the scene target's time (a `light sphere` alone is 8 000 triangles): prepare only
     * what a parser bug could have shaped, and let the scene tests build the large ones. */
    if (s.triangle_count <= FUZZ_PREPARE_MAX_TRIANGLES) scene_prepare(&s, &e);
    scene_free(&s);
}
