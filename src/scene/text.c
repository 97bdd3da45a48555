/* Line-oriented text reading shared by the OBJ, MTL and scene-file parsers. */
#include "restir/scene/text.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static long line_of_offset(const char *data, size_t offset)
{
    long line = 1;
    size_t i;
    for (i = 0; i < offset; ++i)
        if (data[i] == '\n') line++;
    return line;
}

/* Bytes since the last '\n' byte, updated for the got bytes at buf + n (the line number
 * too). A hostile file (one 1 GB line) is refused after TEXT_MAX_LINE bytes, before the
 * buffer grows to its size; in UTF-16 files the '\n' byte is counted as in UTF-8. */
static int track_line_length(const char *path, const char *buf, size_t n, size_t got, size_t *line_bytes, long *line,
                             rerror *e)
{
    size_t i;
    for (i = n; i < n + got; ++i) {
        if (buf[i] == '\n') {
            (*line)++;
            *line_bytes = 0;
        } else if (++*line_bytes > TEXT_MAX_LINE) {
            return rerror_at(e, path, *line, "line longer than %d bytes (a corrupt or hostile file?)", TEXT_MAX_LINE);
        }
    }
    return 0;
}

/* A NUL byte outside a UTF-16 file (recognised by its byte-order mark) is binary data:
 * refused as soon as it is read, so /dev/urandom costs one buffer, not all memory. */
static int check_binary(const char *path, const char *buf, size_t n, size_t got, long line, rerror *e)
{
    const unsigned char *u = (const unsigned char *)buf;
    const char *nul;
    if (n + got >= 2 && ((u[0] == 0xFF && u[1] == 0xFE) || (u[0] == 0xFE && u[1] == 0xFF))) return 0;
    if (n + got < 2 && got && u[0] == 0xFF) return 0; /* maybe a BOM split across reads */
    nul = got ? memchr(buf + n, '\0', got) : NULL;
    if (nul)
        return rerror_at(e, path, line + line_of_offset(buf + n, (size_t)(nul - (buf + n))) - 1, "NUL byte in a text file (binary data, or UTF-16 without a byte-order mark)");
    return 0;
}

static int read_whole_file(const char *path, char **data, size_t *size, rerror *e)
{
    FILE *f = fopen(path, "rb");
    size_t cap = 1 << 16, n = 0, got, line_bytes = 0;
    long line = 1;
    char *buf;
    if (!f) return rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
    buf = malloc(cap);
    if (!buf) {
        fclose(f);
        return rerror_at(e, path, 0, "out of memory");
    }
    for (;;) {
        if (n + 1 >= cap) {
            char *bigger = cap < ((size_t)-1) / 2 ? realloc(buf, cap * 2) : NULL;
            if (!bigger) {
                free(buf);
                fclose(f);
                return rerror_at(e, path, 0, "out of memory reading the file");
            }
            buf = bigger;
            cap *= 2;
        }
        got = fread(buf + n, 1, cap - 1 - n, f);
        if (check_binary(path, buf, n, got, line, e) ||
            track_line_length(path, buf, n, got, &line_bytes, &line, e)) {
            free(buf);
            fclose(f);
            return -1;
        }
        if (n + got > TEXT_MAX_FILE) {
            free(buf);
            fclose(f);
            return rerror_at(e, path, 0, "longer than %lu bytes (a corrupt or hostile file, or an endless stream?)",
                             (unsigned long)TEXT_MAX_FILE);
        }
        n += got;
        if (got == 0) break;
    }
    if (ferror(f)) {
        free(buf);
        fclose(f);
        return rerror_at(e, path, 0, "cannot read: %s", strerror(errno));
    }
    fclose(f);
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return 0;
}

static size_t put_utf8(char *out, unsigned long cp)
{
    if (cp < 0x80) {
        out[0] = (char)cp;
        return 1;
    }
    if (cp < 0x800) {
        out[0] = (char)(0xC0 | (cp >> 6));
        out[1] = (char)(0x80 | (cp & 0x3F));
        return 2;
    }
    if (cp < 0x10000) {
        out[0] = (char)(0xE0 | (cp >> 12));
        out[1] = (char)(0x80 | ((cp >> 6) & 0x3F));
        out[2] = (char)(0x80 | (cp & 0x3F));
        return 3;
    }
    out[0] = (char)(0xF0 | (cp >> 18));
    out[1] = (char)(0x80 | ((cp >> 12) & 0x3F));
    out[2] = (char)(0x80 | ((cp >> 6) & 0x3F));
    out[3] = (char)(0x80 | (cp & 0x3F));
    return 4;
}

