/* The audit of every command beyond issue 27's list (docs/hostile-cases.md, second half):
 * what the table of scripts/hostile.sh shows but does not assert (a file left intact, a
 * number in a message), and the progress and signal behaviour of the commands beside
 * render (docs/cli.md, "Interrupted commands other than render", "Progress beyond
 * render"). Each check failed on the code before the audit. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "restir/core/image.h"
#include "restir/core/pfm.h"
#include "restir/core/progress.h"
#include "pt_util.h"
#include "test.h"

#define SMALL "scenes/cornell.scene --size 16x16 --threads 2 --max-depth 4"

static char out[65536];

/* Run k: noise in [0, 1) from a linear congruential stream (noise, not statistics). */
static void noise_run(void *user, int k, image *img)
{
    uint32_t state = test_seed() * 2654435761u + (uint32_t)k;
    size_t p;
    (void)user;
    for (p = 0; p < 3 * (size_t)img->width * (size_t)img->height; ++p) {
        state = state * 1664525u + 1013904223u;
        img->px[p] = (float)(state >> 8) / 16777216.0f;
    }
}

/* K noise images of 512 x 512 (3 MB each: reading four takes longer than the 0.01 s between
 * two lines) as NAMEk.pfm; their paths, space-separated. */
static int write_noise_runs(char *list, size_t size, const char *name, int k)
{
    return test_write_runs(list, size, 512, 512, k, name, noise_run, NULL);
}

/* Entries of a directory other than . and .. (-1 if it cannot be read). */
static int directory_entries(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *ent;
    int n = 0;
    if (!d) return -1;
    while ((ent = readdir(d)) != NULL)
        if (strcmp(ent->d_name, ".") && strcmp(ent->d_name, "..")) ++n;
    closedir(d);
    return n;
}

/* An output naming a link to a device is refused before any work and the link survives
 * (as root, the atomic write's rename replaced /dev/full itself by a regular file). */
TEST(audit_output_to_a_device_refused)
{
    static char runs[4096];
    char link[2048], ref[2048]; /* copies: test_tmp_path's buffers rotate */
    struct stat st;
    CHECK(write_noise_runs(runs, sizeof runs, "audit_dev", 2) == 0 && write_noise_runs(ref, sizeof ref, "audit_ref", 1) == 0);
    snprintf(link, sizeof link, "%s", test_tmp_path("audit-null-link"));
    remove(link);
    CHECK(symlink("/dev/null", link) == 0);
    CHECKF(test_cli(out, sizeof out, "compare %s %s --json %s", ref, ref, link) == 2 && strstr(out, "not a regular file"),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "render " SMALL " --spp 1 --no-png -o %s", link) == 2, "%s", out);
    CHECKF(test_cli(out, sizeof out, "check --a %s --ref %s --z-map %s", runs, ref, link) == 2, "%s", out);
    CHECK(lstat(link, &st) == 0 && S_ISLNK(st.st_mode)); /* not replaced */
    CHECK(lstat("/dev/null", &st) == 0 && S_ISCHR(st.st_mode));
    remove(link);
}

/* A line longer than the old 4096-byte buffer: every number whole (the split gave a mean
 * of 998.1 for 1..2000), and a mean that overflows is an error, not "inf +- -nan". */
TEST(audit_stats_mean_ci_reads_whole_lines)
{
    FILE *f = fopen(test_tmp_path("audit-line.txt"), "w");
    int i;
    CHECK(f != NULL);
    if (!f) return;
    for (i = 1; i <= 2000; ++i) fprintf(f, "%d ", i);
    fclose(f);
    CHECKF(test_cli(out, sizeof out, "stats mean-ci %s --format '%%.9g %%.9g'", test_tmp_path("audit-line.txt")) == 0 &&
               !strncmp(out, "1000.5 ", 7),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "stats mean-ci %s", test_write_file("audit-big.txt", "1e308 1e308 -1e308\n")) == 2 &&
               strstr(out, "overflows"),
           "%s", out);
}

