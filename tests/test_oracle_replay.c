/* One stage of a dump recomputed on the dump's own inputs (issue 31, round 2; docs/oracle.md
 * §5): `restir inspect --from-dump` (one pixel, every number, the dump's record compared),
 * `restir replay` (every pixel, dumped and diffed) and `--history-from-dump` (the previous
 * frame's final reservoirs from the dump, not from the oracle's own run). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/oracle/region_input.h"
#include "restir/oracle/stage_dump.h"
#include "dump_util.h"
#include "test.h"
#include "text_util.h"

static char out[262144];

#define REPLAY_COMMON "scenes/pillars.scene --method restir --preset gris-realtime --spatial-passes 2 --size 40x28 " \
                      "--radius 6 --sequence 0..2 --quiet --no-png --threads 2"
#define REPLAY_W 40
#define PIXEL_X 21
#define PIXEL_Y 15

#ifdef RESTIR_REAL_FLOAT
#define HAND_TOL 1e-5
#else
#define HAND_TOL 1e-12
#endif
static int near(double a, double b) { return fabs(a - b) <= HAND_TOL * fmax(fabs(a), fabs(b)) + 1e-300; }

static const char *replay_dir(const char *name) { return dump_scratch("replay_", name); }

/* A dump made once per test process with `args` (key: its directory name; a directory left
 * by an earlier process, maybe by another build, is replaced). */
static const char *dump_of(const char *name, const char *args)
{
    char pfm[1100];
    snprintf(pfm, sizeof pfm, "%s/%s.pfm", test_tmpdir(), name);
    return dump_once(args, pfm, replay_dir(name));
}

static const char *reference(void) { return dump_of("A", REPLAY_COMMON); }

static const char *copy_of(const char *from, const char *name)
{
    const char *d = replay_dir(name);
    dump_copy(from, d);
    return d;
}

/* Multiplies W (and wsum) of record p of dir/frame/stage by `scale` (p < 0: every record). */
static void scale_w(const char *dir, int frame, const char *stage, long p, double scale)
{
    char path[1200];
    stage_dump_path(path, sizeof path, dir, (uint32_t)frame, stage, "resv");
    dump_scale_w(path, path, p, scale, 1);
}

typedef struct {
    double valid, c, J, target, target_own, target_back, m, w, W_in;
} domain_numbers;

/* The domains of an inspect --json object (at most 16), returns their count. */
static int read_domains(const char *json, domain_numbers *d, int max)
{
    const char *p = strstr(json, "\"domains\": [");
    int n = 0;
    while (p && n < max && (p = strstr(p, "\"u\": ")) != NULL) {
        const char *end = strstr(p, "\"selected\": ");
        if (end && p > end) break;
        d[n].valid = json_after(&p, "valid");
        d[n].W_in = json_after(&p, "W_in");
        d[n].c = json_after(&p, "c");
        d[n].J = json_after(&p, "J");
        d[n].target = json_after(&p, "target");
        d[n].target_own = json_after(&p, "target_own");
        d[n].target_back = json_after(&p, "target_back");
        d[n].m = json_after(&p, "m");
        d[n].w = json_after(&p, "w");
        ++n;
    }
    return n;
}

/* Hand arithmetic on a printed step: w_i = m_i p̂(y_i) W_i J_i (GRIS Eq. 19), wsum = sum w_i,
 * W = wsum / p̂(Y) (Eq. 22), c = sum c_i (GRIS §6.2). */
static void check_sums(const char *json, const char *what)
{
    domain_numbers d[16];
    const char *p = strstr(json, "\"out\": ");
    int n = read_domains(json, d, 16), i;
    double wsum = 0, c = 0, out_wsum, out_target, out_W, out_c;
    CHECKF(n >= 1 && p, "%s: %s", what, json);
    if (n < 1 || !p) return;
    for (i = 0; i < n; ++i) {
        c += d[i].c;
        if (!d[i].valid) continue;
        CHECKF(near(d[i].w, d[i].m * d[i].target * d[i].W_in * d[i].J), "%s: w_%d != m p^ W J", what, i);
        wsum += d[i].w;
    }
    out_wsum = json_after(&p, "wsum");
    out_target = json_after(&p, "target");
    out_W = json_after(&p, "W");
    out_c = json_after(&p, "confidence");
    CHECKF(near(out_wsum, wsum), "%s: wsum %.17g, sum of w_i %.17g", what, out_wsum, wsum);
    CHECKF(out_target == 0 ? out_W == 0 : near(out_W, out_wsum / out_target), "%s: W != wsum / p^(Y)", what);
    CHECKF(near(out_c, c), "%s: confidence %.17g, sum of c_i %.17g", what, out_c, c);
}

