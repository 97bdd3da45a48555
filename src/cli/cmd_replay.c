/* restir replay and restir inspect --from-dump (cmd_replay.h): one stage of one frame of a
 * dump recomputed on the dump's own inputs by re-running its recorded render command. */
#include "cmd_replay.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "restir/core/json_text.h"
#include "restir/core/rng.h"
#include "restir/oracle/dump_diff.h"
#include "restir/oracle/region_input.h"
#include "restir/oracle/stage_dump.h"
#include "restir/restir/mis.h"
#include "restir/restir/mutate.h"
#include "args.h"
#include "cmd_diff_dump.h"
#include "cmd_render.h"
#include "render_replay.h"

int replay_args_push(replay_args *l, const char *s)
{
    size_t n = strlen(s) + 1;
    if (l->argc >= REPLAY_MAX_ARGS - 1 || !(l->argv[l->argc] = malloc(n))) return -1;
    memcpy(l->argv[l->argc++], s, n);
    l->argv[l->argc] = NULL;
    return 0;
}

void replay_args_free(replay_args *l)
{
    int i;
    for (i = 0; i < l->argc; ++i) free(l->argv[i]);
    l->argc = 0;
}

/* Options of the recorded command that a replay replaces (with a value, then flags). */
static const char *const dropped_valued[] = {"-o", "--png", "--sequence", "--dump-dir", "--dump-stages",
                                             "--dump-region", "--dump-halo", "--from-dump", "--from-stage", "--stats", "--runs",
                                             "--checkpoint", "--checkpoint-every", "--resume", "--progress",
                                             "--progress-every", NULL};
static const char *const dropped_ablate[] = {"--ablate", NULL};
static const char *const dropped_flags[] = {"--quiet", "--no-png", "--accumulate", "--history-from-dump", NULL};

static int listed(const char *const *names, const char *arg, int *with_value)
{
    int i;
    for (i = 0; names[i]; ++i) {
        size_t n = strlen(names[i]);
        if (!strncmp(arg, names[i], n) && (arg[n] == '\0' || arg[n] == '=')) {
            *with_value = arg[n] == '=';
            return 1;
        }
    }
    return 0;
}

int replay_command_line(const char *dir, int drop_ablate, replay_args *l, rerror *e)
{
    char path[4200], key[64], arg[4096];
    json_reader r;
    int found = 0, skip = 0;
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    if (json_reader_open(&r, path, e)) return -1;
    if (json_expect(&r, '{')) goto fail;
    for (;;) {
        if (json_read_string(&r, key, sizeof key) || json_expect(&r, ':')) goto fail;
        if (strcmp(key, "command_line")) {
            if (json_skip_value(&r)) goto fail;
        } else {
            found = 1;
            if (json_expect(&r, '[')) goto fail;
            while (json_peek(&r) != ']') {
                int inline_value = 0;
                if (json_read_string(&r, arg, sizeof arg)) goto fail;
                if (skip) skip = 0;
                else if (listed(dropped_valued, arg, &inline_value) ||
                         (drop_ablate && listed(dropped_ablate, arg, &inline_value)))
                    skip = !inline_value;
                else if (!listed(dropped_flags, arg, &inline_value) && replay_args_push(l, arg)) {
                    rerror_set(e, "out of memory");
                    goto fail;
                }
                if (json_peek(&r) == ',') r.pos++;
            }
            if (json_expect(&r, ']')) goto fail;
        }
        if (json_peek(&r) != ',') break;
        r.pos++;
    }
    json_reader_close(&r);
    if (!found || l->argc < 2 || strcmp(l->argv[0], "render"))
        return rerror_at(e, path, 0, "no \"command_line\" of a restir render: the dump does not say which options "
                                     "made it (--options-from ORACLE_DUMP takes them from the oracle's dump of the "
                                     "same run)");
    return 0;
fail:
    json_reader_close(&r);
    return -1;
}

/* What a replay of stage S of frame F needs from DIR, checked before anything runs. */
typedef struct {
    const char *dir, *stage;
    const char *options_dir;    /* --options-from: whose command line (NULL: dir's) */
    long frame;
    stage_manifest m;
    char prev[STAGE_NAME_SIZE]; /* the stage before S in DIR's stage order ("" if S is first) */
    int history;                /* S is temporal and F is not DIR's first frame */
    /* a region dump (manifest "region"): its files expanded into a temporary whole-image
       dump (region_input.h) that the render restarts from; rin.check: the pixels replayed */
    int region;
    region_input_plan rin;
    char tmp[64];
} replay_plan;

static int file_exists(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (fp) fclose(fp);
    return fp != NULL;
}

