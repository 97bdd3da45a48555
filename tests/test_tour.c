/* The first five minutes and the reading path (README.md, docs/tour.md):
 *   - every README command in a block marked ```sh tested runs (tests/readme_commands.sh),
 *     so the README cannot drift from the program;
 *   - the worked example of docs/tour.md is what `restir inspect` prints today, and its
 *     numbers redo by hand: the MIS weights of one GRIS step (GRIS Eq. 36 with confidences),
 *     the resampling weights (Eq. 19), the selection (WRS) and W (Eq. 22), from the printed
 *     inputs only. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "test.h"
#include "text_util.h"

static char out[65536];

TEST(readme_commands_run)
{
    char cmd[2048];
    int status;
    snprintf(cmd, sizeof cmd, "sh tests/readme_commands.sh README.md %s %s/readme > %s/readme.log 2>&1", RESTIR_BIN,
             test_tmpdir(), test_tmpdir());
    status = system(cmd);
    if (status != 0) {
        FILE *f;
        size_t n = 0;
        snprintf(cmd, sizeof cmd, "%s/readme.log", test_tmpdir());
        if ((f = fopen(cmd, "rb"))) {
            n = fread(out, 1, sizeof out - 1, f);
            fclose(f);
        }
        out[n] = '\0';
    }
    CHECKF(status == 0, "a README command failed:\n%s", out);
}

/* The worked example of docs/tour.md (the command is also in the README). */
#define TOUR_ARGS "inspect scenes/cornell.scene --size 64x64 --pixel 20,40 --neighbor 23,40"

/* The printed numbers are the estimator's reals to 17 digits: the hand computation in double
 * agrees to rounding (binary32 build: to its rounding). */
#ifdef RESTIR_REAL_FLOAT
#define HAND_TOL 1e-5
#else
#define HAND_TOL 1e-13
#endif
static int near(double a, double b) { return fabs(a - b) <= HAND_TOL * fmax(fabs(a), fabs(b)); }

typedef struct {
    double c, W, target_X, J, target_y, target_from_1_y, m, w, u;
    int valid;
} tour_domain;

static void read_domain(const char **p, tour_domain *d)
{
    d->c = json_after(p, "c");
    d->W = json_after(p, "W");
    d->target_X = json_after(p, "target_X");
    d->valid = (int)json_after(p, "valid");
    d->J = json_after(p, "J");
    d->target_y = json_after(p, "target_y");
    d->target_from_1_y = json_after(p, "target_from_1_y");
    d->m = json_after(p, "m");
    d->w = json_after(p, "w");
    d->u = json_after(p, "u");
}

/* The arithmetic of a two-domain Talbot GRIS step from its printed inputs (the object at p:
 * "domains", then selected, wsum, target_Y, W, confidence). */
static void check_step_by_hand(const char *p, const char *what)
{
    tour_domain d[2];
    double wsum, target_Y, W, conf, m0, m1, w0, w1, sum = 0;
    int selected, j, hand_selected = -1;
    for (j = 0; j < 2; ++j) read_domain(&p, &d[j]);
    selected = (int)json_after(&p, "selected");
    wsum = json_after(&p, "wsum");
    target_Y = json_after(&p, "target_Y");
    W = json_after(&p, "W");
    conf = json_after(&p, "confidence");
    CHECKF(d[0].valid && d[1].valid, "%s: both candidates must be valid for the example", what);
    /* the canonical domain: identity shift, p̂(y_0) is the pixel's own target */
    CHECKF(d[0].J == 1 && d[0].target_y == d[0].target_X, "%s", what);
    /* p̂_{<-1}(y_1) = p̂_1(X_1) / |dT_1/dX_1| (mis.h, the diagonal) */
    CHECKF(near(d[1].target_from_1_y, d[1].target_X / d[1].J), "%s: %.17g", what, d[1].target_from_1_y);
    /* GRIS Eq. 36 with confidences: m_i(y) = c_i p̂_{<-i}(y) / sum_k c_k p̂_{<-k}(y) */
    m0 = d[0].c * d[0].target_y / (d[0].c * d[0].target_y + d[1].c * d[0].target_from_1_y);
    m1 = d[1].c * d[1].target_from_1_y / (d[0].c * d[1].target_y + d[1].c * d[1].target_from_1_y);
    CHECKF(near(m0, d[0].m) && near(m1, d[1].m), "%s: m %.17g %.17g vs printed %.17g %.17g", what, m0, m1, d[0].m,
           d[1].m);
    /* GRIS Eq. 19: w_j = m_j(y_j) p̂(y_j) W_j |dT_j/dX_j| */
    w0 = m0 * d[0].target_y * d[0].W * d[0].J;
    w1 = m1 * d[1].target_y * d[1].W * d[1].J;
    CHECKF(near(w0, d[0].w) && near(w1, d[1].w), "%s: w %.17g %.17g vs printed %.17g %.17g", what, w0, w1, d[0].w,
           d[1].w);
    /* weighted reservoir sampling: candidate j replaces the selection if u_j < w_j / (w_0 + .. + w_j) */
    for (j = 0; j < 2; ++j) {
        double wj = j ? w1 : w0;
        sum += wj;
        if (wj > 0 && d[j].u < wj / sum) hand_selected = j;
    }
    CHECKF(near(sum, wsum), "%s: wsum %.17g vs %.17g", what, sum, wsum);
    CHECKF(hand_selected == selected, "%s: selected %d by hand, %d printed", what, hand_selected, selected);
    if (selected < 0) return;
    /* GRIS Eq. 22: W = wsum / p̂(Y); the confidence is the sum of the inputs' (GRIS §6.2) */
    CHECKF(near(target_Y, d[selected].target_y), "%s", what);
    CHECKF(near(W, sum / d[selected].target_y), "%s: W %.17g vs %.17g by hand", what, W, sum / d[selected].target_y);
    CHECKF(conf == d[0].c + d[1].c, "%s", what);
}

