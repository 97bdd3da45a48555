/* Private to src/cli. SIGINT / SIGTERM during a render (docs/cli.md, "Interrupted renders"):
 * the handler only sets a flag that stops the parallel loops at the next tile boundary
 * (threads.h, threads_set_cancel) and the renderers between passes (pt) or frames (restir),
 * dropping the pass or frame in progress; the render command then writes what is complete and
 * exits with 128 + the signal number (130 / 143). A second signal exits at once. */
#ifndef RESTIR_CLI_STOP_H
#define RESTIR_CLI_STOP_H

#include <signal.h>

/* A repeat of the stop signal this soon after the first is the same request (stop.c). */
#define STOP_REPEAT_SECONDS 0.25

/* Nonzero once SIGINT or SIGTERM arrived after stop_signals_install. */
extern volatile sig_atomic_t stop_requested;

void stop_signals_install(void);
void stop_signals_restore(void);
/* The signal that stopped the render (SIGINT, SIGTERM), or 0. */
int stop_signal(void);
/* "SIGINT" / "SIGTERM". */
const char *stop_signal_name(void);

#endif
