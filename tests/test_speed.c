/* Speed work without changing a bit (issue 17, docs/performance.md): the images of a few
 * small renders must have the checksums recorded with the code BEFORE the speed changes
 * (main at ea610ee: binary BVH, one hash per random number). Fixed seed 1 on purpose (the
 * recorded checksums are for that seed; SEED= does not apply). Covers the path tracer on
 * the Cornell box (GGX plastic + Lambert), on the glass scene (delta lobes, ~3k
 * triangles) and on a generated displaced sphere (4.8k triangles: the 4-wide BVH), and the
 * ReSTIR PT frame (initial resampling + spatial reuse) on the Cornell box. A deliberate
 * one-ulp change anywhere in these paths changes the checksum. */
#include <stdio.h>
#include <string.h>
#include "restir/vec.h"
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
