/* Private to src/cli. `restir check` (cmd_check.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_CHECK_H
#define RESTIR_SRC_CLI_CMD_CHECK_H

int cmd_check(int argc, char **argv);

#endif
