/* The options of `restir render --method restir` (docs/restir-pt.md "CLI"). */
#ifndef RESTIR_CLI_RENDER_RESTIR_H
#define RESTIR_CLI_RENDER_RESTIR_H

#include "args.h"
#include "restir/restir.h"

/* The most rows render_restir_options writes (no terminating row). */
#define RENDER_RESTIR_OPTION_ROWS 51

/* Writes the ReSTIR-specific option rows into rows[0..n-1] (destinations inside *o, which
 * should hold restir_options_default) and returns n <= RENDER_RESTIR_OPTION_ROWS. The
 * render command's common options (--seed, --jitter, --threads, --quiet, --frame) are
 * not among them: the caller copies those into o->seed, o->jitter, o->threads, o->quiet. */
int render_restir_options(cli_option *rows, restir_options *o);

/* `--preset NAME` must act before every other option so that explicit options override it:
 * scans argv for it and applies the preset to *o (gris-offline: GRIS §8.3). Returns 0, or 2
 * after a message on stderr for an unknown preset. */
int render_restir_apply_preset(int argc, char **argv, restir_options *o);

#endif
