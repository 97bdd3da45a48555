/* Progress bar with ETA, drawn on stderr only when it is a terminal. */
#include "restir/core/progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void progress_begin(progress *p, const char *label, int quiet)
{
    p->enabled = !quiet && isatty(2);
    p->start_seconds = now_seconds();
    p->last_draw_seconds = 0;
    p->label = label;
}

void progress_update(progress *p, long done, long total)
{
    double t, elapsed, eta;
    int i, filled;
    if (!p->enabled || total <= 0) return;
    t = now_seconds();
    if (done < total && t - p->last_draw_seconds < 0.2) return;
    p->last_draw_seconds = t;
    elapsed = t - p->start_seconds;
    eta = done > 0 ? elapsed * (double)(total - done) / (double)done : 0;
    filled = (int)(30 * done / total);
    fprintf(stderr, "\r%s [", p->label);
    for (i = 0; i < 30; ++i) fputc(i < filled ? '#' : '.', stderr);
    fprintf(stderr, "] %3d%%  %.1fs elapsed, ETA %.1fs ", (int)(100 * done / total), elapsed, eta);
    fflush(stderr);
}

void progress_end(progress *p)
{
    if (p->enabled) fprintf(stderr, "\n");
}
