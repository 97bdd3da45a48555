/* Small JSON writer helpers and a strict pull reader (json_text.h). */
#include "restir/core/json_text.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void json_put_string(FILE *fp, const char *s)
{
    fputc('"', fp);
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(fp, "\\%c", c);
        else if (c == '\n')
            fputs("\\n", fp);
        else if (c == '\t')
            fputs("\\t", fp);
        else if (c < 0x20)
            fprintf(fp, "\\u%04x", c);
        else
            fputc(c, fp);
    }
    fputc('"', fp);
}

/* The shortest of %.15g, %.16g, %.17g that reads back as exactly v. */
void json_put_number(FILE *fp, double v)
{
    char buf[40];
    int digits;
    if (!isfinite(v)) {
        fputs("null", fp);
        return;
    }
    for (digits = 15; digits < 17; ++digits) {
        snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (strtod(buf, NULL) == v) break;
    }
    if (digits == 17) snprintf(buf, sizeof buf, "%.17g", v);
    fputs(buf, fp);
}

#define JSON_MAX_BYTES (64L << 20)

int json_reader_open(json_reader *r, const char *path, rerror *e)
{
    FILE *fp = fopen(path, "rb");
    long size;
    memset(r, 0, sizeof *r);
    r->path = path;
    r->line = 1;
    r->e = e;
    if (!fp) return rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
    if (fseek(fp, 0, SEEK_END) != 0 || (size = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) != 0) {
        fclose(fp);
        return rerror_at(e, path, 0, "cannot read: %s", strerror(errno));
    }
    if (size > JSON_MAX_BYTES) {
        fclose(fp);
        return rerror_at(e, path, 0, "file too large for a JSON sidecar (%ld bytes)", size);
    }
    r->text = rmalloc((size_t)size + 1, 1, e);
    if (!r->text) {
        fclose(fp);
        return -1;
    }
    if (fread(r->text, 1, (size_t)size, fp) != (size_t)size) {
        fclose(fp);
        json_reader_close(r);
        return rerror_at(e, path, 0, "read failed");
    }
    fclose(fp);
    r->text[size] = '\0';
    if (strlen(r->text) != (size_t)size) {
        json_reader_close(r);
        return rerror_at(e, path, 0, "NUL byte in a JSON file");
    }
    return 0;
}

void json_reader_close(json_reader *r)
{
    free(r->text);
    r->text = NULL;
}

static void skip_space(json_reader *r)
{
    for (;;) {
        char c = r->text[r->pos];
        if (c == '\n') r->line++;
        if (c != ' ' && c != '\t' && c != '\n' && c != '\r') return;
        r->pos++;
    }
}

int json_peek(json_reader *r)
{
    skip_space(r);
    return (unsigned char)r->text[r->pos];
}

int json_expect(json_reader *r, char c)
{
    if (json_peek(r) != (unsigned char)c) {
        if (!r->text[r->pos]) return rerror_at(r->e, r->path, r->line, "JSON ends where '%c' was expected", c);
        return rerror_at(r->e, r->path, r->line, "expected '%c' in JSON, found '%c'", c, r->text[r->pos]);
    }
    r->pos++;
    return 0;
}

int json_read_string(json_reader *r, char *buf, size_t size)
{
    size_t n = 0;
    if (json_expect(r, '"')) return -1;
    for (;;) {
        char c = r->text[r->pos++];
        if (c == '\0' || c == '\n') return rerror_at(r->e, r->path, r->line, "unterminated JSON string");
        if (c == '"') break;
        if ((unsigned char)c < 0x20) return rerror_at(r->e, r->path, r->line, "control character in a JSON string");
        if (c == '\\') {
            char d = r->text[r->pos++];
            switch (d) {
            case '"': case '\\': case '/': c = d; break;
            case 'n': c = '\n'; break;
            case 't': c = '\t'; break;
            case 'r': c = '\r'; break;
            case 'b': c = '\b'; break;
            case 'f': c = '\f'; break;
            case 'u': {
                char hex[5];
                long code;
                char *end;
                size_t k;
                /* at most the 4 digits, never past the text's end: a file ending in "\u"
                 * was read beyond its buffer (the fuzzer's finding under ASan,
                 * tests/data/fuzz/dump/crash-json-truncated-u-escape.json) */
                for (k = 0; k < 4 && isxdigit((unsigned char)r->text[r->pos + k]); ++k) hex[k] = r->text[r->pos + k];
                hex[k] = '\0';
                code = strtol(hex, &end, 16);
                if (k < 4 || end != hex + 4 || code <= 0 || code >= 128)
                    return rerror_at(r->e, r->path, r->line, "unsupported \\u escape in a JSON string");
                r->pos += 4;
                c = (char)code;
                break;
            }
            default: return rerror_at(r->e, r->path, r->line, "bad escape '\\%c' in a JSON string", d);
            }
        }
        if (n + 1 >= size) return rerror_at(r->e, r->path, r->line, "JSON string too long");
        buf[n++] = c;
    }
    buf[n] = '\0';
    return 0;
}

int json_read_number(json_reader *r, double *v)
{
    char *end;
    int c = json_peek(r);
    if (!(c == '-' || (c >= '0' && c <= '9'))) return rerror_at(r->e, r->path, r->line, "expected a number in JSON");
    errno = 0;
    *v = strtod(r->text + r->pos, &end);
    if (end == r->text + r->pos || errno == ERANGE || !isfinite(*v))
        return rerror_at(r->e, r->path, r->line, "bad number in JSON");
    r->pos = (size_t)(end - r->text);
    return 0;
}

static int skip_literal(json_reader *r, const char *word)
{
    size_t n = strlen(word);
    if (strncmp(r->text + r->pos, word, n) != 0) return rerror_at(r->e, r->path, r->line, "unexpected text in JSON");
    r->pos += n;
    return 0;
}

static int skip_value_depth(json_reader *r, int depth)
{
    int c = json_peek(r);
    char scratch[4096];
    double v;
    if (depth > 64) return rerror_at(r->e, r->path, r->line, "JSON nested too deeply");
    if (c == '"') return json_read_string(r, scratch, sizeof scratch);
    if (c == '{' || c == '[') {
        char close = c == '{' ? '}' : ']';
        r->pos++;
        if (json_peek(r) == close) {
            r->pos++;
            return 0;
        }
        for (;;) {
            if (c == '{') {
                if (json_read_string(r, scratch, sizeof scratch) || json_expect(r, ':')) return -1;
            }
            if (skip_value_depth(r, depth + 1)) return -1;
            if (json_peek(r) == ',') {
                r->pos++;
                continue;
            }
            return json_expect(r, close);
        }
    }
    if (c == 't') return skip_literal(r, "true");
    if (c == 'f') return skip_literal(r, "false");
    if (c == 'n') return skip_literal(r, "null");
    return json_read_number(r, &v);
}

int json_skip_value(json_reader *r) { return skip_value_depth(r, 0); }

int json_expect_end(json_reader *r)
{
    if (json_peek(r) != '\0') return rerror_at(r->e, r->path, r->line, "unexpected text after the JSON value");
    return 0;
}
