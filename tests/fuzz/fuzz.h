/* Fuzz targets for every parser (docs/fuzzing.md). A target is written once:
 *
 *   FUZZ_TARGET(obj) { ...parse data[0..size)... return 0; }
 *
 * defines fuzz_obj(data, size). Built with -DFUZZ_LIBFUZZER (make fuzz: clang
 * -fsanitize=fuzzer,address,undefined) it also defines LLVMFuzzerTestOneInput, one
 * target per binary. Without it the targets are ordinary functions that the test
 * suite calls on every committed input of tests/data/fuzz/NAME/ (tests/test_fuzz.c),
 * so the harnesses compile and run in every build and cannot rot. */
#ifndef RESTIR_TESTS_FUZZ_H
#define RESTIR_TESTS_FUZZ_H

#include <stddef.h>
#include <stdint.h>

#ifdef FUZZ_LIBFUZZER
#define FUZZ_TARGET(name)                                                                                              \
    int fuzz_##name(const uint8_t *data, size_t size);                                                                 \
    int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);                                                      \
    int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) { return fuzz_##name(data, size); }                   \
    int fuzz_##name(const uint8_t *data, size_t size)
#else
#define FUZZ_TARGET(name) int fuzz_##name(const uint8_t *data, size_t size)
#endif

/* The targets (one file each under tests/fuzz/). Each returns 0 whatever the input:
 * rejecting it is fine, crashing, leaking or tripping a sanitizer is the finding. */
int fuzz_obj(const uint8_t *data, size_t size);
int fuzz_mtl(const uint8_t *data, size_t size);
int fuzz_scene(const uint8_t *data, size_t size);
int fuzz_pfm(const uint8_t *data, size_t size);
int fuzz_dump(const uint8_t *data, size_t size);
int fuzz_cli(const uint8_t *data, size_t size);
int fuzz_exr(const uint8_t *data, size_t size);
int fuzz_png(const uint8_t *data, size_t size);
int fuzz_inflate(const uint8_t *data, size_t size);

/* The readers take a path, so the input goes to a file NAME in a private directory
 * (on tmpfs, /dev/shm, when there is one; removed at exit). Next to it lie the
 * companion files quad.obj and quad.mtl (a lit quad), tex.obj and tex.mtl (a textured
 * emissive quad) and sky.pfm (its maps; an environment map) that fuzzed scene files and OBJ
 * files can name. Returns the file's path, or NULL if it cannot be written. */
const char *fuzz_write_file(const char *name, const uint8_t *data, size_t size);

/* Writes the input to NAME (.obj or .scene), loads it with scene_load and, if that
 * succeeds and it has at most FUZZ_PREPARE_MAX_TRIANGLES triangles, builds it with
 * scene_prepare (BVH, emitters): a hostile file must be rejected with a message or give a
 * scene every later stage can build. */
#define FUZZ_PREPARE_MAX_TRIANGLES 4096
void fuzz_load_scene(const char *name, const uint8_t *data, size_t size);

#endif
