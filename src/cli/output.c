/* Output file naming and writing for the render command. */
#include "output.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/duplication.h"

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

/* --aov duplicates: the PNG is the heat map of Enhanced Fig. 5 (black at D = 0 .. red at
 * D >= 20%, D = count / 288), not a tone-mapped preview. */
int write_duplicates_outputs(const image *img, const char *pfm_path, const char *png_path)
{
    rerror e;
    unsigned char *rgb8 = NULL;
    size_t i, n = (size_t)img->width * (size_t)img->height;
    int status = 0;
    if (pfm_path && pfm_write(pfm_path, img, &e)) status = 2;
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
