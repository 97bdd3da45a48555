/* Private to src/cli. `restir merge` (cmd_merge.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_MERGE_H
#define RESTIR_SRC_CLI_CMD_MERGE_H

int cmd_merge(int argc, char **argv);

#endif
