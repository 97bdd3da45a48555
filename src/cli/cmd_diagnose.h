/* Private to src/cli. `restir diagnose A B` (cmd_diagnose.c): which known bug (ablation or
 * option variant) makes B's stage dumps from A's inputs; exit 0 with a verdict, 2 bad input. */
#ifndef RESTIR_SRC_CLI_CMD_DIAGNOSE_H
#define RESTIR_SRC_CLI_CMD_DIAGNOSE_H

int cmd_diagnose(int argc, char **argv);

#endif