/* Every reuse stage of frame 2, recomputed for one pixel: identical to the dump's record,
 * and the printed numbers redo by hand (the temporal Talbot weights, GRIS Eq. 36 with
 * confidences: m_1 = c_1 p̂_{<-1}(y_1) / (c_0 p̂(y_1) + c_1 p̂_{<-1}(y_1))). */
TEST(oracle_inspect_from_dump_every_stage)
{
    const char *a = reference(), *stages[] = {"temporal", "spatial1", "spatial2"};
    int s, status;
    for (s = 0; s < 3; ++s) {
        status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage %s --pixel %d,%d", a, stages[s],
                          PIXEL_X, PIXEL_Y);
        CHECKF(status == 0 && strstr(out, "identical to the recomputation"), "%s: exit %d\n%s", stages[s], status, out);
        status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage %s --pixel %d,%d --json", a,
                          stages[s], PIXEL_X, PIXEL_Y);
        CHECKF(status == 0 && strstr(out, "\"differs\": []"), "%s: exit %d\n%s", stages[s], status, out);
        check_sums(out, stages[s]);
        if (s == 0) {
            domain_numbers d[2];
            CHECKF(read_domains(out, d, 2) == 2 && d[1].valid, "the temporal step has a history: %s", out);
            if (test_has_failed()) return;
            CHECKF(near(d[1].m, d[1].c * d[1].target_own / (d[0].c * d[1].target + d[1].c * d[1].target_own)),
                   "m_1 is not GRIS Eq. 36: %s", out);
            CHECKF(near(d[0].m, d[0].c * d[0].target / (d[0].c * d[0].target + d[1].c * d[1].target_back)),
                   "m_0 is not GRIS Eq. 36: %s", out);
        }
    }
}

/* A GPU-style record that differs is named, field by field; an input changed in the dump
 * changes the recomputation (the stage really reads the dump's previous stage). */
TEST(oracle_inspect_from_dump_names_differences)
{
    const char *b = copy_of(reference(), "edited");
    long p = PIXEL_Y * REPLAY_W + PIXEL_X;
    int status;
    scale_w(b, 2, "spatial1", p, 1.5);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage spatial1 --pixel %d,%d", b, PIXEL_X,
                      PIXEL_Y);
    CHECKF(status == 0 && strstr(out, "DIFFERS from the recomputation in 2 field(s)") && strstr(out, "  W: dump ") &&
               strstr(out, "  wsum: dump "),
           "exit %d\n%s", status, out);
    /* the input of spatial2 is spatial1: the edited record enters spatial2's recomputation */
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage spatial2 --pixel %d,%d", b, PIXEL_X,
                      PIXEL_Y);
    CHECKF(status == 0 && strstr(out, "DIFFERS from the recomputation"), "spatial2 did not read the edited input:\n%s",
           out);
}

/* What the dump lacks is refused (exit 2) with the missing file named. */
TEST(oracle_inspect_from_dump_refuses_missing_inputs)
{
    const char *b = copy_of(reference(), "holes");
    char path[1200];
    int status;
    stage_dump_path(path, sizeof path, b, 2, "temporal", "resv");
    remove(path);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage spatial1 --pixel 3,3", b);
    CHECKF(status == 2 && strstr(out, "frame_0002/temporal.resv: missing"), "exit %d\n%s", status, out);
    stage_dump_path(path, sizeof path, b, 1, "spatial2", "resv");
    remove(path);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage temporal --pixel 3,3", b);
    CHECKF(status == 2 && strstr(out, "frame_0001/spatial2.resv: missing") && strstr(out, "final reservoirs"),
           "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage initial --pixel 3,3", b);
    CHECKF(status == 2 && strstr(out, "not a reuse step"), "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 7 --stage temporal --pixel 3,3", b);
    CHECKF(status == 2 && strstr(out, "frame 7 is not in the dump's frames 0..2"), "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 1 --stage spatial1 --pixel 40,3", b);
    CHECKF(status == 2 && strstr(out, "outside"), "exit %d\n%s", status, out);
}

/* Stochastic pairwise MIS (Stochastic MIS Eq. 14: w_i = m̃_i p̂ W J over the picked domains)
 * and the Enhanced pair step, recomputed and identical to their dumps. */
