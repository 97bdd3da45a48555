/* Path-tracer checkpoints (src/render/pt_checkpoint.c; docs/formats.md): the accumulation
 * state on disk, written atomically, read back for --resume and restir merge. */
#ifndef RESTIR_RENDER_PT_CHECKPOINT_H
#define RESTIR_RENDER_PT_CHECKPOINT_H

#include "restir/render/pt.h"

/* ---- checkpoints (docs/path-tracer.md, "Checkpoint format") ---- */
int pt_checkpoint_write(const char *path, const pt_state *st, rerror *e);
int pt_checkpoint_read(const char *path, pt_state *st, rerror *e);

#endif
