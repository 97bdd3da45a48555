/* Command-line entry points. Each command lives in src/cli/cmd_<name>.c, parses its
 * own options (the CLI is the only place that parses arguments, docs/design.md, Layout) and
 * returns the process exit status: 0 success, 1 a negative verdict (e.g. `check`
 * found a difference), 2 bad usage or bad input (message "file:line: what"). */
#ifndef RESTIR_CLI_H
#define RESTIR_CLI_H

#define RESTIR_VERSION "0.1.0"

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv); /* argv[0] is the command name */
    const char *summary;
} cli_command;

/* The command table (src/cli/main.c). */
extern const cli_command cli_commands[];

#endif
