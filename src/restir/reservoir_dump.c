/* Reservoir dump files: byte-exact little-endian encoding (docs/formats.md). */
#include "restir/restir/reservoir_dump.h"
#include "restir/core/atomic_file.h"
#include "restir/core/le_bytes.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* A corrupt header must not make us allocate gigabytes: at most 2^26 records. */
#define RESERVOIR_DUMP_MAX_RECORDS ((uint64_t)1 << 26)

/* ---- the real-valued composites (le_bytes.h has the primitives; real is stored as binary64) ---- */
static void put_vec3(unsigned char **p, vec3 v) { le_put_f64(p, (double)v.x); le_put_f64(p, (double)v.y); le_put_f64(p, (double)v.z); }
static void put_rgb(unsigned char **p, rgb c) { le_put_f64(p, (double)c.r); le_put_f64(p, (double)c.g); le_put_f64(p, (double)c.b); }

static vec3 get_vec3(const unsigned char **p)
{
    vec3 v;
    v.x = (real)le_get_f64(p);
    v.y = (real)le_get_f64(p);
    v.z = (real)le_get_f64(p);
    return v;
}

static rgb get_rgb(const unsigned char **p)
{
    rgb c;
    c.r = (real)le_get_f64(p);
    c.g = (real)le_get_f64(p);
    c.b = (real)le_get_f64(p);
    return c;
}

/* ---- records ---- */
size_t reservoir_record_size(uint32_t flags)
{
    return (flags & RESERVOIR_DUMP_FLAG_PSS) ? RESERVOIR_DUMP_RECORD_PSS : RESERVOIR_DUMP_RECORD_BASE;
}

/* Field order and offsets: docs/formats.md, "Record". */
void reservoir_record_encode(const reservoir *r, uint32_t flags, unsigned char *buf)
{
    const path_sample *s = &r->y;
    unsigned char *p = buf;
    int i;
    le_put_f64(&p, r->wsum);
    le_put_f64(&p, r->W);
    le_put_f64(&p, r->confidence);
    le_put_u32(&p, r->n_invalid);
    le_put_u32(&p, 0);
    le_put_u32(&p, s->seed);
    le_put_u32(&p, s->pixel);
    le_put_u32(&p, s->sample);
    le_put_u8(&p, s->length);
    le_put_u8(&p, s->technique);
    le_put_u8(&p, s->rc_k);
    le_put_u8(&p, s->n_pss);
    for (i = 0; i < PATH_MAX_LENGTH; ++i) le_put_u8(&p, s->lobe[i]);
    le_put_u32(&p, s->rc_triangle);
    le_put_f32(&p, s->rc_bary[0]);
    le_put_f32(&p, s->rc_bary[1]);
    le_put_vec3f(&p, s->rc_position);
    le_put_vec3f(&p, s->rc_normal);
    le_put_u32(&p, s->rc_flags);
    put_vec3(&p, s->rc_wo);
    le_put_f64(&p, s->rc_pdf_prev);
    le_put_f64(&p, s->rc_geom);
    le_put_f64(&p, s->rc_pdf);
    put_rgb(&p, s->rc_radiance);
    le_put_f64(&p, s->light_pdf);
    put_rgb(&p, s->F);
    le_put_f64(&p, s->target);
    if (flags & RESERVOIR_DUMP_FLAG_PSS)
        for (i = 0; i < PATH_MAX_PSS; ++i) le_put_f64(&p, s->pss ? s->pss[i] : 0); /* NULL: zeros (path_sample.h) */
}

void reservoir_record_decode(const unsigned char *buf, uint32_t flags, reservoir *r, real *pss)
{
    path_sample *s = &r->y;
    const unsigned char *p = buf;
    int i;
    path_sample_clear(s);
    r->wsum = (real)le_get_f64(&p);
    r->W = (real)le_get_f64(&p);
    r->confidence = (real)le_get_f64(&p);
    r->n_invalid = le_get_u32(&p);
    (void)le_get_u32(&p);
    s->seed = le_get_u32(&p);
    s->pixel = le_get_u32(&p);
    s->sample = le_get_u32(&p);
    s->length = (uint8_t)le_get_u8(&p);
    s->technique = (uint8_t)le_get_u8(&p);
    s->rc_k = (uint8_t)le_get_u8(&p);
    s->n_pss = (uint8_t)le_get_u8(&p);
    for (i = 0; i < PATH_MAX_LENGTH; ++i) s->lobe[i] = (uint8_t)le_get_u8(&p);
    s->rc_triangle = le_get_u32(&p);
    s->rc_bary[0] = le_get_f32(&p);
    s->rc_bary[1] = le_get_f32(&p);
    s->rc_position = le_get_vec3f(&p);
    s->rc_normal = le_get_vec3f(&p);
    {
        uint32_t flags_word = le_get_u32(&p);
        /* Out-of-range words keep unknown bits, so path_sample_check rejects them. */
        s->rc_flags = (uint8_t)(flags_word > 0xFFu ? 0xFFu : flags_word);
    }
    s->rc_wo = get_vec3(&p);
    s->rc_pdf_prev = (real)le_get_f64(&p);
    s->rc_geom = (real)le_get_f64(&p);
    s->rc_pdf = (real)le_get_f64(&p);
    s->rc_radiance = get_rgb(&p);
    s->light_pdf = (real)le_get_f64(&p);
    s->F = get_rgb(&p);
    s->target = (real)le_get_f64(&p);
    if (flags & RESERVOIR_DUMP_FLAG_PSS) {
        for (i = 0; i < PATH_MAX_PSS; ++i) pss[i] = (real)le_get_f64(&p);
        s->pss = pss;
    }
}

