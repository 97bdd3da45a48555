/* The inputs a golden vector may hold (vectors.h, vectors_input_problem): the evaluators
 * cast numbers to uint32_t and int, index arrays with them and hand them to the RNG, whose
 * address check aborts. A vector file is input, so a number outside the function's domain
 * is a bad vector (exit 2), never undefined behaviour or SIGABRT (issue 27). */
#include "restir/oracle/vectors_domain.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "restir/oracle/vectors.h"

enum arg_kind {
    ARG_U32,  /* a whole number in [0, 2^32 - 1] (seeds, pixels, samples, RNG words) */
    ARG_INT,  /* a whole number in [lo, hi] */
    ARG_UNIT, /* a random number in [0, 1] */
    ARG_UNIT_TAIL /* every input from index `index` on is a random number in [0, 1] */
};

typedef struct {
    const char *fn;
    int index;
    enum arg_kind kind;
    double lo, hi;
} arg_rule;

/* Only the inputs that are cast, used as indices or passed to the RNG need a rule; the
 * real-valued inputs (targets, confidences, directions) may hold anything, "inf" and "nan"
 * included: the functions' guards are part of what the vectors test. */
static const arg_rule rules[] = {
    {"rng_u", 0, ARG_U32, 0, 0},          {"rng_u", 1, ARG_U32, 0, 0},
    {"rng_u", 2, ARG_U32, 0, 0},          {"rng_u", 3, ARG_INT, 0, 255}, /* stream (docs/rng.md) */
    {"rng_u", 4, ARG_INT, 0, 255},        /* vertex */
    {"rng_u", 5, ARG_INT, 0, 65535},      /* slot */
    {"rng_pcg4d", 0, ARG_U32, 0, 0},      {"rng_pcg4d", 1, ARG_U32, 0, 0},
    {"rng_pcg4d", 2, ARG_U32, 0, 0},      {"rng_pcg4d", 3, ARG_U32, 0, 0},
    {"shift_path", 1, ARG_U32, 0, 0},     {"reuse_transform_draw", 0, ARG_INT, 1, 4096},
    {"reuse_transform_draw", 2, ARG_U32, 0, 0}, {"reuse_transform_draw", 3, ARG_U32, 0, 0},
    {"reuse_transform_draw", 4, ARG_U32, 0, 0}, {"reuse_partner_offset", 0, ARG_INT, 1, 4096},
    {"reuse_partner_offset", 2, ARG_U32, 0, 0}, {"reuse_partner_offset", 3, ARG_U32, 0, 0},
    {"reuse_partner_offset", 4, ARG_INT, 0, 1}, {"reuse_partner_offset", 5, ARG_INT, 0, 1},
    {"reuse_partner_offset", 6, ARG_INT, 0, 1}, {"reuse_partner_offset", 7, ARG_INT, -65536, 65536},
    {"reuse_partner_offset", 8, ARG_INT, -65536, 65536}, {"reuse_partner_offset", 9, ARG_INT, -65536, 65536},
    {"reuse_partner_offset", 10, ARG_INT, -65536, 65536},
    {"rc_footprint_test", 0, ARG_INT, 0, 4},  /* material type (x_{k-1}) */
    {"rc_footprint_test", 18, ARG_INT, -2, 3}, /* lobe: -1 NEE, -2 none */
    {"rc_footprint_test", 19, ARG_INT, 0, 1},
    {"rc_footprint_test", 20, ARG_INT, 0, 4},
    {"rc_footprint_test", 38, ARG_INT, -2, 3},
    /* n, N~, N~_c are checked by the evaluator; the picks' random numbers after the domains: */
    {"stochastic_pairwise_weights", -1, ARG_UNIT_TAIL, 0, 0},
    {"stochastic_pick", -1, ARG_UNIT_TAIL, 0, 0},
    /* whole steps (vectors_step.c): seeds, pixels, counts; the evaluators check the pixels */
    {"temporal_resample", 0, ARG_INT, 0, 3},  {"temporal_resample", 2, ARG_U32, 0, 0},
    {"temporal_resample", 3, ARG_U32, 0, 0},  {"temporal_resample", 4, ARG_INT, 0, 4096},
    {"temporal_resample", 5, ARG_INT, 0, 4096}, {"temporal_resample", 6, ARG_INT, -1, 4096},
    {"temporal_resample", 7, ARG_INT, -1, 4096}, {"temporal_resample", 10, ARG_UNIT, 0, 0},
    {"temporal_resample", 11, ARG_UNIT, 0, 0},
    {"mutate_reservoir", 0, ARG_INT, 0, 2},   {"mutate_reservoir", 1, ARG_U32, 0, 0},
    {"mutate_reservoir", 2, ARG_INT, 0, 4096}, {"mutate_reservoir", 3, ARG_INT, 0, 4096},
    {"mutate_reservoir", 4, ARG_INT, 1, 4},   {"mutate_reservoir", 5, ARG_INT, 1, 64},
    {"mutate_propose", 0, ARG_INT, 0, 2},     {"mutate_propose", 1, ARG_U32, 0, 0},
    {"mutate_propose", 2, ARG_INT, 0, 4096},  {"mutate_propose", 3, ARG_INT, 0, 4096},
    {"mutate_propose", 4, ARG_UNIT_TAIL, 0, 0},
    {"stochastic_pairwise_resample", 0, ARG_U32, 0, 0}, {"stochastic_pairwise_resample", 4, ARG_INT, 0, 4096},
    {"stochastic_pairwise_resample", 5, ARG_INT, 0, 4096},
    {"stochastic_pairwise_resample", -1, ARG_UNIT_TAIL, 0, 0},
    {NULL, 0, ARG_U32, 0, 0},
};

