/* The per-pixel spatial count of `--stats` after a restart (noticed in session 12): it divided
 * by the initial stage's pixel count, which is 0 when the initial stage is read from a dump,
 * and printed the total shifts as "per pixel". A restart from our own dump must report what
 * the uninterrupted run reports. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "test.h"

#define RESTART_COMMON "scenes/pillars.scene --method restir --preset gris-realtime --size 24x16 " \
                       "--sequence 0..1 --quiet --no-png --threads 2"

/* The last "shifts_per_pixel_per_frame" value of a stats file (the run's total), or -1. */
static double last_shifts_per_pixel(const char *path)
{
    char *text = test_read_text(path), *at, *last = NULL;
    double v = -1;
    if (!text) return -1;
    for (at = text; (at = strstr(at, "\"shifts_per_pixel_per_frame\": ")) != NULL; ++at) last = at;
    if (last) v = atof(last + strlen("\"shifts_per_pixel_per_frame\": "));
    free(text);
    return v;
}

TEST(stats_shifts_per_pixel_survive_restart)
{
    static char out[8192];
    char a[1100], b[1100];
    double whole, restarted;
    const char *t = test_tmpdir();
    snprintf(a, sizeof a, "%s/spp_whole.json", t);
    snprintf(b, sizeof b, "%s/spp_restart.json", t);
    CHECKF(test_cli(out, sizeof out, "render " RESTART_COMMON " -o %s/spp_a.pfm --dump-dir %s/spp_dump --stats %s", t,
                    t, a) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out,
                    "render " RESTART_COMMON " -o %s/spp_b.pfm --from-dump %s/spp_dump --from-stage temporal --stats %s",
                    t, t, b) == 0,
           "%s", out);
    whole = last_shifts_per_pixel(a);
    restarted = last_shifts_per_pixel(b);
    CHECKF(whole > 0 && whole < 10 && restarted == whole, "whole %g, restarted %g", whole, restarted);
}
