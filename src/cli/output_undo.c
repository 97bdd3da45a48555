/* Undoing the outputs of a failed --sequence (output.h): exit 2 leaves nothing. */
#include "output_undo.h"

#include "output.h"

#include <stdio.h>

int remove_sequence_frames(const char *prefix, const char *ext, const int *frames, int count, int with_png)
{
    char path[4200];
    int i, removed = 0;
    for (i = 0; i < count; ++i) {
        snprintf(path, sizeof path, "%s.%04d.%s", prefix, frames[i], ext);
        removed += remove(path) == 0;
        snprintf(path, sizeof path, "%s.%04d.png", prefix, frames[i]);
        if (with_png) remove(path);
    }
    return removed;
}
