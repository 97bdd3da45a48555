/* A minimal PNG writer of our own (no zlib): 8-bit RGB, filter type 0 ("None") on
 * every row, and a zlib stream made of STORED (uncompressed) deflate blocks.
 *
 * Formats: PNG = ISO/IEC 15948 (W3C PNG 2nd ed.), zlib = RFC 1950, deflate = RFC 1951.
 *   file   = signature, IHDR, IDAT..., IEND; each chunk = length(BE32) type data CRC-32(type+data)
 *   zlib   = CMF 0x78 (deflate, 32K window), FLG 0x01 (FCHECK: 0x7801 % 31 == 0), blocks, Adler-32(BE)
 *   stored = 1 header byte (BFINAL bit, BTYPE 00; byte aligned), LEN (LE16), NLEN = ~LEN, LEN bytes
 * Each stored block (<= 65535 bytes) goes into its own IDAT chunk, so the writer
 * streams with a fixed buffer. The files are ~1.0x the raw size: previews, not archives. */
#include "restir/core/png.h"

#include "restir/core/atomic_file.h"
#include "restir/core/checksum.h"
#include "restir/core/image.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* ---- checksums ---- */

static uint32_t crc_table[256];
static pthread_once_t crc_table_once = PTHREAD_ONCE_INIT;

