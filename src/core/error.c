/* Error messages in the "file:line: what is wrong" form. */
#include "restir/core/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

int rerror_set(rerror *e, const char *fmt, ...)
{
    va_list ap;
    if (!e) return -1;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
    return -1;
}

int rerror_at(rerror *e, const char *file, long line, const char *fmt, ...)
{
    va_list ap;
    int n;
    if (!e) return -1;
    if (line > 0)
        n = snprintf(e->msg, sizeof e->msg, "%s:%ld: ", file, line);
    else
        n = snprintf(e->msg, sizeof e->msg, "%s: ", file);
    if (n < 0 || (size_t)n >= sizeof e->msg) return -1;
    va_start(ap, fmt);
    vsnprintf(e->msg + n, sizeof e->msg - (size_t)n, fmt, ap);
    va_end(ap);
    return -1;
}

void *rmalloc(size_t count, size_t size, rerror *e)
{
    void *p;
    size_t bytes;
    if (size && count > (size_t)-1 / size) {
        rerror_set(e, "allocation of %zu x %zu bytes overflows", count, size);
        return NULL;
    }
    bytes = count * size;
    p = malloc(bytes > 0 ? bytes : 1);
    if (!p) rerror_set(e, "out of memory (%zu bytes)", bytes);
    return p;
}

void *rcalloc(size_t count, size_t size, rerror *e)
{
    void *p = calloc(count ? count : 1, size ? size : 1);
    if (!p) rerror_set(e, "out of memory (%zu x %zu bytes)", count, size);
    return p;
}
