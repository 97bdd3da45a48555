/* Outputs checked before work and undone after a failure (outputs_ready.h). */
#include "outputs_ready.h"

#include <stdio.h>
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

int inputs_distinct(const char *command, const named_file *ins, int n_in)
{
    int i, j;
    for (i = 0; i < n_in; ++i)
        for (j = i + 1; j < n_in; ++j)
            if (ins[i].path && ins[j].path && same_file(ins[i].path, ins[j].path)) {
                fprintf(stderr, "restir %s: %s %s and %s %s are one file: the same file twice is not two independent inputs\n",
                        command, ins[i].role, ins[i].path, ins[j].role, ins[j].path);
                return 2;
            }
    return 0;
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