/* Table of the reflected CRC-32 with polynomial 0xEDB88320 (ISO 3309), one entry per byte. */
static void crc_table_build(void)
{
    uint32_t n, c;
    int k;
    for (n = 0; n < 256; ++n) {
        c = n;
        for (k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        crc_table[n] = c;
    }
}

uint32_t crc32_update(uint32_t crc, const void *data, size_t size)
{
    const unsigned char *b = data;
    size_t i;
    pthread_once(&crc_table_once, crc_table_build); /* thread-safe first use */
    crc ^= 0xFFFFFFFFu;
    for (i = 0; i < size; ++i) crc = crc_table[(crc ^ b[i]) & 0xff] ^ (crc >> 8);
    return crc ^ 0xFFFFFFFFu;
}

/* RFC 1950 §8.2: s1 = 1 + sum of bytes, s2 = sum of the s1 values, both mod 65521.
 * The modulo is taken every 5552 bytes, the most after which s2 still fits 32 bits
 * (the inflate of a large EXR or PNG checks megabytes). */
uint32_t adler32_update(uint32_t adler, const void *data, size_t size)
{
    const unsigned char *b = data;
    uint32_t s1 = adler & 0xffff, s2 = adler >> 16;
    while (size > 0) {
        size_t i, n = size < 5552 ? size : 5552;
        for (i = 0; i < n; ++i) {
            s1 += b[i];
            s2 += s1;
        }
        s1 %= 65521u;
        s2 %= 65521u;
        b += n;
        size -= n;
    }
    return s2 << 16 | s1;
}

/* ---- chunks ---- */

static void put_be32(unsigned char *b, uint32_t v)
{
    b[0] = (unsigned char)(v >> 24);
    b[1] = (unsigned char)(v >> 16 & 0xff);
    b[2] = (unsigned char)(v >> 8 & 0xff);
    b[3] = (unsigned char)(v & 0xff);
}

/* Writes length, type, data, CRC-32 over type and data. Returns 0 on success. */
static int write_chunk(FILE *fp, const char type[4], const unsigned char *data, size_t size)
{
    unsigned char word[4];
    uint32_t crc = crc32_update(0, type, 4);
    crc = crc32_update(crc, data, size);
    put_be32(word, (uint32_t)size);
    if (fwrite(word, 1, 4, fp) != 4 || fwrite(type, 1, 4, fp) != 4) return -1;
    if (size && fwrite(data, 1, size, fp) != size) return -1;
    put_be32(word, crc);
    return fwrite(word, 1, 4, fp) == 4 ? 0 : -1;
}

#define STORED_MAX 65535u

/* The filtered image data: per row one filter byte (0 = None), then the row's RGB bytes.
 * `pos` is an offset into that byte sequence; copies up to `n` bytes of it into out. */
static size_t filtered_bytes(const unsigned char *rgb8, int width, size_t pos, unsigned char *out, size_t n)
{
    size_t row_size = 1 + 3 * (size_t)width, done = 0;
    while (done < n) {
        size_t row = pos / row_size, col = pos % row_size, take;
        if (col == 0) {
            out[done++] = 0;
            pos++;
            continue;
        }
        take = row_size - col;
        if (take > n - done) take = n - done;
        memcpy(out + done, rgb8 + row * 3 * (size_t)width + (col - 1), take);
        done += take;
        pos += take;
    }
    return done;
}

/* IDAT chunks: the zlib header in the first, the Adler-32 trailer in the last. */
static int write_image_data(FILE *fp, int width, int height, const unsigned char *rgb8)
{
    size_t total = (1 + 3 * (size_t)width) * (size_t)height, pos = 0;
    /* zlib header (2) + block header (5) + block + trailer (4) */
    unsigned char *buf = malloc(2 + 5 + STORED_MAX + 4);
    uint32_t adler = 1;
    int status = 0;
    if (!buf) return -1;
    while (pos < total && status == 0) {
        size_t n = total - pos < STORED_MAX ? total - pos : STORED_MAX, k = 0;
        int last = pos + n == total;
        if (pos == 0) {
            buf[k++] = 0x78; /* CMF: CM = 8 (deflate), CINFO = 7 (32K window) */
            buf[k++] = 0x01; /* FLG: no dictionary, level 0, FCHECK making 0x7801 divisible by 31 */
        }
        buf[k++] = (unsigned char)(last ? 1 : 0); /* BFINAL, BTYPE = 00 (stored) */
        buf[k++] = (unsigned char)(n & 0xff);
        buf[k++] = (unsigned char)(n >> 8);
        buf[k++] = (unsigned char)(~n & 0xff);
        buf[k++] = (unsigned char)(~n >> 8 & 0xff);
        filtered_bytes(rgb8, width, pos, buf + k, n);
        adler = adler32_update(adler, buf + k, n);
        k += n;
        pos += n;
        if (last) {
            put_be32(buf + k, adler);
            k += 4;
        }
        status = write_chunk(fp, "IDAT", buf, k);
    }
    free(buf);
    return status;
}

int png_write_rgb8(const char *path, int width, int height, const unsigned char *rgb8, rerror *e)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char ihdr[13];
    atomic_file f;
    if (width <= 0 || height <= 0 || width > 0x7fffffff / 4 || height > 0x7fffffff / 4)
        return rerror_at(e, path, 0, "PNG size %d x %d is invalid", width, height);
    put_be32(ihdr, (uint32_t)width);
    put_be32(ihdr + 4, (uint32_t)height);
    ihdr[8] = 8;  /* bit depth */
    ihdr[9] = 2;  /* colour type 2: truecolour RGB */
    ihdr[10] = 0; /* compression method 0: deflate */
    ihdr[11] = 0; /* filter method 0 (adaptive, we always use type None) */
    ihdr[12] = 0; /* no interlace */
    if (atomic_file_open(&f, path, e)) return -1;
    if (fwrite(signature, 1, 8, f.fp) != 8 || write_chunk(f.fp, "IHDR", ihdr, 13) ||
        write_image_data(f.fp, width, height, rgb8) || write_chunk(f.fp, "IEND", NULL, 0)) {
        int err = errno;
        atomic_file_abort(&f);
        return rerror_at(e, path, 0, "write failed: %s", strerror(err));
    }
    return atomic_file_commit(&f, e);
}

/* sRGB opto-electronic transfer function, IEC 61966-2-1 (piecewise: linear toe, 1/2.4 power). */
static double srgb_oetf(double v)
{
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

static unsigned char preview_byte(float value, double gain)
{
    double v = (double)value * gain;
    if (!(v > 0)) v = 0; /* also maps NaN to black */
    if (v > 1) v = 1;
    return (unsigned char)(srgb_oetf(v) * 255.0 + 0.5);
}

int png_write_preview(const char *path, const image *img, double exposure, rerror *e)
{
    double gain = pow(2.0, exposure);
    size_t i, n;
    unsigned char *rgb8;
    int status;
    if (img->width <= 0 || img->height <= 0 || !img->px) return rerror_at(e, path, 0, "cannot write an empty image");
    n = (size_t)img->width * (size_t)img->height * 3;
    rgb8 = rmalloc(n, 1, e);
    if (!rgb8) return -1;
    for (i = 0; i < n; ++i) rgb8[i] = preview_byte(img->px[i], gain);
    status = png_write_rgb8(path, img->width, img->height, rgb8, e);
    free(rgb8);
    return status;
}