TEST(tour_worked_example_by_hand)
{
    const char *p, *q;
    double shifted_target_J;
    int status = test_cli(out, sizeof out, TOUR_ARGS " --json");
    CHECKF(status == 0, "exit %d: %s", status, out);
    if (test_has_failed()) return;
    CHECKF(strstr(out, "\"mis\": \"talbot\"") != NULL, "the example is a Talbot step: %s", out);
    p = strstr(out, "\"shift\": ");
    q = strstr(out, "\"gris_step\": ");
    CHECKF(p && q, "%s", out);
    if (!p || !q) return;
    shifted_target_J = json_after(&p, "target_times_J");
    /* p̂_{<-1}(y_0) is the pixel's sample shifted to the neighbour times J: the shift section */
    p = q;
    CHECKF(near(json_after(&p, "target_from_1_y"), shifted_target_J), "p^_{<-1}(y_0) is not the shift's p^(y) J");
    check_step_by_hand(q, "spatial step");
}

/* The temporal step (--temporal, frame 1 against frame 0) redoes by hand the same way. */
TEST(tour_temporal_step_by_hand)
{
    const char *q;
    int status = test_cli(out, sizeof out, TOUR_ARGS " --first-frame 1 --temporal --json");
    CHECKF(status == 0, "exit %d: %s", status, out);
    if (test_has_failed()) return;
    q = strstr(out, "\"temporal_step\": ");
    CHECKF(q != NULL, "%s", out);
    if (!q) return;
    check_step_by_hand(q, "temporal step");
    status = test_cli(out, sizeof out, TOUR_ARGS " --temporal");
    CHECKF(status == 2 && strstr(out, "--first-frame >= 1"), "exit %d: %s", status, out);
}

/* docs/tour.md shows the text output between its inspect-example markers verbatim
 * (regenerate with scripts/tour_example.sh). The numbers are the double build's: the
 * binary32 build only checks that the command runs. */
TEST(tour_example_matches_inspect)
{
    static char doc[131072];
    const char *begin_mark = "<!-- inspect-example begin -->\n```\n", *end_mark = "```\n<!-- inspect-example end -->";
    char *b, *e;
    size_t n = 0;
    FILE *f = fopen("docs/tour.md", "rb");
    int status = test_cli(out, sizeof out, TOUR_ARGS);
    CHECKF(status == 0, "exit %d: %s", status, out);
    CHECK(f != NULL);
    if (!f || status) return;
#ifdef RESTIR_REAL_FLOAT
    fclose(f);
    return;
#endif
    n = fread(doc, 1, sizeof doc - 1, f);
    fclose(f);
    doc[n] = '\0';
    b = strstr(doc, begin_mark);
    e = b ? strstr(b, end_mark) : NULL;
    CHECKF(b && e, "docs/tour.md has no inspect-example block");
    if (!b || !e) return;
    b += strlen(begin_mark);
    *e = '\0';
    CHECKF(!strcmp(b, out), "docs/tour.md's worked example differs from `restir " TOUR_ARGS
           "` (run scripts/tour_example.sh):\n--- doc\n%s--- now\n%s", b, out);
}
