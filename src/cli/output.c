/* Output file naming and writing for the render command. */
#include "output.h"

#include <stdio.h>
#include <string.h>

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

void preview_path(char *buf, size_t size, const char *pfm_path)
{
    size_t n = strlen(pfm_path);
    if (n > 4 && !strcmp(pfm_path + n - 4, ".pfm"))
        snprintf(buf, size, "%.*s.png", (int)(n - 4), pfm_path);
    else
        snprintf(buf, size, "%s.png", pfm_path);
}

int write_outputs(const image *img, const char *pfm_path, const char *png_path, double exposure)
{
    rerror e;
    if ((pfm_path && pfm_write(pfm_path, img, &e)) || (png_path && *png_path && png_write_preview(png_path, img, exposure, &e))) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    return 0;
}