static int plan_replay(replay_plan *p, rerror *e)
{
    char path[4200];
    int i, at = -1;
    if (stage_manifest_read(p->dir, &p->m, e)) return -1;
    if (p->frame < p->m.first || p->frame > p->m.last)
        return rerror_set(e, "%s/manifest.json: frame %ld is not in the dump's frames %ld..%ld", p->dir, p->frame,
                          p->m.first, p->m.last);
    for (i = 0; i < p->m.n_order; ++i)
        if (!strcmp(p->m.order[i], p->stage)) at = i;
    if (at < 0) {
        char list[STAGE_MAX * (STAGE_NAME_SIZE + 2)] = "";
        for (i = 0; i < p->m.n_order; ++i) {
            if (i) strcat(list, ", ");
            strcat(list, p->m.order[i]);
        }
        return rerror_set(e, "%s/manifest.json: no stage '%s' (stage order: %s)", p->dir, p->stage, list);
    }
    p->prev[0] = '\0';
    if (at > 0) {
        snprintf(p->prev, sizeof p->prev, "%s", p->m.order[at - 1]);
        stage_dump_path(path, sizeof path, p->dir, (uint32_t)p->frame, p->prev, "resv");
        if (!stage_manifest_dumped(&p->m, p->prev) || !file_exists(path))
            return rerror_set(e, "%s: missing: stage '%s' of frame %ld needs the output of '%s' (the stage before it)",
                              path, p->stage, p->frame, p->prev);
    }
    p->history = !strcmp(p->stage, "temporal") && p->frame > p->m.first;
    if (p->history) {
        const char *last = p->m.order[p->m.n_order - 1];
        stage_dump_path(path, sizeof path, p->dir, (uint32_t)(p->frame - 1), last, "resv");
        if (!stage_manifest_dumped(&p->m, last) || !file_exists(path))
            return rerror_set(e, "%s: missing: the temporal stage of frame %ld needs frame %ld's final reservoirs "
                                 "(its last stage, '%s')", path, p->frame, p->frame - 1, last);
    }
    return 0;
}

/* The render command of the plan (out_prefix: -o; dump_dir: NULL or --dump-dir with S only). */
static int plan_command(const replay_plan *p, const char *out_prefix, const char *dump_dir, replay_args *l, rerror *e)
{
    char frames[64];
    int status = 0;
    if (replay_command_line(p->options_dir ? p->options_dir : p->dir, 0, l, e)) return -1;
    snprintf(frames, sizeof frames, "%ld..%ld", p->frame, p->frame);
    status |= replay_args_push(l, "--sequence") | replay_args_push(l, frames) | replay_args_push(l, "-o") | replay_args_push(l, out_prefix);
    status |= replay_args_push(l, "--no-png") | replay_args_push(l, "--quiet");
    if (p->prev[0]) status |= replay_args_push(l, "--from-dump") | replay_args_push(l, p->region ? p->tmp : p->dir) | replay_args_push(l, "--from-stage") | replay_args_push(l, p->prev);
    if (p->history) status |= replay_args_push(l, "--history-from-dump");
    if (dump_dir) status |= replay_args_push(l, "--dump-dir") | replay_args_push(l, dump_dir) | replay_args_push(l, "--dump-stages") | replay_args_push(l, p->stage);
    if (dump_dir && p->region) { /* only the replayed pixels: the others' inputs are not all in the dump */
        char rect[128];
        snprintf(rect, sizeof rect, "%ld,%ld,%ld,%ld", p->rin.check.x, p->rin.check.y, p->rin.check.width,
                 p->rin.check.height);
        status |= replay_args_push(l, "--dump-region") | replay_args_push(l, rect);
    }
    if (status) return rerror_set(e, "replay: the command line is too long");
    return 0;
}

/* A region dump as input (docs/oracle.md §6): the pixels of `check` (inside the dumped
 * rectangle) are replayed; the stage before S and frame F-1's final state are expanded into
 * a temporary whole-image dump with empty records outside the rectangle, and the render's
 * listener refuses a checked pixel whose stage reads outside it (region_input.h). */
static int plan_region(replay_plan *p, const stage_region *check, rerror *e)
{
    const stage_region *r = &p->m.region;
    const char *tmpdir = getenv("TMPDIR");
    if (check->x < r->x || check->y < r->y || check->x + check->width > r->x + r->width ||
        check->y + check->height > r->y + r->height)
        return rerror_set(e, "%s/manifest.json: pixels %ld,%ld,%ld,%ld are not all in the dumped rectangle "
                             "%ld,%ld,%ld,%ld (missing input: their own records)", p->dir, check->x, check->y,
                          check->width, check->height, r->x, r->y, r->width, r->height);
    if (!p->prev[0]) return 0; /* the first stage reads nothing of the dump */
    snprintf(p->tmp, sizeof p->tmp, "%.40s/restir-region-XXXXXX", tmpdir && *tmpdir && strlen(tmpdir) < 40 ? tmpdir : "/tmp");
    if (!mkdtemp(p->tmp)) return rerror_set(e, "%s: cannot create a temporary directory", p->tmp);
    p->region = 1;
    p->rin.dir = p->dir;
    p->rin.tmp = p->tmp;
    p->rin.stage = p->stage;
    p->rin.prev = p->prev;
    p->rin.m = &p->m;
    p->rin.frame = p->frame;
    p->rin.history = p->history;
    p->rin.check = *check;
    if (region_input_dir_make(&p->rin, e)) {
        region_input_dir_remove(&p->rin);
        p->region = 0;
        return -1;
    }
    return 0;
}

