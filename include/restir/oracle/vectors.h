/* Golden test vectors (restir vectors, docs/oracle.md "Golden vectors"): one JSON-lines
 * file per formula family, each line one evaluation of a library function:
 *
 *   {"family": "mis", "fn": "mis_weights", "eq": ["GRIS 36", ...], "case": "...",
 *    "sig": "names of in -> names of out", "in": [numbers], "out": [numbers]}
 *
 * Numbers are written with 17 significant digits (binary64 round trip); non-finite
 * values are the strings "inf", "-inf", "nan". Integers (flags, lobe indices, RNG words) are written as numbers too.
 * The check (vectors_check_file) re-evaluates every line from its "in" and compares
 * "out" bit for bit, so a GPU build's unit tests can do the same with our files. */
#ifndef RESTIR_VECTORS_H
#define RESTIR_VECTORS_H

#include <stddef.h>
#include "restir/core/error.h"

#define VECTORS_MAX_IN 128
#define VECTORS_MAX_OUT 64

typedef struct {
    const char *family; /* file name without .jsonl */
    const char *fn;     /* function name as in "fn" */
    const char *sig;    /* "in names -> out names" */
    /* out[] from in[0..n_in-1]; returns the number of outputs, -1 for malformed input */
    int (*eval)(const double *in, int n_in, double *out);
} vector_fn;

/* The families (NULL-terminated) in file order. */
const char *const *vectors_families(void);
/* Writes DIR/FAMILY.jsonl for every family (atomically; creates DIR). */
int vectors_write(const char *dir, rerror *e);
/* Re-evaluates every line of a vectors file. *lines counts the lines, *bad the lines
 * whose outputs differ (the first one is described in e->msg, returns 1); -1 if the
 * file is malformed, 0 if every line reproduces. */
int vectors_check_file(const char *path, long *lines, long *bad, rerror *e);
/* 1 if the generator writes a vector tagged `eq` (e.g. "GRIS 19"). */
int vectors_cover(const char *eq);

#endif
