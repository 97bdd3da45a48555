/* PNG reader (ISO/IEC 15948), dependency-free: every colour type and bit depth
 * (grey 1/2/4/8/16, RGB 8/16, palette 1/2/4/8, grey+alpha 8/16, RGBA 8/16), tRNS,
 * the five filter types, Adam7 interlace; CRC-32 of every chunk checked. docs/images.md.
 *
 * The sRGB rule: a PNG holds 8- or 16-bit codes v in [0, max]. With PNG_LINEAR each
 * channel is v / max (data maps: normals, roughness, masks). With PNG_SRGB the colour
 * channels (grey, R, G, B, palette colours) are decoded with the sRGB EOTF of
 * IEC 61966-2-1 (c = v/max; c <= 0.04045 ? c/12.92 : ((c+0.055)/1.055)^2.4) into
 * linear values (colour textures, pictures); alpha is always v / max. The file's gAMA,
 * cHRM, sRGB and iCCP chunks are ignored: the caller decides which kind of map it reads.
 * Values are computed in double and rounded once to float. */
#ifndef RESTIR_PNG_READ_H
#define RESTIR_PNG_READ_H

#include "restir/core/image_io.h"

#define PNG_LINEAR 0
#define PNG_SRGB 1

/* out->channels: 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA; a tRNS chunk adds alpha
 * (palette entries without a tRNS entry, and colours other than the key, get alpha 1).
 * Errors "path: PNG: what". */
int png_read(const char *path, int flags, fimage *out, rerror *e);

/* The sRGB EOTF above (for tests and callers that decode 8-bit colours themselves). */
double srgb_to_linear(double c);

#endif
