/* Output file naming and writing for the render command. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "output.h"
#include "restir/core/image_io.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/pfm.h"
#include "restir/core/png.h"
#include "restir/restir/duplication.h"
#include <sys/stat.h>
#include <unistd.h>

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

void default_output_path(char *buf, size_t size, const char *scene_path, const char *suffix)
{
    const char *base = strrchr(scene_path, '/');
    const char *dot;
    size_t stem;
    base = base ? base + 1 : scene_path;
    dot = strrchr(base, '.');
    stem = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    snprintf(buf, size, "out/%.*s%s.pfm", (int)stem, base, suffix);
}

void output_prefix(char *buf, size_t size, const char *pfm_path)
{
    size_t n = strlen(pfm_path);
    int strip = (n > 4 && !strcmp(pfm_path + n - 4, ".pfm")) || image_path_is(pfm_path, "exr"); /* x.exr: x.png */
    snprintf(buf, size, "%.*s", (int)(strip ? n - 4 : n), pfm_path);
}

void preview_path(char *buf, size_t size, const char *pfm_path)
{
    char prefix[4096];
    output_prefix(prefix, sizeof prefix, pfm_path);
    snprintf(buf, size, "%s.png", prefix);
}

/* The directory part of path ("." when there is none). */
static void directory_of(const char *path, char *dir, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(dir, size, ".");
    else if (slash == path) snprintf(dir, size, "/");
    else snprintf(dir, size, "%.*s", (int)(slash - path), path);
}

/* 1 if dir resolves to /dev or /proc (or below): their entries are devices and links
 * that an atomic rename would replace for every process. */
static int system_directory(const char *dir)
{
    char real[PATH_MAX];
    if (!realpath(dir, real)) return 0;
    return !strcmp(real, "/dev") || !strncmp(real, "/dev/", 5) || !strcmp(real, "/proc") || !strncmp(real, "/proc/", 6);
}

int output_path_check(const char *path, rerror *e)
{
    char dir[4096], parent[4096];
    struct stat st;
    int missing;
    if (!*path) return rerror_set(e, "empty output path");
    if (strlen(path) >= sizeof dir - 32) return rerror_set(e, "%s: path too long", path);
    if (path[strlen(path) - 1] == '/' || (stat(path, &st) == 0 && S_ISDIR(st.st_mode)))
        return rerror_set(e, "%s: is a directory, not an output file", path);
    /* Outputs are written to a temporary file and renamed over the path (atomic_file.c):
     * over /dev/full, /dev/null or a FIFO that would replace the device node itself (as
     * root) instead of writing into it, so only a regular file (or none) is accepted. */
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return rerror_set(e, "%s: is not a regular file (a device, FIFO or socket): outputs are written to a temporary "
                             "file renamed into place, which would replace it", path);
    directory_of(path, dir, sizeof dir);
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode)) return rerror_set(e, "%s: %s is not a directory", path, dir);
        if (system_directory(dir))
            return rerror_set(e, "%s: is in %s, not a place for output files (the rename into place would replace a "
                                 "device or a link such as /dev/stdout)", path, dir);
        if (access(dir, W_OK | X_OK) != 0) return rerror_set(e, "%s: directory %s is not writable", path, dir);
        return 0;
    }
    /* One missing level is created when the file is written (ensure_parent_dir), as for out/. */
    missing = errno == ENOENT;
    directory_of(dir, parent, sizeof parent);
    if (missing && stat(parent, &st) == 0 && S_ISDIR(st.st_mode) && access(parent, W_OK | X_OK) == 0) return 0;
    return rerror_set(e, "%s: directory %s does not exist", path, dir);
}

int write_outputs(const image *img, const char *pfm_path, const char *png_path, double exposure)
{
    return write_outputs_preview(img, img, pfm_path, png_path, exposure);
}

int write_outputs_preview(const image *img, const image *preview, const char *pfm_path, const char *png_path,
                          double exposure)
{
    rerror e;
    if (pfm_path && image_write(pfm_path, img, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (png_path && *png_path && png_write_preview(png_path, preview, exposure, &e)) {
        /* exit 2 leaves nothing behind: not the PFM of this call either */
        if (pfm_path) remove(pfm_path);
        fprintf(stderr, "%s\n", e.msg);
        if (pfm_path) fprintf(stderr, "%s: removed (its preview could not be written)\n", pfm_path);
        return 2;
    }
    return 0;
}

/* --aov duplicates: the PNG is the heat map of Enhanced Fig. 5 (black at D = 0 .. red at
 * D >= 20%, D = count / 288), not a tone-mapped preview. */
int write_duplicates_outputs(const image *img, const char *pfm_path, const char *png_path)
{
    rerror e;
    unsigned char *rgb8 = NULL;
    size_t i, n = (size_t)img->width * (size_t)img->height;
    int status = 0;
    if (pfm_path && image_write(pfm_path, img, &e)) status = 2;
    if (!status && png_path && *png_path) {
        if (!(rgb8 = malloc(3 * n))) {
            fprintf(stderr, "%s: out of memory\n", png_path);
            return 2;
        }
        for (i = 0; i < n; ++i)
            duplication_heat_colour(duplication_score((unsigned)img->px[3 * i], DUPLICATION_RADIUS), 0.2, rgb8 + 3 * i);
        if (png_write_rgb8(png_path, img->width, img->height, rgb8, &e)) status = 2;
        free(rgb8);
    }
    if (status) fprintf(stderr, "%s\n", e.msg);
    return status;
}
