/* Minimal JSON text support for our small machine-readable files (moments sidecars,
 * `check --json`): writing strings and numbers, and a strict pull reader over a
 * whole file held in memory. Not a general JSON library: no \u escapes beyond
 * ASCII control characters on output, and \uXXXX input is accepted for code points
 * below 128 only. Errors are "file:line: what". */
#ifndef RESTIR_JSON_TEXT_H
#define RESTIR_JSON_TEXT_H

#include <stddef.h>
#include <stdio.h>
#include "restir/core/error.h"

/* Writes s as a quoted JSON string ("\"", "\\" and control characters escaped). */
void json_put_string(FILE *fp, const char *s);
/* Writes a number with 17 significant digits, or null if it is not finite. */
void json_put_number(FILE *fp, double v);

typedef struct {
    const char *path; /* for messages */
    char *text;       /* NUL-terminated file contents (owned) */
    size_t pos;
    long line;
    rerror *e;
} json_reader;

/* Loads a whole file (at most 64 MiB). */
int json_reader_open(json_reader *r, const char *path, rerror *e);
void json_reader_close(json_reader *r);
/* The next non-whitespace character without consuming it ('\0' at the end). */
int json_peek(json_reader *r);
/* Consumes the character c (after whitespace) or fails with "expected 'c'". */
int json_expect(json_reader *r, char c);
int json_read_string(json_reader *r, char *buf, size_t size);
int json_read_number(json_reader *r, double *v);
/* Skips one value of any type. */
int json_skip_value(json_reader *r);
/* After whitespace, fails unless the text has ended. */
int json_expect_end(json_reader *r);

#endif
