/* Deterministic parallelism: work is split into fixed tiles (or fixed index ranges),
 * each tile's result depends only on its own pixels, so output bytes do not depend on
 * the thread count or on scheduling. threads == 1 starts no thread at all. */
#ifndef RESTIR_THREADS_H
#define RESTIR_THREADS_H

#include <signal.h>

/* Called once per tile: pixels [x0,x1) x [y0,y1). `worker` is in [0, threads). */
typedef void (*tile_fn)(void *ctx, int x0, int y0, int x1, int y1, int worker);
/* Called once per item index in [0, count). */
typedef void (*item_fn)(void *ctx, long index, int worker);

/* Number of online cores (at least 1). */
int threads_default(void);

/* Runs fn over all tiles of a width x height image with `threads` workers.
 * Optional progress: after each finished tile, progress(ctx_progress, done, total)
 * is called from whichever worker finished it, under a lock. Returns 0, or -1 if
 * threads could not be started (then everything ran on the calling thread). */
int parallel_tiles(int width, int height, int tile_size, int threads, tile_fn fn, void *ctx,
                   void (*progress)(void *ctx_progress, long done, long total), void *ctx_progress);

/* Runs fn(ctx, i, worker) for every i in [0, count), in chunks, with `threads` workers. */
int parallel_items(long count, int threads, item_fn fn, void *ctx);

/* CPU seconds the workers of every parallel_tiles / parallel_items call so far have spent
 * in their tiles (all callers; the calling thread only waits while workers run). The
 * process's CPU time minus this is its serial part (issue 17: the Amdahl bound of thread
 * scaling, `restir bench scaling`). */
double threads_parallel_cpu_seconds(void);

/* Stopping at a tile boundary (issue 27: Ctrl-C within about a second in every method):
 * while a cancel flag is set and nonzero, parallel_tiles and parallel_items hand out no
 * further tile or chunk (those already started finish), so the work of the call is
 * incomplete and the caller must discard it (threads_cancelled() says so). Process-wide;
 * returns the previous flag so that callers can nest. NULL: nothing cancels. */
volatile sig_atomic_t *threads_set_cancel(volatile sig_atomic_t *flag);
/* An outer flag for a caller that discards the whole of what it runs once stopped
 * (`restir bench`: an interrupted benchmark's timings are worthless): while set and
 * nonzero it cancels like the cancel flag, whatever the code it runs sets with
 * threads_set_cancel (the renderers a benchmark runs set their own, often NULL).
 * NULL (the default): none. */
void threads_set_abort(volatile sig_atomic_t *flag);
/* 1 if the cancel flag or the abort flag is set and nonzero (a parallel call since may be
 * incomplete). */
int threads_cancelled(void);

/* A process-wide hook called after every finished tile or chunk, under the pool's lock
 * (one call at a time), e.g. a progress heartbeat during a long frame (progress.c).
 * NULL: none. */
void threads_set_tick(void (*tick)(void *ctx), void *ctx);

#endif
