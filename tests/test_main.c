/* Test runner: runs every registered test (or those whose name contains one of
 * the filters), prints one line per test and ends with "N passed, N failed". */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include "restir/metrics/stats.h"
#include "test.h"

#define X(name, is_long) void test_##name(void);
#include "test_registry.h"
#undef X

typedef struct {
    const char *name;
    void (*fn)(void);
    int is_long;
} test_entry;

static const test_entry all_tests[] = {
#define X(name, is_long) {#name, test_##name, is_long},
#include "test_registry.h"
#undef X
};

static int current_failed;
static char current_message[2048];
static uint32_t run_seed = 1;

void test_fail(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    int n;
    if (current_failed) return;
    current_failed = 1;
    n = snprintf(current_message, sizeof current_message, "%s:%d: ", file, line);
    va_start(ap, fmt);
    vsnprintf(current_message + n, sizeof current_message - (size_t)n, fmt, ap);
    va_end(ap);
}

int test_has_failed(void) { return current_failed; }

/* ---- margins of failed tests (test.h: test_margin) ---- */

static double current_margin; /* largest |z| reported by test_margin, or -1 */

void test_margin(double z)
{
    if (z != z) return;
    if (fabs(z) > current_margin) current_margin = fabs(z);
}

/* The largest |z| of "z <number>" / "z = <number>" in msg, and of the normal z of
 * two-sided "p <number>" / "p = <number>" (a chi-square or Welch p-value); -1 if none. */
static double margin_from_message(const char *msg)
{
    double best = -1;
    const char *c;
    for (c = msg; *c; ++c) {
        const char *after = c + 1;
        char *end;
        double x;
        if ((*c != 'z' && *c != 'p') || (c > msg && (isalnum((unsigned char)c[-1]) || c[-1] == '_'))) continue;
        if (*after == ' ' && after[1] == '=') after += 2;
        else if (*after == '=') after += 1;
        else if (*after != ' ') continue;
        x = strtod(after, &end);
        if (end == after || x != x) continue;
        if (*c == 'p') x = x > 0 && x <= 1 ? -stats_normal_quantile(x / 2) : (x == 0 ? 40 : -1);
        if (fabs(x) > best) best = fabs(x);
    }
    return best;
}

static void record_margin(const char *name)
{
    const char *path = getenv("RESTIR_TEST_MARGIN_FILE");
    double z = current_margin >= 0 ? current_margin : margin_from_message(current_message);
    FILE *f;
    if (!path || !*path || !(f = fopen(path, "a"))) return;
    if (z >= 0) fprintf(f, "%s z %.2f\n", name, z > 40 ? 40 : z);
    else fprintf(f, "%s exact\n", name);
    fclose(f);
}
uint32_t test_seed(void) { return run_seed; }
const char *test_tmpdir(void) { return RESTIR_TMP; }

const char *test_tmp_path(const char *name)
{
    static char slots[8][1024];
    static int next;
    char *p = slots[next++ & 7];
    snprintf(p, sizeof slots[0], "%s/%s", RESTIR_TMP, name);
    return p;
}

#define KEPT_PATHS 64
static char kept[KEPT_PATHS][1024];
static int n_kept;

const char *test_tmp_keep(const char *name)
{
    if (n_kept == KEPT_PATHS) {
        test_fail(__FILE__, __LINE__, "more than %d test_tmp_keep paths in one test", KEPT_PATHS);
        n_kept = KEPT_PATHS - 1;
    }
    snprintf(kept[n_kept], sizeof kept[0], "%s/%s", RESTIR_TMP, name);
    return kept[n_kept++];
}

int test_files_equal(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    int ca, cb, same = fa && fb;
    while (same) {
        ca = fgetc(fa);
        cb = fgetc(fb);
        if (ca != cb) same = 0;
        if (ca == EOF) break;
    }
    if (fa) fclose(fa);
    if (fb) fclose(fb);
    return same;
}

