/* Undoing a failed sequence's stage dumps (src/oracle/stage_dump_undo.c): an exit with status
 * 2 leaves no partial dump behind. */
#ifndef RESTIR_ORACLE_STAGE_DUMP_UNDO_H
#define RESTIR_ORACLE_STAGE_DUMP_UNDO_H

#include "restir/oracle/stage_dump.h"

/* After a failed run (exit 2 leaves nothing): removes the dump files this run wrote
 * (frames first_frame .. the frame in progress: the G-buffer and every stage file), their
 * frame directories and the manifest if they are then empty, and dump_dir if this run
 * created it. Nothing is removed when the dump directory is also the restart's input.
 * Returns the number of files removed (stage_dump_undo.c). */
int stage_io_remove_written(const stage_io *io);

#endif
