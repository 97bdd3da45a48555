/* PNG reader (ISO/IEC 15948 = W3C PNG 2nd edition), no libpng, no zlib.
 *
 * The whole file is loaded (its size is known), the chunks are walked once (CRC-32 of
 * each checked, chunk order checked), the IDAT payloads are concatenated and inflated
 * into a buffer of exactly the size the header implies (src/core/inflate.c), then each
 * row is unfiltered (§9) and its samples converted to float. Every size is checked
 * before anything is allocated: the pixel count against IMAGE_MAX_PIXELS and the
 * decompressed size against what the IDAT bytes could possibly inflate to. */
#include "restir/core/png_read.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/checksum.h"
#include "restir/core/inflate.h"

/* DEFLATE expands at most 258 bytes per 2 bits (~1032x); anything claiming more is corrupt. */
#define DEFLATE_MAX_RATIO 1032
#define PNG_MAX_FILE ((size_t)1 << 31)

typedef struct {
    uint32_t width, height;
    int depth, colour, interlace;
    int samples;                /* samples per pixel in the file: 1, 2, 3 or 4 */
    unsigned char palette[768]; /* RGB */
    int palette_size;
    unsigned char trns_alpha[256]; /* palette alpha */
    int trns_count;                /* palette entries with alpha; -1: no tRNS */
    unsigned trns_key[3];          /* grey or RGB key of colour types 0 and 2 */
    int has_trns;
} png_info;

static uint32_t be32(const unsigned char *b)
{
    return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3];
}

double srgb_to_linear(double c)
{
    /* IEC 61966-2-1 sRGB EOTF */
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* §11.2.2: allowed bit depths per colour type; sets the samples per pixel. */
static int check_ihdr(const char *path, png_info *p, const unsigned char *d, rerror *e)
{
    static const struct {
        int colour, samples;
        unsigned depths; /* bit set of allowed depths */
    } types[] = {{0, 1, 1u << 1 | 1u << 2 | 1u << 4 | 1u << 8 | 1u << 16},
                 {2, 3, 1u << 8 | 1u << 16},
                 {3, 1, 1u << 1 | 1u << 2 | 1u << 4 | 1u << 8},
                 {4, 2, 1u << 8 | 1u << 16},
                 {6, 4, 1u << 8 | 1u << 16}};
    size_t i;
    p->width = be32(d);
    p->height = be32(d + 4);
    p->depth = d[8];
    p->colour = d[9];
    p->interlace = d[12];
    if (p->width == 0 || p->height == 0 || p->width > 0x7fffffffu || p->height > 0x7fffffffu)
        return rerror_at(e, path, 0, "PNG: image size %lu x %lu is invalid", (unsigned long)p->width,
                         (unsigned long)p->height);
    if ((double)p->width * p->height > (double)IMAGE_MAX_PIXELS)
        return rerror_at(e, path, 0, "PNG: image size %lu x %lu is too large (at most %ld pixels)",
                         (unsigned long)p->width, (unsigned long)p->height, IMAGE_MAX_PIXELS);
    if (d[10] != 0 || d[11] != 0)
        return rerror_at(e, path, 0, "PNG: compression method %d / filter method %d is not 0", d[10], d[11]);
    if (p->interlace > 1) return rerror_at(e, path, 0, "PNG: interlace method %d is unknown", p->interlace);
    for (i = 0; i < sizeof types / sizeof types[0]; ++i) {
        if (types[i].colour != p->colour) continue;
        if (p->depth > 16 || !(types[i].depths >> p->depth & 1))
            return rerror_at(e, path, 0, "PNG: bit depth %d is not allowed for colour type %d", p->depth, p->colour);
        p->samples = types[i].samples;
        return 0;
    }
    return rerror_at(e, path, 0, "PNG: colour type %d is unknown", p->colour);
}

/* PLTE and tRNS (§11.2.3, §11.3.2.1). */
static int read_palette(const char *path, png_info *p, const unsigned char *d, uint32_t len, rerror *e)
{
    if (p->palette_size) return rerror_at(e, path, 0, "PNG: more than one PLTE chunk");
    if (p->colour == 0 || p->colour == 4) return rerror_at(e, path, 0, "PNG: PLTE chunk in a greyscale image");
    if (len == 0 || len % 3 != 0 || len > 768)
        return rerror_at(e, path, 0, "PNG: PLTE chunk of %lu bytes (must be 3 x 1..256)", (unsigned long)len);
    memcpy(p->palette, d, len);
    p->palette_size = (int)(len / 3);
    return 0;
}

static int read_trns(const char *path, png_info *p, const unsigned char *d, uint32_t len, rerror *e)
{
    if (p->has_trns) return rerror_at(e, path, 0, "PNG: more than one tRNS chunk");
    if (p->colour == 3) {
        if (!p->palette_size) return rerror_at(e, path, 0, "PNG: tRNS chunk before PLTE");
        if (len > (uint32_t)p->palette_size)
            return rerror_at(e, path, 0, "PNG: tRNS has %lu entries for a palette of %d", (unsigned long)len,
                             p->palette_size);
        memcpy(p->trns_alpha, d, len);
        p->trns_count = (int)len;
    } else if (p->colour == 0 || p->colour == 2) {
        uint32_t want = p->colour == 0 ? 2 : 6, i;
        if (len != want)
            return rerror_at(e, path, 0, "PNG: tRNS chunk of %lu bytes (colour type %d needs %lu)",
                             (unsigned long)len, p->colour, (unsigned long)want);
        for (i = 0; i < want / 2; ++i) p->trns_key[i] = (unsigned)d[2 * i] << 8 | d[2 * i + 1];
    } else {
        return rerror_at(e, path, 0, "PNG: tRNS chunk in an image with an alpha channel");
    }
    p->has_trns = 1;
    return 0;
}

/* Bytes of one row of a pass `w` pixels wide (without the filter byte). */
static size_t row_bytes(const png_info *p, uint32_t w) { return ((size_t)w * p->samples * p->depth + 7) / 8; }

/* Adam7 (§8.2): origin and step of each pass; pass 0 is the whole image without interlace. */
static const int adam7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};

