/* Checksums of the PNG format: CRC-32 (ISO 3309 / ITU-T V.42, the one PNG chunks
 * and zlib's gzip use) and Adler-32 (RFC 1950, the zlib stream trailer). */
#ifndef RESTIR_CHECKSUM_H
#define RESTIR_CHECKSUM_H

#include <stddef.h>
#include <stdint.h>

/* Running CRC-32: start with crc = 0, feed the bytes in any number of pieces. */
uint32_t crc32_update(uint32_t crc, const void *data, size_t size);
/* Running Adler-32: start with adler = 1. */
uint32_t adler32_update(uint32_t adler, const void *data, size_t size);

#endif