TEST(oracle_inspect_from_dump_stochastic_and_pair_step)
{
    const char *st = dump_of("stoch", "scenes/cornell.scene --method restir --preset gris-realtime --size 32x24 "
                                      "--radius 5 --neighbors 4 --mis stochastic-pairwise --spatial-passes 2 "
                                      "--sequence 0..1 --quiet --no-png --threads 2");
    const char *pr = dump_of("pair", "scenes/cornell.scene --method restir --preset gris-realtime --size 32x24 "
                                     "--radius 5 --pairing paired --mis pairwise-defensive --sequence 0..1 --quiet "
                                     "--no-png --threads 2");
    int status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 1 --stage spatial2 --pixel 16,12 --json", st);
    CHECKF(status == 0 && strstr(out, "\"step\": \"stochastic pairwise MIS step\"") && strstr(out, "\"differs\": []") &&
               strstr(out, "\"u_pick\": ["),
           "exit %d\n%s", status, out);
    check_sums(out, "stochastic step");
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 1 --stage spatial1 --pixel 16,12 --json", pr);
    CHECKF(status == 0 && strstr(out, "\"step\": \"pair step (Enhanced 3)\"") && strstr(out, "\"differs\": []"),
           "exit %d\n%s", status, out);
    check_sums(out, "pair step");
}

/* --history-from-dump: frame 2's temporal stage reads frame 1's final reservoirs from the
 * dump. Replayed on the oracle's own dump it is bit-identical; on a dump whose frame-1
 * final state was changed (a GPU's history) the temporal stage follows the dump, which the
 * oracle's own history would not. */
