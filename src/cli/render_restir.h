/* Private to src/cli. The options of `restir render --method restir` (docs/restir-pt.md "CLI"). */
#ifndef RESTIR_CLI_RENDER_RESTIR_H
#define RESTIR_CLI_RENDER_RESTIR_H

#include "args.h"
#include "restir/frame/options.h"

/* The most rows render_restir_options writes (no terminating row). */
#define RENDER_RESTIR_OPTION_ROWS 51

/* Writes the ReSTIR-specific option rows into rows[0..n-1] (destinations inside *o, which
 * should hold restir_options_default) and returns n <= RENDER_RESTIR_OPTION_ROWS. The
 * render command's common options (--seed, --jitter, --threads, --quiet, --frame) are
 * not among them: the caller copies those into o->seed, o->jitter, o->threads, o->quiet. */
int render_restir_options(cli_option *rows, restir_options *o);

/* The --preset row (destination: the index of the preset, 0 = none). */
cli_option render_restir_preset_row(int *preset);
/* Applies preset index `preset` (gris-offline, gris-realtime: GRIS §8.3) to every option of
 * options[] (parsed; given[i] = 1 if options[i] was on the command line) whose destination
 * lies in *o and that was not given: the options given beside --preset win, in any order. */
void render_restir_apply_preset(const cli_option *options, const int *given, int preset, restir_options *o);

#endif
