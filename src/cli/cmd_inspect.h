/* Private to src/cli. `restir inspect` (cmd_inspect.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_INSPECT_H
#define RESTIR_SRC_CLI_CMD_INSPECT_H

int cmd_inspect(int argc, char **argv);

#endif
