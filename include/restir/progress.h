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
} progress;

/* Process-wide: how progress_begin shows progress (`restir render --progress`), and the
 * seconds between two plain lines (--progress-every; default 5). */
void progress_set_mode(enum progress_mode mode, double line_seconds);
extern const char *const progress_mode_names[]; /* "auto", "none", "bar", "lines", NULL */

void progress_begin(progress *p, const char *label, int quiet);
void progress_update(progress *p, long done, long total); /* rate-limited redraw or line */
void progress_end(progress *p);

/* Monotonic wall-clock seconds. */
double now_seconds(void);

#endif
