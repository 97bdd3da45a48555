/* Private to src/cli. `restir plot` (cmd_plot.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_PLOT_H
#define RESTIR_SRC_CLI_CMD_PLOT_H

int cmd_plot(int argc, char **argv);

#endif