static void plan_done(replay_plan *p)
{
    if (p->region) region_input_dir_remove(&p->rin);
    p->region = 0;
}

static void remove_frame_image(const char *prefix, long frame)
{
    char path[4300];
    snprintf(path, sizeof path, "%.4200s.%04d.pfm", prefix, (int)frame);
    remove(path);
}

/* ---- restir replay ------------------------------------------------------------------------ */

/* The replayed pixels of a region dump: --region, else the halo's core, else the rectangle. */
static int replay_region(replay_plan *p, const char *text, rerror *e)
{
    stage_region check;
    if (!p->m.region.width) {
        if (text) return rerror_set(e, "--region: %s is not a region dump (its manifest has no \"region\")", p->dir);
        return 0;
    }
    if (text) {
        if (stage_region_parse(text, &check, e)) return -1;
    } else
        check = p->m.core.width ? p->m.core : p->m.region;
    return plan_region(p, &check, e);
}

int cmd_replay(int argc, char **argv)
{
    replay_plan p;
    replay_args l;
    const char *positional[1], *stage = NULL, *out = NULL, *options_from = NULL, *region = NULL;
    long frame = -1;
    int count, status, frame_i = -1;
    char prefix[4200];
    rerror e;
    cli_option options[] = {
        {"--frame", OPT_INT, &frame_i, "the frame F to recompute", NULL, 0, 1e8, NULL},
        {"--stage", OPT_STRING, &stage, "the stage S to recompute (a name of DIR's stage order)", NULL, 0, 0, NULL},
        {"--dump-dir", OPT_STRING, &out, "write S's output of frame F here (a stage dump: manifest, S.resv, G-buffer)", NULL, 0, 0, NULL},
        {"--options-from", OPT_STRING, &options_from, "take the render command line (scene, options) from this dump's manifest instead of DIR's (a GPU build's dump: the oracle's dump of the same run)", NULL, 0, 0, NULL},
        {"--region", OPT_STRING, &region, "DIR is a region dump: replay the pixels of X,Y,W,H (default: the manifest's halo core, else the whole dumped rectangle); refused (exit 2) if a pixel's stage reads outside the dumped rectangle", NULL, 0, 0, NULL},
        {NULL, 0, NULL, NULL, NULL, 0, 0, NULL},
    };
    status = cli_parse("replay", argc, argv, options, positional, 1, &count);
    if (status == 1) {
        cli_print_help(stdout, "replay", "DIR --frame F --stage S --dump-dir OUT", options);
        return 0;
    }
    if (status) return status;
    if (count != 1 || frame_i < 0 || !stage || !out) {
        fprintf(stderr, "restir replay: expected DIR --frame F --stage S --dump-dir OUT (see restir replay --help)\n");
        return 2;
    }
    frame = frame_i;
    memset(&p, 0, sizeof p);
    memset(&l, 0, sizeof l);
    p.dir = positional[0];
    p.stage = stage;
    p.frame = frame;
    p.options_dir = options_from;
    snprintf(prefix, sizeof prefix, "%s/replay.pfm", out);
    if (plan_replay(&p, &e) || replay_region(&p, region, &e) || plan_command(&p, prefix, out, &l, &e)) {
        fprintf(stderr, "restir replay: %s\n", e.msg);
        replay_args_free(&l);
        plan_done(&p);
        return 2;
    }
    status = cmd_render(l.argc, l.argv);
    replay_args_free(&l);
    plan_done(&p);
    snprintf(prefix, sizeof prefix, "%s/replay", out);
    remove_frame_image(prefix, frame); /* the shaded frame is not what a replay is for */
    if (status) return status;
    {
        char *diff_argv[4];
        diff_argv[0] = "diff-dump";
        diff_argv[1] = (char *)out;
        diff_argv[2] = (char *)p.dir;
        diff_argv[3] = NULL;
        return cmd_diff_dump(3, diff_argv);
    }
}

/* ---- restir inspect --from-dump -------------------------------------------------------- */

typedef struct {
    const char *stage;
    int found, have_final, have_mutation;
    pixel_trace t;
    pixel_trace mutation; /* the chain after the step (--mutations), if it ran in stage S */
    reservoir final; /* the stage's complete output at the pixel (after a mutation in it) */
} trace_catch;

static void catch_output(void *user, const char *stage, const reservoir *r)
{
    trace_catch *c = user;
    if (strcmp(stage, c->stage)) return;
    c->final = *r;
    c->have_final = 1;
}

static void catch_trace(void *user, const pixel_trace *t)
{
    trace_catch *c = user;
    /* a mutation chain belongs to stage mutate-S (its own dump stage) and is shown with S too */
    if (t->step == PIXEL_TRACE_MUTATION) {
        if (!strcmp(t->stage, c->stage) || (!strncmp(t->stage, "mutate-", 7) && !strcmp(t->stage + 7, c->stage))) {
            c->mutation = *t;
            c->have_mutation = 1;
        }
        return;
    }
    if (strcmp(t->stage, c->stage)) return; /* a later stage of the same frame */
    c->t = *t;
    c->found = 1;
}

