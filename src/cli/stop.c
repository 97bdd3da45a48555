/* Stopping a render on SIGINT / SIGTERM (stop.h). */
#include "stop.h"

#include <string.h>

volatile sig_atomic_t stop_requested;
static struct sigaction old_int, old_term;

static void on_stop_signal(int sig)
{
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
