/* Private to src/cli. Every file a command will write, checked before any work (issue 27's
 * audit): each output can be written (output_path_check), no two outputs name one file and
 * no output names an input (outputs_distinct); and, after a failure, the files this call
 * wrote are removed again (an exit != 0 leaves nothing). */
#ifndef RESTIR_SRC_CLI_OUTPUTS_READY_H
#define RESTIR_SRC_CLI_OUTPUTS_READY_H

#include <sys/types.h>
#include "collide.h"

/* 0, or 2 after printing "restir COMMAND: what is wrong" (an output path that cannot be
 * written, two outputs that collide, an output that is an input). On 0 the outputs are
 * registered for removal on SIGINT / SIGTERM (signal_cleanup.h). */
int outputs_ready(const char *command, const named_file *outs, int n_out, const named_file *ins, int n_in);

/* 2 after printing "restir COMMAND: ROLE A and ROLE B are one file" if two existing files
 * of ins[] are one (the same inode: also another spelling or a link; K runs of one file
 * are not K independent runs), else 0. O(n log n). */
int inputs_distinct(const char *command, const named_file *ins, int n_in);

/* Removes output_set.c's ".staged.PID" from an error message, so that it names the output
 * the user gave ("z.pfm: write failed", not "z.pfm.staged.28785: write failed"). */
void message_unstaged(char *msg);

/* What is at a path before a command writes it, so that a failure can remove what this
 * call wrote and nothing older (an atomic write replaces the inode). */
typedef struct {
    int existed;
    dev_t dev;
    ino_t ino;
} file_before;

void file_before_note(file_before *b, const char *path);
/* Removes path if this call wrote it (it exists and is not the file noted before);
 * returns 1 if removed. */
int file_remove_if_written(const file_before *b, const char *path);

#endif