static const char *step_names[] = {"temporal GRIS step", "spatial GRIS step", "pair step (Enhanced 3)",
                                   "stochastic pairwise MIS step"};

static const char *mis_name(int mis)
{
    return mis < 0 ? "stochastic-pairwise" : mis_family_name((mis_family)mis);
}

/* A field of the dump's record that differs from the recomputation. */
typedef struct {
    const char *field;
    double dump, recomputed;
} field_diff;

static int record_diffs(const reservoir *d, const reservoir *r, field_diff *out)
{
    int n = 0;
    /* bit identity, non-finite included: NaN != NaN is a difference */
#define CMP(name, a, b)                                                                                            \
    if (!((double)(a) == (double)(b))) {                                                                          \
        out[n].field = name;                                                                                      \
        out[n].dump = (double)(a);                                                                                \
        out[n].recomputed = (double)(b);                                                                          \
        ++n;                                                                                                      \
    }
    if (!dump_same_sample(&d->y, &r->y)) {
        out[n].field = "sample (initial-candidate id)";
        out[n].dump = path_sample_is_valid(&d->y) ? (double)d->y.pixel : -1;
        out[n].recomputed = path_sample_is_valid(&r->y) ? (double)r->y.pixel : -1;
        ++n;
    }
    CMP("W", d->W, r->W)
    CMP("wsum", d->wsum, r->wsum)
    CMP("confidence", d->confidence, r->confidence)
    CMP("target", d->y.target, r->y.target)
    CMP("F.r", d->y.F.r, r->y.F.r)
    CMP("F.g", d->y.F.g, r->y.F.g)
    CMP("F.b", d->y.F.b, r->y.F.b)
    CMP("n_invalid", d->n_invalid, r->n_invalid)
#undef CMP
    return n;
}

static void print_id(FILE *f, const path_sample *y, int json)
{
    if (!path_sample_is_valid(y)) {
        fprintf(f, json ? "null" : "none");
        return;
    }
    if (json)
        fprintf(f, "{\"seed\": %u, \"pixel\": %u, \"sample\": %u, \"length\": %d, \"technique\": %d}", y->seed,
                y->pixel, y->sample, y->length, y->technique);
    else
        fprintf(f, "(pixel %u, sample %u, d %d, %s)", y->pixel, y->sample, y->length,
                y->technique == PATH_TECH_NEE ? "NEE" : "BSDF");
}

