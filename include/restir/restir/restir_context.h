/* The shared vocabulary of ReSTIR PT's path reuse (docs/restir-pt.md): which shift
 * mapping is used, why a shift fails, the reconnection criterion's parameters, the
 * deliberately broken variants, and the context every pass and shift reads.
 *
 * Path indexing follows GRIS §7.1 (path_sample.h): x0 camera, x1 primary hit, ..., x_d
 * the emitter vertex; k is the reconnection index (x_k is copied by a reconnection). */
#ifndef RESTIR_RESTIR_CONTEXT_H
#define RESTIR_RESTIR_CONTEXT_H

#include "restir/render/vertex_sampling.h"

/* The shift mappings of GRIS §7.4 (Enhanced §2.3). The shift also decides which
 * reconnection index a sample stores (connectability.h, rc_select). */
enum restir_shift {
    RESTIR_SHIFT_RECONNECTION = 0, /* y_2 = x_2 always (k = 2; ReSTIR GI made unbiased) */
    RESTIR_SHIFT_REPLAY = 1,       /* random replay of every number from y_1 (no k) */
    RESTIR_SHIFT_HYBRID = 2        /* replay up to y_{k-1}, reconnect to x_k (GRIS §7.4-7.6) */
};
#define RESTIR_SHIFT_COUNT 3

/* Why a shift T(x) produced no offset path. Every value is counted in --stats so users
 * can see why reuse fails (docs/restir-pt.md, "Failure reasons"). */
enum shift_failure {
    SHIFT_OK = 0,
    SHIFT_FAIL_EMPTY,           /* the base reservoir holds no sample */
    SHIFT_FAIL_NO_PRIMARY,      /* the destination pixel has no primary hit */
    SHIFT_FAIL_UNSHIFTABLE,     /* the base's own reconnection fails (PATH_RC_FLAG_UNSHIFTABLE) */
    SHIFT_FAIL_REPLAY_SAMPLE,   /* a replayed BSDF sample produced no direction */
    SHIFT_FAIL_REPLAY_ZERO,     /* a replayed bounce has zero throughput */
    SHIFT_FAIL_REPLAY_MISS,     /* a replayed ray left the scene */
    SHIFT_FAIL_REPLAY_NO_LIGHT, /* the replayed last vertex is no (front-facing) emitter */
    SHIFT_FAIL_NEE,             /* the replayed light sample is occluded or contributes 0 */
    SHIFT_FAIL_RC_EARLIER,      /* invertibility: an earlier offset vertex pair is connectable */
    SHIFT_FAIL_RC_PREV,         /* invertibility: y_{k-1} itself would be the reconnection vertex */
    SHIFT_FAIL_RC_ROUGHNESS,    /* y_{k-1} is not rough for the base's lobe ell_{k-1} */
    SHIFT_FAIL_RC_DISTANCE,     /* ||x_k - y_{k-1}|| < d_min (distance condition, GRIS §7.5) */
    SHIFT_FAIL_RC_OFFSET_RECONNECTS, /* no k in the base, but the offset path would have one */
    SHIFT_FAIL_DELTA_LOBE,      /* a Dirac lobe at x_{k-1} or x_k: reconnection impossible */
    SHIFT_FAIL_LOBE_UNAVAILABLE,/* y_{k-1} cannot sample the base lobe (P(ell|wo) = 0, no such lobe) */
    SHIFT_FAIL_OCCLUDED,        /* the reconnection segment y_{k-1} -> x_k is blocked */
    SHIFT_FAIL_BSDF_ZERO,       /* the BSDF at y_{k-1} or x_k is 0 for the reconnected directions
                                   (e.g. x_k below y_{k-1}'s surface, or w_k and the new incoming
                                   direction on opposite sides of a reflecting x_k) */
    SHIFT_FAIL_ZERO,            /* F(y) = 0 otherwise: G = 0 (grazing), no emission towards y_{d-1} */
    SHIFT_FAIL_NONFINITE,       /* F(y) or the Jacobian is not finite */
    SHIFT_FAIL_RC_FOOTPRINT,    /* Enhanced Eq. 5: a ray footprint of the pair is below c/100 times
                                   the primary-ray footprint (--rc-criterion footprint) */
    SHIFT_FAILURE_COUNT
};

/* Deliberately broken variants (`--ablate NAME`, docs/statistics.md): the merge test must
 * reject each of them. */
