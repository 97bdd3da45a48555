/* Progress bar with ETA on stderr, shown only when stderr is a terminal and not --quiet. */
#ifndef RESTIR_PROGRESS_H
#define RESTIR_PROGRESS_H

typedef struct {
    int enabled;
    double start_seconds;
    double last_draw_seconds;
    const char *label;
} progress;

void progress_begin(progress *p, const char *label, int quiet);
void progress_update(progress *p, long done, long total); /* rate-limited redraw */
void progress_end(progress *p);

/* Monotonic wall-clock seconds. */
double now_seconds(void);

#endif