/* ---- header ---- */
static void encode_header(const reservoir_dump_info *info, uint32_t flags, unsigned char *buf)
{
    unsigned char *p = buf;
    size_t n = strlen(info->tag);
    memcpy(p, RESERVOIR_DUMP_MAGIC, 8);
    p += 8;
    le_put_u32(&p, RESERVOIR_DUMP_VERSION);
    le_put_u32(&p, RESERVOIR_DUMP_HEADER_SIZE);
    le_put_u32(&p, (uint32_t)reservoir_record_size(flags));
    le_put_u32(&p, flags);
    le_put_u32(&p, info->width);
    le_put_u32(&p, info->height);
    le_put_u32(&p, info->frame);
    le_put_u32(&p, (uint32_t)(8 * sizeof(real)));
    le_put_u64(&p, (uint64_t)info->width * info->height);
    memset(p, 0, RESERVOIR_DUMP_TAG_SIZE);
    memcpy(p, info->tag, n);
}

/* Parses and checks the header; *count receives the number of records. */
static int decode_header(const char *path, const unsigned char *buf, reservoir_dump_info *info, uint64_t *count,
                         rerror *e)
{
    const unsigned char *p = buf + 8;
    uint32_t version, header_size, record_size;
    int i;
    if (memcmp(buf, RESERVOIR_DUMP_MAGIC, 8) != 0)
        return rerror_at(e, path, 0, "not a reservoir dump (magic is not \"%s\")", RESERVOIR_DUMP_MAGIC);
    version = le_get_u32(&p);
    header_size = le_get_u32(&p);
    record_size = le_get_u32(&p);
    info->flags = le_get_u32(&p);
    info->width = le_get_u32(&p);
    info->height = le_get_u32(&p);
    info->frame = le_get_u32(&p);
    info->real_bits = le_get_u32(&p);
    *count = le_get_u64(&p);
    if (version != RESERVOIR_DUMP_VERSION)
        return rerror_at(e, path, 0, "reservoir dump version %u is not supported (expected %u)", version,
                         RESERVOIR_DUMP_VERSION);
    if (header_size != RESERVOIR_DUMP_HEADER_SIZE)
        return rerror_at(e, path, 0, "header size %u, expected %u", header_size, RESERVOIR_DUMP_HEADER_SIZE);
    if (info->flags & ~RESERVOIR_DUMP_FLAG_PSS) return rerror_at(e, path, 0, "unknown flags 0x%x", info->flags);
    if (record_size != reservoir_record_size(info->flags))
        return rerror_at(e, path, 0, "record size %u does not match the flags (expected %u)", record_size,
                         (unsigned)reservoir_record_size(info->flags));
    if (info->real_bits != 32 && info->real_bits != 64)
        return rerror_at(e, path, 0, "real_bits %u is neither 32 nor 64", info->real_bits);
    if (info->width == 0 || info->height == 0) return rerror_at(e, path, 0, "empty dump (%u x %u)", info->width,
                                                                info->height);
    if (*count != (uint64_t)info->width * info->height)
        return rerror_at(e, path, 0, "record count %llu != width * height = %u * %u", (unsigned long long)*count,
                         info->width, info->height);
    if (*count > RESERVOIR_DUMP_MAX_RECORDS)
        return rerror_at(e, path, 0, "%llu records is more than the supported %llu", (unsigned long long)*count,
                         (unsigned long long)RESERVOIR_DUMP_MAX_RECORDS);
    for (i = 0; i < RESERVOIR_DUMP_TAG_SIZE; ++i) {
        unsigned char c = p[i];
        if (c != 0 && (c < 0x20 || c > 0x7e)) return rerror_at(e, path, 0, "tag is not printable ASCII");
        info->tag[i] = (char)c;
    }
    info->tag[RESERVOIR_DUMP_TAG_SIZE] = '\0';
    return 0;
}

