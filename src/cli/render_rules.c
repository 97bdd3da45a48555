/* The render command's compatibility rules (src/cli/render_rules.h). */
#include "render_rules.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image_io.h"
#include "collide.h"
#include "render_outputs.h"
#include "signal_cleanup.h"
#include "output.h"
#include "render_replay.h"
#include "stop.h"

static int ablation_index(const char *const *names, const char *name)
{
    int i;
    for (i = 0; names[i]; ++i)
        if (!strcmp(names[i], name)) return i;
    return -1;
}

/* Hands the shared options to the chosen method. */
/* --dump-dir DIR [--dump-stages a,b], --from-dump DIR --from-stage S (docs/oracle.md). */
static int apply_stage_options(render_args *a)
{
    rerror e;
    int any = a->sio.dump_dir || a->dump_stages || a->sio.from_dir || a->from_stage || a->dump_region || a->dump_halo ||
              a->history_from_dump;
    if (!any) return 0;
    if (!a->sequence) {
        fprintf(stderr, "restir render: --dump-dir, --dump-stages, --from-dump and --from-stage need --sequence A..B\n");
        return 2;
    }
    if (a->dump_stages && !a->sio.dump_dir) {
        fprintf(stderr, "restir render: --dump-stages needs --dump-dir DIR\n");
        return 2;
    }
    if (a->dump_region && (!a->sio.dump_dir || stage_region_parse(a->dump_region, &a->sio.region, &e))) {
        fprintf(stderr, "restir render: %s\n", a->sio.dump_dir ? e.msg : "--dump-region needs --dump-dir DIR");
        return 2;
    }
    if (a->dump_halo > 0 && !a->dump_region) {
        fprintf(stderr, "restir render: --dump-halo needs --dump-region X,Y,W,H\n");
        return 2;
    }
    a->sio.halo = a->dump_halo;
    if (!a->sio.from_dir != !a->from_stage) {
        fprintf(stderr, "restir render: --from-dump DIR and --from-stage S go together\n");
        return 2;
    }
    if (a->dump_stages && stage_io_set_stages(&a->sio, a->dump_stages, &e)) {
        fprintf(stderr, "restir render: %s\n", e.msg);
        return 2;
    }
    if (a->from_stage) {
        if (strlen(a->from_stage) >= sizeof a->sio.from_stage) {
            fprintf(stderr, "restir render: --from-stage: '%s' is too long\n", a->from_stage);
            return 2;
        }
        strcpy(a->sio.from_stage, a->from_stage);
    }
    stage_io_hook(&a->sio, &a->hook);
    a->seq.stages = &a->hook;
    return apply_replay_options(a); /* --history-from-dump, inspect --from-dump's pixel trace */
}

/* --sequence A..B, --mcap C|inf, --accumulate, --no-temporal (restir only). */
static int apply_sequence_options(render_args *a)
{
    char *end;
    if (a->mcap) {
        double c = strcmp(a->mcap, "inf") ? strtod(a->mcap, &end) : INFINITY;
        if (strcmp(a->mcap, "inf") && (end == a->mcap || *end || !(c > 0) || isinf(c))) {
            fprintf(stderr, "restir render: --mcap: expected a number > 0 or inf, got '%s'\n", a->mcap);
            return 2;
        }
        a->restir.temporal.mcap = c;
    }
    if (a->no_temporal) a->restir.temporal.enabled = 0;
    if ((a->sequence || a->accumulate) && a->method != METHOD_RESTIR) {
        fprintf(stderr, "restir render: --sequence and --accumulate need --method restir\n");
        return 2;
    }
    if (a->restir.mutation.count > 0 && !a->sequence) { /* mutations live in the real-time pipeline */
        fprintf(stderr, "restir render: --mutations needs --method restir --sequence A..B\n");
        return 2;
    }
    if (a->accumulate && !a->sequence) {
        fprintf(stderr, "restir render: --accumulate needs --sequence A..B\n");
        return 2;
    }
    if (!a->sequence) return 0;
    if (a->pt.o.time_limit > 0) {
        fprintf(stderr, "restir render: --sequence cannot be combined with --time-limit\n");
        return 2;
    }
    if (a->runs > 0 && (a->accumulate || a->pt.o.checkpoint_path || a->pt.o.resume_path)) {
        fprintf(stderr, "restir render: --sequence with --runs K: not with --accumulate, --checkpoint or --resume\n");
        return 2;
    }
    {
        long first = strtol(a->sequence, &end, 10), last;
        const char *rest = end;
        int ok = end != a->sequence && rest[0] == '.' && rest[1] == '.';
        if (ok) {
            last = strtol(rest + 2, &end, 10);
            ok = end != rest + 2 && !*end && first >= 0 && last >= first && last < 100000000;
        }
        if (!ok) {
            fprintf(stderr, "restir render: --sequence: expected A..B with 0 <= A <= B, got '%s'\n", a->sequence);
            return 2;
        }
        a->seq.first = (int)first;
        a->seq.last = (int)last;
    }
    a->seq.accumulate = a->accumulate;
    /* the path tracer's --checkpoint FILE / --resume FILE rows serve sequences too */
    a->seq.checkpoint = a->pt.o.checkpoint_path;
    a->seq.resume = a->pt.o.resume_path;
    return 0;
}

