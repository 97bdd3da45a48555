/* Private to src/cli. `restir vectors` (cmd_vectors.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_VECTORS_H
#define RESTIR_SRC_CLI_CMD_VECTORS_H

int cmd_vectors(int argc, char **argv);

#endif
