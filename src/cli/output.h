/* Writing a rendered image: PFM (the data) and a PNG preview, both atomically. */
#ifndef RESTIR_CLI_OUTPUT_H
#define RESTIR_CLI_OUTPUT_H

#include "restir/image.h"

/* Default output path "out/<scene stem>.pfm" into buf. */
void default_output_path(char *buf, size_t size, const char *scene_path, const char *suffix);
/* The PNG preview path next to a .pfm path ("x.pfm" -> "x.png"). */
void preview_path(char *buf, size_t size, const char *pfm_path);
/* Writes the PFM (unless pfm_path is NULL) and the PNG (unless png_path is NULL or empty);
 * prints errors; returns 0 or 2. */
int write_outputs(const image *img, const char *pfm_path, const char *png_path, double exposure);
/* The same for a duplicate-count image (--aov duplicates): PFM as is, PNG = heat map. */
int write_duplicates_outputs(const image *img, const char *pfm_path, const char *png_path);

#endif
