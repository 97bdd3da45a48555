/* Option rows of `restir render --method restir` (src/cli/render_restir.h). */
#include "render_restir.h"

#include <string.h>

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
    rows[n++] = row("--spatial-passes", OPT_INT, &o->spatial_passes,
                    "0: initial resampling only (default); 1: merge with one random neighbour", NULL, 0, 1);
    rows[n++] = row("--neighbors", OPT_INT, &o->neighbors, "neighbours per spatial pass (1)", NULL, 1, 1);
    rows[n++] = row("--radius", OPT_REAL, &o->radius, "neighbour disk radius in pixels (default 10)", NULL, 1, 4096);
    rows[n++] = row("--mis", OPT_CHOICE, &o->mis, "resampling MIS of the merge: talbot (GRIS Eq. 36)", restir_mis_names,
                    0, 0);
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
    rows[n++] = row("--paths", OPT_CHOICE, &o->paths, "all (default) or indirect (path length >= 3 only)",
                    restir_paths_names, 0, 0);
    rows[n++] = row("--ablate", OPT_CHOICE, &o->ablation,
                    "deliberately broken variant: none, jacobian (|dT/dx| = 1), light-pdf (stale light pdf)",
                    restir_ablation_names, 0, 0);
    rows[n++] = row("--russian-roulette", OPT_FLAG, &o->russian_roulette,
                    "Russian roulette in initial sampling (in the source pdf only)", NULL, 0, 0);
    return n;
}
