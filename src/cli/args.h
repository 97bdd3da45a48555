/* Private to src/cli. Table-driven option parsing shared by every command: a command lists its
 * options once (name, type, destination, help) and gets parsing, validation and --help. */
#ifndef RESTIR_CLI_ARGS_H
#define RESTIR_CLI_ARGS_H

#include <stddef.h>
#include <stdio.h>
#include "restir/core/vec.h"

enum cli_option_type {
    OPT_FLAG,   /* int, set to 1 */
    OPT_INT,    /* int >= 0 unless min is set */
    OPT_UINT32, /* uint32_t */
    OPT_REAL,   /* double */
    OPT_STRING, /* const char * */
    OPT_VEC3,   /* double[3] from "x,y,z" */
    OPT_SIZE,   /* int[2] from "WxH" */
    OPT_CHOICE, /* int index into `choices` (NULL-terminated) */
    OPT_LIST    /* cli_list: the value and the arguments after it up to the next option */
};

/* Destination of an OPT_LIST row: items[0..count) point into argv; at most max. */
typedef struct {
    const char **items;
    int count, max;
} cli_list;

typedef struct {
    const char *name; /* "--spp" */
    enum cli_option_type type;
    void *dest;
    const char *help;
    const char *const *choices; /* OPT_CHOICE only */
    double min, max;            /* numeric bounds when min < max */
    int *seen;                  /* optional: set to 1 when given */
} cli_option;

/* The two rows of --progress auto|none|bar|lines and --progress-every SECONDS that render
 * has, for the other long-running commands (check, compare --covariance, merge, bench):
 * mode is an int (enum progress_mode, progress.h), every a double (0: the default 5 s). */
#define CLI_PROGRESS_ROWS(mode, every)                                                                                  \
    {"--progress", OPT_CHOICE, (mode), "auto (default: a bar on a terminal, plain lines with the ETA otherwise), none, bar or lines", \
     progress_mode_names, 0, 0, NULL},                                                                                  \
    {"--progress-every", OPT_REAL, (every), "seconds between two progress lines (default 5)", NULL, 0.01, 3600, NULL}

/* Parses argv[1..argc-1]. Non-option arguments go to positional[] (up to max_positional).
 * Returns 0, 1 if --help was printed, or 2 after printing "restir CMD: what is wrong". */
int cli_parse(const char *command, int argc, char **argv, const cli_option *options, const char **positional,
              int max_positional, int *positional_count);

/* A preset: every option whose destination lies in the struct at `to` (size bytes) and
 * that was not given (given[i] = 0 for options[i]) takes the value at the same offset of
 * the struct at `from`. So `--preset P` and the options given beside it need one parse
 * and no order: the options given win, the preset fills the rest. */
void cli_take_unset(const cli_option *options, const int *given, void *to, const void *from, size_t size);

/* Points the `seen` of every option that has none at given[i] (zeroed here; room for
 * every row), so given[i] tells whether options[i] was on the command line. */
void cli_track_given(cli_option *options, int *given);
/* given[i] of the option called name (0 if there is none). */
int cli_given(const cli_option *options, const int *given, const char *name);

void cli_print_help(FILE *out, const char *command, const char *usage, const cli_option *options);

#endif