TEST(oracle_replay_reads_foreign_history)
{
    const char *a = reference(), *b = copy_of(a, "gpu"), *o1 = replay_dir("out1"), *o2 = replay_dir("out2");
    int status;
    char cmd[3000];
    snprintf(cmd, sizeof cmd, "rm -rf %s %s", o1, o2);
    CHECK(system(cmd) == 0);
    status = test_cli(out, sizeof out, "replay %s --frame 2 --stage temporal --dump-dir %s", a, o1);
    CHECKF(status == 0 && strstr(out, "frame    2 temporal") && strstr(out, " ok"), "exit %d\n%s", status, out);
    scale_w(b, 1, "spatial2", -1, 1.5); /* the GPU's frame-1 output: every W 1.5 times ours */
    status = test_cli(out, sizeof out, "replay %s --frame 2 --stage temporal --dump-dir %s", b, o2);
    CHECKF(status == 1 && strstr(out, "frame    2 temporal"), "the replay did not read the dump's history: exit %d\n%s",
           status, out);
    /* the same stage from the oracle's own frame-1 state agrees with the unedited dump */
    status = test_cli(out, sizeof out, "diff-dump %s %s", o1, a);
    CHECKF(status == 0, "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "render " REPLAY_COMMON " -o %s/h.pfm --history-from-dump", test_tmpdir());
    CHECKF(status == 2 && strstr(out, "--history-from-dump needs --from-dump"), "exit %d\n%s", status, out);
}

/* ---- restir diagnose: the three planted GPU-style bugs of issue 31 ----------------------- */

#define DIAG_COMMON "scenes/pillars.scene --method restir --preset gris-realtime --spatial-passes 2 --size 24x16 " \
                    "--radius 6 --mcap 2 --sequence 0..2 --quiet --no-png --threads 2"

/* The oracle patched by `ablation` stands in for a GPU build; diagnose must name it and the
 * stage where it first shows. */
static void diagnose_names(const char *ablation, const char *meaning, const char *where)
{
    const char *a = dump_of("diagA", DIAG_COMMON);
    char name[64];
    const char *b;
    int status;
    snprintf(name, sizeof name, "diag_%s", ablation);
    {
        char args[1024];
        snprintf(args, sizeof args, DIAG_COMMON " --ablate %s", ablation);
        b = dump_of(name, args);
    }
    status = test_cli(out, sizeof out, "diagnose %s %s", a, b);
    CHECKF(status == 0, "exit %d\n%s", status, out);
    {
        char verdict[256];
        snprintf(verdict, sizeof verdict, "verdict: most likely --ablate %s (%s), first visible at %s", ablation, meaning,
                 where);
        CHECKF(strstr(out, verdict) != NULL, "expected '%s':\n%s", verdict, out);
    }
}

TEST(oracle_diagnose_temporal_current_camera)
{
    diagnose_names("temporal-target", "the temporal reverse shift evaluated with the current frame's camera and scene",
                   "frame 1, stage temporal");
}

TEST(oracle_diagnose_mcap_wrong_reservoir)
{
    diagnose_names("mcap-current", "the temporal M-cap applied to the current reservoir instead of the history",
                   "frame 1, stage temporal");
}

TEST(oracle_diagnose_neighbor_rng_off_by_one)
{
    diagnose_names("neighbor-rng", "the neighbour choice's RNG sample index off by one", "frame 0, stage spatial1");
}

/* B = A: nothing to name. */
TEST(oracle_diagnose_agreement)
{
    const char *a = dump_of("diagA", DIAG_COMMON);
    int status = test_cli(out, sizeof out, "diagnose %s %s", a, a);
    CHECKF(status == 0 && strstr(out, "verdict: B agrees with the unmodified oracle"), "exit %d\n%s", status, out);
}

/* ---- per-frame statistical verdicts for sequences --------------------------------------- */

#define RUNS_COMMON "scenes/cornell.scene --method restir --preset gris-realtime --size 24x16 --sequence 0..2 " \
                    "--runs 16 --quiet --no-png --threads 2"

/* --runs K with --sequence: one moments file set per frame that `restir check` reads, and
 * per-run dumps DIR/run_KK. The paired per-channel diff-dump --stat of two independent run
 * sets (seeds 1000 SEED.. and 1000 SEED + 100..) passes every frame and stage; with a 16% bias planted in
 * frame 2's temporal stage of B (every run's W and wsum times 1.16: a GPU build whose
 * temporal pass is biased from frame 2) the first row it flags is frame 2, temporal, in
 * each of R, G and B. */
TEST(oracle_sequence_runs_paired_stat)
{
    const char *ra = replay_dir("runsA"), *rb = replay_dir("runsB");
    char cmd[3000], dir[1200];
    int status, k;
    uint32_t seed;
    snprintf(cmd, sizeof cmd, "rm -rf %s %s && mkdir -p %s %s", ra, rb, ra, rb);
    CHECK(system(cmd) == 0);
    seed = 1000u * test_seed(); /* A: seeds seed..seed+15, B: seed+100.. */
    status = test_cli(out, sizeof out, "render " RUNS_COMMON " --seed %u -o %s/x.pfm --dump-dir %s/d", seed, ra, ra);
    CHECKF(status == 0, "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "render " RUNS_COMMON " --seed %u -o %s/x.pfm --dump-dir %s/d", seed + 100, rb,
                      rb);
    CHECKF(status == 0, "exit %d\n%s", status, out);
    if (test_has_failed()) return;
    status = test_cli(out, sizeof out, "check --a-moments %s/x.0002.moments.json --b-moments %s/x.0002.moments.json", ra,
                      rb);
    CHECKF(status == 0 && strstr(out, "verdict: consistent"), "frame 2's moments: exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "diff-dump %s/d %s/d --stat", ra, rb);
    CHECKF(status == 0 && strstr(out, "paired runs: 16 per side"), "unbiased run sets: exit %d\n%s", status, out);
    for (k = 0; k < 16; ++k) {
        snprintf(dir, sizeof dir, "%s/d/run_%02d", rb, k);
        scale_w(dir, 2, "temporal", -1, 1.16);
    }
    status = test_cli(out, sizeof out, "diff-dump %s/d %s/d --stat --json", ra, rb);
    CHECKF(status == 1, "the 16%% temporal bias passed: exit %d\n%s", status, out);
    {
        /* every row before frame 2 temporal passes; that row fails in each channel */
        const char *row = strstr(out, "{\"frame\": 2, \"stage\": \"temporal\"");
        const char *firstfail = strstr(out, "\"pass\": false");
        double crit, t;
        const char *p = out;
        int c;
        crit = (p = strstr(out, "\"critical_t\": ")) ? strtod(p + 14, NULL) : NAN;
        CHECKF(row && firstfail && firstfail > row && firstfail < row + 200, "first flagged row is not frame 2 "
               "temporal:\n%s", out);
        if (!row) return;
        p = strstr(row, "\"t\": [") + 6;
        for (c = 0; c < 3; ++c) {
            t = strtod(p, (char **)&p);
            CHECKF(fabs(t) > crit, "channel %d: |t| %.3g <= %.3g", c, t, crit);
            p += strspn(p, ", ");
        }
    }
}

/* ---- docs/tour.md §6: the worked examples of one stage of a real sequence -------------- */

/* The dumps of docs/tour.md §6 ("A step of a real sequence"): the commands there. */
#define TOUR_SEQ "scenes/cornell.scene --method restir --preset gris-realtime --size 32x24 --radius 5 --sequence 0..1 " \
                 "--quiet --no-png"

static const struct {
    const char *name, *args, *stage, *pixel, *marker;
} tour_examples[] = {
    {"tour-temporal", "scenes/pillars.scene --method restir --preset gris-realtime --size 40x28 --radius 6 "
                      "--sequence 0..1 --quiet --no-png", "temporal", "21,15", "inspect-temporal"},
    {"tour-stochastic", TOUR_SEQ " --neighbors 4 --mis stochastic-pairwise", "spatial1", "16,12", "inspect-stochastic"},
    {"tour-paired", TOUR_SEQ " --pairing paired --mis pairwise-defensive", "spatial1", "16,12", "inspect-paired"},
    {"tour-mutation", TOUR_SEQ " --neighbors 4 --mutations 2", "mutate-temporal", "8,14", "inspect-mutation"},
};

/* Mutations Alg. 3 by hand along the printed chain: the acceptance a = p̂(z)/p̂(x) times the
 * kernel ratio T(z->x)/T(x->z) (Eqs. 14, 19, 20); accepted iff u < a; W after an accepted
 * iteration is the W before it times p̂(x)/p̂(z) (Eq. 23), a rejected one keeps W. The chain
 * starts from the step's output ("out") or, for a mutation stage, from its input ("in"). */
static void check_chain(const char *json)
{
    const char *p = strstr(json, "\"iterations\": [");
    const char *step = strstr(json, "\"in\": {") ? strstr(json, "\"in\": {") : strstr(json, "\"out\": ");
    double W, prev;
    int n = 0;
    CHECKF(p && step, "no mutation chain: %s", json);
    if (!p || !step) return;
    prev = json_after(&step, "W");
    while ((p = strstr(p, "\"outcome\": \"")) != NULL) {
        int accepted = !strncmp(p + 12, "accepted", 8), rejected = !strncmp(p + 12, "rejected", 8);
        double tx = json_after(&p, "target_x"), tz = json_after(&p, "target_z"), ratio = json_after(&p, "ratio");
        double a = json_after(&p, "a"), u = json_after(&p, "u");
        W = json_after(&p, "W");
        if (accepted || rejected) {
            CHECKF(near(a, tz / tx * ratio), "iteration %d: a %.17g, p^(z)/p^(x) T ratio %.17g", n, a, tz / tx * ratio);
            CHECKF(accepted == (u < a), "iteration %d: u %.17g, a %.17g, %s", n, u, a, accepted ? "accepted" : "rejected");
        }
        CHECKF(accepted ? near(W, prev * tx / tz) : W == prev, "iteration %d: W %.17g from %.17g (p^ %.17g -> %.17g)",
               n, W, prev, tx, tz);
        prev = W;
        ++n;
    }
    CHECKF(n >= 1, "no iteration: %s", json);
}

/* out with every "DIR/" replaced by "dumps/NAME/" (the doc's directory). */
static void as_doc_paths(char *text, const char *dir, const char *name)
{
    static char buf[262144];
    char doc_dir[256];
    size_t n = strlen(dir), o = 0;
    const char *p = text;
    snprintf(doc_dir, sizeof doc_dir, "dumps/%s", name);
    while (*p && o + 300 < sizeof buf) {
        if (!strncmp(p, dir, n)) {
            o += (size_t)sprintf(buf + o, "%s", doc_dir);
            p += n;
        } else
            buf[o++] = *p++;
    }
    buf[o] = '\0';
    strcpy(text, buf);
}

/* Each example of docs/tour.md §6 is what `restir inspect --from-dump` prints today (double
 * build), and its JSON redoes by hand: w_i = m_i p̂ W J, wsum, W = wsum / p̂(Y), c = sum c_i. */
TEST(tour_sequence_steps_match_inspect)
{
    static char doc[262144];
    size_t i, n;
    FILE *f = fopen("docs/tour.md", "rb");
    CHECK(f != NULL);
    if (!f) return;
    n = fread(doc, 1, sizeof doc - 1, f);
    fclose(f);
    doc[n] = '\0';
    for (i = 0; i < sizeof tour_examples / sizeof tour_examples[0]; ++i) {
        char begin_mark[128], end_mark[128], name[64];
        const char *dir, *b, *e;
        int status;
        snprintf(name, sizeof name, "doc_%s", tour_examples[i].name);
        dir = dump_of(name, tour_examples[i].args);
        status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 1 --stage %s --pixel %s --json", dir,
                          tour_examples[i].stage, tour_examples[i].pixel);
        CHECKF(status == 0 && strstr(out, "\"differs\": []"), "%s: exit %d\n%s", tour_examples[i].name, status, out);
        if (strncmp(tour_examples[i].stage, "mutate-", 7)) check_sums(out, tour_examples[i].name);
        if (strstr(tour_examples[i].args, "--mutations")) check_chain(out);
        status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 1 --stage %s --pixel %s", dir,
                          tour_examples[i].stage, tour_examples[i].pixel);
        CHECKF(status == 0, "%s: exit %d\n%s", tour_examples[i].name, status, out);
#ifdef RESTIR_REAL_FLOAT
        continue; /* the doc's numbers are the double build's */
#endif
        as_doc_paths(out, dir, tour_examples[i].name);
        snprintf(begin_mark, sizeof begin_mark, "<!-- %s begin -->\n```\n", tour_examples[i].marker);
        snprintf(end_mark, sizeof end_mark, "```\n<!-- %s end -->", tour_examples[i].marker);
        b = strstr(doc, begin_mark);
        e = b ? strstr(b, end_mark) : NULL;
        CHECKF(b && e, "docs/tour.md has no %s block; now:\n%s", tour_examples[i].marker, out);
        if (!b || !e) continue;
        b += strlen(begin_mark);
        CHECKF((size_t)(e - b) == strlen(out) && !strncmp(b, out, (size_t)(e - b)),
               "docs/tour.md's %s block differs from the inspect output:\n--- now\n%s", tour_examples[i].marker, out);
    }
}

