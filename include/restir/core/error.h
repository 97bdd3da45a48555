/* Error reporting. Every fallible function takes an `rerror *` and returns
 * nonzero on failure after filling it with one line in the form
 * "file:line: what is wrong" (or "file: what is wrong" when no line applies).
 * The CLI prints that line and exits with status 2 (bad input). */
#ifndef RESTIR_ERROR_H
#define RESTIR_ERROR_H

#include <stddef.h>

typedef struct {
    char msg[1024];
} rerror;

/* Formats the message; returns -1 so callers can `return rerror_set(...)`. */
int rerror_set(rerror *e, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* "file:line: message" (line <= 0 omits the line number). Returns -1. */
int rerror_at(rerror *e, const char *file, long line, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* Allocation that reports through rerror instead of returning NULL silently. */
void *rmalloc(size_t count, size_t size, rerror *e);
void *rcalloc(size_t count, size_t size, rerror *e);

#endif
