/* What a spatial pass reuses and how (GRIS §6.3 step 3; Enhanced §3; Stochastic MIS §4-§5):
 * the neighbour candidates (pattern, count, radius, paired reuse textures, geometric
 * rejection), the GRIS step that resamples them (a deterministic MIS family, or stochastic
 * pairwise MIS) and whether the domains come from a reuse cell instead. The spatial
 * technique's own options, defaults and validation; the frame composes them
 * (include/restir/frame/options.h). */
#ifndef RESTIR_SPATIAL_OPTIONS_H
#define RESTIR_SPATIAL_OPTIONS_H

#include "restir/core/error.h"
#include "restir/restir/mis.h"
#include "restir/restir/neighbors.h"

enum restir_pairing { RESTIR_PAIRING_DISK = 0, RESTIR_PAIRING_PAIRED = 1 };
extern const char *const restir_pairing_names[]; /* "disk", "paired" */

/* The GRIS step of a pass: spatial_resample with the MIS family `mis` (spatial.h), or
 * stochastic_pairwise_resample (stochastic_spatial.h, Stochastic MIS §4), which has no
 * family: its weights are unbiased estimates of the defensive pairwise ones. */
enum spatial_algorithm { SPATIAL_GRIS_STEP = 0, SPATIAL_STOCHASTIC_PAIRWISE = 1 };
extern const char *const spatial_algorithm_names[]; /* "gris-step", "stochastic-pairwise" */

typedef struct {
    enum spatial_algorithm algorithm; /* default SPATIAL_GRIS_STEP */
    mis_family mis;                   /* of the GRIS step (default MIS_TALBOT, GRIS Eq. 36) */
    int neighbors;                    /* n candidates per pixel and pass (disk patterns; default 6) */
    double radius;                    /* neighbour disk radius in pixels (default 10, GRIS §8.3 offline) */
    enum neighbor_pattern pattern;    /* default r2 */
    enum restir_pairing pairing;      /* disk (default: `pattern`) or paired (Enhanced §3) */
    int no_reject;                    /* 1: no normal/depth rejection of neighbours */
    double normal_cos;                /* reject if dot(n_i, n_j) < this (default 0.5) */
    double depth_ratio;               /* reject if |d_i - d_j| > this * min(d_i, d_j) (default 0.1) */
    enum pairing_eq3 eq3_reading;     /* paired: the reading of Enhanced Eq. 3 (default port-round,
                                         pairing.h; signed-ceil was the default before issue 28) */
    int cells;                        /* domains = a reuse cell found by the Stochastic MIS §5.1 search
                                         (reuse_cells.h) instead of neighbor_select; either algorithm */
} spatial_options;

void spatial_options_default(spatial_options *o);
/* 0, or -1 with "spatial: what is wrong" (or the neighbour selection's own message). */
int spatial_options_validate(const spatial_options *o, rerror *e);
/* The neighbour selection options of o (neighbors.h); --pairing paired selects NEIGHBOR_PAIRED. */
void spatial_neighbor_options(neighbor_options *no, const spatial_options *o);
/* The name of the weights a pass uses: the MIS family's, or "stochastic-pairwise". */
const char *spatial_mis_name(const spatial_options *o);

#endif
