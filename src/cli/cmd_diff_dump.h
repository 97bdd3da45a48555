/* Private to src/cli. `restir diff-dump` (cmd_diff_dump.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_DIFF_DUMP_H
#define RESTIR_SRC_CLI_CMD_DIFF_DUMP_H

int cmd_diff_dump(int argc, char **argv);

#endif
