/* Output groups: stage everything, then rename everything (see output_set.h). */
#include "restir/metrics/output_set.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

void output_set_init(output_set *s) { s->count = 0; }

const char *output_set_stage(output_set *s, const char *final_path, rerror *e)
{
    int i = s->count;
    if (i >= OUTPUT_SET_MAX) {
        rerror_set(e, "%s: too many output files in one group", final_path);
        return NULL;
    }
    if (strlen(final_path) >= sizeof s->final_path[0]) {
        rerror_set(e, "%s: path too long", final_path);
        return NULL;
    }
    strcpy(s->final_path[i], final_path);
    snprintf(s->staged_path[i], sizeof s->staged_path[i], "%s.staged.%ld", final_path, (long)getpid());
    s->count++;
    return s->staged_path[i];
}

int output_set_commit(output_set *s, rerror *e)
{
    int i;
    for (i = 0; i < s->count; ++i) {
        if (rename(s->staged_path[i], s->final_path[i]) != 0) {
            int err = errno;
            int j;
            /* no incomplete set: the files of this set already renamed go too */
            for (j = 0; j < i; ++j) remove(s->final_path[j]);
            for (j = i; j < s->count; ++j) remove(s->staged_path[j]);
            s->count = 0;
            return rerror_set(e, "%s: cannot rename into place: %s", s->final_path[i], strerror(err));
        }
    }
    s->count = 0;
    return 0;
}

void output_set_abort(output_set *s)
{
    int i;
    for (i = 0; i < s->count; ++i) remove(s->staged_path[i]);
    s->count = 0;
}
