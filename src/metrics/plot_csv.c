/* The CSV tables of `restir plot` (plot.h, docs/statistics.md "plot"). */
#include "restir/metrics/plot_csv.h"

#include "restir/metrics/plot.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CSV_MAX_LINE 65536
#define CSV_MAX_COLUMNS 256

/* Splits one line into fields in place (quotes removed, "" unescaped). Returns the
 * field count, or -1 on a malformed quote. */
static int split_fields(char *line, char **fields, int max_fields)
{
    int n = 0;
    char *r = line, *w, *q;
    for (;;) {
        if (n == max_fields) return -2;
        q = r;
        while (*q == ' ' || *q == '\t') q++;
        fields[n++] = w = r;
        if (*q == '"') { /* spaces around a quoted field are ignored */
            r = q + 1;
            for (;;) {
                if (*r == '\0') return -1;
                if (*r == '"' && r[1] == '"') {
                    *w++ = '"';
                    r += 2;
                } else if (*r == '"') {
                    r++;
                    break;
                } else {
                    *w++ = *r++;
                }
            }
            while (*r == ' ' || *r == '\t') r++;
            if (*r != ',' && *r != '\0') return -1;
        } else {
            while (*r && *r != ',') *w++ = *r++;
        }
        if (*r == '\0') {
            *w = '\0';
            return n;
        }
        *w = '\0'; /* at the comma */
        r++;
    }
}

static char *trim(char *s)
{
    char *end;
    while (*s == ' ' || *s == '\t') s++;
    end = s + strlen(s);
    while (end > s && (end[-1] == ' ' || end[-1] == '\t')) *--end = '\0';
    return s;
}

static int parse_cell(const char *cell, double *v)
{
    char *end;
    if (!*cell) {
        *v = NAN;
        return 0;
    }
    errno = 0;
    *v = strtod(cell, &end);
    return end == cell || *end || !isfinite(*v) ? -1 : 0;
}

/* Appends one row (column-major storage grows by doubling the row capacity). */
static int append_row(plot_table *t, int *capacity, const double *row, rerror *e)
{
    int c;
    if (t->rows == *capacity) {
        int cap = *capacity ? 2 * *capacity : 64, r;
        double *grown = rmalloc((size_t)cap * (size_t)t->columns, sizeof *grown, e);
        if (!grown) return -1;
        for (c = 0; c < t->columns; ++c)
            for (r = 0; r < t->rows; ++r) grown[(size_t)c * cap + r] = t->values[(size_t)c * *capacity + r];
        free(t->values);
        t->values = grown;
        *capacity = cap;
    }
    for (c = 0; c < t->columns; ++c) t->values[(size_t)c * *capacity + t->rows] = row[c];
    t->rows++;
    return 0;
}

/* Makes the storage exactly rows long per column. */
static void compact(plot_table *t, int capacity)
{
    int c, r;
    for (c = 1; c < t->columns; ++c)
        for (r = 0; r < t->rows; ++r) t->values[(size_t)c * t->rows + r] = t->values[(size_t)c * capacity + r];
}

int plot_csv_read(const char *path, plot_table *t, rerror *e)
{
    FILE *fp;
    char *line = NULL, *fields[CSV_MAX_COLUMNS];
    double row[CSV_MAX_COLUMNS];
    long lineno = 0;
    int capacity = 0, c;
    memset(t, 0, sizeof *t);
    fp = fopen(path, "rb");
    if (!fp) return rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
    line = rmalloc(CSV_MAX_LINE, 1, e);
    if (!line) goto fail;
    while (fgets(line, CSV_MAX_LINE, fp)) {
        size_t len = strlen(line);
        int n;
        lineno++;
        if (len == CSV_MAX_LINE - 1 && line[len - 1] != '\n') {
            rerror_at(e, path, lineno, "line too long");
            goto fail;
        }
        while (len && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = '\0';
        {
            const char *content = trim(line);
            if (!*content || *content == '#') continue;
        }
        n = split_fields(line, fields, CSV_MAX_COLUMNS);
        if (n == -2) {
            rerror_at(e, path, lineno, "more than %d columns", CSV_MAX_COLUMNS);
            goto fail;
        }
        if (n < 0) {
            rerror_at(e, path, lineno, "malformed quoted field");
            goto fail;
        }
        if (!t->names) { /* the header */
            if (n < 2) {
                rerror_at(e, path, lineno, "the header needs an x column and at least one series");
                goto fail;
            }
            t->names = rcalloc((size_t)n, sizeof *t->names, e);
            if (!t->names) goto fail;
            t->columns = n;
            for (c = 0; c < n; ++c) {
                const char *name = trim(fields[c]);
                t->names[c] = rmalloc(strlen(name) + 1, 1, e);
                if (!t->names[c]) goto fail;
                strcpy(t->names[c], name);
            }
            continue;
        }
        if (n != t->columns) {
            rerror_at(e, path, lineno, "%d fields, the header has %d", n, t->columns);
            goto fail;
        }
        for (c = 0; c < n; ++c)
            if (parse_cell(trim(fields[c]), &row[c])) {
                rerror_at(e, path, lineno, "column %d: '%s' is not a number", c + 1, trim(fields[c]));
                goto fail;
            }
        if (isnan(row[0])) {
            rerror_at(e, path, lineno, "the x value (column 1) is empty");
            goto fail;
        }
        if (append_row(t, &capacity, row, e)) goto fail;
    }
    if (ferror(fp)) {
        rerror_at(e, path, 0, "read error");
        goto fail;
    }
    if (!t->names) {
        rerror_at(e, path, 0, "empty CSV: no header row");
        goto fail;
    }
    if (t->rows == 0) {
        rerror_at(e, path, 0, "no data rows");
        goto fail;
    }
    compact(t, capacity);
    free(line);
    fclose(fp);
    return 0;
fail:
    free(line);
    fclose(fp);
    plot_table_free(t);
    return -1;
}

void plot_table_free(plot_table *t)
{
    int c;
    if (t->names)
        for (c = 0; c < t->columns; ++c) free(t->names[c]);
    free(t->names);
    free(t->values);
    memset(t, 0, sizeof *t);
}