/* The tutorial of docs/oracle.md §7: a "GPU" dump (the oracle patched with mcap-current)
 * inspected with the oracle's options (--options-from A) shows the uncapped history in the
 * confidence field of the record it names; with its own command line it agrees with itself. */
TEST(oracle_inspect_options_from_names_the_planted_bug)
{
    const char *a = dump_of("diagA", DIAG_COMMON);
    const char *b = dump_of("diag_mcap-current", DIAG_COMMON " --ablate mcap-current");
    int status = test_cli(out, sizeof out, "diff-dump %s %s", a, b);
    CHECKF(status == 1 && strstr(out, "first difference: frame 1, stage temporal"), "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "replay %s --options-from %s --frame 1 --stage temporal --dump-dir %s", b, a,
                      replay_dir("opt_out"));
    CHECKF(status == 1 && strstr(out, "frame    1 temporal") && strstr(out, "confidence"), "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "replay %s --frame 1 --stage temporal --dump-dir %s", b, replay_dir("opt_self"));
    CHECKF(status == 0, "the patched build replayed with its own options: exit %d\n%s", status, out);
}

/* With --mutations the chain is a dump stage of its own (mutate-temporal): inspect of the
 * temporal step compares the step's output (identical) and shows the chain that follows;
 * inspect of mutate-temporal compares the chain's output with its record (identical). */
TEST(oracle_inspect_from_dump_after_mutation)
{
    const char *d = dump_of("mutate", "scenes/cornell.scene --method restir --preset gris-realtime --size 32x24 "
                                      "--sequence 0..1 --mutations 2 --quiet --no-png --threads 2");
    int status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 1 --stage temporal --pixel 16,12", d);
    CHECKF(status == 0 && strstr(out, "temporal.resv): identical to the recomputation") &&
               strstr(out, "mutation after the step"),
           "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 1 --stage mutate-temporal --pixel 16,12", d);
    CHECKF(status == 0 && strstr(out, "mutate-temporal.resv): identical to the recomputation") &&
               strstr(out, "it 0: "),
           "exit %d\n%s", status, out);
}

/* B may be a region dump (what a 1080p GPU run writes): diagnose compares its rectangle
 * (and says so in --json). */
TEST(oracle_diagnose_region_dump)
{
    const char *a = dump_of("diagA", DIAG_COMMON);
    const char *b = dump_of("diag_region", DIAG_COMMON " --ablate neighbor-rng --dump-region 4,4,12,8");
    int status = test_cli(out, sizeof out, "diagnose %s %s --json", a, b);
    CHECKF(status == 0 && strstr(out, "\"most_likely\": [\"--ablate neighbor-rng\"]") &&
               strstr(out, "\"departs\": {\"frame\": 0, \"stage\": \"spatial1\""),
           "exit %d\n%s", status, out);
}

/* ---- region dumps as inputs (docs/oracle.md §6 "From a region dump") ------------------- */

/* inspect --from-dump and replay on a `--dump-region ... --dump-halo N` dump give the
 * whole-image dump's output bit for bit for pixels whose every input was dumped, and refuse
 * (exit 2, naming the pixel and the missing input) a pixel at the rectangle's edge. */
#define REGION_COMMON "scenes/pillars.scene --method restir --preset gris-realtime --spatial-passes 2 --size 40x28 " \
                      "--radius 6 --sequence 0..2 --quiet --no-png --threads 2"
#define REGION_ARGS "--dump-region 14,10,10,8 --dump-halo 7" /* files: 7,3,24,22 */

static char other[262144];

/* s with every occurrence of word removed (the dump's directory in printed file names). */
static void strip(char *s, const char *word)
{
    size_t n = strlen(word);
    char *p;
    while ((p = strstr(s, word)) != NULL) memmove(p, p + n, strlen(p + n) + 1);
}

/* The bytes of dir/frame_0002/NAME after the header of `skip` bytes (size in *size), NULL if
 * unreadable. */
static unsigned char *file_bytes(const char *dir, const char *name, long skip, long *size)
{
    char path[1200];
    unsigned char *buf;
    FILE *fp;
    snprintf(path, sizeof path, "%s/frame_0002/%s", dir, name);
    if (!(fp = fopen(path, "rb"))) return NULL;
    fseek(fp, 0, SEEK_END);
    *size = ftell(fp) - skip;
    fseek(fp, skip, SEEK_SET);
    buf = malloc((size_t)*size);
    if (buf && fread(buf, 1, (size_t)*size, fp) != (size_t)*size) {
        free(buf);
        buf = NULL;
    }
    fclose(fp);
    return buf;
}

static unsigned char *records(const char *dir, const char *stage, long *size)
{
    char name[64];
    snprintf(name, sizeof name, "%s.resv", stage);
    return file_bytes(dir, name, 64, size);
}

/* inspect of one pixel on the region dump prints what it prints on the whole-image dump
 * (the file names aside), at every reuse stage of frame 2, history included. */
TEST(oracle_region_dump_inspect_equals_whole)
{
    const char *whole = dump_of("region_whole", REGION_COMMON), *region = dump_of("region_rect", REGION_COMMON " " REGION_ARGS);
    const char *stages[] = {"temporal", "spatial1", "spatial2"};
    int s, a, b;
    for (s = 0; s < 3; ++s) {
        a = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage %s --pixel 18,13 --json", whole,
                     stages[s]);
        b = test_cli(other, sizeof other, "inspect --from-dump %s --frame 2 --stage %s --pixel 18,13 --json", region,
                     stages[s]);
        CHECKF(a == 0 && b == 0 && strstr(other, "\"differs\": []"), "%s: exit %d / %d\n%s", stages[s], a, b, other);
        strip(out, whole);
        strip(other, region);
        CHECKF(!strcmp(out, other), "%s: the region dump's inspect differs:\n%s\n---\n%s", stages[s], out, other);
    }
}

