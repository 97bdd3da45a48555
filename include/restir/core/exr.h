/* OpenEXR reader and writer, dependency-free (docs/images.md).
 *
 * Read: single-part scanline files; HALF, FLOAT and UINT channels (UINT is converted
 * to float, exactly up to 2^24); compression NONE, RLE, ZIPS, ZIP and PIZ (own inflate,
 * own PIZ Huffman + wavelet + LUT decoder). Channels R, G, B (+ A) give RGB(A); else Y
 * (+ A) gives Y(A); other channels are skipped. Refused by name, with an error: tiled,
 * multi-part and deep files; PXR24, B44, B44A, DWAA, DWAB and unknown compressions;
 * subsampled channels. The image returned covers the DISPLAY window: data-window pixels
 * outside it are dropped, display pixels the data window does not cover are 0. Chunks are
 * found through the offset table, so either lineOrder (increasing or decreasing y)
 * reads the same; every chunk's y is checked against its table slot.
 *
 * Write: RGB, FLOAT or HALF channels, compression NONE or ZIP (fixed-Huffman deflate),
 * data window = display window = the image, increasing y, atomically. */
#ifndef RESTIR_EXR_H
#define RESTIR_EXR_H

#include <stdint.h>
#include "restir/core/image_io.h"

/* Compression codes of the file format. */
enum { EXR_NONE = 0, EXR_RLE = 1, EXR_ZIPS = 2, EXR_ZIP = 3, EXR_PIZ = 4, EXR_PXR24 = 5, EXR_B44 = 6,
       EXR_B44A = 7, EXR_DWAA = 8, EXR_DWAB = 9 };
/* Pixel types of the file format. */
enum { EXR_UINT = 0, EXR_HALF = 1, EXR_FLOAT = 2 };

/* Errors "path: EXR: what". */
int exr_read(const char *path, fimage *out, rerror *e);
/* exr_read with a lower bound of the caller's: refuses, before allocating, a file whose
 * decoded data or returned image would exceed max_bytes (0: only the built-in limits).
 * The fuzz target uses it so that inputs claiming big images do not dominate the run. */
int exr_read_bounded(const char *path, size_t max_bytes, fimage *out, rerror *e);
/* compression EXR_NONE or EXR_ZIP; pixel_type EXR_FLOAT or EXR_HALF (rounded to nearest even). */
int exr_write(const char *path, const image *img, int compression, int pixel_type, rerror *e);

/* IEEE 754 binary16 <-> binary32: half_to_float is exact; float_to_half rounds to
 * nearest, ties to even (overflow to infinity, NaN stays NaN with its top payload bits). */
float half_to_float(uint16_t h);
uint16_t float_to_half(float f);

#endif
