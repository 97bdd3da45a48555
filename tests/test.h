/* A small test harness. A test is `TEST(name) { ... }` (or TEST_LONG for suites
 * run only by `make test-long`) in any file under tests/; the Makefile generates the
 * registry. CHECK* record a failure and return from the test. */
#ifndef RESTIR_TEST_H
#define RESTIR_TEST_H

#include <stddef.h>
#include <stdint.h>
#include <math.h>

#define TEST(name) void test_##name(void)
#define TEST_LONG(name) void test_##name(void)

void test_fail(const char *file, int line, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 3, 4)))
#endif
    ;
int test_has_failed(void);

/* Optional machine-readable margin of a statistical check (scripts/mutation-score.sh):
 * the normal-equivalent z of the statistic a test decides on. When the environment
 * variable RESTIR_TEST_MARGIN_FILE names a file, each failing test appends one line
 * "name z |z|" (the largest |z| given here, else the largest "z <number>" or two-sided
 * "p <number>" found in its failure message) or "name exact" (no statistic: a
 * deterministic assertion failed). */
void test_margin(double z);

#define CHECK(cond)                                                 \
    do {                                                            \
        if (!(cond)) {                                              \
            test_fail(__FILE__, __LINE__, "CHECK(%s)", #cond);      \
            return;                                                 \
        }                                                           \
    } while (0)

#define CHECKF(cond, ...)                                           \
    do {                                                            \
        if (!(cond)) {                                              \
            test_fail(__FILE__, __LINE__, __VA_ARGS__);             \
            return;                                                 \
        }                                                           \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                          \
    do {                                                                               \
        double check_a_ = (double)(a), check_b_ = (double)(b), check_t_ = (double)(tol); \
        if (!(fabs(check_a_ - check_b_) <= check_t_)) {                                \
            test_fail(__FILE__, __LINE__, "%s = %.17g, %s = %.17g, |diff| > %g", #a,   \
                      check_a_, #b, check_b_, check_t_);                               \
            return;                                                                    \
        }                                                                              \
    } while (0)

/* The run seed: --seed N or SEED=N (default 1). Statistical tests derive their
 * randomness from it, so CI is deterministic and other seeds can be tried. */
uint32_t test_seed(void);

/* A scratch directory for this run (created on start). */
const char *test_tmpdir(void);
/* Path in the scratch directory; returns a static buffer rotated among 8 slots. */
const char *test_tmp_path(const char *name);

/* Runs `build/restir ARGS` (ARGS formatted like printf), captures stdout+stderr
 * into out (NUL-terminated, may be NULL), returns the exit status (or -1). */
int test_cli(char *out, size_t out_size, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* test_tmp_path that stays valid until the test ends (up to 64 per test; more is a test
 * failure): the paths a test keeps while it calls test_cli and test_tmp_path. */
const char *test_tmp_keep(const char *name);

/* test_cli under `timeout --preserve-status -s SIG SECONDS` (ARGS as they are): the signal
 * reaches restir after SECONDS; returns its exit status (-1 if it did not exit). */
int test_cli_signal(char *out, size_t out_size, const char *sig, double seconds, const char *args);

/* Writes text to a file in the scratch directory; returns its path (static, rotated). */
const char *test_write_file(const char *name, const char *text);
/* 1 if both files exist and hold the same bytes. */
int test_files_equal(const char *a, const char *b);
int test_file_exists(const char *path);
/* The whole file as a NUL-terminated string (caller frees), or NULL. */
char *test_read_text(const char *path);

#endif
