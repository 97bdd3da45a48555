/* restir diagnose A B (docs/oracle.md §7): which known bug makes dump B?
 *
 * A is an oracle dump (its manifest's command line gives the scene, options and frames); B
 * the dump of the build under test, of the same scene and options. The oracle is re-run on
 * A's command line once per variant: unmodified, each `--ablate` name, and option variants a
 * GPU build gets wrong by construction (no M-cap, the other pairwise confidence form, no
 * stochastic confidence scaling). Each variant's dump is compared with B record by record
 * (the base record's bytes, docs/formats.md "Record": same sample and every field); the
 * agreement of a frame and stage is the fraction of identical records. Variants are ranked
 * by mean agreement; the verdict names the best one and the first frame and stage where
 * the unmodified oracle departs from B. A variant the options refuse (e.g. pair-mis without
 * paired reuse) is listed as not applicable. */
#include "cmd_diagnose.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "restir/core/json_text.h"
#include "restir/oracle/stage_dump.h"
#include "restir/restir/reservoir_dump.h"
#include "restir/restir/restir_context.h"
#include "args.h"
#include "cmd_render.h"
#include "cmd_replay.h"

#define DIAG_MAX_VARIANTS 32
#define DIAG_MAX_ROWS 512 /* frames x stages compared */

typedef struct {
    char name[96];      /* "oracle", "--ablate NAME" or the options */
    const char *args[3]; /* extra render arguments */
    int applicable;
    double row[DIAG_MAX_ROWS]; /* agreement per compared (frame, stage) */
    double mean;
    int index; /* order of the list (ties keep it) */
} variant;

typedef struct {
    long frame;
    char stage[STAGE_NAME_SIZE];
} row_key;

/* Option variants: what a GPU build gets wrong as a whole choice rather than a line. */
static const char *const option_variants[][3] = {
    {"--mcap", "inf", "no temporal M-cap"},
    {"--mis", "talbot", "spatial MIS: Talbot"},
    {"--mis", "pairwise", "spatial MIS: pairwise"},
    {"--mis", "pairwise-defensive", "spatial MIS: defensive pairwise"},
    {"--mis", "constant", "spatial MIS: constant"},
    {"--temporal-mis", "talbot", "temporal MIS: Talbot"},
    {"--temporal-mis", "pairwise", "temporal MIS: pairwise"},
    {"--temporal-mis", "pairwise-defensive", "temporal MIS: defensive pairwise"},
    {"--temporal-mis", "constant", "temporal MIS: constant"},
    {"--pairwise-confidence", "falcor", "the Falcor confidence form of defensive pairwise MIS"},
    {"--pairwise-confidence", "stochastic", "the Stochastic MIS Eq. 11 confidence form"},
    {"--no-confidence-scaling", NULL, "stochastic pairwise MIS without the c_i N~/M scaling"},
};

/* What a named ablation means, for the verdict (restir_context.h). */
static const char *ablation_meaning(const char *name)
{
    static const char *const table[][2] = {
        {"jacobian", "the shift Jacobian |dT/dx| taken as 1"},
        {"light-pdf", "the light pdf not recomputed after a reconnection at k = d"},
        {"temporal-target", "the temporal reverse shift evaluated with the current frame's camera and scene"},
        {"temporal-suffix", "samples crossing frames with their cached suffix (animated scenes)"},
        {"stochastic-p", "stochastic pairwise MIS without the P(i) correction"},
        {"footprint-base-only", "the footprint criterion tested on the base path only"},
        {"dual-mv-vertex", "a dual-MV history resampled from the occluder pixel's x1"},
        {"pair-mis", "the pair step dropping one side of each pair from the MIS"},
        {"mutation-w", "an accepted mutation keeping W"},
        {"rv-kernel", "the mutation kernel ratio taken as 1"},
        {"light-ris-pdf", "the BSDF side's MIS weight with p_0 under light RIS"},
        {"mcap-current", "the temporal M-cap applied to the current reservoir instead of the history"},
        {"neighbor-rng", "the neighbour choice's RNG sample index off by one"},
    };
    size_t i;
    for (i = 0; i < sizeof table / sizeof table[0]; ++i)
        if (!strcmp(table[i][0], name)) return table[i][1];
    return "";
}

