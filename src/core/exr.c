/* OpenEXR scanline reader and writer, no OpenEXR library (include/restir/core/exr.h).
 *
 * File layout (OpenEXR "File Layout" document): magic 76 2f 31 01, a version word
 * (version 2 in the low byte, flags above it: 0x200 tiled, 0x400 long names, 0x800 deep,
 * 0x1000 multi-part), the header (attributes `name\0 type\0 size value`, ended by a 0
 * byte), the line offset table (one uint64 per chunk, in increasing y whatever the
 * lineOrder), then the chunks `int32 y, int32 packed size, data`. Uncompressed chunk
 * data is line by line, and within a line channel by channel (in header order, which is
 * alphabetical), `width` little-endian values each. All integers are little-endian.
 *
 * A chunk whose packed size equals its unpacked size is stored raw (writers fall back to
 * raw when compression does not pay). Decompressors (each reproduces the unpacked bytes):
 *   RLE   signed count bytes (n < 0: -n literal bytes; else n+1 copies of one byte),
 *         then the ZIP byte predictor and interleave below.
 *   ZIPS/ZIP  zlib stream (1 or 16 lines per chunk); then predictor: b[i] += b[i-1] - 128,
 *         and de-interleave: the first half holds the even bytes, the second the odd ones.
 *   PIZ   (32 lines) bitmap of the 16-bit values present + LUT, Huffman code of the
 *         LUT indices with a run-length symbol, and a 2D Haar-like wavelet per channel
 *         (piz_* below). */
#include "restir/core/exr.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/inflate.h"

#define EXR_MAX_FILE ((size_t)1 << 32)
#define EXR_MAX_CHANNELS 64
/* The most bytes any supported compression can expand one input byte to (deflate's
 * ~1032, PIZ's run-length symbol ~450, RLE 64): a header asking for more is corrupt. */
#define EXR_MAX_RATIO 1100
/* Display-window pixels that no data-window pixel covers are zeros made from nothing.
 * Any display window up to 2^24 pixels is accepted (4096 x 4096: every 4K or UHD frame
 * around any crop or element); beyond that the uncovered part may have at most 1024
 * pixels per byte of the file, so a tiny file cannot make the reader allocate a
 * gigabyte of zeros (docs/images.md, Limits). */
#define EXR_MAX_PADDING ((double)(1 << 24))
#define EXR_PADDING_PER_BYTE 1024.0

/* ---- half <-> float ---- */

float half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h >> 15) << 31, exp = h >> 10 & 31, mant = h & 1023u, bits;
    float f;
    if (exp == 0) {
        /* zero or subnormal: mant * 2^-24 is exact in float */
        f = (float)mant * 5.9604644775390625e-8f;
        return sign ? -f : f;
    }
    if (exp == 31) bits = sign | 0x7f800000u | mant << 13; /* infinity or NaN */
    else bits = sign | (exp + 112) << 23 | mant << 13;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* half bits -> float for every half: the readers convert megabytes of halves */
static float half_table[65536];
static pthread_once_t half_table_once = PTHREAD_ONCE_INIT;

static void half_table_build(void)
{
    uint32_t h;
    for (h = 0; h < 65536; ++h) half_table[h] = half_to_float((uint16_t)h);
}

/* Rounds `value` right by `shift` bits to nearest, ties to even. */
static uint32_t round_shift(uint32_t value, int shift)
{
    uint32_t q = value >> shift, rem = value & ((1u << shift) - 1), half = 1u << (shift - 1);
    return q + (rem > half || (rem == half && (q & 1)));
}

uint16_t float_to_half(float f)
{
    uint32_t bits, sign, exp, mant;
    int e;
    memcpy(&bits, &f, sizeof bits);
    sign = bits >> 16 & 0x8000u;
    exp = bits >> 23 & 255;
    mant = bits & 0x7fffffu;
    if (exp == 255) {
        uint32_t m = mant >> 13;
        return (uint16_t)(sign | 0x7c00u | (mant ? m | (m == 0) : 0)); /* NaN keeps a nonzero payload */
    }
    e = (int)exp - 112; /* half exponent field */
    if (e >= 31) return (uint16_t)(sign | 0x7c00u);
    if (e <= 0) {
        /* subnormal half: units of 2^-24; below 2^-25 everything rounds to zero */
        if (e < -10) return (uint16_t)sign;
        return (uint16_t)(sign | round_shift(mant | 0x800000u, 14 - e)); /* may round up into the normals */
    }
    /* a carry out of the mantissa bumps the exponent, up to infinity: still correct */
    return (uint16_t)(sign | round_shift((uint32_t)e << 23 | mant, 13));
}

/* ---- little-endian helpers ---- */

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}
static int32_t le32s(const unsigned char *b)
{
    uint32_t u = le32(b);
    return u <= 0x7fffffffu ? (int32_t)u : -(int32_t)(~u) - 1;
}
static uint64_t le64(const unsigned char *b) { return le32(b) | (uint64_t)le32(b + 4) << 32; }
static void put32(unsigned char *b, uint32_t v)
{
    b[0] = (unsigned char)(v & 0xff);
    b[1] = (unsigned char)(v >> 8 & 0xff);
    b[2] = (unsigned char)(v >> 16 & 0xff);
    b[3] = (unsigned char)(v >> 24);
}

/* ---- header ---- */

typedef struct {
    char name[256];
    int type;   /* EXR_UINT, EXR_HALF, EXR_FLOAT */
    int size;   /* bytes per value: 4, 2, 4 */
    int target; /* output channel, -1: skipped */
} exr_channel;

typedef struct {
    exr_channel ch[EXR_MAX_CHANNELS];
    int nch;
    int compression, line_order;
    int32_t data[4], display[4]; /* xMin yMin xMax yMax */
    int have; /* bit set of the required attributes seen */
    size_t header_end;
} exr_header;

