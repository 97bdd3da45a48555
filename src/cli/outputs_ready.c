/* Outputs checked before work and undone after a failure (outputs_ready.h). */
#include "outputs_ready.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/error.h"
#include "output.h"
#include "signal_cleanup.h"

int outputs_ready(const char *command, const named_file *outs, int n_out, const named_file *ins, int n_in)
{
    rerror e;
    int i;
    for (i = 0; i < n_out; ++i)
        if (outs[i].path && outs[i].path[0] && output_path_check(outs[i].path, &e)) {
            fprintf(stderr, "restir %s: %s %s\n", command, outs[i].role, e.msg);
            return 2;
        }
    if (outputs_distinct(command, outs, n_out, ins, n_in, NULL)) return 2;
    for (i = 0; i < n_out; ++i) cleanup_register(outs[i].path);
    cleanup_install(command);
    return 0;
}

/* One input's identity: inputs_distinct sorts these (K runs of check or merge may be
 * thousands: comparing every pair with stat(2) was quadratic). */
typedef struct {
    dev_t dev;
    ino_t ino;
    int index;
} input_id;

static int compare_ids(const void *pa, const void *pb)
{
    const input_id *a = pa, *b = pb;
    if (a->dev != b->dev) return a->dev < b->dev ? -1 : 1;
    if (a->ino != b->ino) return a->ino < b->ino ? -1 : 1;
    return a->index - b->index;
}

int inputs_distinct(const char *command, const named_file *ins, int n_in)
{
    input_id *ids = n_in > 0 ? malloc((size_t)n_in * sizeof *ids) : NULL;
    struct stat st;
    int i, n = 0, status = 0;
    if (n_in > 0 && !ids) return 0; /* no memory for the check: the inputs are read anyway */
    for (i = 0; i < n_in; ++i) /* a missing input is reported when it is read */
        if (ins[i].path && stat(ins[i].path, &st) == 0) {
            ids[n].dev = st.st_dev;
            ids[n].ino = st.st_ino;
            ids[n++].index = i;
        }
    qsort(ids, (size_t)n, sizeof *ids, compare_ids);
    for (i = 1; i < n && !status; ++i)
        if (ids[i].dev == ids[i - 1].dev && ids[i].ino == ids[i - 1].ino) {
            const named_file *a = &ins[ids[i - 1].index], *b = &ins[ids[i].index];
            fprintf(stderr, "restir %s: %s %s and %s %s are one file: the same file twice is not two independent inputs\n",
                    command, a->role, a->path, b->role, b->path);
            status = 2;
        }
    free(ids);
    return status;
}

void message_unstaged(char *msg)
{
    char *p;
    while ((p = strstr(msg, ".staged.")) != NULL) {
        char *end = p + strlen(".staged.");
        while (*end >= '0' && *end <= '9') ++end;
        memmove(p, end, strlen(end) + 1);
    }
}

void file_before_note(file_before *b, const char *path)
{
    struct stat st;
    b->existed = stat(path, &st) == 0;
    b->dev = b->existed ? st.st_dev : 0;
    b->ino = b->existed ? st.st_ino : 0;
}

int file_remove_if_written(const file_before *b, const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) return 0;
    if (b->existed && st.st_dev == b->dev && st.st_ino == b->ino) return 0; /* not touched by this call */
    return remove(path) == 0;
}
