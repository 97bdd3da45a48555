/* Scratch stage dumps of the oracle tests (docs/oracle.md): their directories, a dump made
 * once per test process, a fresh copy to plant a difference in. */
#ifndef RESTIR_TESTS_DUMP_UTIL_H
#define RESTIR_TESTS_DUMP_UTIL_H

#include "restir/restir/reservoir.h"

/* The scratch path PREFIX NAME (concatenated) in the test directory; the result is static,
 * rotated among 8 slots of its own (test_tmp_path's slots are not touched). */
const char *dump_scratch(const char *prefix, const char *name);

/* `restir render ARGS -o PFM --dump-dir DIR`, run once per test process for each DIR (a
 * directory an earlier process left, maybe another build's, is removed first). Returns a
 * copy of DIR that stays valid for the whole process; a failed run is recorded as a test
 * failure (with the command's output), returns DIR itself and is tried again on the next call. */
const char *dump_once(const char *args, const char *pfm, const char *dir);

/* dst becomes a fresh copy of the dump directory src: `cp -r src dst` into an existing dst
 * (a reused build directory) would nest src inside it and leave dst's old dumps in place,
 * stale files that the test would then diff (false alarms and false passes). A failure is
 * recorded as a test failure. Returns dst, or NULL if the copy failed. */
const char *dump_copy(const char *src, const char *dst);

/* Plants a difference in record i of a reservoir dump (docs/oracle.md: the records are the
 * pixels in row-major order). */
typedef void (*dump_edit_fn)(void *user, long i, reservoir *r);
/* Reads the reservoir dump file src, calls edit(user, i, record i) for every record in
 * order and writes the result to dst (may be src). Returns the number of records, or -1
 * after recording a test failure (the file could not be read or written). */
long dump_edit(const char *src, const char *dst, dump_edit_fn edit, void *user);
/* dump_edit with W of record p (p < 0: every record) multiplied by scale, and its wsum too
 * when with_wsum (a W planted consistently with the resampling sum). */
long dump_scale_w(const char *src, const char *dst, long p, double scale, int with_wsum);

#endif
