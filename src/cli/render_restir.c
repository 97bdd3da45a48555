/* Option rows of `restir render --method restir` (src/cli/render_restir.h). */
#include "render_restir.h"

#include <stdio.h>
#include <string.h>

static const char *const preset_names[] = {"none", "gris-offline", "gris-realtime", NULL};
static int preset_dummy;

int render_restir_apply_preset(int argc, char **argv, restir_options *o)
{
    int i;
    for (i = 1; i + 1 < argc; ++i) {
        if (strcmp(argv[i], "--preset")) continue;
        if (!strcmp(argv[i + 1], "gris-offline")) restir_options_preset_gris_offline(o);
        else if (!strcmp(argv[i + 1], "gris-realtime")) restir_options_preset_gris_realtime(o);
        else if (strcmp(argv[i + 1], "none")) {
            fprintf(stderr, "restir render: --preset: unknown preset '%s' (none, gris-offline, gris-realtime)\n",
                    argv[i + 1]);
            return 2;
        }
    }
    return 0;
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

int render_restir_options(cli_option *rows, restir_options *o)
{
    int n = 0;
    rows[n++] = row("--shift", OPT_CHOICE, &o->shift,
                    "shift mapping: reconnection (y2 = x2), replay (random replay), hybrid (default; GRIS 7.4)",
                    restir_shift_names, 0, 0);
    rows[n++] = row("--preset", OPT_CHOICE, &preset_dummy,
                    "gris-offline: 32 path trees, 3 spatial passes, 6 neighbours, radius 10 (GRIS 8.3); "
                    "gris-realtime: 1 path tree, temporal talbot cap 20, 1 spatial pass, 3 neighbours, radius 20, "
                    "pairwise-defensive (GRIS 8.3, use with --sequence); other options override it",
                    preset_names, 0, 0);
    rows[n++] = row("--spatial-passes", OPT_INT, &o->spatial_passes,
                    "K spatial reuse passes, 0..16 (0: initial resampling only; default 0)", NULL, 0,
                    RESTIR_MAX_SPATIAL_PASSES);
    rows[n++] = row("--neighbors", OPT_INT, &o->neighbors, "neighbour candidates per pixel and pass (default 6)", NULL,
                    1, NEIGHBOR_MAX_COUNT);
    rows[n++] = row("--radius", OPT_REAL, &o->radius,
                    "neighbour disk radius in pixels (default 10; box: half-size floor(R))", NULL, 1, 4096);
    rows[n++] = row("--pattern", OPT_CHOICE, &o->pattern,
                    "neighbour pattern: uniform disk, r2 (low-discrepancy disk, default), box window",
                    neighbor_pattern_names, 0, 0);
    rows[n++] = row("--pairing", OPT_CHOICE, &o->pairing,
                    "spatial neighbours: disk (the --pattern, default) or paired (reciprocal pairs from reuse textures, "
                    "Enhanced 3; sigma = 0.532 radius)",
                    restir_pairing_names, 0, 0);
    rows[n++] = row("--no-reject", OPT_FLAG, &o->no_reject, "keep neighbours whatever their normal and depth", NULL,
                    0, 0);
    rows[n++] = row("--normal-cos", OPT_REAL, &o->normal_cos,
                    "reject a neighbour if dot(n_i, n_j) < this (default 0.5)", NULL, -1, 1);
    rows[n++] = row("--depth-ratio", OPT_REAL, &o->depth_ratio,
                    "reject a neighbour if |d_i - d_j| > this * min(d_i, d_j) (default 0.1)", NULL, 0, 1e9);
    rows[n++] = row("--mis", OPT_CHOICE, &o->mis,
                    "resampling MIS: constant (biased, GRIS 5.6), talbot (default, Eq. 36), pairwise (Eq. 37), "
                    "pairwise-defensive (Eq. 38), stochastic-pairwise (Stochastic MIS Eqs. 16-19: Ne picks by Eq. 17)",
                    restir_mis_names, 0, 0);
    rows[n++] = row("--stochastic-n", OPT_INT, &o->stochastic_n,
                    "stochastic-pairwise: candidates picked per pixel and pass, N~ (default 1)", NULL, 1,
                    STOCHASTIC_MAX_PICKS);
    rows[n++] = row("--stochastic-nc", OPT_INT, &o->stochastic_nc,
                    "stochastic-pairwise: uniform picks estimating the canonical weight, N~_c (default 1)", NULL, 1,
                    STOCHASTIC_MAX_PICKS);
    rows[n++] = row("--reuse-cells", OPT_FLAG, &o->cells,
                    "spatial domains = the pixels of one 8x8-tile reuse cell found by the Stochastic MIS 5.1 search "
                    "(instead of --pattern neighbours; any --mis)",
                    NULL, 0, 0);
    rows[n++] = row("--no-confidence-scaling", OPT_FLAG, &o->no_confidence_scaling,
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
                    "(footprint criterion not tested on the offset), mutation-w (no Mutations Eq. 16 W update), "
                    "rv-kernel (symmetric path-mutation kernel, Mutations Eq. 20 dropped)",
                    restir_ablation_names, 0, 0);
    rows[n++] = row("--temporal-mis", OPT_CHOICE, &o->temporal_mis,
                    "temporal MIS (--sequence): constant (biased), talbot (default), pairwise, pairwise-defensive",
                    restir_mis_names, 0, 0);
    rows[n++] = row("--mutations", OPT_INT, &o->mutations,
                    "with --sequence: N MCMC mutations per pixel after the --mutate-after stage (Mutations Alg. 3; default 0)",
                    NULL, 0, MUTATE_MAX_ITERATIONS);
    rows[n++] = row("--mutation", OPT_CHOICE, &o->mutation,
                    "path mutation (Mutations §4.3): rv (reconnection vertex, default), pp (partial path), fp (full path)",
                    mutate_strategy_names, 0, 0);
    rows[n++] = row("--mutate-after", OPT_CHOICE, &o->mutate_after,
                    "stages followed by mutations: temporal (default), initial, spatial, or a comma list of them",
                    mutate_after_names, 0, 0);
    rows[n++] = row("--russian-roulette", OPT_FLAG, &o->russian_roulette,
                    "Russian roulette in initial sampling (in the source pdf only)", NULL, 0, 0);
    return n;
}
