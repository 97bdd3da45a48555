/* Reading line-oriented text formats (OBJ, MTL, scene files): whole-file reading with
 * encoding checks, logical lines, tokens, and strict number parsing.
 *
 * Lines are cut in place inside one buffer that holds the whole file, so reading is
 * linear in the file size. A physical line may hold at most TEXT_MAX_LINE bytes (the
 * reader stops there, so a hostile 1 GB line never gets a 1 GB buffer). */
#ifndef RESTIR_TEXT_H
#define RESTIR_TEXT_H

#include <stddef.h>
#include "restir/core/error.h"

#define TEXT_MAX_LINE (1 << 22) /* bytes per physical line (4 MiB) */
#define TEXT_MAX_FILE ((size_t)1 << 31) /* bytes per file (2 GiB): a stream without end is refused */

typedef struct {
    char *data;        /* the whole file, NUL-terminated (UTF-16 input decoded to UTF-8) */
    size_t size;
    char *cursor;      /* start of the next physical line */
    long line;         /* number (1-based) of the first physical line of the last logical line */
    long next_line;    /* number of the physical line at cursor */
    const char *path;  /* as given to text_open (not copied) */
} text_reader;

/* Reads the file. A UTF-8 byte-order mark is skipped; UTF-16 with a byte-order mark is
 * decoded; a NUL byte anywhere else is an error ("file:line: ... NUL byte"). */
int text_open(text_reader *t, const char *path, rerror *e);
void text_close(text_reader *t);

/* The next logical line, NUL-terminated in place, or NULL at the end of the file.
 * A backslash immediately before the line break joins the next physical line (OBJ/MTL
 * continuation lines; not on comment lines). A '#' at the start of the line or after
 * whitespace begins a comment, which is cut off. t->line is the line's number. */
char *text_next_line(text_reader *t);

/* Whitespace inside lines: space, tab, CR, vertical tab, form feed. */
int text_is_space(int c);
char *text_skip_space(char *p);
/* The next whitespace-separated token, NUL-terminated in place; *p moves past it.
 * NULL when the line has no more tokens. */
char *text_next_token(char **p);
/* The rest of the line with leading and trailing whitespace removed (in place). */
char *text_rest(char *p);

enum number_status {
    NUMBER_OK = 0,
    NUMBER_MALFORMED,   /* not [+-]digits[.digits][(e|E)[+-]digits] */
    NUMBER_NOT_FINITE,  /* nan, inf, 1.#INF, ... */
    NUMBER_OUT_OF_RANGE /* overflows the destination type */
};

/* Strict decimal numbers: the whole token must match
 *   [+-] ( digits [ '.' [digits] ] | '.' digits ) [ (e|E) [+-] digits ]
 * (no hexadecimal, no nan/inf, no leading or trailing garbage). The conversion is
 * correctly rounded (strtof/strtod on the validated token, C locale). */
enum number_status text_parse_float(const char *token, float *out);
enum number_status text_parse_double(const char *token, double *out);
/* [+-]digits; *end (if not NULL) receives the first character after the digits, and
 * the digits need not end the token (face vertices such as 1/2/3). */
enum number_status text_parse_long(const char *s, const char **end, long *out);
/* "malformed number", "number is not finite", "number out of range". */
const char *text_number_problem(enum number_status st);

/* The directory part of path including the trailing '/', or "" (into out). */
void text_directory_of(const char *path, char *out, size_t out_size);
/* dir + name unless name is absolute. Returns -1 if it does not fit. */
int text_join_path(char *out, size_t out_size, const char *dir, const char *name);

#endif
