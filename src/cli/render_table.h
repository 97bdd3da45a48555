/* Private to src/cli. The option table of `restir render`, built in pieces: the command's own
 * rows, the scene overrides (scene_args.h), the path tracer's rows (render_pt.h), the --preset
 * row and ReSTIR's rows (render_restir.h) without the ones the path tracer already has. */
#ifndef RESTIR_CLI_RENDER_TABLE_H
#define RESTIR_CLI_RENDER_TABLE_H

#include "render_args.h"

#define RENDER_TABLE_ROWS 114 /* room for every row and the terminating one */

/* Writes the rows (destinations in *a) and the terminating zero row into options[] and
 * which rows belong to which method into methods[0..2] (pt, restir, aov); returns the
 * count of rows. */
int render_table_build(cli_option *options, render_args *a, method_rows *methods);

#endif