static const char *compression_name(int c)
{
    static const char *names[] = {"NONE", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB"};
    return c >= 0 && c < 10 ? names[c] : "unknown";
}

static int parse_channels(const char *path, exr_header *h, const unsigned char *v, size_t n, rerror *e)
{
    size_t pos = 0;
    h->nch = 0;
    for (;;) {
        size_t len;
        exr_channel *c;
        int32_t xs, ys, type;
        if (pos >= n) return rerror_at(e, path, 0, "EXR: channel list is not terminated");
        if (v[pos] == 0) break;
        len = strnlen((const char *)v + pos, n - pos);
        if (len >= 256 || n - pos - len < 1 + 16)
            return rerror_at(e, path, 0, "EXR: channel list entry is truncated or its name too long");
        if (h->nch == EXR_MAX_CHANNELS)
            return rerror_at(e, path, 0, "EXR: more than %d channels", EXR_MAX_CHANNELS);
        c = &h->ch[h->nch++];
        memcpy(c->name, v + pos, len + 1);
        pos += len + 1;
        type = le32s(v + pos);
        xs = le32s(v + pos + 8);
        ys = le32s(v + pos + 12);
        pos += 16;
        if (type < 0 || type > 2)
            return rerror_at(e, path, 0, "EXR: channel '%s' has unknown pixel type %ld", c->name, (long)type);
        if (xs != 1 || ys != 1)
            return rerror_at(e, path, 0, "EXR: channel '%s' is subsampled (%ld x %ld); not supported", c->name,
                             (long)xs, (long)ys);
        c->type = type;
        c->size = type == EXR_HALF ? 2 : 4;
        c->target = -1;
    }
    if (h->nch == 0) return rerror_at(e, path, 0, "EXR: no channels");
    return 0;
}

static int parse_box(const char *path, const char *what, const unsigned char *v, int32_t box[4], rerror *e)
{
    int i;
    for (i = 0; i < 4; ++i) box[i] = le32s(v + 4 * i);
    if (box[2] < box[0] || box[3] < box[1])
        return rerror_at(e, path, 0, "EXR: %s (%ld,%ld)-(%ld,%ld) is empty", what, (long)box[0], (long)box[1],
                         (long)box[2], (long)box[3]);
    if (((double)box[2] - box[0] + 1) * ((double)box[3] - box[1] + 1) > (double)IMAGE_MAX_PIXELS)
        return rerror_at(e, path, 0, "EXR: %s of %.0f x %.0f pixels is too large (at most %ld)", what,
                         (double)box[2] - box[0] + 1, (double)box[3] - box[1] + 1, IMAGE_MAX_PIXELS);
    return 0;
}

enum { HAVE_CHANNELS = 1, HAVE_COMPRESSION = 2, HAVE_DATA = 4, HAVE_DISPLAY = 8, HAVE_LINE_ORDER = 16 };

/* One attribute; the ones the reader needs are checked for type and size. */
static int parse_attribute(const char *path, exr_header *h, const char *name, const char *type,
                           const unsigned char *v, size_t n, rerror *e)
{
    if (!strcmp(name, "tiles") || (!strcmp(name, "type") && strcmp(type, "string") == 0 &&
                                   !(n == 13 && !memcmp(v, "scanlineimage", 13))))
        return rerror_at(e, path, 0, "EXR: tiled or deep images are not supported (scanline images only)");
#define EXPECT(t, size)                                                                                                \
    if (strcmp(type, t) || n != (size))                                                                                \
        return rerror_at(e, path, 0, "EXR: attribute '%s' has type '%s' and %lu bytes", name, type, (unsigned long)n);
    if (!strcmp(name, "channels")) {
        if (strcmp(type, "chlist")) return rerror_at(e, path, 0, "EXR: attribute 'channels' has type '%s'", type);
        h->have |= HAVE_CHANNELS;
        return parse_channels(path, h, v, n, e);
    }
    if (!strcmp(name, "compression")) {
        EXPECT("compression", 1)
        h->compression = v[0];
        h->have |= HAVE_COMPRESSION;
    } else if (!strcmp(name, "dataWindow")) {
        EXPECT("box2i", 16)
        h->have |= HAVE_DATA;
        return parse_box(path, "dataWindow", v, h->data, e);
    } else if (!strcmp(name, "displayWindow")) {
        EXPECT("box2i", 16)
        h->have |= HAVE_DISPLAY;
        return parse_box(path, "displayWindow", v, h->display, e);
    } else if (!strcmp(name, "lineOrder")) {
        EXPECT("lineOrder", 1)
        if (v[0] > 2) return rerror_at(e, path, 0, "EXR: lineOrder %d is unknown", v[0]);
        h->line_order = v[0];
        h->have |= HAVE_LINE_ORDER;
    }
#undef EXPECT
    return 0;
}

static int parse_header(const char *path, const unsigned char *f, size_t size, exr_header *h, rerror *e)
{
    size_t pos = 8;
    uint32_t version;
    memset(h, 0, sizeof *h);
    if (size < 8 || le32(f) != 20000630u) return rerror_at(e, path, 0, "not an OpenEXR file (bad magic number)");
    version = le32(f + 4);
    if ((version & 0xff) != 2) return rerror_at(e, path, 0, "EXR: file format version %lu is not 2",
                                                (unsigned long)(version & 0xff));
    if (version & 0x1000) return rerror_at(e, path, 0, "EXR: multi-part files are not supported");
    if (version & 0x800) return rerror_at(e, path, 0, "EXR: deep data files are not supported");
    if (version & 0x200) return rerror_at(e, path, 0, "EXR: tiled images are not supported (scanline images only)");
    if (version & ~0x4ffu) return rerror_at(e, path, 0, "EXR: unknown flags 0x%lx in the version field",
                                            (unsigned long)(version & ~0x4ffu));
    for (;;) {
        size_t nlen, tlen;
        int32_t asize;
        const char *name, *type;
        if (pos >= size) return rerror_at(e, path, 0, "EXR: header is truncated");
        if (f[pos] == 0) break;
        name = (const char *)f + pos;
        nlen = strnlen(name, size - pos);
        if (nlen >= 256 || size - pos - nlen < 2) return rerror_at(e, path, 0, "EXR: header is truncated");
        type = name + nlen + 1;
        tlen = strnlen(type, size - pos - nlen - 1);
        if (tlen >= 256 || size - pos - nlen - 1 - tlen < 1 + 4) return rerror_at(e, path, 0, "EXR: header is truncated");
        pos += nlen + 1 + tlen + 1;
        asize = le32s(f + pos);
        pos += 4;
        if (asize < 0 || (size_t)asize > size - pos)
            return rerror_at(e, path, 0, "EXR: attribute '%s' of %ld bytes runs past the end of the file", name,
                             (long)asize);
        if (parse_attribute(path, h, name, type, f + pos, (size_t)asize, e)) return -1;
        pos += (size_t)asize;
    }
    h->header_end = pos + 1;
    if ((h->have & 31) != 31)
        return rerror_at(e, path, 0, "EXR: header lacks a required attribute (channels, compression, dataWindow, "
                                     "displayWindow, lineOrder)");
    if (h->compression > EXR_PIZ)
        return rerror_at(e, path, 0, "EXR: compression %s (%d) is not supported (NONE, RLE, ZIPS, ZIP, PIZ are)",
                         compression_name(h->compression), h->compression);
    return 0;
}

/* R, G, B (+A) or Y (+A): sets each channel's target and returns the output channel count. */
static int choose_channels(const char *path, exr_header *h, rerror *e)
{
    int i, r = -1, g = -1, b = -1, y = -1, a = -1;
    for (i = 0; i < h->nch; ++i) {
        const char *n = h->ch[i].name;
        if (!strcmp(n, "R")) r = i;
        else if (!strcmp(n, "G")) g = i;
        else if (!strcmp(n, "B")) b = i;
        else if (!strcmp(n, "Y")) y = i;
        else if (!strcmp(n, "A")) a = i;
    }
    if (r >= 0 && g >= 0 && b >= 0) {
        h->ch[r].target = 0;
        h->ch[g].target = 1;
        h->ch[b].target = 2;
        if (a >= 0) h->ch[a].target = 3;
        return a >= 0 ? 4 : 3;
    }
    if (y >= 0) {
        h->ch[y].target = 0;
        if (a >= 0) h->ch[a].target = 1;
        return a >= 0 ? 2 : 1;
    }
    return rerror_at(e, path, 0, "EXR: no R, G, B or Y channel (first channel: '%s')", h->ch[0].name);
}

/* ---- ZIP / RLE post-processing ---- */

/* Undoes the predictor (b[i] = b[i-1] + d[i] - 128) and the even/odd byte split. */
static void unpredict_deinterleave(unsigned char *t, size_t n, unsigned char *out)
{
    size_t i, half = (n + 1) / 2;
    for (i = 1; i < n; ++i) t[i] = (unsigned char)(t[i - 1] + t[i] - 128);
    for (i = 0; i < n / 2; ++i) {
        out[2 * i] = t[i];
        out[2 * i + 1] = t[half + i];
    }
    if (n % 2) out[n - 1] = t[n / 2];
}

static void interleave_predict(const unsigned char *in, size_t n, unsigned char *t)
{
    size_t i, half = (n + 1) / 2;
    unsigned char prev;
    for (i = 0; i < n; ++i) t[i % 2 ? half + i / 2 : i / 2] = in[i];
    prev = t[0];
    for (i = 1; i < n; ++i) {
        unsigned char cur = t[i];
        t[i] = (unsigned char)(cur - prev + 128);
        prev = cur;
    }
}

static int rle_decode(const unsigned char *in, size_t n, unsigned char *out, size_t want, rerror *e)
{
    size_t i = 0, o = 0;
    while (i < n) {
        int c = (signed char)in[i++];
        if (c < 0) {
            size_t k = (size_t)-c;
            if (k > n - i || k > want - o) return rerror_set(e, "RLE run runs past the end of the chunk");
            memcpy(out + o, in + i, k);
            i += k;
            o += k;
        } else {
            size_t k = (size_t)c + 1;
            if (i >= n || k > want - o) return rerror_set(e, "RLE run runs past the end of the chunk");
            memset(out + o, in[i++], k);
            o += k;
        }
    }
    if (o != want) return rerror_set(e, "RLE data gives %lu bytes, %lu expected", (unsigned long)o,
                                     (unsigned long)want);
    return 0;
}

/* ---- PIZ ---- */

#define HUF_SYMBOLS 65537 /* 16-bit values plus the run-length symbol */
#define HUF_MAX_LEN 58
#define HUF_FAST 12

typedef struct {
    uint8_t len[HUF_SYMBOLS];
    uint32_t fast[1 << HUF_FAST];  /* (symbol << 6) | length; 0: longer code or none */
    uint64_t first[HUF_MAX_LEN + 1]; /* code of the first symbol of each length */
    uint32_t count[HUF_MAX_LEN + 1], offset[HUF_MAX_LEN + 1];
    uint32_t sorted[HUF_SYMBOLS]; /* symbols by length, then by value */
    uint32_t present[HUF_SYMBOLS], npresent; /* the symbols with a code, increasing */
    uint16_t lut[65536]; /* zero beyond lut_used (calloc, then kept so) */
    uint32_t lut_used;
    unsigned char bitmap[8192];
} piz_state;

typedef struct {
    const unsigned char *in;
    size_t nbytes;
    uint64_t pos, nbits; /* bit position (most-significant bit first) and stream length in bits */
    uint64_t buf;        /* the next nb bits from pos, most-significant first (pos + nb is a whole byte) */
    int nb;
} msb_bits;

static void msb_fill(msb_bits *b)
{
    while (b->nb <= 56) {
        uint64_t i = (b->pos + (uint64_t)b->nb) >> 3;
        b->buf |= (uint64_t)(i < b->nbytes ? b->in[i] : 0) << (56 - b->nb); /* zeros past the end */
        b->nb += 8;
    }
}

/* The next n bits (1 <= n <= 32). */
static uint64_t read_msb(msb_bits *b, int n)
{
    uint64_t v;
    if (b->nb < n) msb_fill(b);
    v = b->buf >> (64 - n);
    b->buf <<= n;
    b->nb -= n;
    b->pos += (uint64_t)n;
    return v;
}

/* The packed code-length table: 6-bit lengths, 59..62 = runs of 2..5 zero lengths,
 * 63 + 8 bits = a run of 6..261 zero lengths. */
static int huf_read_lengths(piz_state *s, msb_bits *b, uint32_t lo, uint32_t hi, rerror *e)
{
    uint32_t i = lo;
    s->npresent = 0;
    while (i <= hi) {
        uint32_t l, run = 0;
        if (b->pos + 6 > b->nbits) return rerror_set(e, "PIZ: Huffman table is truncated");
        l = (uint32_t)read_msb(b, 6);
        if (l == 63) {
            if (b->pos + 8 > b->nbits) return rerror_set(e, "PIZ: Huffman table is truncated");
            run = (uint32_t)read_msb(b, 8) + 6;
        } else if (l >= 59) {
            run = l - 59 + 2;
        }
        if (run) {
            if (run > hi + 1 - i) return rerror_set(e, "PIZ: Huffman table zero run is too long");
            i += run;
        } else {
            if (l) s->present[s->npresent++] = i;
            s->len[i++] = (uint8_t)l;
        }
    }
    return 0;
}

/* OpenEXR's canonical code: longer codes take the numerically smaller values; within a
 * length, codes increase with the symbol. Builds the counts, first codes and fast table. */
static int huf_build(piz_state *s, rerror *e)
{
    uint64_t c = 0;
    uint32_t i, l, next[HUF_MAX_LEN + 1];
    memset(s->count, 0, sizeof s->count);
    memset(s->fast, 0, sizeof s->fast);
    /* only the symbols with a code: a table may span all 65537 symbols with few codes */
    for (i = 0; i < s->npresent; ++i) s->count[s->len[s->present[i]]]++;
    for (l = HUF_MAX_LEN; l > 0; --l) {
        uint64_t nc = (c + s->count[l]) >> 1;
        s->first[l] = c;
        c = nc;
    }
    s->offset[1] = 0;
    for (l = 1; l < HUF_MAX_LEN; ++l) s->offset[l + 1] = s->offset[l] + s->count[l];
    for (l = 1; l <= HUF_MAX_LEN; ++l) {
        next[l] = s->offset[l];
        if (s->count[l] && (s->first[l] + s->count[l] - 1) >> l)
            return rerror_set(e, "PIZ: Huffman code lengths are over-subscribed");
    }
    for (i = 0; i < s->npresent; ++i) {
        uint32_t sym = s->present[i], len = s->len[sym];
        uint64_t code, k, lo, hi;
        code = s->first[len] + (next[len] - s->offset[len]);
        s->sorted[next[len]++] = sym;
        if (len > HUF_FAST) continue;
        lo = code << (HUF_FAST - len);
        hi = (code + 1) << (HUF_FAST - len);
        for (k = lo; k < hi; ++k) s->fast[k] = sym << 6 | len;
    }
    return 0;
}

/* One symbol; -1 if the bits are no code. */
static long huf_symbol(const piz_state *s, msb_bits *b)
{
    uint64_t v;
    uint32_t entry;
    int l;
    if (b->nb < HUF_FAST) msb_fill(b);
    v = b->buf >> (64 - HUF_FAST);
    entry = s->fast[v];
    if (entry) {
        int len = (int)(entry & 63);
        b->buf <<= len;
        b->nb -= len;
        b->pos += (uint64_t)len;
        return (long)(entry >> 6);
    }
    /* longer codes: extend the 12 bits one at a time (on a copy, kept if a code matches) */
    {
        msb_bits t = *b;
        read_msb(&t, HUF_FAST);
        for (l = HUF_FAST + 1; l <= HUF_MAX_LEN; ++l) {
            v = v << 1 | read_msb(&t, 1);
            if (s->count[l] && v >= s->first[l] && v - s->first[l] < s->count[l]) {
                *b = t;
                return (long)s->sorted[s->offset[l] + (v - s->first[l])];
            }
        }
    }
    return -1;
}

/* Huffman-coded 16-bit values (header: min and max symbol, table length, bit count,
 * reserved; then the packed table, then the codes). The largest symbol present is the
 * run-length code: it is followed by 8 bits, the number of extra copies of the last value. */
static int huf_decode(piz_state *s, const unsigned char *in, size_t n, uint16_t *out, size_t nout, rerror *e)
{
    msb_bits b;
    uint32_t lo, hi;
    uint64_t nbits;
    size_t o = 0;
    if (n < 20) return nout == 0 ? 0 : rerror_set(e, "PIZ: Huffman data is truncated");
    lo = le32(in);
    hi = le32(in + 4);
    nbits = le32(in + 12);
    if (lo >= HUF_SYMBOLS || hi >= HUF_SYMBOLS || lo > hi) return rerror_set(e, "PIZ: Huffman table range is invalid");
    memset(&b, 0, sizeof b);
    b.in = in + 20;
    b.nbytes = n - 20;
    b.nbits = (uint64_t)b.nbytes * 8;
    if (huf_read_lengths(s, &b, lo, hi, e) || huf_build(s, e)) return -1;
    /* the codes start at the next byte */
    b.in += (b.pos + 7) / 8;
    b.nbytes -= (size_t)((b.pos + 7) / 8);
    b.pos = 0;
    b.buf = 0;
    b.nb = 0;
    if (nbits > (uint64_t)b.nbytes * 8) return rerror_set(e, "PIZ: Huffman bit count exceeds the data");
    b.nbits = nbits;
    while (o < nout) {
        long sym = huf_symbol(s, &b);
        if (sym < 0 || b.pos > b.nbits) return rerror_set(e, "PIZ: invalid or truncated Huffman code");
        if ((uint32_t)sym == hi) {
            size_t run;
            if (b.pos + 8 > b.nbits) return rerror_set(e, "PIZ: Huffman data is truncated");
            run = (size_t)read_msb(&b, 8);
            if (o == 0 || run > nout - o) return rerror_set(e, "PIZ: run-length code out of place");
            while (run--) {
                out[o] = out[o - 1];
                o++;
            }
        } else {
            out[o++] = (uint16_t)sym;
        }
    }
    return 0;
}

/* Inverse of the wavelet's two basis functions (OpenEXR ImfWav): the 14-bit version
 * (plain differences and means; used when all LUT indices are below 2^14) and the 16-bit
 * one (modular arithmetic). (l, h) -> (a, b). */
static inline int as_int16(uint16_t v) { return v < 0x8000 ? (int)v : (int)v - 0x10000; }

static inline void wdec14(uint16_t l, uint16_t h, uint16_t *a, uint16_t *b)
{
    int hs = as_int16(h);
    int floor_half = hs >= 0 ? hs / 2 : -((1 - hs) / 2); /* floor(hs / 2) without shifting a negative */
    int ai = as_int16(l) + (h & 1) + floor_half;
    *a = (uint16_t)ai; /* conversion to unsigned: modulo 2^16, as the 16-bit original wraps */
    *b = (uint16_t)(ai - hs);
}

static inline void wdec16(uint16_t l, uint16_t h, uint16_t *a, uint16_t *b)
{
    uint16_t bb = (uint16_t)((int)l - (h >> 1));
    *b = bb;
    *a = (uint16_t)((int)h + bb - 0x8000);
}

static inline void wdec(int w14, uint16_t l, uint16_t h, uint16_t *a, uint16_t *b)
{
    if (w14) wdec14(l, h, a, b);
    else wdec16(l, h, a, b);
}

/* 2D inverse wavelet of an nx x ny array with element stride ox and row stride oy,
 * from the coarsest level (largest power of two <= min(nx, ny)) to the finest. */
static void wav2_decode(uint16_t *in, int nx, int ox, int ny, int oy, uint16_t maxval)
{
    int w14 = maxval < (1 << 14), n = nx < ny ? nx : ny, p = 1, p2;
    while (p <= n) p <<= 1;
    p >>= 1;
    p2 = p;
    p >>= 1;
    for (; p >= 1; p2 = p, p >>= 1) {
        int x, y;
        /* pairs at distance p inside blocks of 2p x 2p; odd column and odd row at the edges */
        for (y = 0; y + p2 <= ny; y += p2) {
            uint16_t *row = in + (size_t)y * oy;
            for (x = 0; x + p2 <= nx; x += p2) {
                uint16_t *p00 = row + (size_t)x * ox, *p01 = p00 + (size_t)p * ox, *p10 = p00 + (size_t)p * oy,
                         *p11 = p10 + (size_t)p * ox, i00, i01, i10, i11;
                wdec(w14, *p00, *p10, &i00, &i10);
                wdec(w14, *p01, *p11, &i01, &i11);
                wdec(w14, i00, i01, p00, p01);
                wdec(w14, i10, i11, p10, p11);
            }
            if (nx & p) {
                uint16_t *p00 = row + (size_t)x * ox, *p10 = p00 + (size_t)p * oy, i00;
                wdec(w14, *p00, *p10, &i00, p10);
                *p00 = i00;
            }
        }
        if (ny & p) {
            uint16_t *row = in + (size_t)y * oy;
            for (x = 0; x + p2 <= nx; x += p2) {
                uint16_t *p00 = row + (size_t)x * ox, *p01 = p00 + (size_t)p * ox, i00;
                wdec(w14, *p00, *p01, &i00, p01);
                *p00 = i00;
            }
        }
    }
}

/* PIZ chunk -> unpacked bytes (lines x channels x width, little-endian 16-bit words). */
static int piz_decode(piz_state *s, const exr_header *h, int width, int lines, const unsigned char *in, size_t n,
                      unsigned char *out, size_t want, uint16_t *tmp, rerror *e)
{
    size_t pos = 4, nwords = want / 2, k, start;
    uint32_t lo, hi, i, count = 0, hlen;
    uint16_t maxval;
    int c, y;
    if (n < 4) return rerror_set(e, "PIZ: chunk is truncated");
    lo = in[0] | (uint32_t)in[1] << 8;
    hi = in[2] | (uint32_t)in[3] << 8;
    if (hi >= 8192) return rerror_set(e, "PIZ: bitmap range %lu..%lu is invalid", (unsigned long)lo,
                                      (unsigned long)hi);
    memset(s->bitmap, 0, sizeof s->bitmap);
    if (lo <= hi) {
        if (n - pos < hi - lo + 1) return rerror_set(e, "PIZ: chunk is truncated");
        memcpy(s->bitmap + lo, in + pos, hi - lo + 1);
        pos += hi - lo + 1;
    }
    /* reverse LUT: index -> value, for 0 and every value whose bit is set; indices
     * past the last value map to 0 (only the entries the last chunk set need clearing) */
    s->lut[count++] = 0;
    for (i = lo <= hi ? 8 * lo : 1; lo <= hi && i < 8 * (hi + 1); ++i) {
        if (!s->bitmap[i >> 3]) {
            i |= 7; /* a zero byte: none of its 8 values occurs */
            continue;
        }
        if (i != 0 && s->bitmap[i >> 3] >> (i & 7) & 1) s->lut[count++] = (uint16_t)i;
    }
    maxval = (uint16_t)(count - 1);
    for (i = count; i < s->lut_used; ++i) s->lut[i] = 0;
    s->lut_used = count;
    if (n - pos < 4) return rerror_set(e, "PIZ: chunk is truncated");
    hlen = le32(in + pos);
    pos += 4;
    if (hlen > n - pos) return rerror_set(e, "PIZ: Huffman data runs past the chunk");
    if (huf_decode(s, in + pos, hlen, tmp, nwords, e)) return -1;
    /* the words are stored channel by channel (each lines x width x words-per-value) */
    start = 0;
    for (c = 0; c < h->nch; ++c) {
        int words = h->ch[c].size / 2, j;
        for (j = 0; j < words; ++j) wav2_decode(tmp + start + j, width, words, lines, width * words, maxval);
        start += (size_t)width * lines * words;
    }
    for (k = 0; k < nwords; ++k) tmp[k] = s->lut[tmp[k]];
    /* back to line-interleaved little-endian bytes */
    k = 0;
    for (y = 0; y < lines; ++y) {
        start = 0;
        for (c = 0; c < h->nch; ++c) {
            size_t words = (size_t)width * (h->ch[c].size / 2), w;
            const uint16_t *src = tmp + start + (size_t)y * words;
            for (w = 0; w < words; ++w, k += 2) {
                out[k] = (unsigned char)(src[w] & 0xff);
                out[k + 1] = (unsigned char)(src[w] >> 8);
            }
            start += words * (size_t)lines;
        }
    }
    return 0;
}

/* ---- reading ---- */

typedef struct {
    const char *path;
    exr_header h;
    int width, lpc;       /* data window width, lines per chunk */
    size_t line_bytes;    /* unpacked bytes of one line */
    unsigned char *unpacked, *scratch;
    uint16_t *words;
    piz_state *piz;
} exr_reader;

static int lines_per_chunk(int compression)
{
    return compression == EXR_ZIP ? 16 : compression == EXR_PIZ ? 32 : 1;
}

/* Unpacked bytes of a line -> floats of the output pixels it covers. */
static void convert_line(const exr_reader *r, const unsigned char *line, int32_t y, fimage *out)
{
    const exr_header *h = &r->h;
    int c, x, x0, x1, nc = out->channels;
    int64_t shift = (int64_t)h->data[0] - h->display[0]; /* output x = data x + shift */
    size_t at = 0;
    float *row;
    if (y < h->display[1] || y > h->display[3]) return;
    row = out->px + (size_t)((int64_t)y - h->display[1]) * out->width * nc;
    /* the data x range that lands inside the display window */
    x0 = shift < 0 ? (int)-shift : 0;
    x1 = (int64_t)r->width + shift > out->width ? (int)(out->width - shift) : r->width;
    if (x1 <= x0) return; /* no column inside */
    for (c = 0; c < h->nch; ++c) {
        const exr_channel *ch = &h->ch[c];
        const unsigned char *v = line + at + (size_t)x0 * ch->size;
        float *o = row + (size_t)(x0 + shift) * nc + ch->target;
        at += (size_t)r->width * ch->size;
        if (ch->target < 0) continue;
        for (x = x0; x < x1; ++x, v += ch->size, o += nc) {
            if (ch->type == EXR_HALF) {
                *o = half_table[v[0] | v[1] << 8];
            } else if (ch->type == EXR_FLOAT) {
                uint32_t bits = le32(v);
                memcpy(o, &bits, sizeof bits);
            } else {
                *o = (float)le32(v);
            }
        }
    }
}

static int read_chunk(exr_reader *r, const unsigned char *f, size_t size, int index, fimage *out, rerror *e)
{
    const exr_header *h = &r->h;
    uint64_t offset = le64(f + h->header_end + 8 * (size_t)index);
    int32_t y, want_y = (int32_t)(h->data[1] + (int64_t)index * r->lpc);
    int lines = (int)((int64_t)h->data[3] - want_y + 1 < r->lpc ? (int64_t)h->data[3] - want_y + 1 : r->lpc), i;
    size_t packed, unpacked = (size_t)lines * r->line_bytes;
    const unsigned char *data;
    const unsigned char *result = r->unpacked;
    rerror sub;
    if (offset < h->header_end || offset > size || size - offset < 8)
        return rerror_at(e, r->path, 0, "EXR: chunk %d offset %llu lies outside the file", index,
                         (unsigned long long)offset);
    y = le32s(f + offset);
    packed = le32(f + offset + 4);
    data = f + offset + 8;
    if (y != want_y)
        return rerror_at(e, r->path, 0, "EXR: chunk %d starts at line %ld, %ld expected (corrupt offset table)", index,
                         (long)y, (long)want_y);
    if (packed > size - offset - 8 || packed > 0x7fffffffu)
        return rerror_at(e, r->path, 0, "EXR: chunk %d of %lu bytes runs past the end of the file", index,
                         (unsigned long)packed);
    if (packed > unpacked || (h->compression == EXR_NONE && packed != unpacked))
        return rerror_at(e, r->path, 0, "EXR: chunk %d has %lu bytes, %lu expected", index, (unsigned long)packed,
                         (unsigned long)unpacked);
    if (packed == unpacked) {
        result = data; /* stored raw */
    } else if (h->compression == EXR_ZIP || h->compression == EXR_ZIPS || h->compression == EXR_RLE) {
        size_t got = unpacked;
        int bad = h->compression == EXR_RLE ? rle_decode(data, packed, r->scratch, unpacked, &sub)
                                            : inflate_zlib(data, packed, r->scratch, unpacked, &got, &sub);
        if (!bad && got != unpacked) bad = rerror_set(&sub, "zlib data gives %lu bytes, %lu expected",
                                                      (unsigned long)got, (unsigned long)unpacked);
        if (bad) return rerror_at(e, r->path, 0, "EXR: chunk %d (%s): %s", index, compression_name(h->compression),
                                  sub.msg);
        unpredict_deinterleave(r->scratch, unpacked, r->unpacked);
    } else {
        if (piz_decode(r->piz, h, r->width, lines, data, packed, r->unpacked, unpacked, r->words, &sub))
            return rerror_at(e, r->path, 0, "EXR: chunk %d (PIZ): %s", index, sub.msg);
    }
    for (i = 0; i < lines; ++i) convert_line(r, result + (size_t)i * r->line_bytes, y + i, out);
    return 0;
}

/* Pixels of the display window that the data window does not cover. */
static double uncovered_pixels(const exr_header *h)
{
    double w = (double)h->display[2] - h->display[0] + 1, ht = (double)h->display[3] - h->display[1] + 1;
    int64_t x0 = h->data[0] > h->display[0] ? h->data[0] : h->display[0];
    int64_t x1 = h->data[2] < h->display[2] ? h->data[2] : h->display[2];
    int64_t y0 = h->data[1] > h->display[1] ? h->data[1] : h->display[1];
    int64_t y1 = h->data[3] < h->display[3] ? h->data[3] : h->display[3];
    double covered = x1 < x0 || y1 < y0 ? 0.0 : (double)(x1 - x0 + 1) * (double)(y1 - y0 + 1);
    return w * ht - covered;
}

/* The limits that depend on the file size, the display window and the caller's bound
 * (max_bytes, 0 = none), all checked before any image buffer is allocated. */
static int check_sizes(const exr_reader *r, size_t size, int64_t height, int channels, size_t max_bytes, rerror *e)
{
    const exr_header *h = &r->h;
    double decoded = (double)r->line_bytes * height, uncovered = uncovered_pixels(h);
    double shown = ((double)h->display[2] - h->display[0] + 1) * ((double)h->display[3] - h->display[1] + 1);
    if (decoded > (double)size * EXR_MAX_RATIO + 65536)
        return rerror_at(e, r->path, 0, "EXR: %d x %.0f pixels cannot come from a file of %lu bytes (corrupt header)",
                         r->width, (double)height, (unsigned long)size);
    if (uncovered > EXR_MAX_PADDING && uncovered > (double)size * EXR_PADDING_PER_BYTE)
        return rerror_at(e, r->path, 0,
                         "EXR: displayWindow leaves %.0f pixels outside the dataWindow, more than 2^24 or 1024 per "
                         "byte of a file of %lu bytes (corrupt header)",
                         uncovered, (unsigned long)size);
    if (max_bytes && (decoded > (double)max_bytes || shown * channels * sizeof(float) > (double)max_bytes))
        return rerror_at(e, r->path, 0, "EXR: image needs more than the %lu bytes allowed", (unsigned long)max_bytes);
    return 0;
}

static int read_image(exr_reader *r, const unsigned char *f, size_t size, size_t max_bytes, fimage *out, rerror *e)
{
    exr_header *h = &r->h;
    int64_t height = (int64_t)h->data[3] - h->data[1] + 1;
    int nchunks, i, channels, c;
    size_t max_chunk;
    r->width = (int)((int64_t)h->data[2] - h->data[0] + 1);
    r->lpc = lines_per_chunk(h->compression);
    nchunks = (int)((height + r->lpc - 1) / r->lpc);
    r->line_bytes = 0;
    for (c = 0; c < h->nch; ++c) r->line_bytes += (size_t)r->width * h->ch[c].size;
    if ((size - h->header_end) / 8 < (size_t)nchunks)
        return rerror_at(e, r->path, 0, "EXR: offset table of %d chunks runs past the end of the file", nchunks);
    if ((channels = choose_channels(r->path, h, e)) < 0) return -1;
    if (check_sizes(r, size, height, channels, max_bytes, e)) return -1;
    pthread_once(&half_table_once, half_table_build);
    max_chunk = r->line_bytes * (size_t)(height < r->lpc ? height : r->lpc);
    if (!(r->unpacked = rmalloc(max_chunk, 1, e)) || !(r->scratch = rmalloc(max_chunk, 1, e))) return -1;
    if (h->compression == EXR_PIZ &&
        (!(r->words = rmalloc(max_chunk / 2 + 1, sizeof(uint16_t), e)) || !(r->piz = rcalloc(1, sizeof(piz_state), e))))
        return -1;
    if (fimage_alloc(out, h->display[2] - h->display[0] + 1, h->display[3] - h->display[1] + 1, channels, e)) return -1;
    for (i = 0; i < nchunks; ++i) {
        if (read_chunk(r, f, size, i, out, e)) {
            fimage_free(out);
            return -1;
        }
    }
    return 0;
}

int exr_read(const char *path, fimage *out, rerror *e) { return exr_read_bounded(path, 0, out, e); }

int exr_read_bounded(const char *path, size_t max_bytes, fimage *out, rerror *e)
{
    exr_reader r;
    size_t size;
    unsigned char *f;
    int status = -1;
    memset(out, 0, sizeof *out);
    memset(&r, 0, sizeof r);
    r.path = path;
    f = image_file_load(path, EXR_MAX_FILE, &size, e);
    if (!f) return -1;
    if (!parse_header(path, f, size, &r.h, e)) status = read_image(&r, f, size, max_bytes, out, e);
    free(r.unpacked);
    free(r.scratch);
    free(r.words);
    free(r.piz);
    free(f);
    return status;
}

/* ---- writing ---- */

static void put_attr(FILE *fp, const char *name, const char *type, const unsigned char *v, uint32_t n)
{
    unsigned char size[4];
    put32(size, n);
    fwrite(name, 1, strlen(name) + 1, fp);
    fwrite(type, 1, strlen(type) + 1, fp);
    fwrite(size, 1, 4, fp);
    fwrite(v, 1, n, fp);
}

static void write_header(FILE *fp, int width, int height, int compression, int pixel_type)
{
    static const unsigned char magic[8] = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
    unsigned char ch[3 * 18 + 1], box[16], one[4], center[8], byte;
    const char *names = "BGR";
    int i;
    float f1 = 1.0f;
    uint32_t bits;
    fwrite(magic, 1, 8, fp);
    memset(ch, 0, sizeof ch);
    for (i = 0; i < 3; ++i) {
        unsigned char *c = ch + 18 * i;
        c[0] = (unsigned char)names[i]; /* name, NUL */
        put32(c + 2, (uint32_t)pixel_type);
        /* pLinear 0 and 3 reserved bytes */
        put32(c + 10, 1); /* xSampling */
        put32(c + 14, 1); /* ySampling */
    }
    put_attr(fp, "channels", "chlist", ch, sizeof ch);
    byte = (unsigned char)compression;
    put_attr(fp, "compression", "compression", &byte, 1);
    put32(box, 0);
    put32(box + 4, 0);
    put32(box + 8, (uint32_t)(width - 1));
    put32(box + 12, (uint32_t)(height - 1));
    put_attr(fp, "dataWindow", "box2i", box, 16);
    put_attr(fp, "displayWindow", "box2i", box, 16);
    byte = 0; /* INCREASING_Y */
    put_attr(fp, "lineOrder", "lineOrder", &byte, 1);
    memcpy(&bits, &f1, 4);
    put32(one, bits);
    put_attr(fp, "pixelAspectRatio", "float", one, 4);
    memset(center, 0, sizeof center);
    put_attr(fp, "screenWindowCenter", "v2f", center, 8);
    put_attr(fp, "screenWindowWidth", "float", one, 4);
    fputc(0, fp);
}

/* Lines y0 .. y0+lines-1 as unpacked bytes: per line B, G, R, each `width` values. */
static void pack_lines(const image *img, int y0, int lines, int pixel_type, unsigned char *out)
{
    int y, c, x;
    for (y = y0; y < y0 + lines; ++y)
        for (c = 2; c >= 0; --c)
            for (x = 0; x < img->width; ++x) {
                float v = image_pixel(img, x, y)[c];
                if (pixel_type == EXR_HALF) {
                    uint16_t hv = float_to_half(v);
                    *out++ = (unsigned char)(hv & 0xff);
                    *out++ = (unsigned char)(hv >> 8);
                } else {
                    uint32_t bits;
                    memcpy(&bits, &v, 4);
                    put32(out, bits);
                    out += 4;
                }
            }
}

int exr_write(const char *path, const image *img, int compression, int pixel_type, rerror *e)
{
    atomic_file af;
    int lpc = compression == EXR_ZIP ? 16 : 1, nchunks, i, ok = 1;
    size_t line_bytes, chunk_max;
    unsigned char *raw = NULL, *tmp = NULL, *z = NULL, *table = NULL;
    long table_at;
    if (img->width <= 0 || img->height <= 0 || !img->px) return rerror_at(e, path, 0, "cannot write an empty image");
    if (compression != EXR_NONE && compression != EXR_ZIP)
        return rerror_at(e, path, 0, "EXR: writing supports NONE and ZIP compression only");
    if (pixel_type != EXR_HALF && pixel_type != EXR_FLOAT)
        return rerror_at(e, path, 0, "EXR: writing supports HALF and FLOAT channels only");
    line_bytes = (size_t)img->width * 3 * (pixel_type == EXR_HALF ? 2 : 4);
    nchunks = (img->height + lpc - 1) / lpc;
    chunk_max = line_bytes * (size_t)lpc;
    if (!(raw = rmalloc(chunk_max, 1, e)) || !(tmp = rmalloc(chunk_max, 1, e)) ||
        !(z = rmalloc(deflate_zlib_bound(chunk_max), 1, e)) || !(table = rcalloc((size_t)nchunks, 8, e)))
        goto fail_alloc;
    if (atomic_file_open(&af, path, e)) goto fail_alloc;
    write_header(af.fp, img->width, img->height, compression, pixel_type);
    table_at = ftell(af.fp);
    fwrite(table, 8, (size_t)nchunks, af.fp);
    for (i = 0; i < nchunks && ok; ++i) {
        int y0 = i * lpc, lines = img->height - y0 < lpc ? img->height - y0 : lpc;
        size_t n = (size_t)lines * line_bytes, packed = n;
        const unsigned char *data = raw;
        unsigned char head[8];
        long at = ftell(af.fp);
        pack_lines(img, y0, lines, pixel_type, raw);
        if (compression == EXR_ZIP) {
            size_t zn;
            interleave_predict(raw, n, tmp);
            zn = deflate_zlib(tmp, n, z);
            if (zn == 0) ok = 0;
            if (zn > 0 && zn < n) {
                data = z; /* otherwise stored raw, as OpenEXR does */
                packed = zn;
            }
        }
        put32(table + 8 * i, (uint32_t)((uint64_t)at & 0xffffffffu));
        put32(table + 8 * i + 4, (uint32_t)((uint64_t)at >> 32));
        put32(head, (uint32_t)y0);
        put32(head + 4, (uint32_t)packed);
        if (at < 0 || fwrite(head, 1, 8, af.fp) != 8 || fwrite(data, 1, packed, af.fp) != packed) ok = 0;
    }
    if (ok && (fseek(af.fp, table_at, SEEK_SET) || fwrite(table, 8, (size_t)nchunks, af.fp) != (size_t)nchunks)) ok = 0;
    free(raw);
    free(tmp);
    free(z);
    free(table);
    if (!ok || ferror(af.fp)) {
        int err = errno;
        atomic_file_abort(&af);
        return rerror_at(e, path, 0, "write failed: %s", strerror(err));
    }
    return atomic_file_commit(&af, e);
fail_alloc:
    free(raw);
    free(tmp);
    free(z);
    free(table);
    return -1;
}
