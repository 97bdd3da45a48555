/* DEFLATE (RFC 1951) decoder and a small encoder, with the zlib wrapper (RFC 1950).
 * Shared by the PNG reader (png_read.c) and the OpenEXR reader/writer (exr.c).
 *
 * The decoder writes into a buffer the caller sized: the readers know the exact
 * decompressed size from the image header, so a hostile stream can never make it
 * allocate; a stream that would produce more than `out_cap` bytes is an error. Every
 * malformed input (bad block type, over-subscribed or incomplete-and-used Huffman code,
 * distance before the start of the output, truncated input, checksum mismatch) is an
 * error with a message, never a crash. */
#ifndef RESTIR_INFLATE_H
#define RESTIR_INFLATE_H

#include <stddef.h>
#include "restir/core/error.h"

/* Raw DEFLATE: decodes blocks until the final one. *out_size receives the bytes written.
 * *in_used (may be NULL) receives the input bytes consumed (the last partial byte counts). */
int inflate_raw(const unsigned char *in, size_t in_size, unsigned char *out, size_t out_cap, size_t *out_size,
                size_t *in_used, rerror *e);
/* zlib stream: 2-byte header (CM 8, no preset dictionary), raw DEFLATE, Adler-32 checked.
 * Bytes after the trailer are ignored. */
int inflate_zlib(const unsigned char *in, size_t in_size, unsigned char *out, size_t out_cap, size_t *out_size,
                 rerror *e);

/* Largest zlib stream deflate_zlib can produce for n input bytes (stored blocks + framing). */
size_t deflate_zlib_bound(size_t n);
/* zlib stream of in[0..n): greedy LZ77 (32 KB window, one hash candidate) coded with the
 * fixed Huffman code (BTYPE 01), or stored blocks (BTYPE 00) when those are smaller.
 * `out` must hold deflate_zlib_bound(n) bytes. Returns the stream's size; 0 only if
 * the hash table cannot be allocated. */
size_t deflate_zlib(const unsigned char *in, size_t n, unsigned char *out);

#endif
