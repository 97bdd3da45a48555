/* capture.h: stdout and stderr into a file by dup2, and back. */
#include "capture.h"

#include <stdio.h>
#include <unistd.h>
#include "test.h"

static int saved_out = -1, saved_err = -1;
static char path[1024];

void capture_begin(void)
{
    FILE *f;
    snprintf(path, sizeof path, "%s", test_tmp_path("capture.txt"));
    fflush(stdout);
    fflush(stderr);
    f = fopen(path, "wb");
    if (!f) return;
    saved_out = dup(1);
    saved_err = dup(2);
    dup2(fileno(f), 1);
    dup2(fileno(f), 2);
    fclose(f);
}

void capture_end(char *out, size_t size)
{
    FILE *f;
    size_t n = 0;
    fflush(stdout);
    fflush(stderr);
    if (saved_out >= 0) {
        dup2(saved_out, 1);
        dup2(saved_err, 2);
        close(saved_out);
        close(saved_err);
        saved_out = saved_err = -1;
    }
    if (!out || !size) return;
    f = fopen(path, "rb");
    if (f) {
        n = fread(out, 1, size - 1, f);
        fclose(f);
    }
    out[n] = '\0';
}