/* The fraction of B's records identical to the variant's (B may be a region dump). */
static int agreement(const char *vdir, const char *bdir, const stage_manifest *bm, long frame, const char *stage,
                     double *out, rerror *e)
{
    char pv[4200], pb[4200];
    reservoir *rv = NULL, *rb = NULL;
    reservoir_dump_info iv, ib;
    size_t size = reservoir_record_size(0);
    unsigned char *xv = malloc(size), *xb = malloc(size);
    long n, i, same = 0;
    int status = -1;
    stage_dump_path(pv, sizeof pv, vdir, (uint32_t)frame, stage, "resv");
    stage_dump_path(pb, sizeof pb, bdir, (uint32_t)frame, stage, "resv");
    if (!xv || !xb) {
        rerror_set(e, "out of memory");
        goto done;
    }
    if (reservoir_dump_read(pv, &rv, &iv, e) || reservoir_dump_read(pb, &rb, &ib, e)) goto done;
    n = (long)ib.width * (long)ib.height;
    for (i = 0; i < n; ++i) {
        long x = bm->region.width ? bm->region.x + i % (long)ib.width : i % (long)ib.width;
        long y = bm->region.width ? bm->region.y + i / (long)ib.width : i / (long)ib.width;
        if (x >= (long)iv.width || y >= (long)iv.height) {
            rerror_set(e, "%s: pixel (%ld, %ld) is outside A's %ux%u image", pb, x, y, iv.width, iv.height);
            goto done;
        }
        reservoir_record_encode(&rv[y * (long)iv.width + x], 0, xv);
        reservoir_record_encode(&rb[i], 0, xb);
        same += !memcmp(xv, xb, size);
    }
    *out = n > 0 ? (double)same / (double)n : 1;
    status = 0;
done:
    free(rv);
    free(rb);
    free(xv);
    free(xb);
    return status;
}

/* Removes what a variant's render wrote (its dump and frames) and the directory. */
static void remove_variant(const char *dir, const stage_manifest *am)
{
    char path[4300];
    long f;
    int s;
    for (f = am->first; f <= am->last; ++f) {
        for (s = 0; s < am->n_order; ++s) {
            stage_dump_path(path, sizeof path, dir, (uint32_t)f, am->order[s], "resv");
            remove(path);
        }
        stage_dump_path(path, sizeof path, dir, (uint32_t)f, "gbuffer", "gbuf");
        remove(path);
        snprintf(path, sizeof path, "%.4200s/frame_%04ld", dir, f);
        rmdir(path);
        snprintf(path, sizeof path, "%.4200s/frame.%04ld.pfm", dir, f);
        remove(path);
    }
    snprintf(path, sizeof path, "%.4200s/manifest.json", dir);
    remove(path);
    rmdir(dir);
}

/* Runs variant v on A's command line into dir and fills its agreement rows. */
static int run_variant(variant *v, const char *adir, const char *bdir, const stage_manifest *am,
                       const stage_manifest *bm, const row_key *rows, int n_rows, const char *dir, rerror *e)
{
    replay_args l;
    char frames[64], prefix[4300];
    int i, status = 0;
    memset(&l, 0, sizeof l);
    if (replay_command_line(adir, 1, &l, e)) return -1;
    snprintf(frames, sizeof frames, "%ld..%ld", am->first, am->last);
    snprintf(prefix, sizeof prefix, "%.4200s/frame.pfm", dir);
    status |= replay_args_push(&l, "--sequence") | replay_args_push(&l, frames) | replay_args_push(&l, "-o") |
              replay_args_push(&l, prefix) | replay_args_push(&l, "--no-png") | replay_args_push(&l, "--quiet") |
              replay_args_push(&l, "--dump-dir") | replay_args_push(&l, dir);
    for (i = 0; i < 3 && v->args[i]; ++i) status |= replay_args_push(&l, v->args[i]);
    if (status) {
        replay_args_free(&l);
        return rerror_set(e, "diagnose: the command line is too long");
    }
    {
        /* a variant the options refuse is not applicable; its messages are not the user's */
        int saved, null;
        fflush(stderr);
        saved = dup(2);
        null = open("/dev/null", O_WRONLY);
        if (saved >= 0 && null >= 0) dup2(null, 2);
        status = cmd_render(l.argc, l.argv);
        fflush(stderr);
        if (saved >= 0 && null >= 0) dup2(saved, 2);
        if (saved >= 0) close(saved);
        if (null >= 0) close(null);
    }
    replay_args_free(&l);
    v->applicable = status == 0;
    v->mean = 0;
    if (!v->applicable) {
        remove_variant(dir, am);
        return 0;
    }
    for (i = 0; i < n_rows; ++i) {
        if (agreement(dir, bdir, bm, rows[i].frame, rows[i].stage, &v->row[i], e)) {
            remove_variant(dir, am);
            return -1;
        }
        v->mean += v->row[i] / n_rows;
    }
    remove_variant(dir, am);
    return 0;
}

