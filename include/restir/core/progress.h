/* Progress on stderr: a redrawn bar on a terminal, plain lines with the ETA every few
 * seconds elsewhere (logs, batch jobs: issue 27 found 46 s of silence), or nothing. */
#ifndef RESTIR_PROGRESS_H
#define RESTIR_PROGRESS_H

enum progress_mode {
    PROGRESS_AUTO,  /* bar when stderr is a terminal, lines otherwise (default) */
    PROGRESS_NONE,
    PROGRESS_BAR,
    PROGRESS_LINES
};

typedef struct {
    int enabled;
    int lines;                 /* 1: plain lines, 0: the bar */
    int printed;               /* lines printed so far (a final line only after one) */
    double start_seconds;
    double last_draw_seconds;
    const char *label;
    long done, total;          /* the last progress_update (for the heartbeat) */
} progress;

/* Process-wide: how progress_begin shows progress (`restir render --progress`), and the
 * seconds between two plain lines (--progress-every; default 5). */
void progress_set_mode(enum progress_mode mode, double line_seconds);
extern const char *const progress_mode_names[]; /* "auto", "none", "bar", "lines", NULL */

/* Plain lines also come while one pass or frame runs for long: progress_begin registers a
 * heartbeat on the tile pool (threads_set_tick) that repeats the last state with the time
 * (`restir: 0% (0/1), 10.0 s elapsed, ETA unknown (the first step is running)`);
 * progress_end removes it. One progress at a time. */
void progress_begin(progress *p, const char *label, int quiet);
void progress_update(progress *p, long done, long total); /* rate-limited redraw or line */
/* The total to report before the first update (the heartbeat's "0/N"). */
void progress_expect(progress *p, long total);
void progress_end(progress *p);
/* For a run without a known total (`restir bench all`): 1 if a free-form line is due now
 * (enabled, and --progress-every seconds since the last line or the begin; always on a
 * terminal), and then counts it as drawn. */
int progress_line_due(progress *p);

/* Monotonic wall-clock seconds. */
double now_seconds(void);

#endif