static void print_text(FILE *f, const replay_plan *p, long width, const pixel_trace *t, const field_diff *diffs,
                       int nd, const char *dump_file, int have_dump)
{
    int i;
    fprintf(f, "frame %ld, stage %s, pixel (%ld, %ld): %s, MIS %s, M = %d domain(s)\n", p->frame, p->stage,
            t->pixel % width, t->pixel / width, step_names[t->step], mis_name(t->mis), t->m);
    fprintf(f, "inputs: %s%s%s/frame_%04ld/%s.resv%s\n", p->prev[0] ? "" : "(none: first stage)",
            p->prev[0] ? "" : "", p->dir, p->frame, p->prev[0] ? p->prev : "-",
            p->history ? " and frame F-1's final reservoirs from the dump" : "");
    fprintf(f, "selection numbers u_i: rng(seed %u, pixel %u, sample %u, stream RIS %d, vertex %u, slot i)\n", t->key.seed,
            t->key.pixel, t->key.sample, (int)RNG_RIS, t->vertex);
    if (t->step != PIXEL_TRACE_TEMPORAL)
        fprintf(f, "neighbour candidates: rng(seed %u, pixel %u, sample %u, stream NEIGHBOR %d, vertex k, slots 0-1)\n",
                t->key.seed, t->key.pixel, t->neighbor_sample, (int)RNG_NEIGHBOR);
    else if (t->m > 1)
        fprintf(f, "source pixel in frame %ld: (%ld, %ld); M-cap %.17g x c_0\n", p->frame - 1, t->d[1].pixel % width,
                t->d[1].pixel / width, (double)t->mcap);
    else
        fprintf(f, "no history (first frame, disocclusion or no source pixel): the output is the input\n");
    if (t->step == PIXEL_TRACE_STOCHASTIC) {
        fprintf(f, "picks: N~ = %d, u_pick (vertex %u) =", t->n_picks, (unsigned)RNG_VERTEX_STOCHASTIC_PICK(t->pass));
        for (i = 0; i < t->n_picks; ++i) fprintf(f, " %.17g", (double)t->up[i]);
        fprintf(f, "; N~_c = %d, u_canonical (vertex %u) =", t->n_canonical,
                (unsigned)RNG_VERTEX_STOCHASTIC_CANONICAL(t->pass));
        for (i = 0; i < t->n_canonical; ++i) fprintf(f, " %.17g", (double)t->uc[i]);
        fprintf(f, "; m~_c = %.17g\n", (double)t->m_c);
    }
    for (i = 0; i < t->kept; ++i) {
        const pixel_trace_domain *d = &t->d[i];
        fprintf(f, "  domain %d: pixel (%ld, %ld)", i, d->pixel < 0 ? -1 : d->pixel % width, d->pixel < 0 ? -1 : d->pixel / width);
        if (d->candidate >= 0) fprintf(f, ", candidate k = %d", d->candidate);
        fprintf(f, ", sample ");
        print_id(f, &d->in.y, 0);
        fprintf(f, "\n    in: W %.17g, c %.17g, p^_%d(X_%d) %.17g; u_%d %.17g\n", (double)d->in.W,
                (double)d->in.confidence, i, i, (double)d->in.y.target, i, (double)d->u);
        if (t->step == PIXEL_TRACE_STOCHASTIC && i > 0)
            fprintf(f, "    P(%d) %.17g, picked K = %d\n", i, (double)d->P, d->picks);
        if (!d->valid) {
            fprintf(f, "    shift: %s -> w_%d = 0 (c_%d %.17g still counts)\n",
                    !path_sample_is_valid(&d->in.y) ? "no sample" : t->step == PIXEL_TRACE_STOCHASTIC && !d->picks ? "not picked" : "FAILED",
                    i, i, (double)d->confidence);
            continue;
        }
        fprintf(f, "    shift: ok, J %.17g; p^(y_%d) %.17g, p^_{<-%d}(y_%d) %.17g", (double)d->jacobian, i,
                (double)d->target, i, i, (double)d->target_own);
        if (i > 0 && t->step != PIXEL_TRACE_STOCHASTIC) fprintf(f, ", p^_{<-%d}(y_0) %.17g", i, (double)d->target_back);
        fprintf(f, "\n");
        fprintf(f, "    c_%d %.17g, m_%d %.17g, w_%d = m p^ W J = %.17g%s\n", i, (double)d->confidence, i, (double)d->m, i,
                (double)d->w, i == t->selected ? "   <- selected" : "");
    }
    if (t->kept < t->m) fprintf(f, "  (%d more domain(s) not recorded)\n", t->m - t->kept);
    fprintf(f, "output: selected domain %d, sample ", t->selected);
    print_id(f, &t->out.y, 0);
    fprintf(f, "\n  wsum %.17g, p^(Y) %.17g, W = wsum / p^(Y) = %.17g, confidence %.17g, n_invalid %u\n",
            (double)t->out.wsum, (double)t->out.y.target, (double)t->out.W, (double)t->out.confidence,
            (unsigned)t->out.n_invalid);
    if (!have_dump) {
        fprintf(f, "dump record: %s is not in the dump (nothing to compare)\n", dump_file);
        return;
    }
    if (nd == 0) {
        fprintf(f, "dump record (%s): identical to the recomputation\n", dump_file);
        return;
    }
    fprintf(f, "dump record (%s): DIFFERS from the recomputation in %d field(s):\n", dump_file, nd);
    for (i = 0; i < nd; ++i)
        fprintf(f, "  %s: dump %.17g, recomputed %.17g\n", diffs[i].field, diffs[i].dump, diffs[i].recomputed);
}

static void json_num(FILE *f, const char *key, double v, int comma)
{
    fprintf(f, "\"%s\": ", key);
    if (isfinite(v)) fprintf(f, "%.17g", v);
    else fprintf(f, "\"%s\"", isnan(v) ? "nan" : v > 0 ? "inf" : "-inf");
    if (comma) fprintf(f, ", ");
}