/* Standard output is a promised output: a write error there is exit 2, not 0. */
TEST(audit_stdout_write_error_is_exit_2)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s stats t-table > /dev/full 2>/dev/null", RESTIR_BIN);
    CHECK(WEXITSTATUS(system(cmd)) == 2);
    snprintf(cmd, sizeof cmd, "%s help > /dev/full 2>/dev/null", RESTIR_BIN);
    CHECK(WEXITSTATUS(system(cmd)) == 2);
    snprintf(cmd, sizeof cmd, "%s help > /dev/null 2>/dev/null", RESTIR_BIN);
    CHECK(WEXITSTATUS(system(cmd)) == 0);
}

/* SIGTERM while generate builds or writes its OBJ: exit 143 and an empty directory (the
 * default action left OUT.obj.tmp.PID and OUT.mtl.tmp.PID). */
TEST(audit_sigterm_removes_partial_outputs)
{
    char dir[1024], cmd[4096];
    int status;
    snprintf(dir, sizeof dir, "%s", test_tmp_path("audit-sigterm"));
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
    CHECK(system(cmd) == 0);
    snprintf(cmd, sizeof cmd,
             "timeout --preserve-status -s TERM 0.4 %s generate sphere --subdivisions 600 -o '%s/s.obj' >/dev/null "
             "2>&1",
             RESTIR_BIN, dir);
    status = system(cmd);
    CHECKF(WIFEXITED(status) && WEXITSTATUS(status) == 143, "status %d", status);
    CHECKF(directory_entries(dir) == 0, "%d file(s) left in %s", directory_entries(dir), dir);
}

/* check, compare --covariance, merge and bench print plain progress lines in a log with
 * --progress lines (stderr is a file here); check --quiet none at all (a short call prints
 * none by default: progress.c's rule, tested with render in test_progress_stop.c). */
TEST(audit_progress_lines_beyond_render)
{
    static char runs[4096], runs_b[4096];
    CHECK(write_noise_runs(runs, sizeof runs, "audit_pa", 4) == 0 && write_noise_runs(runs_b, sizeof runs_b, "audit_pb", 4) == 0);
    CHECKF(test_cli(out, sizeof out, "check --a %s --b %s --progress lines --progress-every 0.01", runs, runs_b) != 2 &&
               strstr(out, "check: reading runs: 100% (8/8), ") && strstr(out, "ETA"),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "check --a %s --b %s --quiet --progress lines --progress-every 0.01", runs, runs_b) !=
                   2 &&
               !strstr(out, "ETA"),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "compare --covariance %s --radius 1 --progress lines --progress-every 0.01", runs) ==
                   0 &&
               strstr(out, "compare --covariance: 100% (4/4), "),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "merge -o %s %s --counts 1,1,1,1 --no-png --progress lines --progress-every 0.01",
                    test_tmp_path("audit-merged.pfm"), runs) == 0 &&
               strstr(out, "merge: reading inputs: 100% (4/4), "),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "bench rays --generated 4 --size 16x16 --repeats 1 --threads 1 --progress bar") == 0 &&
               strstr(out, "bench: step 1: rays on generated:displaced_sphere"),
           "%s", out);
    CHECK(test_cli(out, sizeof out, "merge -o x.pfm %s --counts 1,1,1,1 --progress sometimes", runs) == 2);
}

/* `restir generate` shows render's progress per phase (building the mesh, writing the
 * OBJ) as plain lines with the ETA in a log, none with --progress none, none by default for
 * a call shorter than --progress-every (5 s); the files are complete either way. */
