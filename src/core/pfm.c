/* Portable float map (PFM) reader and writer.
 *
 * The format (Paul Debevec's HDRShop convention, as read by pbrt, Mitsuba, OpenImageIO,
 * Pillow): three whitespace-separated ASCII tokens, then exactly one whitespace byte,
 * then raw 32-bit IEEE floats:
 *     "PF" (RGB) or "Pf" (greyscale)   width height   scale
 * The sign of `scale` gives the byte order of the floats (negative = little-endian);
 * its magnitude is a brightness hint that we, like Pillow and OpenImageIO, ignore.
 * Rows are stored BOTTOM to top; our images keep row 0 at the top, so both
 * directions flip. The reader is strict: anything it cannot read exactly is an error. */
#include "restir/core/pfm.h"

#include "restir/core/atomic_file.h"
#include "restir/core/image.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Larger dimensions are treated as a corrupt header rather than attempted. */
#define PFM_MAX_DIMENSION (1 << 20)
#define PFM_MAX_TOKEN 64

typedef struct {
    FILE *fp;
    const char *path;
    long line; /* 1-based line of the header being parsed */
    rerror *e;
} pfm_reader;

static int is_space(int c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/* Skips at least one whitespace byte (the spec's separator) and then any more. */
static int skip_separator(pfm_reader *r, const char *before)
{
    int c = getc(r->fp), count = 0;
    while (c != EOF && is_space(c)) {
        if (c == '\n') r->line++;
        count++;
        c = getc(r->fp);
    }
    if (c == EOF) return rerror_at(r->e, r->path, r->line, "PFM header ends before %s", before);
    ungetc(c, r->fp);
    if (count == 0) return rerror_at(r->e, r->path, r->line, "PFM header: expected whitespace before %s", before);
    return 0;
}

/* Reads one non-whitespace token (stops before the next byte, which is left unread). */
static int read_token(pfm_reader *r, char *token, const char *what)
{
    int c, n = 0;
    if (skip_separator(r, what)) return -1;
    for (;;) {
        c = getc(r->fp);
        if (c == EOF || is_space(c)) break;
        if (n + 1 >= PFM_MAX_TOKEN) return rerror_at(r->e, r->path, r->line, "PFM header: %s is too long", what);
        token[n++] = (char)c;
    }
    token[n] = '\0';
    if (c != EOF) ungetc(c, r->fp);
    return 0;
}

static int parse_dimension(pfm_reader *r, const char *what, int *out)
{
    char token[PFM_MAX_TOKEN];
    long value = 0;
    int i;
    if (read_token(r, token, what)) return -1;
    for (i = 0; token[i]; ++i) {
        if (token[i] < '0' || token[i] > '9')
            return rerror_at(r->e, r->path, r->line, "PFM header: %s '%s' is not a positive integer", what, token);
        value = value * 10 + (token[i] - '0');
        if (value > PFM_MAX_DIMENSION)
            return rerror_at(r->e, r->path, r->line, "PFM header: %s '%s' is too large (max %d)", what, token,
                             PFM_MAX_DIMENSION);
    }
    if (value <= 0) return rerror_at(r->e, r->path, r->line, "PFM header: %s '%s' is not positive", what, token);
    *out = (int)value;
    return 0;
}

static int parse_scale(pfm_reader *r, double *scale)
{
    char token[PFM_MAX_TOKEN], *end;
    if (read_token(r, token, "scale")) return -1;
    errno = 0;
    *scale = strtod(token, &end);
    if (end == token || *end != '\0')
        return rerror_at(r->e, r->path, r->line, "PFM header: scale '%s' is not a number", token);
    if (!isfinite(*scale) || errno == ERANGE)
        return rerror_at(r->e, r->path, r->line, "PFM header: scale '%s' is not finite", token);
    if (*scale == 0)
        return rerror_at(r->e, r->path, r->line, "PFM header: scale is zero (its sign gives the byte order)");
    return 0;
}

/* Header up to and including the single whitespace byte that precedes the data. */
static int parse_header(pfm_reader *r, int *width, int *height, int *channels, int *little_endian)
{
    char magic[3] = {0, 0, 0};
    double scale;
    int c;
    if (fread(magic, 1, 2, r->fp) != 2 || magic[0] != 'P' || (magic[1] != 'F' && magic[1] != 'f'))
        return rerror_at(r->e, r->path, 1, "not a PFM file (magic is not \"PF\" or \"Pf\")");
    *channels = magic[1] == 'F' ? 3 : 1;
    if (parse_dimension(r, "width", width) || parse_dimension(r, "height", height) || parse_scale(r, &scale))
        return -1;
    c = getc(r->fp);
    if (c == EOF || !is_space(c))
        return rerror_at(r->e, r->path, r->line, "PFM header: expected one whitespace byte after the scale");
    *little_endian = scale < 0;
    return 0;
}

static float decode_float(const unsigned char *b, int little_endian)
{
    uint32_t bits;
    float f;
    if (little_endian)
        bits = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    else
        bits = (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 | (uint32_t)b[0] << 24;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static void encode_float_le(float f, unsigned char *b)
{
    uint32_t bits;
    memcpy(&bits, &f, sizeof bits);
    b[0] = (unsigned char)(bits & 0xff);
    b[1] = (unsigned char)(bits >> 8 & 0xff);
    b[2] = (unsigned char)(bits >> 16 & 0xff);
    b[3] = (unsigned char)(bits >> 24 & 0xff);
}

/* Reads the rows (bottom-to-top in the file) into the top-row-first image. */
static int read_pixels(pfm_reader *r, image *img, int channels, int little_endian)
{
    size_t row_bytes = (size_t)img->width * (size_t)channels * 4;
    unsigned char *row = rmalloc(row_bytes, 1, r->e);
    int y, x;
    if (!row) return -1;
    for (y = img->height - 1; y >= 0; --y) {
        size_t got = fread(row, 1, row_bytes, r->fp);
        if (got != row_bytes) {
            free(row);
            return rerror_at(r->e, r->path, 0, "PFM data is short: %d of %d rows present", img->height - 1 - y,
                             img->height);
        }
        for (x = 0; x < img->width; ++x) {
            float *p = image_pixel(img, x, y);
            if (channels == 3) {
                p[0] = decode_float(row + 12 * (size_t)x, little_endian);
                p[1] = decode_float(row + 12 * (size_t)x + 4, little_endian);
                p[2] = decode_float(row + 12 * (size_t)x + 8, little_endian);
            } else {
                p[0] = p[1] = p[2] = decode_float(row + 4 * (size_t)x, little_endian);
            }
        }
    }
    free(row);
    if (getc(r->fp) != EOF) return rerror_at(r->e, r->path, 0, "unexpected bytes after the PFM pixel data");
    return 0;
}

int pfm_read(const char *path, image *out, int *channels, rerror *e)
{
    pfm_reader r;
    struct stat st;
    int width = 0, height = 0, nch = 3, little_endian = 1;
    long header_end;
    double data_bytes;
    out->width = out->height = 0;
    out->px = NULL;
    r.fp = fopen(path, "rb");
    r.path = path;
    r.line = 1;
    r.e = e;
    if (!r.fp) return rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
    if (parse_header(&r, &width, &height, &nch, &little_endian)) goto fail;
    if ((long)width * (long)height > IMAGE_MAX_PIXELS) {
        rerror_at(e, path, r.line, "PFM header: %d x %d pixels is too large (at most %ld)", width, height,
                  IMAGE_MAX_PIXELS);
        goto fail;
    }
    /* Check the file really holds the data before allocating for it (a corrupt
     * header must not make us allocate gigabytes). */
    header_end = ftell(r.fp);
    data_bytes = (double)width * height * nch * 4;
    if (header_end >= 0 && fstat(fileno(r.fp), &st) == 0 && S_ISREG(st.st_mode) &&
        (double)(st.st_size - header_end) < data_bytes) {
        rerror_at(e, path, 0, "PFM data is short: %.0f bytes for %d x %d x %d floats, %.0f present", data_bytes, width,
                  height, nch, (double)(st.st_size - header_end));
        goto fail;
    }
    if (image_alloc(out, width, height, e)) goto fail;
    if (read_pixels(&r, out, nch, little_endian)) {
        image_free(out);
        goto fail;
    }
    fclose(r.fp);
    if (channels) *channels = nch;
    return 0;
fail:
    fclose(r.fp);
    return -1;
}

int pfm_write(const char *path, const image *img, rerror *e)
{
    atomic_file f;
    unsigned char *row;
    size_t row_bytes;
    int x, y, c;
    if (img->width <= 0 || img->height <= 0 || !img->px) return rerror_at(e, path, 0, "cannot write an empty image");
    row_bytes = (size_t)img->width * 12;
    row = rmalloc(row_bytes, 1, e);
    if (!row) return -1;
    if (atomic_file_open(&f, path, e)) {
        free(row);
        return -1;
    }
    fprintf(f.fp, "PF\n%d %d\n-1.0\n", img->width, img->height);
    for (y = img->height - 1; y >= 0; --y) {
        for (x = 0; x < img->width; ++x)
            for (c = 0; c < 3; ++c) encode_float_le(image_pixel(img, x, y)[c], row + 12 * (size_t)x + 4 * (size_t)c);
        if (fwrite(row, 1, row_bytes, f.fp) != row_bytes) break;
    }
    free(row);
    if (y >= 0) {
        atomic_file_abort(&f);
        return rerror_at(e, path, 0, "write failed: %s", strerror(errno));
    }
    return atomic_file_commit(&f, e);
}
