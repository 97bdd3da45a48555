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

static char directory[64];
static const char *const companions[] = {"quad.obj", "quad.mtl"};

static void remove_directory(void)
{
    /* Only the names the targets use: the directory holds nothing else. */
    static const char *const names[] = {"quad.obj", "quad.mtl", "input.obj", "input.mtl", "input.scene",
                                        "input.pfm", "input.rsv", "input.exr", "input.png", NULL};
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

static int make_directory(void)
{
    const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : getenv("TMPDIR");
    char path[128];
    if (!base || strlen(base) > 32) base = "/tmp";
    snprintf(directory, sizeof directory, "%s/restir-fuzz-XXXXXX", base);
    if (!mkdtemp(directory)) return -1;
    atexit(remove_directory);
    snprintf(path, sizeof path, "%s/%s", directory, companions[0]);
    if (write_bytes(path, quad_obj, sizeof quad_obj - 1)) return -1;
    snprintf(path, sizeof path, "%s/%s", directory, companions[1]);
    return write_bytes(path, quad_mtl, sizeof quad_mtl - 1);
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
    scene_prepare(&s, &e);
    scene_free(&s);
}
