/* Binary dump of reservoirs (one per pixel): the exact per-pass intermediate buffers
 * a GPU implementation can be diffed against (docs/formats.md). docs/formats.md gives the
 * layout byte by byte.
 *
 * A file is a 64-byte header followed by width*height fixed-size records, everything
 * little-endian regardless of the host: unsigned integers as such, `float` fields as
 * IEEE binary32, `real` fields always as IEEE binary64 (so float and double builds write
 * the same format). Records are 216 bytes, or 576 with the optional primary-sample
 * vectors (header flag RESERVOIR_DUMP_FLAG_PSS). Writes are atomic; the reader is strict
 * (magic, version, sizes, file length, and path_sample_check on every record). */
#ifndef RESTIR_RESERVOIR_DUMP_H
#define RESTIR_RESERVOIR_DUMP_H

#include <stddef.h>
#include <stdint.h>
#include "restir/restir/reservoir.h"

#define RESERVOIR_DUMP_MAGIC "RSTRRESV" /* 8 bytes, no terminator in the file */
#define RESERVOIR_DUMP_VERSION 1u
#define RESERVOIR_DUMP_HEADER_SIZE 64u
#define RESERVOIR_DUMP_RECORD_BASE 216u
#define RESERVOIR_DUMP_RECORD_PSS (RESERVOIR_DUMP_RECORD_BASE + 8u * PATH_MAX_PSS)
#define RESERVOIR_DUMP_FLAG_PSS 1u /* records carry the PATH_MAX_PSS primary-sample numbers */
#define RESERVOIR_DUMP_TAG_SIZE 16 /* pass name, NUL-padded ASCII */

typedef struct {
    uint32_t width, height; /* records = width * height, row-major, row 0 at the top */
    uint32_t frame;         /* frame index of the pass */
    uint32_t flags;         /* RESERVOIR_DUMP_FLAG_*: set by the writer (ignored on input) */
    uint32_t real_bits;     /* 64 or 32: the writer's sizeof(real) (set by the writer; informational) */
    char tag[RESERVOIR_DUMP_TAG_SIZE + 1]; /* e.g. "initial", "spatial1" */
} reservoir_dump_info;

/* Record size in bytes for the given header flags. */
size_t reservoir_record_size(uint32_t flags);
/* Encodes one record into buf[reservoir_record_size(flags)]. */
void reservoir_record_encode(const reservoir *r, uint32_t flags, unsigned char *buf);
/* Decodes one record (no validation; see path_sample_check). With RESERVOIR_DUMP_FLAG_PSS
 * the PATH_MAX_PSS numbers go to pss (r->y.pss points there); else pss is unused. */
void reservoir_record_decode(const unsigned char *buf, uint32_t flags, reservoir *r, real *pss);

/* Writes info->width * info->height reservoirs to `path` (atomically). The records carry
 * the primary-sample vectors iff some sample has n_pss > 0. A tag without its NUL within
 * the first 17 bytes (longer than 16 characters) is an error. */
int reservoir_dump_write(const char *path, const reservoir *rs, const reservoir_dump_info *info, rerror *e);
/* Reads a dump; *out is malloc'ed (free() it) with info->width * info->height entries; with
 * primary-sample vectors it is a buffer with rows (reservoir_buffer_alloc) holding them. */
int reservoir_dump_read(const char *path, reservoir **out, reservoir_dump_info *info, rerror *e);

#endif
