/* restir diff-dump A B: stage-by-stage comparison of two stage dumps (docs/oracle.md,
 * docs/cli.md). A's manifest gives the frames and the stage order; every stage file of A
 * must exist in B. Exit 0 if every stage passes the tolerances, 1 if one does not, 2 on
 * bad input. */
#include "cmd_diff_dump.h"

#include <math.h>
#include <stdio.h>
#include <sys/stat.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/json_text.h"
#include "restir/oracle/dump_diff.h"
#include "restir/oracle/stage_dump.h"
#include "args.h"

typedef struct {
    const char *a, *b;
    int json, stat, first;
    double max_rel_w, max_rel_target, max_rel_conf, min_same, z;
} diff_args;

static void print_pixel_text(const stage_manifest *m, const dump_diff_pixel *d, long frame)
{
    printf("    pixel %ld,%ld: %s  W %.17g | %.17g  p^ %.17g | %.17g  c %.17g | %.17g\n", d->x, d->y,
           d->same_sample ? "same sample" : "OTHER SAMPLE", d->w[0], d->w[1], d->target[0], d->target[1], d->conf[0],
           d->conf[1]);
    if (!d->same_sample)
        printf("      ids (pixel %u, sample %u, d %d, tech %d) | (pixel %u, sample %u, d %d, tech %d)\n", d->id_pixel[0],
               d->id_sample[0], d->length[0], d->technique[0], d->id_pixel[1], d->id_sample[1], d->length[1],
               d->technique[1]);
    printf("      reproduce: restir inspect %s --pixel %ld,%ld --seed %ld --first-frame %ld%s\n",
           m->scene[0] ? m->scene : "SCENE", d->x, d->y, m->seed, frame, m->inspect_args);
}

static void print_pixel_json(const stage_manifest *m, const dump_diff_pixel *d, long frame)
{
    char cmd[5300];
    printf("{\"x\": %ld, \"y\": %ld, \"same_sample\": %s, \"W\": [", d->x, d->y, d->same_sample ? "true" : "false");
    json_put_number(stdout, d->w[0]);
    printf(", ");
    json_put_number(stdout, d->w[1]);
    printf("], \"target\": [");
    json_put_number(stdout, d->target[0]);
    printf(", ");
    json_put_number(stdout, d->target[1]);
    printf("], \"confidence\": [");
    json_put_number(stdout, d->conf[0]);
    printf(", ");
    json_put_number(stdout, d->conf[1]);
    snprintf(cmd, sizeof cmd, "%s --pixel %ld,%ld --seed %ld --first-frame %ld%s", m->scene[0] ? m->scene : "SCENE",
             d->x, d->y, m->seed, frame, m->inspect_args);
    printf("], \"inspect_args\": ");
    json_put_string(stdout, cmd);
    printf("}");
}

static void put_q(const char *name, const double *q)
{
    int i;
    printf("\"%s\": [", name);
    for (i = 0; i < 4; ++i) {
        if (i) printf(", ");
        json_put_number(stdout, q[i]);
    }
    printf("]");
}

/* ", "name": [a, b], "zname": z */
static void put_means(const char *name, const double *v, const char *zname, double z)
{
    printf(", \"%s\": [", name);
    json_put_number(stdout, v[0]);
    printf(", ");
    json_put_number(stdout, v[1]);
    printf("], \"%s\": ", zname);
    json_put_number(stdout, z);
}