static int whole(double x) { return isfinite(x) && floor(x) == x; }

/* stochastic_pairwise_weights: n, N~, N~_c, 4 numbers, 6 per domain, then the picks;
 * stochastic_pick: m, N~, P[m], then the picks. */
static int tail_start(const char *fn, const double *in, int n_in)
{
    if (n_in < 3 || !whole(in[0]) || fabs(in[0]) > 64) return n_in;
    if (!strcmp(fn, "mutate_propose")) return 4;
    if (!strcmp(fn, "stochastic_pairwise_resample"))
        return n_in > 6 && whole(in[6]) && fabs(in[6]) <= 64 ? 7 + 4 * (int)in[6] : n_in;
    if (!strcmp(fn, "stochastic_pairwise_weights")) return 7 + 6 * (int)in[0];
    return 2 + (int)in[0];
}

static int check_one(const arg_rule *r, int i, double x, char *why, size_t size)
{
    if (r->kind == ARG_U32 && !(whole(x) && x >= 0 && x <= 4294967295.0))
        return snprintf(why, size, "input %d is %.17g, expected a whole number in [0, 4294967295]", i, x), 1;
    if (r->kind == ARG_INT && !(whole(x) && x >= r->lo && x <= r->hi))
        return snprintf(why, size, "input %d is %.17g, expected a whole number in [%g, %g]", i, x, r->lo, r->hi), 1;
    if ((r->kind == ARG_UNIT || r->kind == ARG_UNIT_TAIL) && !(x >= 0 && x <= 1))
        return snprintf(why, size, "input %d is %.17g, expected a random number in [0, 1]", i, x), 1;
    return 0;
}

int vectors_input_problem(const char *fn, const double *in, int n_in, char *why, size_t size)
{
    const arg_rule *r;
    int i;
    for (r = rules; r->fn; ++r) {
        if (strcmp(r->fn, fn)) continue;
        if (r->kind == ARG_UNIT_TAIL) {
            for (i = tail_start(fn, in, n_in); i < n_in; ++i)
                if (check_one(r, i, in[i], why, size)) return 1;
        } else if (r->index < n_in && check_one(r, r->index, in[r->index], why, size)) {
            return 1;
        }
    }
    return 0;
}

/* ---- where the shift vectors' scene is ---- */

#include <unistd.h>

const char *vectors_shift_scene_path(void)
{
    static char path[4200];
    char exe[4096];
    ssize_t n;
    char *slash;
    int i;
    if (access("scenes/cornell.scene", R_OK) == 0) return "scenes/cornell.scene";
    n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) return "scenes/cornell.scene";
    exe[n] = '\0';
    /* build/restir, build/float/restir, build/asan/restir ...: up to three levels up. */
    for (i = 0; i < 3 && (slash = strrchr(exe, '/')) != NULL; ++i) {
        *slash = '\0';
        snprintf(path, sizeof path, "%s/scenes/cornell.scene", exe);
        if (access(path, R_OK) == 0) return path;
    }
    return "scenes/cornell.scene";
}
