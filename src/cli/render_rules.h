/* Private to src/cli. Which `restir render` options go together, and where the options every
 * method shares go: the compatibility rules of docs/cli.md ("an option that does not apply
 * is an error"), checked before anything is loaded. Each returns 0, or 2 after printing
 * "restir render: what is wrong". */
#ifndef RESTIR_CLI_RENDER_RULES_H
#define RESTIR_CLI_RENDER_RULES_H

#include "render_args.h"

/* seed, jitter, threads, quiet, frame (and the stop flag) into the methods' options. */
void apply_common_options(render_args *a);
/* An option of another method (rows[0..nrows) say which rows belong to which) is an error. */
int check_method_options(const render_args *a, const cli_option *options, const int *given,
                         const method_rows *rows, int nrows);
/* --sequence, --mcap, --dump-*, --from-*, --aov duplicates|age, --time-limit, --light-ris,
 * --max-depth, --ablate: checked against each other and handed to the chosen method. */
int apply_shared_options(render_args *a, const cli_option *options, const int *given);
/* Every file the command will write (out, png, --stats, --checkpoint), checked first. */
int check_output_paths(const render_args *a, const char *out, const char *png);

#endif