/* The (frame, stage) rows both dumps hold, in A's frame and stage order. */
static int compared_rows(const char *bdir, const stage_manifest *am, const stage_manifest *bm, row_key *rows)
{
    int n = 0, s;
    long f;
    for (f = am->first; f <= am->last; ++f)
        for (s = 0; s < am->n_order; ++s) {
            char path[4200];
            FILE *fp;
            if (f < bm->first || f > bm->last || !stage_manifest_dumped(bm, am->order[s])) continue;
            stage_dump_path(path, sizeof path, bdir, (uint32_t)f, am->order[s], "resv");
            if (!(fp = fopen(path, "rb"))) continue;
            fclose(fp);
            if (n == DIAG_MAX_ROWS) return n;
            rows[n].frame = f;
            snprintf(rows[n].stage, sizeof rows[n].stage, "%s", am->order[s]);
            ++n;
        }
    return n;
}

static int by_mean(const void *a, const void *b)
{
    const variant *x = a, *y = b;
    if (x->applicable != y->applicable) return y->applicable - x->applicable;
    if (x->mean != y->mean) return x->mean < y->mean ? 1 : -1;
    return x->index - y->index;
}

static void print_verdict(const variant *vs, int n, const variant *oracle, const row_key *rows, int n_rows)
{
    int i, first = -1;
    for (i = 0; i < n_rows && first < 0; ++i)
        if (oracle->row[i] < 1) first = i;
    if (first < 0) {
        printf("verdict: B agrees with the unmodified oracle in every compared record: no known bug to name\n");
        return;
    }
    printf("B departs from the oracle first at frame %ld, stage %s (%.4f of the records identical)\n",
           rows[first].frame, rows[first].stage, oracle->row[first]);
    if (vs[0].mean <= oracle->mean || vs[0].row[first] <= oracle->row[first]) {
        printf("verdict: no variant explains B better than the unmodified oracle: an unknown bug in stage %s "
               "(restir inspect --from-dump B --frame %ld --stage %s --pixel X,Y explains a pixel)\n",
               rows[first].stage, rows[first].frame, rows[first].stage);
        return;
    }
    printf("verdict: most likely %s", vs[0].name);
    if (!strncmp(vs[0].name, "--ablate ", 9)) printf(" (%s)", ablation_meaning(vs[0].name + 9));
    printf(", first visible at frame %ld, stage %s: %.4f of the records identical there (unmodified oracle %.4f), "
           "%.4f over all compared stages\n",
           rows[first].frame, rows[first].stage, vs[0].row[first], oracle->row[first], vs[0].mean);
    for (i = 1; i < n && vs[i].applicable && vs[i].mean == vs[0].mean; ++i)
        printf("  equally likely: %s\n", vs[i].name);
}

/* --json: the table and the verdict as one object. */
static void print_json(const variant *vs, int n, const variant *oracle, const row_key *rows, int n_rows)
{
    int i, r, first = -1;
    for (r = 0; r < n_rows && first < 0; ++r)
        if (oracle->row[r] < 1) first = r;
    printf("{\"rows\": [");
    for (r = 0; r < n_rows; ++r) printf("%s{\"frame\": %ld, \"stage\": \"%s\"}", r ? ", " : "", rows[r].frame, rows[r].stage);
    printf("],\n \"variants\": [");
    for (i = 0; i < n; ++i) {
        printf("%s\n  {\"name\": ", i ? "," : "");
        json_put_string(stdout, vs[i].name);
        printf(", \"applicable\": %s", vs[i].applicable ? "true" : "false");
        if (vs[i].applicable) {
            printf(", \"mean\": %.6f, \"agreement\": [", vs[i].mean);
            for (r = 0; r < n_rows; ++r) printf("%s%.6f", r ? ", " : "", vs[i].row[r]);
            printf("]");
        }
        printf("}");
    }
    printf("],\n \"departs\": ");
    if (first < 0) printf("null");
    else printf("{\"frame\": %ld, \"stage\": \"%s\", \"oracle_agreement\": %.6f}", rows[first].frame,
                rows[first].stage, oracle->row[first]);
    printf(",\n \"most_likely\": [");
    if (first >= 0 && vs[0].mean > oracle->mean && vs[0].row[first] > oracle->row[first])
        for (i = 0; i < n && vs[i].applicable && vs[i].mean == vs[0].mean; ++i) {
            printf("%s", i ? ", " : "");
            json_put_string(stdout, vs[i].name);
        }
    printf("]}\n");
}