/* The G-buffer of a halo dump is the grown rectangle's (7,3,24,22), row for row. */
static void check_halo_gbuffer(const char *whole, const char *region)
{
    long na = 0, nb = 0, y;
    unsigned char *a = file_bytes(whole, "gbuffer.gbuf", 32, &na), *b = file_bytes(region, "gbuffer.gbuf", 32, &nb);
    CHECKF(a && b && na == 40 * 28 * 108 && nb == 24 * 22 * 108, "G-buffer sizes %ld, %ld", na, nb);
    for (y = 0; a && b && nb == 24 * 22 * 108 && na == 40 * 28 * 108 && y < 22; ++y)
        CHECKF(!memcmp(b + y * 24 * 108, a + ((3 + y) * 40 + 7) * 108, 24 * 108), "G-buffer row %ld", 3 + y);
    free(a);
    free(b);
}

/* replay of the region's core writes records byte-identical to the whole-image dump's. */
TEST(oracle_region_dump_replay_equals_whole)
{
    const char *whole = dump_of("region_whole", REGION_COMMON), *region = dump_of("region_rect", REGION_COMMON " " REGION_ARGS);
    const char *stages[] = {"temporal", "spatial2"};
    int s, status;
    check_halo_gbuffer(whole, region);
    for (s = 0; s < 2; ++s) {
        const char *o = replay_dir(stages[s]);
        unsigned char *got, *want;
        long n_got = 0, n_want = 0, y;
        char cmd[1200];
        snprintf(cmd, sizeof cmd, "rm -rf %s", o);
        if (system(cmd) != 0) test_fail(__FILE__, __LINE__, "%s failed", cmd);
        status = test_cli(out, sizeof out, "replay %s --frame 2 --stage %s --dump-dir %s", region, stages[s], o);
        CHECKF(status == 0 && strstr(out, "region 14,10,10,8"), "%s: exit %d\n%s", stages[s], status, out);
        got = records(o, stages[s], &n_got);
        want = records(whole, stages[s], &n_want);
        CHECKF(got && want && n_got == 80 * 216 && n_want == 40 * 28 * 216, "%s: sizes %ld, %ld", stages[s], n_got,
               n_want);
        for (y = 0; got && want && n_got == 80 * 216 && y < 8; ++y)
            CHECKF(!memcmp(got + y * 10 * 216, want + ((10 + y) * 40 + 14) * 216, 10 * 216),
                   "%s: row %ld of the core differs from the whole-image dump", stages[s], 10 + y);
        free(got);
        free(want);
    }
}