static void print_json(FILE *f, const replay_plan *p, long width, const pixel_trace *t, const field_diff *diffs,
                       int nd, const char *dump_file, int have_dump)
{
    int i;
    fprintf(f, "{\"frame\": %ld, \"stage\": \"%s\", \"pixel\": [%ld, %ld], \"step\": \"%s\", \"mis\": \"%s\", \"m\": %d, ",
            p->frame, p->stage, t->pixel % width, t->pixel / width, step_names[t->step], mis_name(t->mis), t->m);
    fprintf(f, "\"rng\": {\"seed\": %u, \"pixel\": %u, \"sample\": %u, \"stream\": %d, \"vertex\": %u, \"neighbor_sample\": %u}, ",
            t->key.seed, t->key.pixel, t->key.sample, (int)RNG_RIS, t->vertex, t->neighbor_sample);
    if (t->step == PIXEL_TRACE_TEMPORAL) json_num(f, "mcap", (double)t->mcap, 1);
    if (t->step == PIXEL_TRACE_STOCHASTIC) {
        fprintf(f, "\"u_pick\": [");
        for (i = 0; i < t->n_picks; ++i) fprintf(f, "%s%.17g", i ? ", " : "", (double)t->up[i]);
        fprintf(f, "], \"u_canonical\": [");
        for (i = 0; i < t->n_canonical; ++i) fprintf(f, "%s%.17g", i ? ", " : "", (double)t->uc[i]);
        fprintf(f, "], ");
        json_num(f, "m_c", (double)t->m_c, 1);
    }
    fprintf(f, "\"domains\": [");
    for (i = 0; i < t->kept; ++i) {
        const pixel_trace_domain *d = &t->d[i];
        fprintf(f, "%s{\"pixel\": [%ld, %ld], \"candidate\": %d, \"slot\": %d, \"sample\": ", i ? ", " : "",
                d->pixel < 0 ? -1 : d->pixel % width, d->pixel < 0 ? -1 : d->pixel / width, d->candidate, i);
        print_id(f, &d->in.y, 1);
        fprintf(f, ", ");
        json_num(f, "u", (double)d->u, 1);
        fprintf(f, "\"valid\": %d, ", d->valid);
        json_num(f, "W_in", (double)d->in.W, 1);
        json_num(f, "c_in", (double)d->in.confidence, 1);
        json_num(f, "target_in", (double)d->in.y.target, 1);
        json_num(f, "c", (double)d->confidence, 1);
        json_num(f, "J", (double)d->jacobian, 1);
        json_num(f, "target", (double)d->target, 1);
        json_num(f, "target_own", (double)d->target_own, 1);
        json_num(f, "target_back", (double)d->target_back, 1);
        json_num(f, "m", (double)d->m, 1);
        json_num(f, "w", (double)d->w, 1);
        fprintf(f, "\"picks\": %d, ", d->picks);
        json_num(f, "P", (double)d->P, 0);
        fprintf(f, "}");
    }
    fprintf(f, "], \"selected\": %d, \"out\": {\"sample\": ", t->selected);
    print_id(f, &t->out.y, 1);
    fprintf(f, ", ");
    json_num(f, "wsum", (double)t->out.wsum, 1);
    json_num(f, "target", (double)t->out.y.target, 1);
    json_num(f, "W", (double)t->out.W, 1);
    json_num(f, "confidence", (double)t->out.confidence, 0);
    fprintf(f, "}, \"dump\": {\"file\": ");
    json_put_string(f, dump_file);
    fprintf(f, ", \"present\": %d, \"differs\": [", have_dump);
    for (i = 0; i < nd; ++i) {
        fprintf(f, "%s{\"field\": \"%s\", ", i ? ", " : "", diffs[i].field);
        json_num(f, "dump", diffs[i].dump, 1);
        json_num(f, "recomputed", diffs[i].recomputed, 0);
        fprintf(f, "}");
    }
    fprintf(f, "]}}\n");
}

static const char *mutation_outcome(int outcome)
{
    if (outcome == MUTATE_TRACE_ACCEPTED) return "accepted";
    if (outcome == MUTATE_TRACE_REJECTED_MH) return "rejected (u >= a)";
    return outcome >= 0 && outcome < MUTATE_REJECT_COUNT ? mutate_reject_names[outcome] : "?";
}

/* The MCMC chain that ran after the step inside the stage (Mutations Alg. 3). */
static void print_mutation(FILE *f, const pixel_trace *m, int json)
{
    const mutate_trace *tr = &m->mutation;
    int i;
    if (json) {
        fprintf(f, "\"mutation\": {\"skip\": ");
        if (tr->skip >= 0) json_put_string(f, mutate_skip_names[tr->skip]);
        else fprintf(f, "null");
        fprintf(f, ", \"rng_vertex\": %d, \"iterations\": [", m->mutate_stage);
        for (i = 0; i < tr->n; ++i) {
            fprintf(f, "%s{\"outcome\": \"%s\", ", i ? ", " : "", mutation_outcome(tr->it[i].outcome));
            json_num(f, "target_x", (double)tr->it[i].target_x, 1);
            json_num(f, "target_z", (double)tr->it[i].target_z, 1);
            json_num(f, "ratio", (double)tr->it[i].ratio, 1);
            json_num(f, "a", (double)tr->it[i].a, 1);
            json_num(f, "u", (double)tr->it[i].u, 1);
            json_num(f, "W", (double)tr->it[i].W, 0);
            fprintf(f, "}");
        }
        fprintf(f, "]}, ");
        return;
    }
    fprintf(f, "mutation after the step (Mutations Alg. 3; numbers: RNG_MUTATE %d, vertex %d, slot 64 it + j):\n",
            (int)RNG_MUTATE, m->mutate_stage);
    if (tr->skip >= 0) {
        fprintf(f, "  the chain did not start: %s\n", mutate_skip_names[tr->skip]);
        return;
    }
    for (i = 0; i < tr->n; ++i) {
        fprintf(f, "  it %d: p^(x) %.17g", i, (double)tr->it[i].target_x);
        if (tr->it[i].outcome < 0)
            fprintf(f, ", p^(z) %.17g, T(z->x)/T(x->z) %.17g, a %.17g, u %.17g", (double)tr->it[i].target_z,
                    (double)tr->it[i].ratio, (double)tr->it[i].a, (double)tr->it[i].u);
        fprintf(f, " -> %s, W %.17g\n", mutation_outcome(tr->it[i].outcome), (double)tr->it[i].W);
    }
    fprintf(f, "  after the chain: W %.17g, sample ", (double)m->out.W);
    print_id(f, &m->out.y, 0);
    fprintf(f, "\n");
}