/* ---- writer ---- */
static uint32_t flags_for(const reservoir *rs, size_t count)
{
    size_t i;
    for (i = 0; i < count; ++i)
        if (rs[i].y.n_pss > 0) return RESERVOIR_DUMP_FLAG_PSS;
    return 0;
}

int reservoir_dump_write(const char *path, const reservoir *rs, const reservoir_dump_info *info, rerror *e)
{
    unsigned char header[RESERVOIR_DUMP_HEADER_SIZE], record[RESERVOIR_DUMP_RECORD_PSS];
    size_t count = (size_t)info->width * info->height, i, size;
    uint32_t flags;
    atomic_file f;
    if (info->width == 0 || info->height == 0) return rerror_at(e, path, 0, "cannot write an empty reservoir dump");
    if (!memchr(info->tag, '\0', RESERVOIR_DUMP_TAG_SIZE + 1))
        return rerror_at(e, path, 0, "tag is longer than %d bytes", RESERVOIR_DUMP_TAG_SIZE);
    flags = flags_for(rs, count);
    size = reservoir_record_size(flags);
    encode_header(info, flags, header);
    if (atomic_file_open(&f, path, e)) return -1;
    if (fwrite(header, 1, sizeof header, f.fp) != sizeof header) goto write_failed;
    for (i = 0; i < count; ++i) {
        reservoir_record_encode(&rs[i], flags, record);
        if (fwrite(record, 1, size, f.fp) != size) goto write_failed;
    }
    return atomic_file_commit(&f, e);
write_failed:
    atomic_file_abort(&f);
    return rerror_at(e, path, 0, "write failed: %s", strerror(errno));
}

/* ---- reader ---- */
static int read_records(FILE *fp, const char *path, reservoir *out, uint64_t count, uint32_t flags, rerror *e)
{
    unsigned char record[RESERVOIR_DUMP_RECORD_PSS];
    size_t size = reservoir_record_size(flags);
    uint64_t i;
    char what[4200];
    for (i = 0; i < count; ++i) {
        if (fread(record, 1, size, fp) != size)
            return rerror_at(e, path, 0, "file is short: record %llu of %llu is missing", (unsigned long long)i,
                             (unsigned long long)count);
        reservoir_record_decode(record, flags, &out[i],
                                (flags & RESERVOIR_DUMP_FLAG_PSS) ? reservoir_buffer_pss_row(out, (size_t)count, (size_t)i)
                                                                  : NULL);
        snprintf(what, sizeof what, "%s: record %llu", path, (unsigned long long)i);
        if (path_sample_check(&out[i].y, what, e)) return -1;
        if (!(out[i].wsum >= 0) || !(out[i].W >= 0) || !(out[i].confidence >= 0))
            return rerror_set(e, "%s: wsum, W and confidence must be >= 0 (NaN is invalid)", what);
    }
    if (getc(fp) != EOF) return rerror_at(e, path, 0, "unexpected bytes after the last record");
    return 0;
}

int reservoir_dump_read(const char *path, reservoir **out, reservoir_dump_info *info, rerror *e)
{
    unsigned char header[RESERVOIR_DUMP_HEADER_SIZE];
    uint64_t count = 0;
    struct stat st;
    FILE *fp = fopen(path, "rb");
    *out = NULL;
    if (!fp) return rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
    if (fread(header, 1, sizeof header, fp) != sizeof header) {
        fclose(fp);
        return rerror_at(e, path, 0, "file is shorter than the %u-byte reservoir dump header",
                         RESERVOIR_DUMP_HEADER_SIZE);
    }
    if (decode_header(path, header, info, &count, e)) goto fail;
    /* Check the length before allocating (a corrupt count must not allocate memory). */
    if (fstat(fileno(fp), &st) == 0 && S_ISREG(st.st_mode) &&
        (uint64_t)st.st_size != RESERVOIR_DUMP_HEADER_SIZE + count * reservoir_record_size(info->flags)) {
        rerror_at(e, path, 0, "file has %lld bytes, the header implies %llu", (long long)st.st_size,
                  (unsigned long long)(RESERVOIR_DUMP_HEADER_SIZE + count * reservoir_record_size(info->flags)));
        goto fail;
    }
    *out = reservoir_buffer_alloc((size_t)count, (info->flags & RESERVOIR_DUMP_FLAG_PSS) != 0, e);
    if (!*out) goto fail;
    if (read_records(fp, path, *out, count, info->flags, e)) {
        free(*out);
        *out = NULL;
        goto fail;
    }
    fclose(fp);
    return 0;
fail:
    fclose(fp);
    return -1;
}
