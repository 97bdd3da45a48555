/* A group of output files committed together: each file is first written completely
 * (by its own atomic writer) to a staged name next to its final path, and only when
 * every file of the group is staged are they renamed into place. An error before the
 * commit removes the staged files, so a command that fails leaves no partial outputs
 * and never replaces an older output with a new one of an incomplete set. */
#ifndef RESTIR_OUTPUT_SET_H
#define RESTIR_OUTPUT_SET_H

#include "restir/core/error.h"

#define OUTPUT_SET_MAX 8

typedef struct {
    int count;
    char final_path[OUTPUT_SET_MAX][4096];
    char staged_path[OUTPUT_SET_MAX][4160];
} output_set;

void output_set_init(output_set *s);
/* Registers `final_path` and returns the staged path to write it to (stable until
 * output_set_abort), or NULL with *e filled. */
const char *output_set_stage(output_set *s, const char *final_path, rerror *e);
/* Renames every staged file to its final path. If a rename fails, removes what is left
 * staged and the files of the set already renamed: no incomplete set is left. */
int output_set_commit(output_set *s, rerror *e);
/* Removes all staged files. */
void output_set_abort(output_set *s);

#endif
