/* restir vectors -o DIR: the golden test vectors (docs/oracle.md "Golden vectors");
 * restir vectors --check FILE...: re-evaluates vector files with this build. */
#include "cmd_vectors.h"

#include <stdio.h>
#include <string.h>
#include "restir/oracle/vectors.h"
#include "args.h"

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
        if (vectors_write(dir, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            return 2;
        }
        while (families[n]) ++n;
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