/* The dump's own record of pixel p in stage `stage` of frame F (0: the file is absent). */
static int dump_record(const replay_plan *p, const char *stage, long pixel, char *path, size_t size, reservoir *rec,
                       rerror *e)
{
    reservoir *rs;
    reservoir_dump_info info;
    stage_dump_path(path, size, p->dir, (uint32_t)p->frame, stage, "resv");
    if (!file_exists(path)) return 0;
    if (reservoir_dump_read(path, &rs, &info, e)) return -1;
    if (p->m.region.width) /* a region dump: the record's index within the rectangle */
        pixel = (pixel / p->m.width - p->m.region.y) * p->m.region.width + pixel % p->m.width - p->m.region.x;
    if (pixel < 0 || (long)info.width * (long)info.height <= pixel) {
        free(rs);
        return rerror_set(e, "%s: %ux%u records, no pixel %ld", path, info.width, info.height, pixel);
    }
    *rec = rs[pixel];
    free(rs);
    return 1;
}

/* A mutation stage (Mutations Algorithm 3 after the stage it names; dumped as
 * mutate-initial, mutate-temporal, mutate-spatial): the pixel's chain as it ran, and the
 * stage's output against the dump's record. */
static int inspect_mutation_stage(const replay_plan *p, const trace_catch *c, long pixel, int json, const long *xy)
{
    char file[4200], in_file[4200];
    reservoir rec, in;
    field_diff diffs[16];
    rerror e;
    int have, have_in, nd = 0, i;
    if (!c->have_mutation || !c->have_final) {
        printf("frame %ld, stage %s, pixel (%ld, %ld): no chain ran here (no primary hit)\n", p->frame, p->stage, xy[0],
               xy[1]);
        return 0;
    }
    reservoir_init(&in);
    have = dump_record(p, p->stage, pixel, file, sizeof file, &rec, &e);
    /* the chain's start: the stage's input, the dump's record of the stage before it */
    have_in = have < 0 ? -1 : dump_record(p, p->prev, pixel, in_file, sizeof in_file, &in, &e);
    if (have < 0 || have_in < 0) {
        fprintf(stderr, "restir inspect: %s\n", e.msg);
        return 2;
    }
    if (have) nd = record_diffs(&rec, &c->final, diffs);
    if (json) {
        printf("{\"in\": {\"file\": ");
        json_put_string(stdout, in_file);
        printf(", \"W\": %.17g, \"target\": %.17g}, ", (double)in.W, (double)in.y.target);
        print_mutation(stdout, &c->mutation, 1);
        printf("\"W\": %.17g, \"confidence\": %.17g, \"dump_record\": %d, \"differs\": [", (double)c->final.W,
               (double)c->final.confidence, have);
        for (i = 0; i < nd; ++i) printf("%s\"%s\"", i ? ", " : "", diffs[i].field);
        printf("]}\n");
        return 0;
    }
    printf("frame %ld, stage %s, pixel (%ld, %ld)\n", p->frame, p->stage, xy[0], xy[1]);
    printf("input (%s): W %.17g, p^ %.17g, sample ", in_file, (double)in.W, (double)in.y.target);
    print_id(stdout, &in.y, 0);
    printf("\n");
    print_mutation(stdout, &c->mutation, 0);
    printf("output: W %.17g, confidence %.17g, sample ", (double)c->final.W, (double)c->final.confidence);
    print_id(stdout, &c->final.y, 0);
    printf("\n");
    if (!have) printf("dump record: %s is not in the dump (nothing to compare)\n", file);
    else if (nd == 0) printf("dump record (%s): identical to the recomputation\n", file);
    else {
        printf("dump record (%s): DIFFERS from the recomputation in %d field(s):\n", file, nd);
        for (i = 0; i < nd; ++i)
            printf("  %s: dump %.17g, recomputed %.17g\n", diffs[i].field, diffs[i].dump, diffs[i].recomputed);
    }
    return 0;
}

static int parse_xy(const char *text, long xy[2])
{
    char extra;
    return text && sscanf(text, "%ld,%ld%c", &xy[0], &xy[1], &extra) == 2;
}