enum restir_ablation {
    RESTIR_ABLATE_NONE = 0,
    RESTIR_ABLATE_JACOBIAN = 1, /* "jacobian": |dT/dx| taken as 1 in resampling weights and MIS */
    RESTIR_ABLATE_LIGHT_PDF = 2, /* "light-pdf": after a shift that moves x_{d-1} (reconnection
                                   at k = d), the light pdf of the last vertex is not recomputed:
                                   the base path's stale value enters the NEE estimate and the
                                   NEE/BSDF MIS weight (pitfall 6, docs/restir-pt.md §11) */
    RESTIR_ABLATE_TEMPORAL_TARGET = 3, /* "temporal-target": temporal reuse evaluates the reverse
                                   shift (current -> previous pixel) with the CURRENT frame's
                                   camera and scene instead of the previous frame's (notes
                                   pitfall 8; GRIS App. B requires the previous frame's) */
    RESTIR_ABLATE_TEMPORAL_SUFFIX = 4, /* "temporal-suffix": in animated scenes a sample crosses
                                   frames with its cached x_k position and suffix radiance L_k
                                   (no rc_retrace_suffix): where objects moved, a reused path
                                   is not a path of the current scene */
    RESTIR_ABLATE_STOCHASTIC_P = 5 /* "stochastic-p": stochastic pairwise MIS picks its Ñ
                                   candidates uniformly among the non-zero samples but weights
                                   them as if P(i) = 1/M (no P(i) correction; Stochastic MIS §3:
                                   "naively choosing input pixels based on their samples") */,
    RESTIR_ABLATE_FOOTPRINT_BASE = 6, /* "footprint-base-only": with --rc-criterion footprint the
                                   shift does not test the criterion on the offset path (no
                                   invertibility check): T is then not a bijection (Enhanced §4) */
    RESTIR_ABLATE_DUAL_MV_VERTEX = 7 /* "dual-mv-vertex": with --motion-vectors dual, a history
                                   found by the dual motion vector is resampled with the reverse
                                   shift starting at the STANDARD previous pixel's x1 (the
                                   occluder) instead of the dual source pixel's: the target of
                                   domain 1 is then not the one its reservoir estimates */,
    RESTIR_ABLATE_PAIR_MIS = 8 /* "pair-mis": the pair step (--pairing paired) drops one side of
                                   each pair from the MIS: the canonical sample's weight ignores
                                   the pre-pass shift X_0 -> partner (p̂_{<-d}(X_0) taken as 0) */,
    RESTIR_ABLATE_MUTATION_W = 9, /* "mutation-w": an accepted MCMC mutation keeps W (no
                                   Mutations Eq. 16 update p̂(x^0)/p̂(x^k)) */
    RESTIR_ABLATE_RV_KERNEL = 10,  /* "rv-kernel": the path mutations' kernel ratio
                                   T(z->x)/T(x->z) of Mutations Eq. 20 taken as 1 (a symmetric
                                   kernel) */
    RESTIR_ABLATE_LIGHT_RIS_PDF = 11 /* "light-ris-pdf": with --light-ris, the BSDF side's MIS
                                   weight uses p_0 while NEE uses p̃ = 1/W (pt's ablation of the
                                   same name, in every path contribution ReSTIR evaluates) */,
    /* Per-stage bugs a GPU build makes (issue 31's planted bugs, docs/oracle.md §7): the
     * estimate stays (nearly) unbiased, so only a stage diff sees them; `restir diagnose`
     * tries them. */
    RESTIR_ABLATE_MCAP_CURRENT = 12, /* "mcap-current": the temporal M-cap is applied to the
                                   current reservoir (c_0 <= C c_1) instead of the history
                                   (c_1 <= C c_0, GRIS §6.2): the history grows uncapped */
    RESTIR_ABLATE_NEIGHBOR_RNG = 13 /* "neighbor-rng": the neighbour choice of spatial pass p
                                   draws its numbers at RNG sample index
                                   neighbor_sample_index(...) + 1 (off by one, neighbors.h) */
};
#define RESTIR_ABLATION_COUNT 14

/* Reconnection criterion (connectability.h). gris (GRIS §7.4-7.5, §8.3; Enhanced §2.3):
 * x_{k-1} and x_k must be rough for their lobes and ||x_k - x_{k-1}|| >= min_distance.
 * footprint (Enhanced §4, Eq. 5): x_{k-1} rough (alpha_min) and the dual ray footprint
 * threshold with constant footprint_c (src/restir/footprint.c). */
enum rc_mode { RC_MODE_GRIS = 0, RC_MODE_FOOTPRINT = 1 };
extern const char *const rc_mode_names[]; /* "gris", "footprint" */

typedef struct {
    real roughness_threshold; /* on the lobe's linear roughness (GRIS §8.3: 0.2; Enhanced alpha_min) */
    real min_distance;        /* d_min in scene units (gris only) */
    enum rc_mode mode;        /* enum rc_mode (default gris) */
    real footprint_c;         /* c of Enhanced Eq. 5 (0.02, Enhanced §7.2) */
    int force_nee;            /* Enhanced §6.2.3: an NEE path without connectable pair reconnects
                                 at its light vertex x_d (hybrid shift) */
} rc_criterion;

typedef struct {
    path_context path; /* scene, lights, MIS: the reference path tracer's per-vertex steps */
    enum restir_shift shift; /* enum restir_shift */
    rc_criterion rc;
    enum restir_ablation ablation; /* enum restir_ablation */
} restir_context;

/* NULL-terminated name tables (index = enum value): "reconnection", "replay", "hybrid";
 * "none", "jacobian", "light-pdf"; and the failure reasons ("ok", "empty", ...). */
extern const char *const restir_shift_names[];
extern const char *const restir_ablation_names[];
extern const char *const shift_failure_names[];

#endif