/* UTF-16 (after its byte-order mark) to UTF-8. Each code unit becomes at most 3 bytes
 * (a surrogate pair, two units, becomes 4), so 3 * units + 1 bytes suffice. */
static int decode_utf16(const char *path, const unsigned char *in, size_t size, int big_endian, char **out_data,
                        size_t *out_size, rerror *e)
{
    size_t units = size / 2, i, n = 0;
    long line = 1;
    char *out;
    if (size % 2) return rerror_at(e, path, 0, "UTF-16 file with an odd number of bytes");
    out = malloc(3 * units + 1);
    if (!out) return rerror_at(e, path, 0, "out of memory");
    for (i = 0; i < units; ++i) {
        unsigned long u = big_endian ? ((unsigned long)in[2 * i] << 8 | in[2 * i + 1])
                                     : ((unsigned long)in[2 * i + 1] << 8 | in[2 * i]);
        if (u == 0) {
            free(out);
            return rerror_at(e, path, line, "NUL character in UTF-16 text");
        }
        if (u >= 0xD800 && u <= 0xDBFF && i + 1 < units) {
            unsigned long lo = big_endian ? ((unsigned long)in[2 * i + 2] << 8 | in[2 * i + 3])
                                          : ((unsigned long)in[2 * i + 3] << 8 | in[2 * i + 2]);
            if (lo >= 0xDC00 && lo <= 0xDFFF) {
                u = 0x10000 + ((u - 0xD800) << 10) + (lo - 0xDC00);
                i++;
            } else {
                free(out);
                return rerror_at(e, path, line, "invalid UTF-16 (unpaired surrogate)");
            }
        } else if (u >= 0xD800 && u <= 0xDFFF) {
            free(out);
            return rerror_at(e, path, line, "invalid UTF-16 (unpaired surrogate)");
        }
        if (u == '\n') line++;
        n += put_utf8(out + n, u);
    }
    out[n] = '\0';
    *out_data = out;
    *out_size = n;
    return 0;
}

int text_open(text_reader *t, const char *path, rerror *e)
{
    char *raw = NULL;
    size_t size = 0;
    const unsigned char *u;
    const char *nul;
    memset(t, 0, sizeof *t);
    t->path = path;
    if (read_whole_file(path, &raw, &size, e)) return -1;
    u = (const unsigned char *)raw;
    if (size >= 2 && ((u[0] == 0xFF && u[1] == 0xFE) || (u[0] == 0xFE && u[1] == 0xFF))) {
        int status = decode_utf16(path, u + 2, size - 2, u[0] == 0xFE, &t->data, &t->size, e);
        free(raw);
        if (status) return -1;
    } else {
        t->data = raw;
        t->size = size;
        nul = memchr(raw, '\0', size);
        if (nul) {
            rerror_at(e, path, line_of_offset(raw, (size_t)(nul - raw)),
                      "NUL byte in a text file (binary data, or UTF-16 without a byte-order mark)");
            free(raw);
            t->data = NULL;
            return -1;
        }
    }
    t->cursor = t->data;
    if ((unsigned char)t->cursor[0] == 0xEF && (unsigned char)t->cursor[1] == 0xBB &&
        (unsigned char)t->cursor[2] == 0xBF)
        t->cursor += 3;
    t->next_line = 1;
    return 0;
}

void text_close(text_reader *t)
{
    free(t->data);
    t->data = NULL;
    t->cursor = NULL;
}