/* The options every method shares, parsed once into render_args, go to the method's
 * options here, once. */
void apply_common_options(render_args *a)
{
    a->pt.o.seed = a->restir.seed = a->seed;
    a->pt.o.jitter = a->restir.jitter = a->jitter;
    a->pt.o.threads = a->restir.threads = a->threads;
    a->pt.o.quiet = a->restir.quiet = a->quiet;
    a->pt.o.frame = a->frame;
    a->restir.stop_flag = &stop_requested;
    /* The duplicate counters are reported by --stats only (--dedup and --aov duplicates
     * read the map themselves). */
    a->restir.no_duplicate_stats = !a->stats;
}

/* An option that does not apply to the chosen method is an error with a hint, not a
 * silent no-op. The shared rows (--max-depth, --time-limit, --checkpoint, --resume,
 * --ablate) are checked by name. */
int check_method_options(const render_args *a, const cli_option *options, const int *given,
                                const method_rows *rows, int nrows)
{
    static const char *const hints[][2] = {
        {"--spp", "restir averages --frames N frames (or --time-limit) of --candidates N path trees"},
        {"--spatial-passes", "the path tracer has no reuse; --method restir"},
        {"--aov", "--method aov --aov CHANNEL"},
    };
    static const char *const pt_rows_restir_shares[] = {"--max-depth", "--time-limit", "--checkpoint", "--resume",
                                                        "--light-ris", "--light-tiles"};
    int r, i, h;
    for (r = 0; r < nrows; ++r) {
        if (rows[r].method == a->method) continue;
        for (i = rows[r].first; i < rows[r].end; ++i) {
            const char *hint = "see restir render --help";
            int shared = 0;
            if (!given[i]) continue;
            for (h = 0; h < (int)(sizeof pt_rows_restir_shares / sizeof *pt_rows_restir_shares) && rows[r].method == METHOD_PT; ++h)
                shared |= !strcmp(options[i].name, pt_rows_restir_shares[h]);
            if (shared) continue; /* restir takes them; aov: checked below */
            for (h = 0; h < (int)(sizeof hints / sizeof hints[0]); ++h)
                if (!strcmp(hints[h][0], options[i].name)) hint = hints[h][1];
            fprintf(stderr, "restir render: %s applies to --method %s, not --method %s (%s)\n", options[i].name,
                    method_names[rows[r].method], method_names[a->method], hint);
            return 2;
        }
    }
    if (a->method == METHOD_AOV) {
        static const char *const lighting[] = {"--max-depth", "--time-limit", "--checkpoint", "--resume", "--ablate",
                                               "--runs", "--light-ris", "--light-tiles"};
        for (h = 0; h < (int)(sizeof lighting / sizeof lighting[0]); ++h)
            if (cli_given(options, given, lighting[h])) {
                fprintf(stderr, "restir render: %s applies to --method pt and --method restir, not --method aov\n",
                        lighting[h]);
                return 2;
            }
    }
    if (a->sequence) { /* each was ignored (exit 0): a sequence renders exactly its frames A..B */
        static const char *const stills[] = {"--frame", "--first-frame", "--frames"};
        for (h = 0; h < 3; ++h)
            if (cli_given(options, given, stills[h])) {
                fprintf(stderr, "restir render: %s is for a still image; --sequence A..B renders frames A to B (one "
                                "pose each, one frame each)\n", stills[h]);
                return 2;
            }
    }
    if (a->runs > 0 && cli_given(options, given, "--progressive")) { /* was ignored: no run writes -o */
        fprintf(stderr, "restir render: --progressive rewrites -o during one render; --runs K writes PREFIX.mean.pfm "
                        "etc. once the K runs are done\n");
        return 2;
    }
    if (a->sequence && cli_given(options, given, "--png")) { /* was ignored: no such file, exit 0 */
        fprintf(stderr, "restir render: --png names one preview; --sequence A..B writes one per frame next to its PFM, "
                        "PREFIX.NNNN.png (-o PREFIX.pfm; --no-png for none)\n");
        return 2;
    }
    if (a->runs > 0 && !a->sequence && (cli_given(options, given, "--checkpoint") || cli_given(options, given, "--resume"))) {
        /* K runs are K renders with seeds S..S+K-1: one checkpoint file cannot hold them, and
         * one resumed state has one seed (it failed as "a different seed" for run 2) */
        fprintf(stderr, "restir render: --runs K with %s: the K runs have K seeds and one checkpoint holds one run "
                        "(checkpoint runs one by one with --seed S, then restir merge; or rerun --runs)\n",
                cli_given(options, given, "--checkpoint") ? "--checkpoint" : "--resume");
        return 2;
    }
    if (cli_given(options, given, "--sample-offset") && cli_given(options, given, "--resume")) {
        fprintf(stderr, "restir render: --sample-offset and --resume: a resumed run continues the checkpoint's own "
                        "sample range (for a disjoint range start a fresh run and use restir merge)\n");
        return 2;
    }
    if (a->method == METHOD_RESTIR && !a->sequence &&
        (cli_given(options, given, "--checkpoint") || cli_given(options, given, "--resume"))) {
        fprintf(stderr, "restir render: --checkpoint and --resume apply to --method pt and to --method restir with "
                        "--sequence A..B (offline restir frames are independent: --first-frame F continues a run)\n");
        return 2;
    }
    return 0;
}