TEST(audit_generate_progress_lines)
{
    const char *obj = test_tmp_path("audit-gen.obj");
    char *text;
    CHECKF(test_cli(out, sizeof out, "generate sphere --subdivisions 100 --progress lines --progress-every 0.01 -o %s", obj) ==
                   0 &&
               strstr(out, "generate: building the mesh: 100% (600/600), ") &&
               strstr(out, "generate: writing OBJ: 100% (") && strstr(out, "ETA"),
           "%s", out);
    text = test_read_text(obj);
    CHECKF(text && strstr(text, "# 60006 vertices, 120002 triangles"), "%.200s", text ? text : "(no OBJ)");
    free(text);
    CHECKF(test_cli(out, sizeof out, "generate sphere --subdivisions 100 --progress none --progress-every 0.01 -o %s", obj) ==
                   0 && !strstr(out, "generate:"),
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "generate sphere --subdivisions 20 -o %s", obj) == 0 && !strstr(out, "ETA"), "%s", out);
    CHECK(test_cli(out, sizeof out, "generate ajar --progress sometimes -o %s", obj) == 2);
}

/* SIGINT during `restir bench` stops it within about a second of the signal, not at the next
 * benchmark boundary (a step takes up to 8 s; `bench restir` is one step of 6 s and more):
 * exit 130, one line on stderr naming the step cut short, and a JSON array that holds the
 * complete steps' entries only and ends with an "incomplete" entry saying so (never a closed
 * array that looks complete). `bench animation` is cut wherever the signal lands: its
 * entries must number the complete steps. */
static int bench_interrupted(const char *args, double *seconds, char **json, char **err)
{
    char cmd[4096];
    const char *json_path = test_tmp_path("audit-bench.json"), *err_path = test_tmp_path("audit-bench.err");
    double t0 = now_seconds();
    int status;
    snprintf(cmd, sizeof cmd, "timeout --preserve-status -s INT 0.5 %s bench %s >'%s' 2>'%s'", RESTIR_BIN, args,
             json_path, err_path);
    status = system(cmd);
    *seconds = now_seconds() - t0 - 0.5;
    *json = test_read_text(json_path);
    *err = test_read_text(err_path);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static int count_of(const char *text, const char *what)
{
    int n = 0;
    for (; text && (text = strstr(text, what)) != NULL; text += strlen(what)) ++n;
    return n;
}

TEST(audit_bench_stops_within_a_second)
{
    static const char *const args[] = {"restir --threads 2", "animation --generated 150 --threads 2"};
    size_t i;
    for (i = 0; i < 2; ++i) {
        char *json, *err, tail[128];
        double seconds;
        int status = bench_interrupted(args[i], &seconds, &json, &err), step = 0, kept;
        const char *line = err ? strstr(err, "restir bench: interrupted by SIGINT during step ") : NULL;
        CHECKF(status == 130, "bench %s: status %d", args[i], status);
        CHECKF(seconds < 2.0, "bench %s: exited %.2f s after the signal", args[i], seconds);
        CHECKF(line && sscanf(line, "restir bench: interrupted by SIGINT during step %d", &step) == 1 && step >= 1 &&
                   strchr(line, '\n') && strchr(line, '\n')[1] == '\0', /* one line, the last */
               "bench %s: %s", args[i], err ? err : "(no stderr)");
        kept = step - 1;
        snprintf(tail, sizeof tail, "{\"bench\": \"incomplete\", \"complete\": false, \"reason\": \"SIGINT\", "
                                    "\"complete_steps\": %d}\n]\n", kept);
        CHECKF(json && strlen(json) >= strlen(tail) && !strcmp(json + strlen(json) - strlen(tail), tail),
               "bench %s: the JSON does not end with %s:\n%.3000s", args[i], tail, json ? json : "");
        if (i == 0)
            CHECKF(step == 1 && !strstr(json ? json : "", "restir_equal_time") && !strstr(json ? json : "", "{\"bench\": \"restir\""),
                   "bench restir: %.3000s", json ? json : "");
        else
            CHECKF(count_of(json, "{\"bench\": \"animation\"") == kept, "bench animation, %d complete steps: %.3000s",
                   kept, json ? json : "");
        free(json);
        free(err);
    }
}
