/* Private to src/cli. Removing the frames a failed sequence wrote (output_undo.c): an exit
 * with status 2 leaves nothing behind. */
#ifndef RESTIR_SRC_CLI_OUTPUT_UNDO_H
#define RESTIR_SRC_CLI_OUTPUT_UNDO_H

#include "output.h"

/* --sequence failed (exit 2): removes PREFIX.NNNN.EXT (EXT pfm or exr, and .png) of the
 * frames written before the failure; returns how many images were removed (output_undo.c). */
int remove_sequence_frames(const char *prefix, const char *ext, const int *frames, int count, int with_png);

#endif