/* Every file the command will write, checked before anything is rendered. */
int check_output_paths(const render_args *a, const char *out, const char *png)
{
    const char *paths[4];
    rerror e;
    size_t n = strlen(out);
    int i, count = 0;
    if (n >= 4 && !strcmp(out + n - 4, ".png")) {
        fprintf(stderr, "restir render: -o %s: -o names the PFM (the data); the PNG preview is written next to it "
                        "(use -o %.*s.pfm, or --png FILE for the preview's name)\n", out, (int)(n - 4), out);
        return 2;
    }
    if (image_output_check(out, &e)) {
        fprintf(stderr, "restir render: -o %s\n", e.msg);
        return 2;
    }
    paths[count++] = out;
    if (png[0]) paths[count++] = png;
    if (a->stats) paths[count++] = a->stats;
    if (a->pt.o.checkpoint_path) paths[count++] = a->pt.o.checkpoint_path;
    for (i = 0; i < count; ++i) {
        if (output_path_check(paths[i], &e)) {
            fprintf(stderr, "restir render: %s\n", e.msg);
            return 2;
        }
    }
    if (png[0] && !strcmp(png, out)) {
        fprintf(stderr, "restir render: --png %s is the PFM's own path\n", png);
        return 2;
    }
    if (render_outputs_distinct(a, out, png)) return 2;
    for (i = 0; i < count; ++i) cleanup_register(paths[i]); /* the second signal's cleanup (stop.c) */
    return 0;
}

/* --aov duplicates|age (issue 12): reservoirs exist only with --method restir (checked by
 * check_method_options), a temporal history only in sequences. */
static int apply_aov_options(render_args *a)
{
    if (a->method != METHOD_RESTIR || (a->aov != AOV_CHOICE_DUPLICATES && a->aov != AOV_CHOICE_AGE)) return 0;
    if (a->aov == AOV_CHOICE_AGE && !a->sequence) {
        fprintf(stderr, "restir render: --aov age needs --sequence A..B\n");
        return 2;
    }
    if (a->runs > 0) {
        fprintf(stderr, "restir render: --aov %s cannot be combined with --runs\n", aov_choices[a->aov]);
        return 2;
    }
    a->restir.output_aov = a->aov == AOV_CHOICE_AGE ? RESTIR_OUTPUT_AGE : RESTIR_OUTPUT_DUPLICATES;
    return 0;
}

int apply_shared_options(render_args *a, const cli_option *options, const int *given)
{
    if (apply_sequence_options(a) || apply_stage_options(a) || apply_aov_options(a)) return 2;
    if (a->method == METHOD_RESTIR) a->restir.time_limit = a->pt.o.time_limit; /* --time-limit */
    if (a->method == METHOD_RESTIR) a->restir.light_ris = a->pt.o.light_ris; /* --light-ris N, --light-tiles */
    if (a->method == METHOD_RESTIR && cli_given(options, given, "--max-depth")) {
        if (a->pt.o.max_depth < 2 || a->pt.o.max_depth > PATH_MAX_LENGTH) {
            fprintf(stderr, "restir render: --max-depth: restir needs 2..%d, got %d\n", PATH_MAX_LENGTH,
                    a->pt.o.max_depth);
            return 2;
        }
        a->restir.max_depth = a->pt.o.max_depth;
    }
    if (!a->ablate) return 0;
    if (a->method == METHOD_PT && render_pt_set_ablation(&a->pt, a->ablate) == 0) return 0;
    if (a->method == METHOD_RESTIR && ablation_index(restir_ablation_names, a->ablate) >= 0) {
        a->restir.ablation = (enum restir_ablation)ablation_index(restir_ablation_names, a->ablate);
        return 0;
    }
    fprintf(stderr, "restir render: --ablate: '%s' is not an ablation of --method %s\n", a->ablate,
            method_names[a->method]);
    return 2;
}
