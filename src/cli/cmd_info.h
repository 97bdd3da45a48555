/* Private to src/cli. `restir info` (cmd_info.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_INFO_H
#define RESTIR_SRC_CLI_CMD_INFO_H

int cmd_info(int argc, char **argv);

#endif
