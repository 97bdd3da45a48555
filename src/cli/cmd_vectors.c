/* restir vectors -o DIR: the golden test vectors (docs/oracle.md "Golden vectors");
 * restir vectors --check FILE...: re-evaluates vector files with this build. */
#include "cmd_vectors.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "restir/oracle/vectors.h"
#include "args.h"
#include "outputs_ready.h"
#include "signal_cleanup.h"

/* vectors_write, and after a failure (a full disk half-way through the families) the
 * files this call wrote and the directory it made are removed again: exit 2 leaves
 * nothing, not a set of vectors that looks complete. */
static int vectors_write_all(const char *dir, const char *const *families, long n, rerror *e)
{
    char path[4200];
    file_before *before = calloc((size_t)n, sizeof *before);
    struct stat st;
    int made_dir = stat(dir, &st) != 0, removed = 0;
    long i;
    if (!before) return rerror_set(e, "%s: out of memory", dir);
    for (i = 0; i < n; ++i) {
        snprintf(path, sizeof path, "%s/%s.jsonl", dir, families[i]);
        file_before_note(&before[i], path);
        cleanup_register(path);
    }
    cleanup_install("vectors");
    if (vectors_write(dir, e)) {
        for (i = 0; i < n; ++i) {
            snprintf(path, sizeof path, "%s/%s.jsonl", dir, families[i]);
            removed += file_remove_if_written(&before[i], path);
        }
        if (made_dir) rmdir(dir);
        if (removed || made_dir) {
            size_t len = strlen(e->msg);
            snprintf(e->msg + len, sizeof e->msg - len, "\nrestir vectors: removed the %d file(s)%s this call wrote",
                     removed, made_dir ? " and the directory" : "");
        }
        free(before);
        return -1;
    }
    free(before);
    return 0;
}

int cmd_vectors(int argc, char **argv)
{
    cli_option options[4];
    const char *positional[32], *dir = NULL;
    int check = 0, count, status, i, failed = 0;
    rerror e;
    {
        const cli_option rows[] = {
            {"-o", OPT_STRING, &dir, "write DIR/FAMILY.jsonl for every formula family", NULL, 0, 0, NULL},
            {"--check", OPT_FLAG, &check, "re-evaluate the given .jsonl files; exit 1 if a line does not reproduce",
             NULL, 0, 0, NULL},
        };
        for (i = 0; i < 2; ++i) options[i] = rows[i];
        memset(&options[2], 0, sizeof options[2]);
    }
    status = cli_parse("vectors", argc, argv, options, positional, 32, &count);
    if (status == 1) {
        cli_print_help(stdout, "vectors", "-o DIR | --check FILE.jsonl...", options);
        return 0;
    }
    if (status) return status;
    if (!check == !dir || (check && count == 0) || (dir && count > 0)) {
        fprintf(stderr, "restir vectors: expected -o DIR, or --check FILE.jsonl... (see restir vectors --help)\n");
        return 2;
    }
    if (dir) {
        const char *const *families = vectors_families();
        long n = 0;
        while (families[n]) ++n;
        if (vectors_write_all(dir, families, n, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            return 2;
        }
        /* Say what was written: a silent exit 0 looked like nothing happened. */
        printf("wrote %ld files %s/{%s,...}.jsonl (restir vectors --check %s/*.jsonl re-evaluates them)\n", n, dir,
               families[0], dir);
        return 0;
    }
    for (i = 0; i < count; ++i) {
        long lines, bad;
        int r = vectors_check_file(positional[i], &lines, &bad, &e);
        if (r < 0) {
            fprintf(stderr, "%s\n", e.msg);
            return 2;
        }
        printf("%s: %ld lines, %ld differ%s%s\n", positional[i], lines, bad, r ? "; first: " : "", r ? e.msg : "");
        if (r) failed = 1;
    }
    return failed;
}
