/* Atomic output: write to "PATH.tmp.PID", then rename over PATH on commit.
 * A failure (or a crash) never leaves a truncated file at PATH. */
#ifndef RESTIR_ATOMIC_FILE_H
#define RESTIR_ATOMIC_FILE_H

#include <stdio.h>
#include "restir/core/error.h"

typedef struct {
    FILE *fp;
    char path[4096];
    char tmp_path[4200];
} atomic_file;

int atomic_file_open(atomic_file *f, const char *path, rerror *e);
/* Flushes, closes and renames; on any error the temporary is removed. */
int atomic_file_commit(atomic_file *f, rerror *e);
/* Closes and removes the temporary (safe to call after a failed commit). */
void atomic_file_abort(atomic_file *f);

/* Creates the directory of `path` (one level, like `mkdir -p` of the parent) if missing. */
int ensure_parent_dir(const char *path, rerror *e);

#endif
