/* restir: dispatch `restir <command> [options]` to the command's own parser. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include "restir/cli/cli.h"
#include "cmd_bench.h"
#include "cmd_check.h"
#include "cmd_compare.h"
#include "cmd_diagnose.h"
#include "cmd_diff_dump.h"
#include "cmd_generate.h"
#include "cmd_info.h"
#include "cmd_inspect.h"
#include "cmd_merge.h"
#include "cmd_plot.h"
#include "cmd_render.h"
#include "cmd_replay.h"
#include "cmd_stats.h"
#include "cmd_vectors.h"

static int cmd_help(int argc, char **argv);

const cli_command cli_commands[] = {
    {"render", cmd_render, "render a scene (.scene or .obj) to PFM + PNG"},
    {"info", cmd_info, "scene statistics: triangles, materials, emitters, BVH"},
    {"compare", cmd_compare, "image metrics (MSE ... MAPE, FLIP) of TEST.pfm against REF.pfm; --covariance, --bias of K runs"},
    {"check", cmd_check, "statistical test: do two renderers estimate the same image?"},
    {"plot", cmd_plot, "line plots (log-log by default) of a CSV table as SVG"},
    {"bench", cmd_bench, "benchmarks as JSON: rays, restir, animation, realtime, stochastic, mutations, scaling, all"},
    {"merge", cmd_merge, "combine path-tracer runs: checkpoints, or images with --counts"},
    {"inspect", cmd_inspect, "one pixel's ReSTIR path sample and its shift to a neighbour"},
    {"generate", cmd_generate, "write a generated scene (10 kinds: ajar, atrium, sphere, ...) as OBJ + MTL + scene file"},
    {"replay", cmd_replay, "recompute one stage of one frame of a stage dump on its own inputs and diff it (docs/oracle.md)"},
    {"diagnose", cmd_diagnose, "which known bug (ablation, option variant) makes dump B from dump A's inputs"},
    {"diff-dump", cmd_diff_dump, "stage-by-stage comparison of two --dump-dir directories (docs/oracle.md)"},
    {"vectors", cmd_vectors, "golden test vectors (JSON lines, one file per formula family), or --check them"},
    {"stats", cmd_stats, "mean-ci: mean and t interval of numbers on stdin; t-table (for scripts/results*)"},
    {"help", cmd_help, "list the commands, or `help COMMAND` for one"},
    {NULL, NULL, NULL},
};

static const cli_command *find_command(const char *name)
{
    const cli_command *c;
    for (c = cli_commands; c->name; ++c)
        if (!strcmp(c->name, name)) return c;
    return NULL;
}

static void print_usage(FILE *out)
{
    const cli_command *c;
    fprintf(out, "usage: restir <command> [options]   (restir <command> --help for its options)\n\ncommands:\n");
    for (c = cli_commands; c->name; ++c) fprintf(out, "  %-10s %s\n", c->name, c->summary);
    fprintf(out, "\nrestir --version prints the version.\n");
}

static int cmd_help(int argc, char **argv)
{
    const cli_command *c;
    char help[] = "--help";
    char *sub_argv[3];
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) { /* help --help: the same list */
        print_usage(stdout);
        return 0;
    }
    c = find_command(argv[1]);
    if (!c) {
        fprintf(stderr, "restir: unknown command '%s'\n", argv[1]);
        return 2;
    }
    if (c->run == cmd_help) {
        print_usage(stdout);
        return 0;
    }
    sub_argv[0] = argv[1];
    sub_argv[1] = help;
    sub_argv[2] = NULL;
    return c->run(2, sub_argv);
}

/* Standard output is a promised output too (compare's table, bench's JSON, stats, help):
 * a full disk or a closed pipe found only at exit must not end in status 0. */
static int finish(const char *command, int status)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        int err = errno;
        fprintf(stderr, "restir %s: writing standard output failed: %s\n", command, err ? strerror(err) : "I/O error");
        if (status == 0) status = 2;
    }
    return status;
}

int main(int argc, char **argv)
{
    const cli_command *c;
    if (argc < 2) {
        print_usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version")) {
        printf("restir %s (%s estimator arithmetic)\n", RESTIR_VERSION,
#ifdef RESTIR_REAL_FLOAT
               "float"
#else
               "double"
#endif
        );
        return finish("--version", 0);
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        print_usage(stdout);
        return finish("--help", 0);
    }
    c = find_command(argv[1]);
    if (!c) {
        fprintf(stderr, "restir: unknown command '%s'\n", argv[1]);
        print_usage(stderr);
        return 2;
    }
    return finish(c->name, c->run(argc - 1, argv + 1));
}
