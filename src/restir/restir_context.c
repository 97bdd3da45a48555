/* Name tables of include/restir/restir/restir_context.h (CLI choices, --stats keys). */
#include "restir/restir/restir_context.h"

#include <stddef.h>

const char *const restir_shift_names[] = {"reconnection", "replay", "hybrid", NULL};
const char *const restir_ablation_names[] = {"none", "jacobian", "light-pdf", "temporal-target", "temporal-suffix",
                                                "stochastic-p", "footprint-base-only", "dual-mv-vertex",
                                                "pair-mis", "mutation-w", "rv-kernel", "light-ris-pdf", "mcap-current",
                                                "neighbor-rng", NULL};
const char *const rc_mode_names[] = {"gris", "footprint", NULL};

/* Index = enum shift_failure. */
const char *const shift_failure_names[] = {
    "ok",
    "empty",
    "no_primary",
    "unshiftable",
    "replay_sample",
    "replay_zero",
    "replay_miss",
    "replay_no_light",
    "nee",
    "rc_earlier",
    "rc_prev",
    "rc_roughness",
    "rc_distance",
    "rc_offset_reconnects",
    "delta_lobe",
    "lobe_unavailable",
    "occluded",
    "bsdf_zero",
    "zero",
    "nonfinite",
    "rc_footprint",
    NULL,
};