static void pass_size(const png_info *p, int pass, uint32_t *w, uint32_t *h)
{
    if (!p->interlace) {
        *w = p->width;
        *h = p->height;
        return;
    }
    *w = p->width > (uint32_t)adam7[pass][0] ? (p->width - adam7[pass][0] + adam7[pass][2] - 1) / adam7[pass][2] : 0;
    *h = p->height > (uint32_t)adam7[pass][1] ? (p->height - adam7[pass][1] + adam7[pass][3] - 1) / adam7[pass][3]
                                              : 0;
}

static double raw_size(const png_info *p)
{
    double total = 0;
    int pass, passes = p->interlace ? 7 : 1;
    for (pass = 0; pass < passes; ++pass) {
        uint32_t w, h;
        pass_size(p, pass, &w, &h);
        if (w && h) total += (double)h * (1 + (double)row_bytes(p, w));
    }
    return total;
}

static int paeth(int a, int b, int c)
{
    int pa = abs(b - c), pb = abs(a - c), pc = abs(a + b - 2 * c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* §9.2: undoes the filter of one row in place; prev is the previous row of the pass (or NULL). */
static int unfilter(unsigned char *row, const unsigned char *prev, size_t n, size_t bpp, int type)
{
    size_t i;
    switch (type) {
    case 0:
        return 0;
    case 1:
        for (i = bpp; i < n; ++i) row[i] = (unsigned char)(row[i] + row[i - bpp]);
        return 0;
    case 2:
        if (prev)
            for (i = 0; i < n; ++i) row[i] = (unsigned char)(row[i] + prev[i]);
        return 0;
    case 3:
        for (i = 0; i < n; ++i) {
            int a = i >= bpp ? row[i - bpp] : 0, b = prev ? prev[i] : 0;
            row[i] = (unsigned char)(row[i] + ((a + b) >> 1));
        }
        return 0;
    case 4:
        for (i = 0; i < n; ++i) {
            int a = i >= bpp ? row[i - bpp] : 0, b = prev ? prev[i] : 0, c = prev && i >= bpp ? prev[i - bpp] : 0;
            row[i] = (unsigned char)(row[i] + paeth(a, b, c));
        }
        return 0;
    default:
        return -1;
    }
}

static unsigned sample(const unsigned char *row, size_t i, int depth)
{
    size_t bit;
    if (depth == 16) return (unsigned)row[2 * i] << 8 | row[2 * i + 1];
    if (depth == 8) return row[i];
    bit = i * (size_t)depth;
    return (unsigned)(row[bit / 8] >> (8 - depth - (int)(bit % 8))) & ((1u << depth) - 1);
}

typedef struct {
    float *colour, *alpha; /* code -> float for colour samples and for alpha */
} lut_pair;

/* One decoded row of a pass into the output pixels at (x0 + i dx, y). */
static int store_row(const png_info *p, const unsigned char *row, uint32_t w, uint32_t y, int x0, int dx,
                     const lut_pair *lut, const float *pal_colour, fimage *out)
{
    uint32_t i;
    int c, nc = out->channels;
    for (i = 0; i < w; ++i) {
        float *o = out->px + ((size_t)y * out->width + x0 + (size_t)i * dx) * nc;
        size_t s = (size_t)i * p->samples;
        if (p->colour == 3) {
            unsigned idx = sample(row, i, p->depth);
            if ((int)idx >= p->palette_size) return -1;
            for (c = 0; c < 3; ++c) o[c] = pal_colour[p->palette[3 * idx + c]];
            if (nc == 4) o[3] = lut->alpha[(int)idx < p->trns_count ? p->trns_alpha[idx] : 255];
            continue;
        }
        if (p->colour == 0 || p->colour == 2) {
            int n = p->samples, is_key = p->has_trns;
            for (c = 0; c < n; ++c) {
                unsigned v = sample(row, s + c, p->depth);
                o[c] = lut->colour[v];
                if (v != (p->trns_key[c] & ((1u << p->depth) - 1))) is_key = 0;
            }
            if (p->has_trns) o[n] = is_key ? 0.0f : 1.0f;
            continue;
        }
        for (c = 0; c < p->samples - 1; ++c) o[c] = lut->colour[sample(row, s + c, p->depth)];
        o[c] = lut->alpha[sample(row, s + c, p->depth)];
    }
    return 0;
}

static int decode_passes(const char *path, const png_info *p, unsigned char *raw, int flags, fimage *out, rerror *e)
{
    unsigned maxval = (1u << p->depth) - 1, v;
    size_t bpp = ((size_t)p->samples * p->depth + 7) / 8;
    lut_pair lut;
    float pal_colour[256];
    int pass, passes = p->interlace ? 7 : 1, status = 0;
    lut.colour = rmalloc((size_t)maxval + 1, sizeof(float), e);
    lut.alpha = rmalloc((size_t)maxval + 1, sizeof(float), e);
    if (!lut.colour || !lut.alpha) {
        free(lut.colour);
        free(lut.alpha);
        return -1;
    }
    for (v = 0; v <= maxval; ++v) {
        double c = (double)v / maxval;
        lut.alpha[v] = (float)c;
        lut.colour[v] = (float)(flags & PNG_SRGB ? srgb_to_linear(c) : c);
    }
    for (v = 0; v < 256; ++v) pal_colour[v] = (float)(flags & PNG_SRGB ? srgb_to_linear(v / 255.0) : v / 255.0);
    if (p->colour == 3) {
        /* palette alpha is 8-bit whatever the index depth */
        free(lut.alpha);
        lut.alpha = rmalloc(256, sizeof(float), e);
        if (!lut.alpha) {
            free(lut.colour);
            return -1;
        }
        for (v = 0; v < 256; ++v) lut.alpha[v] = (float)(v / 255.0);
    }
    for (pass = 0; pass < passes && !status; ++pass) {
        uint32_t w, h, j;
        static const int whole[4] = {0, 0, 1, 1};
        const int *a = p->interlace ? adam7[pass] : whole;
        int x0 = a[0], y0 = a[1], dx = a[2], dy = a[3];
        size_t n;
        unsigned char *prev = NULL;
        pass_size(p, pass, &w, &h);
        if (!w || !h) continue;
        n = row_bytes(p, w);
        for (j = 0; j < h; ++j) {
            unsigned char *row = raw + 1;
            if (unfilter(row, prev, n, bpp, raw[0])) {
                status = rerror_at(e, path, 0, "PNG: row %lu has filter type %d (0..4 exist)", (unsigned long)j,
                                   raw[0]);
                break;
            }
            if (store_row(p, row, w, y0 + j * (uint32_t)dy, x0, dx, &lut, pal_colour, out)) {
                status = rerror_at(e, path, 0, "PNG: palette index beyond the %d PLTE entries", p->palette_size);
                break;
            }
            prev = row;
            raw += 1 + n;
        }
    }
    free(lut.colour);
    free(lut.alpha);
    return status;
}

/* Walks the chunks: IHDR first, PLTE/tRNS before IDAT, IDATs consecutive, IEND last.
 * Copies the IDAT payloads into idat (the caller sized it to the file). */
static int walk_chunks(const char *path, const unsigned char *f, size_t size, png_info *p, unsigned char *idat,
                       size_t *idat_size, rerror *e)
{
    size_t pos = 8;
    int seen_ihdr = 0, idat_state = 0; /* 0 none yet, 1 in the IDAT run, 2 after it */
    *idat_size = 0;
    for (;;) {
        uint32_t len, crc;
        const unsigned char *type, *d;
        if (size - pos < 12) return rerror_at(e, path, 0, "PNG: file ends before the IEND chunk");
        len = be32(f + pos);
        type = f + pos + 4;
        d = type + 4;
        if (len > 0x7fffffffu || len > size - pos - 12)
            return rerror_at(e, path, 0, "PNG: chunk of %lu bytes runs past the end of the file", (unsigned long)len);
        crc = be32(d + len);
        if (crc32_update(0, type, 4 + (size_t)len) != crc)
            return rerror_at(e, path, 0, "PNG: CRC mismatch in chunk '%.4s' (corrupt file)", (const char *)type);
        pos += 12 + (size_t)len;
        if (!seen_ihdr) {
            if (memcmp(type, "IHDR", 4) || len != 13) return rerror_at(e, path, 0, "PNG: first chunk is not IHDR");
            if (check_ihdr(path, p, d, e)) return -1;
            seen_ihdr = 1;
            continue;
        }
        if (idat_state == 1 && memcmp(type, "IDAT", 4)) idat_state = 2;
        if (!memcmp(type, "IDAT", 4)) {
            if (idat_state == 2) return rerror_at(e, path, 0, "PNG: IDAT chunks are not consecutive");
            if (p->colour == 3 && !p->palette_size) return rerror_at(e, path, 0, "PNG: palette image without PLTE");
            idat_state = 1;
            memcpy(idat + *idat_size, d, len);
            *idat_size += len;
        } else if (!memcmp(type, "IEND", 4)) {
            if (!idat_state) return rerror_at(e, path, 0, "PNG: no IDAT chunk");
            return 0;
        } else if (!memcmp(type, "PLTE", 4) || !memcmp(type, "tRNS", 4)) {
            if (idat_state) return rerror_at(e, path, 0, "PNG: %.4s chunk after IDAT", (const char *)type);
            if (type[0] == 'P' ? read_palette(path, p, d, len, e) : read_trns(path, p, d, len, e)) return -1;
        } else if (!memcmp(type, "IHDR", 4)) {
            return rerror_at(e, path, 0, "PNG: more than one IHDR chunk");
        } else if (!(type[0] & 0x20)) {
            return rerror_at(e, path, 0, "PNG: unknown critical chunk '%.4s'", (const char *)type);
        }
        /* other ancillary chunks (gAMA, sRGB, iCCP, text, ...) are ignored */
    }
}

int png_read(const char *path, int flags, fimage *out, rerror *e)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    png_info p;
    unsigned char *file, *idat = NULL, *raw = NULL;
    size_t size, idat_size, got = 0;
    double need;
    int status = -1, channels;
    rerror sub;
    memset(out, 0, sizeof *out);
    memset(&p, 0, sizeof p);
    p.trns_count = -1;
    file = image_file_load(path, PNG_MAX_FILE, &size, e);
    if (!file) return -1;
    if (size < 8 || memcmp(file, signature, 8)) {
        rerror_at(e, path, 0, "not a PNG file (bad signature)");
        goto done;
    }
    if (!(idat = rmalloc(size, 1, e)) || walk_chunks(path, file, size, &p, idat, &idat_size, e)) goto done;
    need = raw_size(&p);
    if (need > (double)idat_size * DEFLATE_MAX_RATIO + 1024) {
        rerror_at(e, path, 0, "PNG: %lu x %lu image needs %.0f bytes, more than %lu compressed bytes can hold",
                  (unsigned long)p.width, (unsigned long)p.height, need, (unsigned long)idat_size);
        goto done;
    }
    if (!(raw = rmalloc((size_t)need, 1, e))) goto done;
    if (inflate_zlib(idat, idat_size, raw, (size_t)need, &got, &sub)) {
        rerror_at(e, path, 0, "PNG image data: %s", sub.msg);
        goto done;
    }
    if (got != (size_t)need) {
        rerror_at(e, path, 0, "PNG image data: %lu bytes, %.0f expected", (unsigned long)got, need);
        goto done;
    }
    channels = p.colour == 3 ? 3 : p.samples;
    if (p.has_trns) channels++;
    if (fimage_alloc(out, (int)p.width, (int)p.height, channels, e)) goto done;
    status = decode_passes(path, &p, raw, flags, out, e);
    if (status) fimage_free(out);
done:
    free(raw);
    free(idat);
    free(file);
    return status;
}
