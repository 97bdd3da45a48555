/* Private to src/cli. `restir bench` (cmd_bench.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_BENCH_H
#define RESTIR_SRC_CLI_CMD_BENCH_H

int cmd_bench(int argc, char **argv);

#endif
