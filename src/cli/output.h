/* Private to src/cli. Writing a rendered image: PFM (the data) and a PNG preview, both
 * atomically. */
#ifndef RESTIR_CLI_OUTPUT_H
#define RESTIR_CLI_OUTPUT_H

#include "restir/core/image.h"

/* Default output path "out/<scene stem>.pfm" into buf. */
void default_output_path(char *buf, size_t size, const char *scene_path, const char *suffix);
/* The path without a final ".pfm" ("x.pfm" -> "x"): the prefix of --runs and --sequence files. */
void output_prefix(char *buf, size_t size, const char *pfm_path);
/* The PNG preview path next to a .pfm path ("x.pfm" -> "x.png"). */
void preview_path(char *buf, size_t size, const char *pfm_path);
/* 0 if a file can be written at path before anything is rendered: not a directory nor
 * another existing non-regular file (a device, a FIFO), not in /dev or /proc, and
 * its directory exists and is writable (or is one missing level below a writable one,
 * created on writing); -1 with `path: what is wrong` in *e. */
int output_path_check(const char *path, rerror *e);
/* Writes the PFM (unless pfm_path is NULL) and the PNG (unless png_path is NULL or empty);
 * if the PNG fails the PFM written by this call is removed. Prints errors; returns 0 or 2. */
int write_outputs(const image *img, const char *pfm_path, const char *png_path, double exposure);
/* The same for a duplicate-count image (--aov duplicates): PFM as is, PNG = heat map. */
int write_duplicates_outputs(const image *img, const char *pfm_path, const char *png_path);
/* The same with a separate image for the PNG (e.g. aov_preview's normalised depth). */
int write_outputs_preview(const image *img, const image *preview, const char *pfm_path, const char *png_path,
                          double exposure);

#endif