/* A pixel whose stage reads outside the dumped rectangle is refused, naming the pixel and
 * the missing input; so is a pixel outside the rectangle, and a replay of the whole
 * rectangle (its edge pixels' neighbours were not dumped) leaves nothing behind. */
TEST(oracle_region_dump_refuses_edge_pixels)
{
    const char *region = dump_of("region_rect", REGION_COMMON " " REGION_ARGS), *o = replay_dir("edge");
    char cmd[1200];
    FILE *fp;
    int status;
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage spatial1 --pixel 10,6", region);
    CHECKF(status == 2 && strstr(out, "pixel (10, 6): missing input") && strstr(out, "previous stage's reservoir at pixel (4, 0)"),
           "exit %d\n%s", status, out);
    status = test_cli(out, sizeof out, "inspect --from-dump %s --frame 2 --stage spatial2 --pixel 2,2", region);
    CHECKF(status == 2 && strstr(out, "not all in the dumped rectangle"), "exit %d\n%s", status, out);
    snprintf(cmd, sizeof cmd, "rm -rf %s", o);
    if (system(cmd) != 0) test_fail(__FILE__, __LINE__, "%s failed", cmd);
    status = test_cli(out, sizeof out, "replay %s --frame 2 --stage spatial1 --dump-dir %s --region 7,3,24,22", region, o);
    CHECKF(status == 2 && strstr(out, "stage spatial1, pixel (") && strstr(out, "missing input"), "exit %d\n%s", status, out);
    fp = fopen(o, "r");
    CHECKF(!fp, "%s was left behind", o);
    if (fp) fclose(fp);
}

