/* Private to src/cli. `restir compare` (cmd_compare.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_COMPARE_H
#define RESTIR_SRC_CLI_CMD_COMPARE_H

int cmd_compare(int argc, char **argv);

#endif
