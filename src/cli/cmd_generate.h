/* Private to src/cli. `restir generate` (cmd_generate.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_GENERATE_H
#define RESTIR_SRC_CLI_CMD_GENERATE_H

int cmd_generate(int argc, char **argv);

#endif