/* One (frame, stage) row; returns 1 if it passes. */
static int report_row(const diff_args *a, const stage_manifest *m, long frame, const char *stage, const dump_diff_result *r,
                      const dump_diff_tolerance *t, int *first_row)
{
    double same = (double)r->same / (double)r->pixels, z = dump_diff_mean_z(r), zc = dump_diff_confidence_z(r),
           zn = dump_diff_nonempty_z(r);
    int pass = a->stat ? fabs(z) <= a->z && fabs(zc) <= a->z && fabs(zn) <= a->z : dump_diff_pass(r, t), i;
    if (a->json) {
        printf("%s\n  {\"frame\": %ld, \"stage\": ", *first_row ? "" : ",", frame);
        json_put_string(stdout, stage);
        printf(", \"pixels\": %ld, \"same_sample\": ", r->pixels);
        json_put_number(stdout, same);
        printf(", \"differing\": %ld, \"target_agreement\": ", r->differing);
        json_put_number(stdout, r->same ? (double)r->target_agree / (double)r->same : 1.0);
        printf(", ");
        put_q("rel_err_W", r->q_w);
        printf(", ");
        put_q("rel_err_target", r->q_target);
        printf(", ");
        put_q("rel_err_confidence", r->q_conf);
        put_means("mean_FW", r->mean_fw, "z", z);
        put_means("mean_confidence", r->mean_c, "z_confidence", zc);
        put_means("nonempty", r->mean_full, "z_nonempty", zn);
        printf(", \"pass\": %s, \"first_differing\": [", pass ? "true" : "false");
        for (i = 0; i < r->n_first; ++i) {
            if (i) printf(", ");
            print_pixel_json(m, &r->firsts[i], frame);
        }
        printf("]}");
    } else {
        printf("frame %4ld %-12s same %.6f  W rel err p50 %.3g p99 %.3g max %.3g  p^ max %.3g  c max %.3g  "
               "mean F*W %.6g | %.6g (z %+.2f)  %s\n",
               frame, stage, same, r->q_w[0], r->q_w[2], r->q_w[3], r->q_target[3], r->q_conf[3], r->mean_fw[0],
               r->mean_fw[1], z, pass ? "ok" : "DIFFERS");
        if (a->stat)
            printf("    mean c %.6g | %.6g (z %+.2f)  non-empty %.6f | %.6f (z %+.2f)\n", r->mean_c[0], r->mean_c[1], zc,
                   r->mean_full[0], r->mean_full[1], zn);
        else
            for (i = 0; i < r->n_first; ++i) print_pixel_text(m, &r->firsts[i], frame);
    }
    *first_row = 0;
    return pass;
}

static int diff_stage(const diff_args *a, const stage_manifest *m, long frame, const char *stage,
                      const dump_diff_tolerance *t, int *first_row, int *first_fail_reported, rerror *e)
{
    char pa[4200], pb[4200];
    reservoir *ra, *rb;
    reservoir_dump_info ia, ib;
    dump_diff_result r;
    FILE *probe;
    int pass;
    stage_dump_path(pa, sizeof pa, a->a, (uint32_t)frame, stage, "resv");
    stage_dump_path(pb, sizeof pb, a->b, (uint32_t)frame, stage, "resv");
    if (!(probe = fopen(pa, "rb"))) return 1; /* not dumped (--dump-stages) */
    fclose(probe);
    if (reservoir_dump_read(pa, &ra, &ia, e)) return -1;
    if (reservoir_dump_read(pb, &rb, &ib, e)) {
        free(ra);
        return -1;
    }
    if (ia.width != ib.width || ia.height != ib.height) {
        free(ra);
        free(rb);
        return rerror_set(e, "%s is %ux%u, %s is %ux%u", pa, ia.width, ia.height, pb, ib.width, ib.height);
    }
    if (dump_diff(ra, rb, (long)ia.width, (long)ia.height, t, &r, e)) {
        free(ra);
        free(rb);
        return -1;
    }
    free(ra);
    free(rb);
    pass = report_row(a, m, frame, stage, &r, t, first_row);
    if (!pass && !*first_fail_reported && !a->json) {
        fprintf(stderr, "restir diff-dump: first difference: frame %ld, stage %s", frame, stage);
        if (r.n_first > 0 && !a->stat) fprintf(stderr, ", pixel %ld,%ld", r.firsts[0].x, r.firsts[0].y);
        fprintf(stderr, "\n");
        *first_fail_reported = 1;
    }
    return pass;
}