int text_is_space(int c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

char *text_skip_space(char *p)
{
    while (text_is_space((unsigned char)*p)) p++;
    return p;
}

/* Cuts a comment: '#' at the start or after whitespace. */
static void cut_comment(char *line)
{
    char *p;
    for (p = line; *p; ++p)
        if (*p == '#' && (p == line || text_is_space((unsigned char)p[-1]))) {
            *p = '\0';
            return;
        }
}

char *text_next_line(text_reader *t)
{
    char *start = t->cursor, *p;
    int comment_line;
    if (!start || (!*start && start >= t->data + t->size)) return NULL;
    t->line = t->next_line;
    comment_line = *text_skip_space(start) == '#';
    p = start;
    for (;;) {
        char *nl = strchr(p, '\n');
        char *before;
        if (!nl) {
            t->cursor = p + strlen(p);
            break;
        }
        t->next_line++;
        before = nl;
        if (before > p && before[-1] == '\r') before--;
        if (!comment_line && before > start && before[-1] == '\\') {
            /* Continuation: the backslash, CR and LF become spaces; keep scanning. */
            char *q;
            for (q = before - 1; q <= nl; ++q) *q = ' ';
            p = nl + 1;
            continue;
        }
        *nl = '\0';
        t->cursor = nl + 1;
        break;
    }
    if (t->cursor > t->data + t->size) t->cursor = t->data + t->size;
    cut_comment(start);
    return start;
}

char *text_next_token(char **p)
{
    char *s = text_skip_space(*p), *q;
    if (!*s) {
        *p = s;
        return NULL;
    }
    q = s;
    while (*q && !text_is_space((unsigned char)*q)) q++;
    if (*q) *q++ = '\0';
    *p = q;
    return s;
}

char *text_rest(char *p)
{
    char *s = text_skip_space(p), *end = s + strlen(s);
    while (end > s && text_is_space((unsigned char)end[-1])) end--;
    *end = '\0';
    return s;
}

static int is_digit(int c) { return c >= '0' && c <= '9'; }

/* Validates the strict decimal grammar; returns the status for a token. */
static enum number_status check_decimal(const char *s)
{
    const char *p = s;
    int mantissa_digits = 0;
    if (*p == '+' || *p == '-') p++;
    if (*p == 'n' || *p == 'N' || *p == 'i' || *p == 'I' || strchr(s, '#')) return NUMBER_NOT_FINITE;
    while (is_digit((unsigned char)*p)) p++, mantissa_digits++;
    if (*p == '.') {
        p++;
        while (is_digit((unsigned char)*p)) p++, mantissa_digits++;
    }
    if (!mantissa_digits) return NUMBER_MALFORMED;
    if (*p == 'e' || *p == 'E') {
        int exponent_digits = 0;
        p++;
        if (*p == '+' || *p == '-') p++;
        while (is_digit((unsigned char)*p)) p++, exponent_digits++;
        if (!exponent_digits) return NUMBER_MALFORMED;
    }
    return *p ? NUMBER_MALFORMED : NUMBER_OK;
}

enum number_status text_parse_float(const char *token, float *out)
{
    enum number_status st = check_decimal(token);
    float v;
    if (st != NUMBER_OK) return st;
    v = strtof(token, NULL);
    if (isinf(v) || isnan(v)) return NUMBER_OUT_OF_RANGE;
    *out = v;
    return NUMBER_OK;
}

enum number_status text_parse_double(const char *token, double *out)
{
    enum number_status st = check_decimal(token);
    double v;
    if (st != NUMBER_OK) return st;
    v = strtod(token, NULL);
    if (isinf(v) || isnan(v)) return NUMBER_OUT_OF_RANGE;
    *out = v;
    return NUMBER_OK;
}

enum number_status text_parse_long(const char *s, const char **end, long *out)
{
    const char *p = s;
    int negative = 0, digits = 0;
    unsigned long v = 0, limit = 2147483647UL; /* indices beyond 2^31 - 1 cannot be stored anyway */
    if (*p == '+' || *p == '-') negative = *p++ == '-';
    while (is_digit((unsigned char)*p)) {
        unsigned long d = (unsigned long)(*p - '0');
        if (v > (limit - d) / 10) {
            while (is_digit((unsigned char)*p)) p++;
            if (end) *end = p;
            return NUMBER_OUT_OF_RANGE;
        }
        v = v * 10 + d;
        p++;
        digits++;
    }
    if (end) *end = p;
    if (!digits) return NUMBER_MALFORMED;
    *out = negative ? -(long)v : (long)v;
    return NUMBER_OK;
}

const char *text_number_problem(enum number_status st)
{
    switch (st) {
    case NUMBER_MALFORMED: return "malformed number";
    case NUMBER_NOT_FINITE: return "number is not finite";
    case NUMBER_OUT_OF_RANGE: return "number out of range";
    default: return "number ok";
    }
}

void text_directory_of(const char *path, char *out, size_t out_size)
{
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) + 1 : 0;
    if (n >= out_size) n = 0;
    memcpy(out, path, n);
    out[n] = '\0';
}

int text_join_path(char *out, size_t out_size, const char *dir, const char *name)
{
    int n = name[0] == '/' ? snprintf(out, out_size, "%s", name) : snprintf(out, out_size, "%s%s", dir, name);
    return (n < 0 || (size_t)n >= out_size) ? -1 : 0;
}
