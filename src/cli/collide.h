/* Private to src/cli. Outputs that would overwrite each other or an input, refused before any
 * work (docs/cli.md, "Outputs never overwrite each other or an input"). */
#ifndef RESTIR_CLI_COLLIDE_H
#define RESTIR_CLI_COLLIDE_H

/* One file a command names: its path and the option that named it ("-o", "--stats",
 * "the PNG preview", "input 2"). A NULL or empty path is skipped. */
typedef struct {
    const char *path;
    const char *role;
} named_file;

/* 1 if a and b name the same file: the same string, the same inode (both exist), or the
 * same resolved directory and the same last component (neither need exist). */
int same_file(const char *a, const char *b);

/* 1 if path names dir itself or a file anywhere below it (resolved as in same_file; the
 * path need not exist). */
int path_within(const char *path, const char *dir);

/* Checks that no two of outs[] name the same file and that no output names one of
 * ins[]; exit status 2 after printing "restir CMD: ROLE PATH is also ROLE", else 0.
 * allow_in_out: an input that may also be an output (render's --resume FILE
 * --checkpoint FILE continues one checkpoint in place), or NULL. */
int outputs_distinct(const char *command, const named_file *outs, int n_out, const named_file *ins, int n_in,
                     const char *allow_in_out);

#endif
