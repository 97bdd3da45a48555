/* Private to src/cli. `restir render` (cmd_render.c): parses its own options and returns the
 * exit status (0 success, 1 a negative verdict, 2 bad usage or input; cli.h). */
#ifndef RESTIR_SRC_CLI_CMD_RENDER_H
#define RESTIR_SRC_CLI_CMD_RENDER_H

int cmd_render(int argc, char **argv);

#endif
