/* A deterministic tile pool on pthreads. Workers take tile indices from a shared
 * counter; which worker renders a tile never changes what the tile contains. */
#include "restir/core/threads.h"

#include <pthread.h>
#include <time.h>
#include <unistd.h>

/* CPU seconds spent by workers inside parallel regions (threads_parallel_cpu_seconds). */
static pthread_mutex_t cpu_lock = PTHREAD_MUTEX_INITIALIZER;
static double parallel_cpu;

static double thread_cpu_seconds(void)
{
    struct timespec t;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) != 0) return 0;
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

double threads_parallel_cpu_seconds(void)
{
    double s;
    pthread_mutex_lock(&cpu_lock);
    s = parallel_cpu;
    pthread_mutex_unlock(&cpu_lock);
    return s;
}

int threads_default(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (int)n;
}

typedef struct {
    pthread_mutex_t lock;
    long next, total;
    long done;
    /* tiles */
    int width, height, tile_size, tiles_x;
    tile_fn tile;
    /* items */
    long item_count, chunk;
    item_fn item;
    void *ctx;
    void (*progress)(void *, long, long);
    void *ctx_progress;
} pool;

typedef struct {
    pool *p;
    int worker;
} worker_arg;

/* The cancel flag (threads_set_cancel): read by the workers, written by a signal handler. */
static volatile sig_atomic_t *cancel_flag;

volatile sig_atomic_t *threads_set_cancel(volatile sig_atomic_t *flag)
{
    volatile sig_atomic_t *old = cancel_flag;
    cancel_flag = flag;
    return old;
}

/* The abort flag (threads_set_abort): outside the nesting of the cancel flag. */
static volatile sig_atomic_t *abort_flag;

void threads_set_abort(volatile sig_atomic_t *flag) { abort_flag = flag; }

int threads_cancelled(void) { return (cancel_flag && *cancel_flag) || (abort_flag && *abort_flag); }

static void (*tick_fn)(void *);
static void *tick_ctx;

void threads_set_tick(void (*tick)(void *ctx), void *ctx)
{
    tick_fn = tick;
    tick_ctx = ctx;
}

static long take_index(pool *p)
{
    long i;
    pthread_mutex_lock(&p->lock);
    i = p->next < p->total && !threads_cancelled() ? p->next++ : -1;
    pthread_mutex_unlock(&p->lock);
    return i;
}

static void finish_index(pool *p)
{
    pthread_mutex_lock(&p->lock);
    p->done++;
    if (p->progress) p->progress(p->ctx_progress, p->done, p->total);
    if (tick_fn) tick_fn(tick_ctx);
    pthread_mutex_unlock(&p->lock);
}

static void run_unit(pool *p, long i, int worker)
{
    if (p->tile) {
        int tx = (int)(i % p->tiles_x), ty = (int)(i / p->tiles_x);
        int x0 = tx * p->tile_size, y0 = ty * p->tile_size;
        int x1 = x0 + p->tile_size < p->width ? x0 + p->tile_size : p->width;
        int y1 = y0 + p->tile_size < p->height ? y0 + p->tile_size : p->height;
        p->tile(p->ctx, x0, y0, x1, y1, worker);
    } else {
        long a = i * p->chunk, b = a + p->chunk < p->item_count ? a + p->chunk : p->item_count;
        for (; a < b; ++a) p->item(p->ctx, a, worker);
    }
}

static void *worker_main(void *arg)
{
    worker_arg *w = arg;
    long i;
    double t0 = thread_cpu_seconds();
    while ((i = take_index(w->p)) >= 0) {
        run_unit(w->p, i, w->worker);
        finish_index(w->p);
    }
    t0 = thread_cpu_seconds() - t0;
    pthread_mutex_lock(&cpu_lock);
    parallel_cpu += t0;
    pthread_mutex_unlock(&cpu_lock);
    return NULL;
}

static int run_pool(pool *p, int threads)
{
    pthread_t ids[256];
    worker_arg args[256];
    int started = 0, i, status = 0;
    if (threads > 256) threads = 256;
    if (threads > p->total) threads = p->total > 0 ? (int)p->total : 1;
    pthread_mutex_init(&p->lock, NULL);
    if (threads > 1) {
        for (i = 0; i < threads; ++i) {
            args[i].p = p;
            args[i].worker = i;
            if (pthread_create(&ids[i], NULL, worker_main, &args[i]) != 0) {
                status = -1;
                break;
            }
            started++;
        }
    }
    if (started == 0) {
        worker_arg self;
        self.p = p;
        self.worker = 0;
        worker_main(&self);
    }
    for (i = 0; i < started; ++i) pthread_join(ids[i], NULL);
    pthread_mutex_destroy(&p->lock);
    return status;
}

int parallel_tiles(int width, int height, int tile_size, int threads, tile_fn fn, void *ctx,
                   void (*progress)(void *, long, long), void *ctx_progress)
{
    pool p = {0};
    if (tile_size < 1) tile_size = 16;
    p.width = width;
    p.height = height;
    p.tile_size = tile_size;
    p.tiles_x = (width + tile_size - 1) / tile_size;
    p.total = (long)p.tiles_x * ((height + tile_size - 1) / tile_size);
    p.tile = fn;
    p.ctx = ctx;
    p.progress = progress;
    p.ctx_progress = ctx_progress;
    return run_pool(&p, threads);
}

int parallel_items(long count, int threads, item_fn fn, void *ctx)
{
    pool p = {0};
    p.item_count = count;
    p.chunk = count / (64L * (threads > 0 ? threads : 1)) + 1;
    p.total = (count + p.chunk - 1) / p.chunk;
    p.item = fn;
    p.ctx = ctx;
    return run_pool(&p, threads);
}
