/* Path-tracer checkpoints: the accumulation state in a small, explicit little-endian
 * binary format (docs/path-tracer.md, "Checkpoint format"), written atomically. */
#include "restir/render/pt_checkpoint.h"

#include "restir/render/pt.h"

#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/render/pt_state.h"

#define PT_CHECKPOINT_MAGIC "RESTIRPT"
#define PT_CHECKPOINT_VERSION 1u
#define PT_CHECKPOINT_MAX_SIDE 65536

/* Byte stream with a running FNV-1a 64 checksum. */
typedef struct {
    FILE *fp;
    uint64_t hash;
    int failed;
} stream;

static void stream_bytes(stream *s, unsigned char *b, size_t n, int writing)
{
    size_t i;
    if (s->failed) return;
    if (writing ? fwrite(b, 1, n, s->fp) != n : fread(b, 1, n, s->fp) != n) {
        s->failed = 1;
        return;
    }
    for (i = 0; i < n; ++i) {
        s->hash ^= b[i];
        s->hash *= 1099511628211ull;
    }
}

static void put_u64(stream *s, uint64_t v, int bytes)
{
    unsigned char b[8];
    int i;
    for (i = 0; i < bytes; ++i) b[i] = (unsigned char)(v >> (8 * i));
    stream_bytes(s, b, (size_t)bytes, 1);
}

static uint64_t get_u64(stream *s, int bytes)
{
    unsigned char b[8];
    uint64_t v = 0;
    int i;
    memset(b, 0, sizeof b);
    stream_bytes(s, b, (size_t)bytes, 0);
    for (i = 0; i < bytes; ++i) v |= (uint64_t)b[i] << (8 * i);
    return v;
}

static void put_f64(stream *s, double d)
{
    uint64_t bits;
    memcpy(&bits, &d, sizeof bits);
    put_u64(s, bits, 8);
}

static double get_f64(stream *s)
{
    uint64_t bits = get_u64(s, 8);
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

int pt_checkpoint_write(const char *path, const pt_state *st, rerror *e)
{
    atomic_file f;
    stream s;
    size_t i, n = 3 * (size_t)st->width * (size_t)st->height;
    uint64_t checksum;
    if (ensure_parent_dir(path, e) || atomic_file_open(&f, path, e)) return -1;
    s.fp = f.fp;
    s.hash = 14695981039346656037ull;
    s.failed = 0;
    stream_bytes(&s, (unsigned char *)PT_CHECKPOINT_MAGIC, 8, 1);
    put_u64(&s, PT_CHECKPOINT_VERSION, 4);
    put_u64(&s, (uint64_t)st->width, 4);
    put_u64(&s, (uint64_t)st->height, 4);
    put_u64(&s, st->seed, 4);
    put_u64(&s, st->sample_offset, 4);
    put_u64(&s, st->spp, 4);
    put_u64(&s, st->fingerprint, 8);
    put_u64(&s, st->nonfinite, 8);
    put_u64(&s, st->first_nonfinite_pixel, 4);
    put_u64(&s, st->first_nonfinite_sample, 4);
    for (i = 0; i < n; ++i) put_f64(&s, st->sum[i]);
    for (i = 0; i < n; ++i) put_f64(&s, st->sum_sq[i]);
    checksum = s.hash;
    put_u64(&s, checksum, 8);
    if (s.failed) {
        atomic_file_abort(&f);
        return rerror_set(e, "%s: write failed", path);
    }
    return atomic_file_commit(&f, e);
}

static int read_header(stream *s, const char *path, pt_state *st, rerror *e)
{
    unsigned char magic[8];
    uint64_t version, width, height;
    stream_bytes(s, magic, 8, 0);
    if (s->failed || memcmp(magic, PT_CHECKPOINT_MAGIC, 8) != 0)
        return rerror_set(e, "%s: not a restir path-tracer checkpoint (bad magic)", path);
    version = get_u64(s, 4);
    if (version != PT_CHECKPOINT_VERSION)
        return rerror_set(e, "%s: checkpoint version %llu, expected %u", path, (unsigned long long)version,
                          PT_CHECKPOINT_VERSION);
    width = get_u64(s, 4);
    height = get_u64(s, 4);
    if (s->failed || width < 1 || height < 1 || width > PT_CHECKPOINT_MAX_SIDE || height > PT_CHECKPOINT_MAX_SIDE)
        return rerror_set(e, "%s: bad image size %llux%llu", path, (unsigned long long)width, (unsigned long long)height);
    if (pt_state_alloc(st, (int)width, (int)height, e)) return -1;
    st->seed = (uint32_t)get_u64(s, 4);
    st->sample_offset = (uint32_t)get_u64(s, 4);
    st->spp = (uint32_t)get_u64(s, 4);
    st->fingerprint = get_u64(s, 8);
    st->nonfinite = get_u64(s, 8);
    st->first_nonfinite_pixel = (uint32_t)get_u64(s, 4);
    st->first_nonfinite_sample = (uint32_t)get_u64(s, 4);
    return 0;
}

int pt_checkpoint_read(const char *path, pt_state *st, rerror *e)
{
    stream s;
    size_t i, n;
    uint64_t expected, stored;
    int extra;
    memset(st, 0, sizeof *st);
    s.fp = fopen(path, "rb");
    if (!s.fp) return rerror_set(e, "%s: cannot open checkpoint", path);
    s.hash = 14695981039346656037ull;
    s.failed = 0;
    if (read_header(&s, path, st, e)) {
        fclose(s.fp);
        return -1;
    }
    n = 3 * (size_t)st->width * (size_t)st->height;
    for (i = 0; i < n; ++i) st->sum[i] = get_f64(&s);
    for (i = 0; i < n; ++i) st->sum_sq[i] = get_f64(&s);
    expected = s.hash;
    stored = get_u64(&s, 8);
    extra = fgetc(s.fp);
    fclose(s.fp);
    if (s.failed) {
        pt_state_free(st);
        return rerror_set(e, "%s: truncated checkpoint", path);
    }
    if (stored != expected || extra != EOF) {
        pt_state_free(st);
        return rerror_set(e, "%s: corrupt checkpoint (checksum mismatch or trailing bytes)", path);
    }
    return 0;
}
