/* Option rows of `restir render --method restir` (src/cli/render_restir.h). */
#include "render_restir.h"
#include "restir/frame/options.h"
#include "restir/frame/pipeline.h"

#include <stdio.h>
#include <string.h>

static const char *const preset_names[] = {"none", "gris-offline", "gris-realtime", NULL};

cli_option render_restir_preset_row(int *preset)
{
    cli_option r;
    memset(&r, 0, sizeof r);
    r.name = "--preset";
    r.type = OPT_CHOICE;
    r.dest = preset;
    r.help = "gris-offline: 32 path trees, 3 spatial passes, 6 neighbours, radius 10 (GRIS 8.3); "
             "gris-realtime: 1 path tree, temporal talbot cap 20, 1 spatial pass, 3 neighbours, radius 20, "
             "pairwise-defensive (GRIS 8.3, use with --sequence); options given beside it override it";
    r.choices = preset_names;
    return r;
}

void render_restir_apply(const cli_option *options, const int *given, int preset, const render_restir_flags *f,
                         restir_options *o)
{
    int mis_given = cli_given(options, given, "--mis");
    if (preset > 0) {
        restir_options p;
        restir_options_default(&p);
        if (preset == 1) restir_options_preset_gris_offline(&p);
        else restir_options_preset_gris_realtime(&p);
        cli_take_unset(options, given, o, &p, sizeof *o);
        if (!mis_given) { /* --mis writes f->mis, not a field of o */
            o->spatial.algorithm = p.spatial.algorithm;
            o->spatial.mis = p.spatial.mis;
        }
    }
    if (mis_given && f->mis == MIS_FAMILY_COUNT) {
        o->spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE;
    } else if (mis_given) {
        o->spatial.algorithm = SPATIAL_GRIS_STEP;
        o->spatial.mis = (mis_family)f->mis;
    }
    if (f->no_confidence_scaling) o->stochastic.confidence_scaling = 0;
}

/* Each technique's options, with the flags that set them. */
static int spatial_check(const restir_options *o, rerror *e) { return spatial_options_validate(&o->spatial, e); }
static int temporal_check(const restir_options *o, rerror *e) { return temporal_options_validate(&o->temporal, e); }
static int stochastic_check(const restir_options *o, rerror *e) { return stochastic_options_validate(&o->stochastic, e); }
static int mutation_check(const restir_options *o, rerror *e) { return mutation_options_validate(&o->mutation, e); }
static int correlation_check(const restir_options *o, rerror *e)
{
    return correlation_options_validate(&o->correlation, e);
}
static int light_ris_check(const restir_options *o, rerror *e) { return light_ris_options_validate(&o->light_ris, e); }