static int frame_dir_exists(const char *dir, long frame)
{
    char path[4200];
    struct stat st;
    snprintf(path, sizeof path, "%s/frame_%04ld", dir, frame);
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int cmd_diff_dump(int argc, char **argv)
{
    diff_args a;
    cli_option options[16];
    const char *positional[2];
    int count, status, n, i, all_pass = 1, first_row = 1, reported = 0;
    long f, last;
    stage_manifest m;
    dump_diff_tolerance t;
    rerror e;
    memset(&a, 0, sizeof a);
    dump_diff_tolerance_default(&t);
    a.first = t.first;
    a.min_same = t.min_same;
    a.z = 4.0;
    {
        const cli_option rows[] = {
            {"--json", OPT_FLAG, &a.json, "one JSON object with a row per frame and stage", NULL, 0, 0, NULL},
            {"--max-rel-w", OPT_REAL, &a.max_rel_w, "relative error of W a same-sample pixel may have (default 0)", NULL, 0, 1e300, NULL},
            {"--max-rel-target", OPT_REAL, &a.max_rel_target, "relative error of the target p^ (default 0)", NULL, 0, 1e300, NULL},
            {"--max-rel-confidence", OPT_REAL, &a.max_rel_conf, "relative error of the confidence c (default 0)", NULL, 0, 1e300, NULL},
            {"--min-same", OPT_REAL, &a.min_same, "fraction of pixels that must hold the same sample (default 1)", NULL, 0, 1, NULL},
            {"--first", OPT_INT, &a.first, "differing pixels listed per stage (default 5, at most 32)", NULL, 0, DUMP_DIFF_MAX_FIRST, NULL},
            {"--stat", OPT_FLAG, &a.stat, "statistical mode for builds with another RNG: compare the image means of luminance(F) W, of c and of the non-empty fraction per stage", NULL, 0, 0, NULL},
            {"--z", OPT_REAL, &a.z, "with --stat: largest |z| that passes (default 4)", NULL, 0, 1e300, NULL},
        };
        for (n = 0; n < (int)(sizeof rows / sizeof rows[0]); ++n) options[n] = rows[n];
    }
    memset(&options[n], 0, sizeof options[n]);
    status = cli_parse("diff-dump", argc, argv, options, positional, 2, &count);
    if (status == 1) {
        cli_print_help(stdout, "diff-dump", "A B [options]  (two --dump-dir directories)", options);
        return 0;
    }
    if (status) return status;
    if (count != 2) {
        fprintf(stderr, "restir diff-dump: expected two dump directories A B (see restir diff-dump --help)\n");
        return 2;
    }
    a.a = positional[0];
    a.b = positional[1];
    t.max_rel_w = a.max_rel_w;
    t.max_rel_target = a.max_rel_target;
    t.max_rel_conf = a.max_rel_conf;
    t.min_same = a.min_same;
    t.first = a.first;
    if (stage_manifest_read(a.a, &m, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (a.json) {
        printf("{\"a\": ");
        json_put_string(stdout, a.a);
        printf(", \"b\": ");
        json_put_string(stdout, a.b);
        printf(", \"mode\": \"%s\", \"rows\": [", a.stat ? "stat" : "identity");
    }
    /* The frames A holds: "written" of them from the first (an interrupted dump has fewer
     * than first..last); a missing frame directory is an error, not a pass. */
    last = m.written >= 0 ? m.first + m.written - 1 : m.last;
    for (f = m.first; f <= last; ++f) {
        if (!frame_dir_exists(a.a, f)) {
            if (a.json) printf("\n]}\n");
            fprintf(stderr, "%s/frame_%04ld: missing (the manifest says frames %ld..%ld)\n", a.a, f, m.first, last);
            return 2;
        }
        for (i = 0; i < m.n_order; ++i) {
            int pass = diff_stage(&a, &m, f, m.order[i], &t, &first_row, &reported, &e);
            if (pass < 0) {
                if (a.json) printf("\n]}\n");
                fprintf(stderr, "%s\n", e.msg);
                return 2;
            }
            if (!pass) all_pass = 0;
        }
    }
    if (a.json) printf("\n], \"pass\": %s}\n", all_pass ? "true" : "false");
    return all_pass ? 0 : 1;
}
