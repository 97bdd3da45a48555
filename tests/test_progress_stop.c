/* Progress where people look, and Ctrl-C that stops (issue 27): plain progress lines with
 * the ETA when stderr is a log, --progress none|bar|lines; SIGINT stops every method at a
 * tile boundary within about a second, keeping what is complete; a second signal exits at
 * once. Timing bounds are generous (a loaded 2-core machine); the signals are sent by
 * `timeout` or raised by the process itself. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "../src/cli/stop.h"
#include "restir/core/progress.h"
#include "restir/render/pt.h"
#include "restir/scene/scene.h"
#include "test.h"

static char out[65536];

/* A log (stderr is a file here) gets plain lines "pt: 37% (a/b), x s elapsed, ETA y s". */
TEST(progress_lines_when_stderr_is_a_log)
{
    const char *pfm = test_tmp_path("progress-lines.pfm");
    int status = test_cli(out, sizeof out,
                          "render scenes/cornell.scene --size 32x32 --max-depth 6 --spp 120 --threads 2 --no-png "
                          "--progress-every 0.02 -o %s", pfm);
    CHECKF(status == 0, "status %d: %s", status, out);
    CHECKF(strstr(out, "pt: ") && strstr(out, "% (") && strstr(out, " s elapsed, ETA ") && !strchr(out, '\r'),
           "no progress line in a log:\n%.2000s", out);
    status = test_cli(out, sizeof out,
                      "render scenes/cornell.scene --size 32x32 --max-depth 6 --spp 120 --threads 2 --no-png "
                      "--progress none --progress-every 0.02 -o %s", pfm);
    CHECKF(status == 0 && !strstr(out, "ETA"), "--progress none printed progress:\n%.2000s", out);
    /* the default (auto: lines every 5 s in a log) keeps a short render's log clean */
    status = test_cli(out, sizeof out, "render scenes/cornell.scene --size 16x16 --spp 4 --threads 2 --no-png -o %s", pfm);
    CHECKF(status == 0 && !strstr(out, "ETA"), "a short render printed progress:\n%.2000s", out);
    /* one long offline ReSTIR frame: the heartbeat says it is alive before the frame ends */
    status = test_cli(out, sizeof out,
                      "render scenes/cornell.scene --size 48x48 --method restir --preset gris-offline --frames 1 "
                      "--threads 2 --no-png --progress lines --progress-every 0.02 -o %s", pfm);
    CHECKF(status == 0 && strstr(out, "restir: 0% (0/1), ") && strstr(out, "ETA unknown (the first step is running)"),
           "no heartbeat during the frame:\n%.2000s", out);
    status = test_cli(out, sizeof out, "render scenes/cornell.scene --size 16x16 --progress sometimes -o %s", pfm);
    CHECKF(status == 2 && strstr(out, "--progress"), "status %d: %s", status, out);
}

/* `timeout --preserve-status -s INT 0.5 restir ARGS`: the status, the output, the seconds. */
static int interrupt_after(const char *args, double *seconds)
{
    double t0 = now_seconds();
    int status = test_cli_signal(out, sizeof out, "INT", 0.5, args);
    *seconds = now_seconds() - t0; /* with the reading of the (short) output */
    return status;
}

/* Each method stops within a generous bound of the signal (a tile, not a frame: one
 * frame of these renders takes seconds), exits 130 and says what it kept. */
TEST(stop_latency_every_method)
{
    static const struct {
        const char *args, *expect;
    } cases[] = {
        /* pt: one 1-spp pass of 512^2 paths of up to 200 segments in a closed box */
        {"render scenes/cornell.scene --size 512x512 --max-depth 200 --spp 100 --threads 2 --quiet", "interrupted by SIGINT"},
        /* offline ReSTIR: 32 path trees, 3 spatial passes per frame */
        {"render scenes/cornell.scene --size 160x160 --method restir --preset gris-offline --frames 100 --threads 2 --quiet",
         "interrupted by SIGINT"},
        /* the real-time pipeline */
        {"render scenes/cornell.scene --size 160x160 --method restir --preset gris-offline --sequence 0..100 --no-temporal "
         "--threads 2 --quiet", "interrupted by SIGINT"},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char args[4096];
        double seconds;
        int status;
        snprintf(args, sizeof args, "%s --no-png -o %s", cases[i].args, test_tmp_path("stop-latency.pfm"));
        status = interrupt_after(args, &seconds);
        CHECKF(status == 130 && strstr(out, cases[i].expect), "case %zu: status %d after %.2f s: %s", i, status, seconds,
               out);
        CHECKF(seconds < 0.5 + 3.0, "case %zu: stopped %.2f s after the start (signal at 0.5 s)", i, seconds);
    }
}

/* Raises SIGINT twice, `gap` seconds apart, in a child with the render's handlers; returns
 * the child's exit status (5: it survived both). */
static int child_two_signals(double gap)
{
    int status;
    pid_t pid;
    fflush(stdout);
    fflush(stderr);
    pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        struct timespec ts;
        FILE *null = fopen("/dev/null", "w"); /* its one line (written to fd 2) is not the suite's output */
        if (null) dup2(fileno(null), 2);
        stop_signals_install();
        raise(SIGINT); /* the first: a request to stop (the flag) */
        if (!stop_signal()) _exit(3);
        ts.tv_sec = (time_t)gap;
        ts.tv_nsec = (long)((gap - (double)ts.tv_sec) * 1e9);
        nanosleep(&ts, NULL);
        raise(SIGINT); /* the second: _exit(130) from the handler, unless it is a repeat */
        _exit(5);
    }
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
    return WEXITSTATUS(status);
}

/* A second SIGINT exits at once (status 130) without waiting for the render to stop; the
 * same signal delivered twice at once (GNU timeout: to the child and to its group) is one
 * request. */
TEST(stop_second_signal_exits_at_once)
{
    int status = child_two_signals(2 * STOP_REPEAT_SECONDS);
    CHECKF(status == 130, "a second signal: child status %d", status);
    status = child_two_signals(0.0);
    CHECKF(status == 5, "a repeated delivery: child status %d", status);
}

/* A stop flag makes every pass 1 spp, staged and cancellable: the same image bits. */
TEST(pt_stop_flag_staging_same_bits)
{
    scene s;
    pt_options o;
    pt_result a, b;
    rerror e;
    volatile sig_atomic_t flag = 0;
    size_t i, n;
    CHECKF(scene_load(&s, "scenes/cornell.scene", &e) == 0, "%s", e.msg);
    s.width = 24;
    s.height = 20;
    CHECK(scene_prepare(&s, &e) == 0);
    pt_options_default(&o);
    o.spp = 8;
    o.max_depth = 5;
    o.threads = 2;
    o.quiet = 1;
    CHECKF(pt_render(&s, &o, &a, &e) == 0, "%s", e.msg);
    o.stop_flag = &flag;
    CHECKF(pt_render(&s, &o, &b, &e) == 0, "%s", e.msg);
    n = 3 * (size_t)s.width * (size_t)s.height;
    for (i = 0; i < n; ++i)
        CHECKF(a.state.sum[i] == b.state.sum[i] && a.state.sum_sq[i] == b.state.sum_sq[i], "pixel value %zu differs", i);
    pt_result_free(&a);
    pt_result_free(&b);
    scene_free(&s);
}
