/* Progress with ETA on stderr (progress.h): a bar on a terminal, plain lines elsewhere. */
#include "restir/core/progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>
#include "restir/core/threads.h"

const char *const progress_mode_names[] = {"auto", "none", "bar", "lines", NULL};
static enum progress_mode mode = PROGRESS_AUTO;
static double line_every = 5.0;

void progress_set_mode(enum progress_mode m, double line_seconds)
{
    mode = m;
    if (line_seconds > 0) line_every = line_seconds;
}

double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One line a log can keep: "pt: 37% (370/1000), 4.1 s elapsed, ETA 7.0 s". */
static void print_line(progress *p, long done, long total, double elapsed, double eta)
{
    if (done > 0)
        fprintf(stderr, "%s: %d%% (%ld/%ld), %.1f s elapsed, ETA %.1f s\n", p->label, (int)(100 * done / total), done,
                total, elapsed, eta);
    else
        fprintf(stderr, "%s: 0%% (0/%ld), %.1f s elapsed, ETA unknown (the first step is running)\n", p->label, total,
                elapsed);
    fflush(stderr);
    p->printed++;
}

/* The tile pool's tick (threads_set_tick): a line every line_every seconds while a long
 * pass or frame runs, with the state of the last progress_update. */
static void heartbeat(void *ctx)
{
    progress *p = ctx;
    double t = now_seconds(), elapsed;
    if (p->total <= 0 || t - p->last_draw_seconds < line_every) return;
    p->last_draw_seconds = t;
    elapsed = t - p->start_seconds;
    print_line(p, p->done, p->total, elapsed, p->done > 0 ? elapsed * (double)(p->total - p->done) / (double)p->done : 0);
}

void progress_begin(progress *p, const char *label, int quiet)
{
    int tty = isatty(2);
    p->enabled = !quiet && mode != PROGRESS_NONE;
    p->lines = mode == PROGRESS_LINES || (mode == PROGRESS_AUTO && !tty);
    p->printed = 0;
    p->start_seconds = now_seconds();
    p->last_draw_seconds = p->start_seconds;
    p->label = label;
    p->done = p->total = 0;
    if (p->enabled && p->lines) threads_set_tick(heartbeat, p);
}

/* The total before the first update: the heartbeat can say "0 of N". */
void progress_expect(progress *p, long total) { p->total = total; }

void progress_update(progress *p, long done, long total)
{
    double t, elapsed, eta;
    int i, filled;
    if (!p->enabled || total <= 0) return;
    p->done = done;
    p->total = total;
    t = now_seconds();
    elapsed = t - p->start_seconds;
    eta = done > 0 ? elapsed * (double)(total - done) / (double)done : 0;
    if (p->lines) {
        /* every line_every seconds; the last one only if the log already has one */
        if (t - p->last_draw_seconds >= line_every || (done >= total && p->printed)) {
            p->last_draw_seconds = t;
            print_line(p, done, total, elapsed, eta);
        }
        return;
    }
    if (done < total && t - p->last_draw_seconds < 0.2) return;
    p->last_draw_seconds = t;
    filled = (int)(30 * done / total);
    fprintf(stderr, "\r%s [", p->label);
    for (i = 0; i < 30; ++i) fputc(i < filled ? '#' : '.', stderr);
    fprintf(stderr, "] %3d%%  %.1fs elapsed, ETA %.1fs ", (int)(100 * done / total), elapsed, eta);
    fflush(stderr);
    p->printed++;
}

int progress_line_due(progress *p)
{
    double t = now_seconds();
    if (!p->enabled || (p->lines && t - p->last_draw_seconds < line_every)) return 0;
    p->last_draw_seconds = t;
    p->printed++;
    return 1;
}

void progress_end(progress *p)
{
    if (p->enabled && p->lines) threads_set_tick(NULL, NULL);
    if (p->enabled && !p->lines && p->printed) fprintf(stderr, "\n");
}
