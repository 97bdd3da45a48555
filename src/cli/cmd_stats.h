/* Private to src/cli. `restir stats` (cmd_stats.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_STATS_H
#define RESTIR_SRC_CLI_CMD_STATS_H

int cmd_stats(int argc, char **argv);

#endif
