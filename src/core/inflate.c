/* DEFLATE decoder and fixed-Huffman encoder (RFC 1951), zlib wrapper (RFC 1950).
 *
 * Decoding: canonical Huffman codes (RFC 1951 §3.2.2) are decoded with a 10-bit lookup
 * table for the short codes and a bit-by-bit walk over the per-length counts for the
 * longer ones. Bits are taken least-significant first from a 64-bit buffer. Reading
 * past the end of the input feeds zero bytes, counted, so the hot loop needs no bounds
 * test per bit: once a symbol has consumed one of those zero bits the stream is
 * reported as truncated. Output goes only into the caller's buffer, bounded by out_cap. */
#include "restir/core/inflate.h"

#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/checksum.h"

#define MAX_BITS 15
#define FAST_BITS 10
#define MAX_LITLEN 288
#define MAX_DIST 32

/* RFC 1951 §3.2.5: length codes 257..285 and distance codes 0..29 (base, extra bits). */
static const uint16_t length_base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                         31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const uint8_t length_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                         2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const uint16_t dist_base[30] = {1,    2,    3,    4,    5,    7,     9,     13,    17,  25,
                                       33,   49,   65,   97,   129,  193,   257,   385,   513, 769,
                                       1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
static const uint8_t dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6,
                                       6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

typedef struct {
    uint16_t fast[1 << FAST_BITS]; /* (symbol << 4) | code length; 0: longer code or unused */
    uint16_t count[MAX_BITS + 1];  /* codes of each length */
    uint16_t symbol[MAX_LITLEN];   /* symbols in canonical code order */
} huffman;

typedef struct {
    const unsigned char *in;
    size_t size, pos;
    uint64_t bits;
    unsigned nbits;
    size_t fake; /* zero bytes fed after the end of the input */
} bitin;

static void refill(bitin *b)
{
    while (b->nbits <= 56) {
        uint64_t byte = 0;
        if (b->pos < b->size) byte = b->in[b->pos++];
        else b->fake++;
        b->bits |= byte << b->nbits;
        b->nbits += 8;
    }
}

static unsigned getbits(bitin *b, unsigned n)
{
    unsigned v;
    if (b->nbits < n) refill(b);
    v = (unsigned)(b->bits & ((1u << n) - 1));
    b->bits >>= n;
    b->nbits -= n;
    return v;
}

/* Some consumed bit was one of the zero bytes fed past the end. */
static int overrun(const bitin *b) { return b->fake * 8 > b->nbits; }

static unsigned reverse_bits(unsigned code, unsigned len)
{
    unsigned r = 0;
    while (len--) {
        r = r << 1 | (code & 1);
        code >>= 1;
    }
    return r;
}

/* Canonical code from code lengths (RFC 1951 §3.2.2). An over-subscribed set is an
 * error; an incomplete one is accepted (RFC 1951 allows a single distance code) and a
 * stream that uses one of its missing codes fails in decode_symbol. */
static int huffman_build(huffman *h, const uint8_t *lengths, int n, const char *what, rerror *e)
{
    uint16_t offs[MAX_BITS + 2], next[MAX_BITS + 1];
    int s, len, left = 1;
    unsigned code = 0;
    memset(h, 0, sizeof *h);
    for (s = 0; s < n; ++s) h->count[lengths[s]]++;
    h->count[0] = 0;
    for (len = 1; len <= MAX_BITS; ++len) {
        left = (left << 1) - h->count[len];
        if (left < 0) return rerror_set(e, "deflate: %s code is over-subscribed", what);
    }
    offs[1] = 0;
    for (len = 1; len <= MAX_BITS; ++len) offs[len + 1] = (uint16_t)(offs[len] + h->count[len]);
    for (len = 1; len <= MAX_BITS; ++len) {
        code = (code + h->count[len - 1]) << 1;
        next[len] = (uint16_t)code;
    }
    for (s = 0; s < n; ++s) {
        unsigned l = lengths[s], r, step;
        if (!l) continue;
        h->symbol[offs[l]++] = (uint16_t)s;
        if (l > FAST_BITS) {
            next[l]++;
            continue;
        }
        r = reverse_bits(next[l]++, l);
        for (step = 1u << l; r < (1u << FAST_BITS); r += step) h->fast[r] = (uint16_t)(s << 4 | l);
    }
    return 0;
}

/* A code longer than FAST_BITS (or none): walk the lengths, most-significant bit first. */
static int decode_slow(bitin *b, const huffman *h)
{
    int code = 0, first = 0, index = 0;
    unsigned len;
    for (len = 1; len <= MAX_BITS; ++len) {
        int count = h->count[len];
        code |= (int)(b->bits >> (len - 1) & 1);
        if (code - first < count) {
            b->bits >>= len;
            b->nbits -= len;
            return h->symbol[index + code - first];
        }
        index += count;
        first = (first + count) << 1;
        code <<= 1;
    }
    return -1;
}

/* One symbol; -1 if the bits are not a code of h. Needs >= 15 bits buffered. */
static inline int decode_symbol(bitin *b, const huffman *h)
{
    unsigned entry = h->fast[b->bits & ((1u << FAST_BITS) - 1)];
    if (!entry) return decode_slow(b, h);
    b->bits >>= entry & 15;
    b->nbits -= entry & 15;
    return (int)(entry >> 4);
}

typedef struct {
    unsigned char *out;
    size_t cap, pos;
} outbuf;

/* Literal/length and distance symbols until end-of-block (RFC 1951 §3.2.5). */
static int inflate_codes(bitin *b, outbuf *o, const huffman *lit, const huffman *dist, rerror *e)
{
    for (;;) {
        int sym;
        if (b->nbits < 48) refill(b); /* a length with extra bits and a distance with extra bits */
        sym = decode_symbol(b, lit);
        if (overrun(b)) return rerror_set(e, "deflate: the stream is truncated");
        if (sym < 0) return rerror_set(e, "deflate: invalid literal/length code");
        if (sym < 256) {
            if (o->pos >= o->cap) return rerror_set(e, "deflate: more data than the expected %zu bytes", o->cap);
            o->out[o->pos++] = (unsigned char)sym;
        } else if (sym == 256) {
            return 0;
        } else {
            size_t len, d, i;
            int ds;
            sym -= 257;
            if (sym >= 29) return rerror_set(e, "deflate: invalid length symbol %d", sym + 257);
            len = length_base[sym] + getbits(b, length_extra[sym]);
            ds = decode_symbol(b, dist);
            if (ds < 0 || ds >= 30) return rerror_set(e, "deflate: invalid distance code");
            d = dist_base[ds] + getbits(b, dist_extra[ds]);
            if (overrun(b)) return rerror_set(e, "deflate: the stream is truncated");
            if (d > o->pos) return rerror_set(e, "deflate: distance %zu reaches before the start of the data", d);
            if (len > o->cap - o->pos)
                return rerror_set(e, "deflate: more data than the expected %zu bytes", o->cap);
            if (d >= len) {
                memcpy(o->out + o->pos, o->out + o->pos - d, len);
            } else {
                for (i = 0; i < len; ++i) o->out[o->pos + i] = o->out[o->pos + i - d]; /* overlapping run */
            }
            o->pos += len;
        }
    }
}

/* Input bytes consumed so far (the partially used byte counts); -1 if past the end. */
static long long consumed_bytes(const bitin *b)
{
    size_t buffered = b->nbits / 8;
    if (b->fake > buffered) return -1;
    return (long long)(b->pos - (buffered - b->fake));
}

/* Stored block (BTYPE 00): byte-aligned LEN, NLEN = ~LEN, then LEN raw bytes. */
static int inflate_stored(bitin *b, outbuf *o, rerror *e)
{
    long long at;
    unsigned len, nlen;
    b->bits >>= b->nbits % 8;
    b->nbits -= b->nbits % 8;
    at = consumed_bytes(b);
    if (at < 0 || b->size - (size_t)at < 4) return rerror_set(e, "deflate: the stream is truncated");
    b->pos = (size_t)at;
    b->bits = 0;
    b->nbits = 0;
    b->fake = 0;
    len = b->in[b->pos] | (unsigned)b->in[b->pos + 1] << 8;
    nlen = b->in[b->pos + 2] | (unsigned)b->in[b->pos + 3] << 8;
    b->pos += 4;
    if (len != (~nlen & 0xffffu)) return rerror_set(e, "deflate: stored block length check fails");
    if (b->size - b->pos < len) return rerror_set(e, "deflate: the stream is truncated");
    if (len > o->cap - o->pos) return rerror_set(e, "deflate: more data than the expected %zu bytes", o->cap);
    memcpy(o->out + o->pos, b->in + b->pos, len);
    o->pos += len;
    b->pos += len;
    return 0;
}

/* Fixed code (BTYPE 01, RFC 1951 §3.2.6): built once (a stream of many small fixed
 * blocks would otherwise rebuild both tables for each). */
static huffman fixed_lit, fixed_dist;
static pthread_once_t fixed_once = PTHREAD_ONCE_INIT;

static void fixed_codes(void)
{
    huffman *lit = &fixed_lit, *dist = &fixed_dist;
    uint8_t l[MAX_LITLEN];
    int i;
    for (i = 0; i < 144; ++i) l[i] = 8;
    for (; i < 256; ++i) l[i] = 9;
    for (; i < 280; ++i) l[i] = 7;
    for (; i < 288; ++i) l[i] = 8;
    huffman_build(lit, l, 288, "literal/length", NULL);
    for (i = 0; i < 30; ++i) l[i] = 5;
    huffman_build(dist, l, 30, "distance", NULL);
}

/* Dynamic code (BTYPE 10, RFC 1951 §3.2.7): code-length code, then the two codes' lengths. */
static int dynamic_codes(bitin *b, huffman *lit, huffman *dist, rerror *e)
{
    static const uint8_t order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
    uint8_t lengths[MAX_LITLEN + MAX_DIST], cl[19];
    huffman clh;
    int hlit, hdist, hclen, i, n;
    refill(b);
    hlit = (int)getbits(b, 5) + 257;
    hdist = (int)getbits(b, 5) + 1;
    hclen = (int)getbits(b, 4) + 4;
    if (hlit > 286 || hdist > 30) return rerror_set(e, "deflate: %d length or %d distance codes", hlit, hdist);
    memset(cl, 0, sizeof cl);
    for (i = 0; i < hclen; ++i) cl[order[i]] = (uint8_t)getbits(b, 3);
    if (huffman_build(&clh, cl, 19, "code-length", e)) return -1;
    n = hlit + hdist;
    for (i = 0; i < n;) {
        int sym, rep;
        uint8_t value = 0;
        if (b->nbits < 32) refill(b);
        sym = decode_symbol(b, &clh);
        if (sym < 0) return rerror_set(e, "deflate: invalid code-length code");
        if (sym < 16) {
            lengths[i++] = (uint8_t)sym;
            continue;
        }
        if (sym == 16) {
            if (i == 0) return rerror_set(e, "deflate: repeat of a code length with none before it");
            value = lengths[i - 1];
            rep = 3 + (int)getbits(b, 2);
        } else if (sym == 17) {
            rep = 3 + (int)getbits(b, 3);
        } else {
            rep = 11 + (int)getbits(b, 7);
        }
        if (i + rep > n) return rerror_set(e, "deflate: code lengths run past the %d expected", n);
        while (rep--) lengths[i++] = value;
    }
    if (overrun(b)) return rerror_set(e, "deflate: the stream is truncated");
    if (lengths[256] == 0) return rerror_set(e, "deflate: no end-of-block code");
    if (huffman_build(lit, lengths, hlit, "literal/length", e)) return -1;
    return huffman_build(dist, lengths + hlit, hdist, "distance", e);
}

int inflate_raw(const unsigned char *in, size_t in_size, unsigned char *out, size_t out_cap, size_t *out_size,
                size_t *in_used, rerror *e)
{
    bitin b;
    outbuf o;
    huffman lit, dist;
    int final = 0;
    long long used;
    memset(&b, 0, sizeof b);
    b.in = in;
    b.size = in_size;
    o.out = out;
    o.cap = out_cap;
    o.pos = 0;
    *out_size = 0;
    while (!final) {
        unsigned type;
        refill(&b);
        final = (int)getbits(&b, 1);
        type = getbits(&b, 2);
        if (overrun(&b)) return rerror_set(e, "deflate: the stream is truncated");
        if (type == 0) {
            if (inflate_stored(&b, &o, e)) return -1;
        } else if (type == 1) {
            pthread_once(&fixed_once, fixed_codes);
            if (inflate_codes(&b, &o, &fixed_lit, &fixed_dist, e)) return -1;
        } else if (type == 2) {
            if (dynamic_codes(&b, &lit, &dist, e) || inflate_codes(&b, &o, &lit, &dist, e)) return -1;
        } else {
            return rerror_set(e, "deflate: invalid block type 3");
        }
    }
    used = consumed_bytes(&b);
    if (used < 0) return rerror_set(e, "deflate: the stream is truncated");
    *out_size = o.pos;
    if (in_used) *in_used = (size_t)used;
    return 0;
}

int inflate_zlib(const unsigned char *in, size_t in_size, unsigned char *out, size_t out_cap, size_t *out_size,
                 rerror *e)
{
    size_t used = 0;
    uint32_t want;
    const unsigned char *t;
    if (in_size < 2) return rerror_set(e, "zlib: the stream is truncated");
    if ((in[0] & 15) != 8 || in[0] >> 4 > 7)
        return rerror_set(e, "zlib: compression method %d window %d is not deflate", in[0] & 15, in[0] >> 4);
    if (((unsigned)in[0] << 8 | in[1]) % 31 != 0) return rerror_set(e, "zlib: header check fails");
    if (in[1] & 0x20) return rerror_set(e, "zlib: a preset dictionary is not supported");
    if (inflate_raw(in + 2, in_size - 2, out, out_cap, out_size, &used, e)) return -1;
    if (in_size - 2 - used < 4) return rerror_set(e, "zlib: the Adler-32 trailer is missing");
    t = in + 2 + used;
    want = (uint32_t)t[0] << 24 | (uint32_t)t[1] << 16 | (uint32_t)t[2] << 8 | t[3];
    if (adler32_update(1, out, *out_size) != want) return rerror_set(e, "zlib: Adler-32 mismatch (corrupt data)");
    return 0;
}

/* ---- encoder ---- */

#define STORED_MAX 65535u
#define HASH_BITS 15
#define WINDOW 32768

size_t deflate_zlib_bound(size_t n) { return 2 + n + 5 * (n / STORED_MAX + 1) + 4; }

typedef struct {
    unsigned char *p, *limit;
    uint64_t acc;
    unsigned n;
    int full; /* the output reached the limit: give up (stored blocks are smaller) */
} bitout;

static void put_bits(bitout *w, unsigned value, unsigned len)
{
    if (w->full) return;
    w->acc |= (uint64_t)value << w->n;
    w->n += len;
    while (w->n >= 8) {
        if (w->p >= w->limit) {
            w->full = 1;
            return;
        }
        *w->p++ = (unsigned char)(w->acc & 0xff);
        w->acc >>= 8;
        w->n -= 8;
    }
}

/* Fixed literal/length code of RFC 1951 §3.2.6, sent most-significant bit first. */
static void put_litlen(bitout *w, unsigned sym)
{
    if (sym < 144) put_bits(w, reverse_bits(0x30 + sym, 8), 8);
    else if (sym < 256) put_bits(w, reverse_bits(0x190 + sym - 144, 9), 9);
    else if (sym < 280) put_bits(w, reverse_bits(sym - 256, 7), 7);
    else put_bits(w, reverse_bits(0xc0 + sym - 280, 8), 8);
}

static void put_match(bitout *w, unsigned len, unsigned dist)
{
    int s = 28, d = 29;
    while (length_base[s] > len) s--;
    put_litlen(w, 257 + (unsigned)s);
    put_bits(w, len - length_base[s], length_extra[s]);
    while (dist_base[d] > dist) d--;
    put_bits(w, reverse_bits((unsigned)d, 5), 5);
    put_bits(w, dist - dist_base[d], dist_extra[d]);
}

static unsigned hash3(const unsigned char *p)
{
    uint32_t v = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16;
    return (v * 2654435761u) >> (32 - HASH_BITS);
}

/* One fixed-Huffman block with greedy matching; 0 if it would not fit before w->limit. */
static int fixed_block(const unsigned char *in, size_t n, bitout *w, int32_t *head)
{
    size_t i = 0;
    put_bits(w, 1, 1); /* BFINAL */
    put_bits(w, 1, 2); /* BTYPE 01 */
    while (i < n && !w->full) {
        size_t best = 0, dist = 0;
        if (n - i >= 3) {
            unsigned h = hash3(in + i);
            int32_t cand = head[h];
            head[h] = (int32_t)i;
            if (cand >= 0 && i - (size_t)cand <= WINDOW) {
                size_t max = n - i < 258 ? n - i : 258, len = 0;
                const unsigned char *a = in + cand, *b = in + i;
                while (len < max && a[len] == b[len]) len++;
                if (len >= 3) {
                    best = len;
                    dist = i - (size_t)cand;
                }
            }
        }
        if (best) {
            size_t k;
            put_match(w, (unsigned)best, (unsigned)dist);
            for (k = i + 1; k < i + best && n - k >= 3; ++k) head[hash3(in + k)] = (int32_t)k;
            i += best;
        } else {
            put_litlen(w, in[i++]);
        }
    }
    put_litlen(w, 256);
    if (w->n) put_bits(w, 0, 8 - w->n); /* flush the last partial byte */
    return !w->full;
}

static size_t stored_blocks(const unsigned char *in, size_t n, unsigned char *out)
{
    size_t pos = 0, k = 0;
    do {
        size_t len = n - pos < STORED_MAX ? n - pos : STORED_MAX;
        out[k++] = (unsigned char)(pos + len == n ? 1 : 0);
        out[k++] = (unsigned char)(len & 0xff);
        out[k++] = (unsigned char)(len >> 8);
        out[k++] = (unsigned char)(~len & 0xff);
        out[k++] = (unsigned char)(~len >> 8 & 0xff);
        memcpy(out + k, in + pos, len);
        k += len;
        pos += len;
    } while (pos < n);
    return k;
}

size_t deflate_zlib(const unsigned char *in, size_t n, unsigned char *out)
{
    size_t stored_size = 5 * (n / STORED_MAX + 1) + n, k;
    uint32_t adler = adler32_update(1, in, n);
    int32_t *head = malloc(sizeof(int32_t) << HASH_BITS);
    bitout w;
    if (!head) return 0;
    memset(head, 0xff, sizeof(int32_t) << HASH_BITS); /* every entry -1 (two's complement): no match yet */
    out[0] = 0x78; /* CM 8 (deflate), CINFO 7 (32 KB window) */
    out[1] = 0x01; /* no dictionary; 0x7801 is a multiple of 31 */
    memset(&w, 0, sizeof w);
    w.p = out + 2;
    w.limit = out + 2 + stored_size;
    if (n > 0 && fixed_block(in, n, &w, head)) k = (size_t)(w.p - out);
    else k = 2 + stored_blocks(in, n, out + 2);
    free(head);
    out[k++] = (unsigned char)(adler >> 24);
    out[k++] = (unsigned char)(adler >> 16 & 0xff);
    out[k++] = (unsigned char)(adler >> 8 & 0xff);
    out[k++] = (unsigned char)(adler & 0xff);
    return k;
}
