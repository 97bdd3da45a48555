/* Private to src/cli. `restir compare --bias` (cmd_bias.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_BIAS_H
#define RESTIR_SRC_CLI_CMD_BIAS_H

int cmd_compare_bias(int argc, char **argv);

#endif