const char *test_write_file(const char *name, const char *text)
{
    const char *path = test_tmp_path(name);
    FILE *f = fopen(path, "wb");
    if (!f) return path;
    fputs(text, f);
    fclose(f);
    return path;
}

int test_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

char *test_read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    long n;
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    if (buf) buf[n] = '\0';
    fclose(f);
    return buf;
}

/* Runs `WRAPPER build/restir ARGS` (WRAPPER may be empty), stdout+stderr into out. */
static int run_restir(char *out, size_t out_size, const char *wrapper, const char *args)
{
    char cmd[8192];
    const char *capture = test_tmp_path("cli-output.txt");
    char capture_copy[1024];
    int status;
    snprintf(capture_copy, sizeof capture_copy, "%s", capture);
    snprintf(cmd, sizeof cmd, "%s%s %s >'%s' 2>&1 </dev/null", wrapper, RESTIR_BIN, args, capture_copy);
    status = system(cmd);
    if (out && out_size) {
        FILE *f = fopen(capture_copy, "rb");
        size_t n = 0;
        if (f) {
            n = fread(out, 1, out_size - 1, f);
            fclose(f);
        }
        out[n] = '\0';
    }
    if (status == -1 || !WIFEXITED(status)) return -1;
    return WEXITSTATUS(status);
}

int test_cli(char *out, size_t out_size, const char *fmt, ...)
{
    char args[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    return run_restir(out, out_size, "", args);
}

int test_cli_signal(char *out, size_t out_size, const char *sig, double seconds, const char *args)
{
    char wrapper[128];
    snprintf(wrapper, sizeof wrapper, "timeout --preserve-status -s %s %g ", sig, seconds);
    return run_restir(out, out_size, wrapper, args);
}

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int selected(const test_entry *t, int run_long, int argc, char **argv, int first_filter)
{
    int i, any_filter = 0;
    if (t->is_long && !run_long) return 0;
    for (i = first_filter; i < argc; ++i) {
        if (!argv[i][0]) continue;
        any_filter = 1;
        if (strstr(t->name, argv[i])) return 1;
    }
    return !any_filter;
}

int main(int argc, char **argv)
{
    int run_long = 0, first_filter = 1, passed = 0, failed = 0;
    size_t i, count = sizeof all_tests / sizeof all_tests[0];
    const char *env_seed = getenv("SEED");
    char mk[1100];

    if (env_seed && *env_seed) run_seed = (uint32_t)strtoul(env_seed, NULL, 10);
    while (first_filter < argc && argv[first_filter][0] == '-') {
        if (!strcmp(argv[first_filter], "--long")) {
            run_long = 1;
            first_filter += 1;
        } else if (!strcmp(argv[first_filter], "--seed") && first_filter + 1 < argc) {
            run_seed = (uint32_t)strtoul(argv[first_filter + 1], NULL, 10);
            first_filter += 2;
        } else {
            fprintf(stderr, "usage: %s [--long] [--seed N] [name-filter ...]\n", argv[0]);
            return 2;
        }
    }
    snprintf(mk, sizeof mk, "mkdir -p '%s'", RESTIR_TMP);
    if (system(mk) != 0) fprintf(stderr, "warning: could not create %s\n", RESTIR_TMP);
    printf("seed %u\n", run_seed);

    for (i = 0; i < count; ++i) {
        const test_entry *t = &all_tests[i];
        double t0;
        if (!selected(t, run_long, argc, argv, first_filter)) continue;
        current_failed = 0;
        current_margin = -1;
        current_message[0] = '\0';
        n_kept = 0;
        t0 = wall_seconds();
        t->fn();
        if (current_failed) {
            printf("FAIL %s (%.2f s): %s\n", t->name, wall_seconds() - t0, current_message);
            record_margin(t->name);
            failed++;
        } else {
            printf("ok   %s (%.2f s)\n", t->name, wall_seconds() - t0);
            passed++;
        }
        fflush(stdout);
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
