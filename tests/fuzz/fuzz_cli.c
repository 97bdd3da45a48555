/* Fuzz target: the command-line parser (src/cli/args.c) and the option checks of
 * `restir render` and `restir inspect` that run before the scene is loaded.
 *
 * The input is the argument list, NUL-separated; its first byte picks the command.
 * The scene argument is appended and names no file, so a command that accepts its
 * options stops at loading the scene: nothing is rendered or written. */
#include <stdlib.h>
#include <string.h>
#include "fuzz.h"

#include "../../src/cli/cmd_inspect.h"
#include "../../src/cli/cmd_render.h"

#define FUZZ_CLI_MAX_ARGS 64

FUZZ_TARGET(cli)
{
    static char absent_scene[] = "/nonexistent-restir-fuzz/absent.scene";
    static char command_render[] = "render", command_inspect[] = "inspect";
    char *argv[FUZZ_CLI_MAX_ARGS + 3], *text, *p, *end;
    int argc = 1, inspect;
    if (size < 1) return 0;
    inspect = data[0] & 1;
    text = malloc(size); /* data[1..size) plus a terminating NUL */
    if (!text) return 0;
    memcpy(text, data + 1, size - 1);
    text[size - 1] = '\0';
    argv[0] = inspect ? command_inspect : command_render;
    for (p = text, end = text + size - 1; p < end && argc <= FUZZ_CLI_MAX_ARGS; p += strlen(p) + 1)
        argv[argc++] = p;
    argv[argc++] = absent_scene;
    argv[argc] = NULL;
    if (inspect) cmd_inspect(argc, argv);
    else cmd_render(argc, argv);
    free(text);
    return 0;
}
