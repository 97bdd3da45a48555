/* Private to src/cli. Every file `restir render` writes, against each other and its inputs,
 * before anything is rendered (docs/cli.md, "Outputs never overwrite each other or an
 * input"): -o or, with --runs, its PREFIX.mean.pfm/.var.pfm/.moments.json/.blocks.bin, or,
 * with --sequence A..B, the frames PREFIX.NNNN.pfm/.png (with --runs their per-frame
 * moments); the PNG preview, --stats, --checkpoint, and the --dump-dir tree's own files. */
#ifndef RESTIR_SRC_CLI_RENDER_OUTPUTS_H
#define RESTIR_SRC_CLI_RENDER_OUTPUTS_H

#include "render_args.h"

/* 0, or 2 after printing which two files collide. out: -o (or its default); png: the
 * preview path ("" for none). */
int render_outputs_distinct(const render_args *a, const char *out, const char *png);

#endif