/* The read rule of docs/oracle.md §6 on hand-made texels: the temporal source is floor(s +
 * mv) (with --dedup the 17 x 17 window around it), nothing without a primary hit or when x1
 * was not visible, unbounded for a disoccluded pixel under dual motion vectors; a spatial
 * pass reads the box of floor(radius + 0.5) (disk) or floor(radius) (box). */
TEST(oracle_region_reads_by_hand)
{
    restir_options o;
    region_reach rr;
    region_read reads[2];
    gbuffer_texel t;
    rerror e;
    restir_options_default(&o);
    o.spatial.radius = 6.4;
    CHECKF(region_reach_for(&rr, &o, &e) == 0 && rr.spatial == 6, "disk reach %d", rr.spatial);
    memset(&t, 0, sizeof t);
    t.valid = t.prev_valid = 1;
    t.pixel[0] = 10.5f;
    t.pixel[1] = 20.5f;
    t.motion[0] = -3.7f; /* floor(6.8) = 6 */
    t.motion[1] = 2.6f;  /* floor(23.1) = 23 */
    CHECK(region_pixel_reads(&rr, "temporal", 40, 30, 10, 20, &t, 1, reads) == 2 && reads[0].box.x0 == 10 &&
          reads[0].box.y1 == 20 && !strcmp(reads[1].what, "history") && reads[1].box.x0 == 6 && reads[1].box.x1 == 6 &&
          reads[1].box.y0 == 23 && reads[1].box.y1 == 23);
    CHECK(region_pixel_reads(&rr, "temporal", 40, 30, 10, 20, &t, 0, reads) == 1); /* first frame: no history */
    rr.dedup = 1;
    CHECK(region_pixel_reads(&rr, "temporal", 40, 30, 10, 20, &t, 1, reads) == 2 && reads[1].box.x0 == 0 &&
          reads[1].box.x1 == 14 && reads[1].box.y0 == 15 && reads[1].box.y1 == 29); /* clipped to the image */
    CHECK(region_pixel_reads(&rr, "spatial2", 40, 30, 10, 20, &t, 1, reads) == 1 && reads[0].box.x0 == 4 &&
          reads[0].box.x1 == 16 && reads[0].box.y0 == 14 && reads[0].box.y1 == 26);
    CHECK(region_pixel_reads(&rr, "mutate-spatial", 40, 30, 10, 20, &t, 1, reads) == 1 && reads[0].box.x0 == 10 &&
          reads[0].box.x1 == 10);
    CHECK(region_pixel_reads(&rr, "boiling", 40, 30, 10, 20, &t, 1, reads) == 1 && reads[0].box.x0 == 0 &&
          reads[0].box.x1 == 15 && reads[0].box.y0 == 16 && reads[0].box.y1 == 29);
    t.prev_valid = 0;
    CHECK(region_pixel_reads(&rr, "temporal", 40, 30, 10, 20, &t, 1, reads) == 1);
    rr.dual = 1;
    CHECK(region_pixel_reads(&rr, "temporal", 40, 30, 10, 20, &t, 1, reads) == -1);
    t.valid = 0;
    CHECK(region_pixel_reads(&rr, "spatial1", 40, 30, 10, 20, &t, 1, reads) == 0);
    o.spatial.pattern = NEIGHBOR_BOX;
    o.spatial.radius = 3.9;
    CHECK(region_reach_for(&rr, &o, &e) == 0 && rr.spatial == 3);
}