int cmd_diagnose(int argc, char **argv)
{
    static variant vs[DIAG_MAX_VARIANTS];
    static row_key rows[DIAG_MAX_ROWS];
    stage_manifest am, bm;
    const char *positional[2];
    char tmpdir[] = "/tmp/restir-diagnose-XXXXXX", dir[4300];
    int count, status, n = 0, n_rows, i, r;
    variant oracle;
    rerror e;
    int json = 0;
    cli_option options[] = {
        {"--json", OPT_FLAG, &json, "one JSON object: compared rows, every variant's agreement per row, where B departs, the most likely variants", NULL, 0, 0, NULL},
        {NULL, 0, NULL, NULL, NULL, 0, 0, NULL},
    };
    status = cli_parse("diagnose", argc, argv, options, positional, 2, &count);
    if (status == 1) {
        cli_print_help(stdout, "diagnose", "A B  (A: an oracle stage dump, B: the build's dump of the same run)", options);
        return 0;
    }
    if (status) return status;
    if (count != 2) {
        fprintf(stderr, "restir diagnose: expected A B (two --dump-dir directories; see restir diagnose --help)\n");
        return 2;
    }
    if (stage_manifest_read(positional[0], &am, &e) || stage_manifest_read(positional[1], &bm, &e)) {
        fprintf(stderr, "restir diagnose: %s\n", e.msg);
        return 2;
    }
    n_rows = compared_rows(positional[1], &am, &bm, rows);
    if (n_rows == 0) {
        fprintf(stderr, "restir diagnose: %s holds no stage file of A's frames %ld..%ld and stages\n", positional[1],
                am.first, am.last);
        return 2;
    }
    memset(vs, 0, sizeof vs);
    snprintf(vs[n++].name, sizeof vs[0].name, "the unmodified oracle");
    for (i = 1; restir_ablation_names[i] && n < DIAG_MAX_VARIANTS; ++i, ++n) {
        snprintf(vs[n].name, sizeof vs[n].name, "--ablate %s", restir_ablation_names[i]);
        vs[n].args[0] = "--ablate";
        vs[n].args[1] = restir_ablation_names[i];
    }
    for (i = 0; i < (int)(sizeof option_variants / sizeof option_variants[0]) && n < DIAG_MAX_VARIANTS; ++i, ++n) {
        snprintf(vs[n].name, sizeof vs[n].name, "%s%s%s (%s)", option_variants[i][0], option_variants[i][1] ? " " : "",
                 option_variants[i][1] ? option_variants[i][1] : "", option_variants[i][2]);
        vs[n].args[0] = option_variants[i][0];
        vs[n].args[1] = option_variants[i][1];
    }
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "restir diagnose: cannot create a temporary directory in /tmp\n");
        return 2;
    }
    for (i = 0; i < n; ++i) {
        snprintf(dir, sizeof dir, "%s/v%02d", tmpdir, i);
        if (run_variant(&vs[i], positional[0], positional[1], &am, &bm, rows, n_rows, dir, &e)) {
            fprintf(stderr, "restir diagnose: %s\n", e.msg);
            rmdir(tmpdir);
            return 2;
        }
    }
    rmdir(tmpdir);
    if (!vs[0].applicable) {
        fprintf(stderr, "restir diagnose: the oracle cannot re-run A's command line (restir render says why: try it)\n");
        return 2;
    }
    for (i = 0; i < n; ++i) vs[i].index = i;
    oracle = vs[0];
    qsort(vs, (size_t)n, sizeof vs[0], by_mean);
    if (json) {
        print_json(vs, n, &oracle, rows, n_rows);
        return 0;
    }
    printf("%d frame(s) x stage(s) compared; agreement = fraction of B's records identical to the variant's\n", n_rows);
    printf("%-8s  %-84s  %s\n", "mean", "variant", "first stage below 1");
    for (i = 0; i < n; ++i) {
        if (!vs[i].applicable) {
            printf("%-8s  %-84s\n", "n/a", vs[i].name);
            continue;
        }
        printf("%.6f  %-84s  ", vs[i].mean, vs[i].name);
        for (r = 0; r < n_rows && vs[i].row[r] >= 1; ++r) continue;
        if (r < n_rows) printf("frame %ld %s (%.4f)\n", rows[r].frame, rows[r].stage, vs[i].row[r]);
        else printf("-\n");
    }
    print_verdict(vs, n, &oracle, rows, n_rows);
    return 0;
}
