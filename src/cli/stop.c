/* Stopping a render on SIGINT / SIGTERM (stop.h). */
#include "stop.h"

#include <string.h>
#include <time.h>
#include <unistd.h>
#include "signal_cleanup.h"

volatile sig_atomic_t stop_requested;
static struct sigaction old_int, old_term;

/* When the first signal came (CLOCK_MONOTONIC seconds). */
static volatile double first_signal_seconds;

static double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts); /* async-signal-safe (POSIX) */
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The first signal asks the render to stop at the next tile boundary and write what is
 * complete; a second one (the user does not want to wait) exits at once, with only
 * async-signal-safe calls: nothing is written, the atomic outputs leave no partial file.
 * One signal often arrives twice within microseconds (GNU timeout sends it to the child
 * and to its process group; a batch system may do likewise), so a repeat within
 * STOP_REPEAT_SECONDS of the first is the same request, not a second one. */
static void on_stop_signal(int sig)
{
    static const char msg[] = "restir: second signal: exiting at once, nothing more written\n";
    if (stop_requested) {
        if (monotonic_seconds() - first_signal_seconds < STOP_REPEAT_SECONDS) return;
        cleanup_remove_temps(); /* the file being written: no PATH.tmp.PID left */
        {
            ssize_t ignored = write(2, msg, sizeof msg - 1);
            (void)ignored;
        }
        _exit(128 + sig);
    }
    first_signal_seconds = monotonic_seconds();
    stop_requested = sig;
}

void stop_signals_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    stop_requested = 0;
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
}

void stop_signals_restore(void)
{
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
}

int stop_signal(void)
{
    return (int)stop_requested;
}

const char *stop_signal_name(void)
{
    return stop_requested == SIGTERM ? "SIGTERM" : "SIGINT";
}