int render_restir_validate(const char *command, const restir_options *o)
{
    static const struct {
        int (*check)(const restir_options *o, rerror *e);
        const char *flags;
    } techniques[] = {
        {spatial_check, "--mis, --neighbors, --radius, --pattern, --pairing, --eq3-reading, --no-reject, --normal-cos, "
                        "--depth-ratio, --reuse-cells"},
        {temporal_check, "--temporal-mis, --mcap, --mcap-mode, --motion-vectors"},
        {stochastic_check, "--stochastic-n, --stochastic-nc"},
        {mutation_check, "--mutations, --mutation, --mutation-kernel, --mutation-sigma, --mutate-after"},
        {correlation_check, "--dedup, --dedup-min, --dedup-alpha, --boiling-filter"},
        {light_ris_check, "--light-ris, --light-tiles"},
    };
    rerror e;
    size_t i;
    for (i = 0; i < sizeof techniques / sizeof *techniques; ++i)
        if (techniques[i].check(o, &e)) {
            fprintf(stderr, "restir %s: %s (%s)\n", command, e.msg, techniques[i].flags);
            return 2;
        }
    if (restir_options_validate(o, &e)) { /* the frame's fields and the rules between techniques */
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    return 0;
}

/* OPT_CHOICE writes an int: every enum a row chooses must be one (C leaves an enum's
 * size to the compiler; gcc and clang make these int-sized). */
#define CHOICE_IS_INT(T, name) typedef char name[sizeof(T) == sizeof(int) ? 1 : -1]
CHOICE_IS_INT(enum restir_shift, shift_is_int);
CHOICE_IS_INT(enum neighbor_pattern, pattern_is_int);
CHOICE_IS_INT(enum restir_pairing, pairing_is_int);
CHOICE_IS_INT(enum pairing_eq3, eq3_is_int);
CHOICE_IS_INT(mis_family, mis_is_int);
CHOICE_IS_INT(enum restir_shading, shading_is_int);
CHOICE_IS_INT(enum rc_mode, rc_mode_is_int);
CHOICE_IS_INT(enum restir_paths, paths_is_int);
CHOICE_IS_INT(enum restir_ablation, ablation_is_int);
CHOICE_IS_INT(enum restir_motion_vectors, motion_vectors_is_int);
CHOICE_IS_INT(enum mutate_strategy, strategy_is_int);
CHOICE_IS_INT(enum mutate_kernel, kernel_is_int);
CHOICE_IS_INT(enum temporal_mcap_mode, mcap_mode_is_int);

/* --mis: the MIS families of the GRIS step, then the stochastic pairwise algorithm. */
static const char *mis_choices[MIS_FAMILY_COUNT + 2];

static void fill_mis_choices(void)
{
    int i;
    for (i = 0; i < MIS_FAMILY_COUNT; ++i) mis_choices[i] = restir_mis_names[i];
    mis_choices[MIS_FAMILY_COUNT] = spatial_algorithm_names[SPATIAL_STOCHASTIC_PAIRWISE];
    mis_choices[MIS_FAMILY_COUNT + 1] = NULL;
}

static cli_option row(const char *name, enum cli_option_type type, void *dest, const char *help,
                      const char *const *choices, double min, double max)
{
    cli_option r;
    memset(&r, 0, sizeof r);
    r.name = name;
    r.type = type;
    r.dest = dest;
    r.help = help;
    r.choices = choices;
    r.min = min;
    r.max = max;
    return r;
}

int render_restir_options(cli_option *rows, restir_options *o, render_restir_flags *f)
{
    int n = 0;
    fill_mis_choices();
    f->mis = (int)o->spatial.mis;
    f->no_confidence_scaling = 0;
    rows[n++] = row("--shift", OPT_CHOICE, &o->shift,
                    "shift mapping: reconnection (y2 = x2), replay (random replay), hybrid (default; GRIS 7.4)",
                    restir_shift_names, 0, 0);
    rows[n++] = row("--spatial-passes", OPT_INT, &o->spatial_passes,
                    "K spatial reuse passes, 0..16 (0: initial resampling only; default 0)", NULL, 0,
                    RESTIR_MAX_SPATIAL_PASSES);
    rows[n++] = row("--neighbors", OPT_INT, &o->spatial.neighbors, "neighbour candidates per pixel and pass (default 6)", NULL,
                    1, NEIGHBOR_MAX_COUNT);
    rows[n++] = row("--radius", OPT_REAL, &o->spatial.radius,
                    "neighbour disk radius in pixels (default 10; box: half-size floor(R))", NULL, 1, 4096);
    rows[n++] = row("--pattern", OPT_CHOICE, &o->spatial.pattern,
                    "neighbour pattern: uniform disk, r2 (low-discrepancy disk, default), box window",
                    neighbor_pattern_names, 0, 0);
    rows[n++] = row("--pairing", OPT_CHOICE, &o->spatial.pairing,
                    "spatial neighbours: disk (the --pattern, default) or paired (reciprocal pairs from reuse textures, "
                    "Enhanced 3; sigma = 0.532 radius)",
                    restir_pairing_names, 0, 0);
    rows[n++] = row("--eq3-reading", OPT_CHOICE, &o->spatial.eq3_reading,
                    "--pairing paired: reading of the garbled Enhanced Eq. 3 (shuffle passes for sigma): port-round "
                    "(default, measured closest to sigma), signed-ceil (the reading before issue 28), signed-round, "
                    "literal-ceil, leading-ceil (docs/results/eq3.md)",
                    pairing_eq3_names, 0, 0);
    rows[n++] = row("--no-reject", OPT_FLAG, &o->spatial.no_reject, "keep neighbours whatever their normal and depth", NULL,
                    0, 0);
    rows[n++] = row("--normal-cos", OPT_REAL, &o->spatial.normal_cos,
                    "reject a neighbour if dot(n_i, n_j) < this (default 0.5)", NULL, -1, 1);
    rows[n++] = row("--depth-ratio", OPT_REAL, &o->spatial.depth_ratio,
                    "reject a neighbour if |d_i - d_j| > this * min(d_i, d_j) (default 0.1)", NULL, 0, 1e9);
    rows[n++] = row("--mis", OPT_CHOICE, &f->mis,
                    "resampling MIS: constant (biased, GRIS 5.6), talbot (default, Eq. 36), pairwise (Eq. 37), "
                    "pairwise-defensive (Eq. 38), stochastic-pairwise (Stochastic MIS Eqs. 16-19: Ne picks by Eq. 17)",
                    mis_choices, 0, 0);
    rows[n++] = row("--pairwise-confidence", OPT_CHOICE, &o->pairwise_confidence,
                    "confidences in pairwise-defensive MIS: stochastic (default: c_S/(c_S + c_c) in each pair, "
                    "Stochastic MIS Eq. 11) or falcor (1/(k+1) per pair with c_c/k inside, the authors' Falcor code; "
                    "docs/mis-derivations.md 3.5)",
                    restir_pairwise_confidence_names, 0, 0);
    rows[n++] = row("--stochastic-n", OPT_INT, &o->stochastic.n_picks,
                    "stochastic-pairwise: candidates picked per pixel and pass, N~ (default 1)", NULL, 1,
                    STOCHASTIC_MAX_PICKS);
    rows[n++] = row("--stochastic-nc", OPT_INT, &o->stochastic.n_canonical_picks,
                    "stochastic-pairwise: uniform picks estimating the canonical weight, N~_c (default 1)", NULL, 1,
                    STOCHASTIC_MAX_PICKS);
    rows[n++] = row("--reuse-cells", OPT_FLAG, &o->spatial.cells,
                    "spatial domains = the pixels of one 8x8-tile reuse cell found by the Stochastic MIS 5.1 search "
                    "(instead of --pattern neighbours; any --mis)",
                    NULL, 0, 0);
    rows[n++] = row("--no-confidence-scaling", OPT_FLAG, &f->no_confidence_scaling,
                    "stochastic-pairwise: keep the neighbours' confidences (no c_i <- c_i N~/M, Stochastic MIS 4.3)",
                    NULL, 0, 0);
    rows[n++] = row("--time-limit", OPT_REAL, &o->time_limit,
                    "render frames until this many seconds have passed (at least one; --frames is then ignored)",
                    NULL, 0, 1e8);
    rows[n++] = row("--frames", OPT_INT, &o->frames, "independent frames averaged (GRIS Eq. 47; default 1)", NULL, 1,
                    1e9);
    rows[n++] = row("--first-frame", OPT_INT, &o->first_frame,
                    "index of the first frame (runs with disjoint frame ranges are independent)", NULL, 0, 1e9);
    rows[n++] = row("--candidates", OPT_INT, &o->candidates, "path trees per pixel and frame, N (default 1)", NULL, 1,
                    65536);
    rows[n++] = row("--max-depth", OPT_INT, &o->max_depth, "longest path in segments, 2..16 (default 10)", NULL, 2,
                    PATH_MAX_LENGTH);
    rows[n++] = row("--roughness-threshold", OPT_REAL, &o->roughness_threshold,
                    "reconnection needs lobe roughness above this (default 0.2)", NULL, 0, 1);
    rows[n++] = row("--distance-threshold", OPT_REAL, &o->distance_threshold,
                    "minimum reconnection segment, fraction of the scene's bounding-box diagonal (default 0.02)", NULL,
                    0, 1);
    rows[n++] = row("--shading", OPT_CHOICE, &o->shading,
                    "pixel estimate: scalar F(Y) W (default) or vector (Enhanced 6.3: sum of m_i F(Y_i) W_i J_i over the "
                    "last spatial pass's inputs)",
                    restir_shading_names, 0, 0);
    rows[n++] = row("--force-nee-reconnection", OPT_FLAG, &o->force_nee_reconnection,
                    "hybrid shift: an NEE path with no connectable pair reconnects at its light vertex (Enhanced 6.2.3)",
                    NULL, 0, 0);
    rows[n++] = row("--rc-criterion", OPT_CHOICE, &o->rc_criterion,
                    "reconnection criterion: gris (roughness + distance, default) or footprint (Enhanced Eq. 5)",
                    rc_mode_names, 0, 0);
    rows[n++] = row("--footprint-c", OPT_REAL, &o->footprint_c,
                    "constant c of the footprint criterion (default 0.02; larger postpones reconnection)", NULL, 0,
                    1e9);
    rows[n++] = row("--paths", OPT_CHOICE, &o->paths, "all (default) or indirect (path length >= 3 only)",
                    restir_paths_names, 0, 0);
    rows[n++] = row("--ablate", OPT_CHOICE, &o->ablation,
                    "deliberately broken variant: none, jacobian (|dT/dx| = 1), light-pdf (stale light pdf), temporal-target, "
                    "temporal-suffix, stochastic-p (stochastic-pairwise without the P(i) correction), footprint-base-only "
                    "(footprint criterion not tested on the offset), dual-mv-vertex (dual-MV history with the occluder "
                    "pixel's x1), pair-mis (pair step: the canonical MIS ignores the "
                    "pre-pass shift to the partner), mutation-w (no Mutations Eq. 16 W update), "
                    "rv-kernel (symmetric path-mutation kernel, Mutations Eq. 20 dropped)",
                    restir_ablation_names, 0, 0);
    rows[n++] = row("--temporal-mis", OPT_CHOICE, &o->temporal.mis,
                    "temporal MIS (--sequence): constant (biased), talbot (default), pairwise, pairwise-defensive",
                    restir_mis_names, 0, 0);
    rows[n++] = row("--mutations", OPT_INT, &o->mutation.count,
                    "with --sequence: N MCMC mutations per pixel after the --mutate-after stage (Mutations Alg. 3; default 0)",
                    NULL, 0, MUTATE_MAX_ITERATIONS);
    rows[n++] = row("--mutation", OPT_CHOICE, &o->mutation.strategy,
                    "path mutation (Mutations §4.3): rv (reconnection vertex, default), pp (partial path), fp (full path)",
                    mutate_strategy_names, 0, 0);
    rows[n++] = row("--mutation-kernel", OPT_CHOICE, &o->mutation.kernel,
                    "PSS perturbation (Mutations 4.1): kelemen (u +- s, default; the oracle's deviation) or gaussian "
                    "(u + s n, n normal: the paper's; docs/deviations.md)",
                    mutate_kernel_names, 0, 0);
    rows[n++] = row("--mutation-sigma", OPT_REAL, &o->mutation.sigma,
                    "--mutation-kernel gaussian: the standard deviation in primary sample space (default 0: the "
                    "paper's amount s = s2 exp(-log(s2/s1) U), s1 = 1/1024, s2 = 1/64)",
                    NULL, 0, 0.5);
    rows[n++] = row("--mcap-mode", OPT_CHOICE, &o->temporal.mcap_mode,
                    "--sequence: relative (default: c_prev <= C c_cur, GRIS 6.4) or absolute (c_prev <= C, Mutations "
                    "Algorithm 2)",
                    temporal_mcap_mode_names, 0, 0);
    rows[n++] = row("--mutate-after", OPT_CHOICE, &o->mutation.stages,
                    "stages followed by mutations: temporal (default), initial, spatial, or a comma list of them",
                    mutate_after_names, 0, 0);
    rows[n++] = row("--russian-roulette", OPT_FLAG, &o->russian_roulette,
                    "Russian roulette in initial sampling (in the source pdf only)", NULL, 0, 0);
    /* correlation under motion (issue 12, docs/correlation.md) */
    rows[n++] = row("--dedup", OPT_FLAG, &o->correlation.dedup,
                    "BIASED. --sequence: duplication-map temporal cap, lerp(--mcap, --dedup-min, D^--dedup-alpha) with D "
                    "the duplicate share of the source pixel's 17x17 window (Enhanced 5)",
                    NULL, 0, 0);
    rows[n++] = row("--dedup-min", OPT_REAL, &o->correlation.dedup_min, "--dedup: c_cap_min, the cap at D = 1 (default 1)", NULL,
                    1e-9, 1e9);
    rows[n++] = row("--dedup-alpha", OPT_REAL, &o->correlation.dedup_alpha,
                    "--dedup: sensitivity alpha (default 0.1; 1 = linear, near 0 = quick reduction)", NULL, 1e-9, 1e9);
    rows[n++] = row("--motion-vectors", OPT_CHOICE, &o->temporal.motion_vectors,
                    "--sequence: temporal source of disoccluded pixels: single (none, default) or dual (follow the "
                    "occluder's motion, Enhanced 6.4 / Zeng et al. 2021; unbiased)",
                    restir_motion_vector_names, 0, 0);
    rows[n++] = row("--boiling-filter", OPT_REAL, &o->correlation.boiling_filter,
                    "BIASED. --sequence: RTXDI boiling filter of strength S in (0,1] after temporal reuse: clears "
                    "reservoirs with weight > (10/S - 9) x their 16x16 group's mean (0 = off, default)",
                    NULL, 0, 1);
    rows[n++] = row("--no-pair-step", OPT_FLAG, &o->no_pair_step,
                    "--pairing paired: a full GRIS step per pixel (4 shifts per pair) instead of the Enhanced 3 pair "
                    "step (2 shifts per pair, same output)",
                    NULL, 0, 0);
    return n;
}
