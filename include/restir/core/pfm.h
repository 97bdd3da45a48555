/* Portable float map (PFM) read and write (src/core/pfm.c; docs/images.md): the oracle's
 * lossless image format, bottom row first as the format defines, written atomically. */
#ifndef RESTIR_CORE_PFM_H
#define RESTIR_CORE_PFM_H

#include "restir/core/image.h"

/* PFM ("PF" colour, "Pf" greyscale). A "Pf" file is read into all three channels;
 * *channels (may be NULL) receives 1 or 3. The scale's sign gives the byte order
 * (negative = little-endian); its magnitude is ignored. Errors: "file: what". */
int pfm_read(const char *path, image *out, int *channels, rerror *e);
/* Writes "PF", little-endian (scale -1.0), atomically. */
int pfm_write(const char *path, const image *img, rerror *e);

#endif
