/* Private to src/cli. SIGINT / SIGTERM during a render (docs/cli.md, "Interrupted renders"):
 * the handler only sets a flag the renderers check between passes (pt) or frames (restir); the
 * render command then writes what it has and exits with 128 + the signal number (130 / 143). */
#ifndef RESTIR_CLI_STOP_H
#define RESTIR_CLI_STOP_H

#include <signal.h>

/* Nonzero once SIGINT or SIGTERM arrived after stop_signals_install. */
extern volatile sig_atomic_t stop_requested;

void stop_signals_install(void);
void stop_signals_restore(void);
/* The signal that stopped the render (SIGINT, SIGTERM), or 0. */
int stop_signal(void);
/* "SIGINT" / "SIGTERM". */
const char *stop_signal_name(void);

#endif