int cmd_inspect_from_dump(int argc, char **argv)
{
    replay_plan p;
    replay_args l;
    const char *dir = NULL, *stage = NULL, *pixel = NULL, *options_from = NULL;
    int frame = -1, json = 0, count, status, have, nd = 0, mutated;
    long xy[2];
    char tmpdir[] = "/tmp/restir-inspect-XXXXXX", prefix[4200], file[4200];
    trace_catch c;
    render_trace_request req;
    reservoir rec;
    field_diff diffs[16];
    rerror e;
    cli_option options[] = {
        {"--from-dump", OPT_STRING, &dir, "the stage dump (a --dump-dir of restir render)", NULL, 0, 0, NULL},
        {"--frame", OPT_INT, &frame, "the frame F", NULL, 0, 1e8, NULL},
        {"--stage", OPT_STRING, &stage, "the stage S: temporal, spatialK or mutate-initial|temporal|spatial (a name of the dump's stage order)", NULL, 0, 0, NULL},
        {"--pixel", OPT_STRING, &pixel, "the pixel x,y (row 0 at the top)", NULL, 0, 0, NULL},
        {"--json", OPT_FLAG, &json, "one JSON object with every number at 17 digits", NULL, 0, 0, NULL},
        {"--options-from", OPT_STRING, &options_from, "take the render command line from this dump's manifest (the oracle's dump of the same run) instead of DIR's", NULL, 0, 0, NULL},
        {NULL, 0, NULL, NULL, NULL, 0, 0, NULL},
    };
    status = cli_parse("inspect", argc, argv, options, NULL, 0, &count);
    if (status == 1) {
        cli_print_help(stdout, "inspect", "--from-dump DIR --frame F --stage S --pixel x,y [--json]", options);
        return 0;
    }
    if (status) return status;
    if (!dir || frame < 0 || !stage || !parse_xy(pixel, xy)) {
        fprintf(stderr, "restir inspect: --from-dump DIR needs --frame F --stage S --pixel x,y\n");
        return 2;
    }
    memset(&p, 0, sizeof p);
    memset(&l, 0, sizeof l);
    p.dir = dir;
    p.stage = stage;
    p.frame = frame;
    p.options_dir = options_from;
    if (plan_replay(&p, &e)) {
        fprintf(stderr, "restir inspect: %s\n", e.msg);
        return 2;
    }
    if (strcmp(stage, "temporal") && strncmp(stage, "spatial", 7) && strncmp(stage, "mutate-", 7)) {
        fprintf(stderr, "restir inspect: --stage %s is not a reuse step (temporal, spatial1, ...); the initial "
                        "sample of a pixel: restir inspect SCENE --pixel x,y --first-frame F (exact)\n", stage);
        return 2;
    }
    if (xy[0] < 0 || xy[1] < 0 || xy[0] >= p.m.width || xy[1] >= p.m.height) {
        fprintf(stderr, "restir inspect: pixel (%ld, %ld) is outside the dump's %ldx%ld image\n", xy[0], xy[1],
                p.m.width, p.m.height);
        return 2;
    }
    if (p.m.region.width) { /* a region dump: this pixel's inputs must all be in it */
        stage_region one;
        one.x = xy[0];
        one.y = xy[1];
        one.width = one.height = 1;
        if (plan_region(&p, &one, &e)) {
            fprintf(stderr, "restir inspect: pixel (%ld, %ld): %s\n", xy[0], xy[1], e.msg);
            return 2;
        }
    }
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "restir inspect: cannot create a temporary directory in /tmp\n");
        plan_done(&p);
        return 2;
    }
    snprintf(prefix, sizeof prefix, "%s/frame.pfm", tmpdir);
    if (plan_command(&p, prefix, NULL, &l, &e)) {
        fprintf(stderr, "restir inspect: %s\n", e.msg);
        replay_args_free(&l);
        rmdir(tmpdir);
        plan_done(&p);
        return 2;
    }
    memset(&c, 0, sizeof c);
    c.stage = stage;
    req.pixel = xy[1] * p.m.width + xy[0];
    req.fn = catch_trace;
    req.stage_output = catch_output;
    req.user = &c;
    render_trace = &req;
    status = cmd_render(l.argc, l.argv);
    render_trace = NULL;
    replay_args_free(&l);
    plan_done(&p);
    snprintf(prefix, sizeof prefix, "%s/frame", tmpdir);
    remove_frame_image(prefix, p.frame);
    rmdir(tmpdir);
    if (status) return status;
    if (!strncmp(stage, "mutate-", 7)) return inspect_mutation_stage(&p, &c, req.pixel, json, xy);
    if (!c.found) {
        printf("frame %ld, stage %s, pixel (%ld, %ld): no primary hit (or no such stage ran): the stage's output is "
               "an empty reservoir\n", p.frame, stage, xy[0], xy[1]);
        return 0;
    }
    have = dump_record(&p, p.stage, req.pixel, file, sizeof file, &rec, &e);
    if (have < 0) {
        fprintf(stderr, "restir inspect: %s\n", e.msg);
        return 2;
    }
    /* a stage that mutates after its step (--mutations): the record is the mutated output */
    mutated = c.have_final && record_diffs(&c.final, &c.t.out, diffs) > 0;
    if (have) nd = record_diffs(&rec, mutated ? &c.final : &c.t.out, diffs);
    if (json) {
        printf("{");
        if (c.have_mutation) print_mutation(stdout, &c.mutation, 1);
        printf("\"mutated\": %d, \"step\": ", mutated);
        print_json(stdout, &p, p.m.width, &c.t, diffs, nd, file, have);
        printf("}\n");
        return 0;
    }
    print_text(stdout, &p, p.m.width, &c.t, diffs, nd, file, have);
    if (c.have_mutation) print_mutation(stdout, &c.mutation, 0);
    if (mutated) {
        printf("(an MCMC mutation inside stage %s changed the step's output: W %.17g, sample ", stage,
               (double)c.final.W);
        print_id(stdout, &c.final.y, 0);
        printf("; the record comparison is against the mutated output)\n");
    }
    return 0;
}
