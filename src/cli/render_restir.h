/* Private to src/cli. The options of `restir render --method restir` (docs/restir-pt.md "CLI"). */
#ifndef RESTIR_CLI_RENDER_RESTIR_H
#define RESTIR_CLI_RENDER_RESTIR_H

#include "args.h"
#include "restir/frame/options.h"

/* The most rows render_restir_options writes (no terminating row). */
#define RENDER_RESTIR_OPTION_ROWS 51

/* The flags that are not one field of restir_options: --mis chooses a MIS family of the
 * spatial GRIS step or, as stochastic-pairwise, the stochastic pairwise algorithm
 * (spatial_options.h); --no-confidence-scaling turns stochastic_options.confidence_scaling
 * off. render_restir_apply maps them, after the preset. */
typedef struct {
    int mis; /* index into the --mis choices: a mis_family, or MIS_FAMILY_COUNT (stochastic-pairwise) */
    int no_confidence_scaling;
} render_restir_flags;

/* Writes the ReSTIR-specific option rows into rows[0..n-1] (destinations inside *o, which
 * should hold restir_options_default, or in *f) and returns n <= RENDER_RESTIR_OPTION_ROWS.
 * The render command's common options (--seed, --jitter, --threads, --quiet, --frame) are
 * not among them: the caller copies those into o->seed, o->jitter, o->threads, o->quiet. */
int render_restir_options(cli_option *rows, restir_options *o, render_restir_flags *f);

/* The --preset row (destination: the index of the preset, 0 = none). */
cli_option render_restir_preset_row(int *preset);
/* Applies preset index `preset` (gris-offline, gris-realtime: GRIS §8.3) to every option of
 * options[] (parsed; given[i] = 1 if options[i] was on the command line) whose destination
 * lies in *o and that was not given, and the spatial algorithm and MIS family unless --mis
 * was given: the options given beside --preset win, in any order. Then maps the flags *f
 * that were given into *o. */
void render_restir_apply(const cli_option *options, const int *given, int preset, const render_restir_flags *f,
                         restir_options *o);
/* Validates o as restir_options_validate does, but says which flags a technique's error
 * came from: prints "restir COMMAND: mutation: count ... (--mutations, --mutation,
 * --mutate-after)" (the library's message alone for the other errors) and returns 2; 0 if
 * o is valid. */
int render_restir_validate(const char *command, const restir_options *o);

#endif
