/* Private to src/cli. One stage of one frame of a stage dump, recomputed by the oracle on the
 * dump's own inputs (cmd_replay.c; docs/oracle.md §6):
 *   restir replay DIR --frame F --stage S --dump-dir OUT   the stage for every pixel, dumped
 *                                                           and diffed against DIR
 *   restir inspect --from-dump DIR --frame F --stage S --pixel X,Y [--json]
 *                                                           the stage for one pixel, every number
 * Both re-run `restir render` with DIR's recorded command line (manifest "command_line"),
 * restarted from the stage before S (--from-dump DIR --from-stage PREV) and, for the
 * temporal stage, with DIR's frame F-1 final reservoirs as the history
 * (--history-from-dump). Exit status as cli.h: 0, 1 (replay: the stage differs), 2. */
#ifndef RESTIR_SRC_CLI_CMD_REPLAY_H
#define RESTIR_SRC_CLI_CMD_REPLAY_H

#include "restir/core/error.h"

int cmd_replay(int argc, char **argv);

/* A render command line (argv[0] = "render"), each argument owned. */
#define REPLAY_MAX_ARGS 256
typedef struct {
    char *argv[REPLAY_MAX_ARGS];
    int argc;
} replay_args;
int replay_args_push(replay_args *l, const char *s); /* -1: full or out of memory */
void replay_args_free(replay_args *l);
/* DIR/manifest.json's "command_line" (the render command that wrote the dump) without what
 * names outputs, frames, dumps or another restart (-o, --sequence, --dump-*, --from-*,
 * --stats, --runs, --resume, --quiet, ...) and, with drop_ablate, --ablate. */
int replay_command_line(const char *dir, int drop_ablate, replay_args *l, rerror *e);
/* `restir inspect` with --from-dump among its arguments. */
int cmd_inspect_from_dump(int argc, char **argv);

#endif
