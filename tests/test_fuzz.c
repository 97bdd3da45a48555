/* The fuzz targets of tests/fuzz/ (docs/fuzzing.md) on every committed input of
 * tests/data/fuzz/NAME/: the seeds, a minimised corpus and the inputs that once crashed
 * a reader (regression inputs, named crash-*). `make fuzz` needs clang's libFuzzer;
 * this runs the same target functions in every build (the ASan+UBSan build of CI
 * included), so a fixed finding stays fixed and the harnesses keep compiling. */
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "fuzz/fuzz.h"
#include "test.h"
#include "restir/frame/pipeline.h"

typedef int (*fuzz_fn)(const uint8_t *, size_t);

static unsigned char *read_input(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    long n;
    if (!f) return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (buf = malloc((size_t)n + 1)) != NULL && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    if (buf) *size = (size_t)n;
    fclose(f);
    return buf;
}

/* The readers' error messages and the CLI's --help are expected output here: send
 * stdout and stderr to /dev/null while the inputs run. */
static int silence(int saved[2])
{
    int null = open("/dev/null", O_WRONLY);
    fflush(stdout);
    fflush(stderr);
    saved[0] = dup(1);
    saved[1] = dup(2);
    if (null < 0 || saved[0] < 0 || saved[1] < 0) return -1;
    dup2(null, 1);
    dup2(null, 2);
    close(null);
    return 0;
}

static void restore(const int saved[2])
{
    fflush(stdout);
    fflush(stderr);
    dup2(saved[0], 1);
    dup2(saved[1], 2);
    close(saved[0]);
    close(saved[1]);
}

/* Runs every file of tests/data/fuzz/<name>/; returns how many ran (-1: no /dev/null). */
static int run_inputs(const char *name, fuzz_fn fn)
{
    char dir[256], path[512];
    DIR *d;
    struct dirent *ent;
    int count = 0, saved[2];
    snprintf(dir, sizeof dir, "tests/data/fuzz/%s", name);
    d = opendir(dir);
    if (!d) return 0;
    if (silence(saved)) {
        closedir(d);
        return -1;
    }
    while ((ent = readdir(d)) != NULL) {
        unsigned char *data;
        size_t size = 0;
        if (ent->d_name[0] == '.') continue;
        snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
        data = read_input(path, &size);
        if (!data) continue;
        fn(data, size);
        free(data);
        count++;
    }
    restore(saved);
    closedir(d);
    return count;
}

TEST(fuzz_inputs)
{
    static const struct {
        const char *name;
        fuzz_fn fn;
    } targets[] = {{"obj", fuzz_obj}, {"mtl", fuzz_mtl},   {"scene", fuzz_scene},
                   {"pfm", fuzz_pfm}, {"dump", fuzz_dump}, {"cli", fuzz_cli},
                   {"exr", fuzz_exr}, {"png", fuzz_png},   {"inflate", fuzz_inflate}};
    size_t i;
    for (i = 0; i < sizeof targets / sizeof targets[0]; ++i) {
        int n = run_inputs(targets[i].name, targets[i].fn);
        CHECKF(n > 0, "tests/data/fuzz/%s: no inputs", targets[i].name);
    }
}
