/* Temporal reuse at one pixel (GRIS §6.3 step 2, §6.4, App. B "Temporal Reuse"; Mutations
 * §2.4 Algorithm 2 and App. B; docs/restir-pt.md "Temporal reuse").
 *
 * Two domains: domain 0 is the pixel's reservoir of the current frame t (canonical: its
 * own initial resampling), domain 1 the reservoir the previous frame t-1 produced (its
 * spatial output) at the reprojected pixel q. The GRIS step is the spatial one
 * (spatial.h, gris_resample) with M = 2, except that the two directions of the shift live
 * in different frames:
 *   forward  y_1 = T_{t-1 -> t}(X_1): replayed/reconnected from the current y_1 in the
 *            current scene (restir_context `cur`);
 *   reverse  T_{t -> t-1}(y): the current candidate shifted back into the previous pixel,
 *            from q's primary vertex OF FRAME t-1 (previous camera, previous poses) in the
 *            previous frame's scene (restir_context `prev`). GRIS App. B: the MIS weights
 *            need the previous frame's target p̂_{t-1}; evaluating it with the current
 *            frame's camera or scene is biased (`--ablate temporal-target`, pitfall 8, docs/restir-pt.md §11).
 *   p̂ from i (GRIS Eq. 35):  [ p̂_t(y_0)                       p̂_t(y_1)            ]
 *                            [ p̂_{t-1}(T^{-1}(y_0)) |dT^{-1}|  p̂_{t-1}(X_1) / J_1  ]
 *   w_j = m_j(y_j) p̂_t(y_j) W_j J_j (GRIS Eq. 19), W = sum w / p̂_t(Y) (GRIS Eq. 22) with
 *   m_j from Talbot (GRIS Eq. 36 = Mutations Eqs. 31-32), pairwise (Eqs. 37-38) or constant.
 *
 * M-capping (GRIS §6.2 M_c, §6.4): the previous reservoir's confidence is capped at
 * mcap times the current one's before the step, c_1 <- min(c_1, C c_0); C = infinity
 * keeps the whole history (the still-camera chain then converges to a wrong value,
 * GRIS Fig. 2/10). The output confidence is c_0 + min(c_1, C c_0).
 * That is the relative cap (--mcap-mode relative, the default). Mutations Algorithm 2 line 3
 * caps absolutely, r_j.M <- min(r_j.M, M_cap) (--mcap-mode absolute): c_1 <- min(c_1, C).
 * The two agree when the current confidence is 1 (one candidate per frame); with N
 * candidates the relative cap lets the history count N times more (N = 32, C = 50: 1600
 * against 50). Either is unbiased: a cap only changes the confidences, which enter the MIS
 * weights of the step, and those sum to one whatever the confidences are (GRIS §6.4). */
#ifndef RESTIR_TEMPORAL_H
#define RESTIR_TEMPORAL_H

#include "restir/restir/spatial.h"

typedef struct {
    uint64_t pixels;            /* pixels with a primary hit in frame t */
    uint64_t no_history;        /* ... whose reprojection failed (off screen, disoccluded, first frame) */
    uint64_t capped;            /* previous confidences lowered by the cap */
    uint64_t dual;              /* histories found by the dual motion vector (Enhanced §6.4) */
    uint64_t dedup_lowered;     /* steps whose cap the duplication map lowered (Enhanced §5) */
    spatial_stats step;         /* the GRIS steps: shifts by outcome (forward and reverse);
                                   step.selected_neighbor = outputs taken from frame t-1 */
} temporal_stats;

/* Animated scenes: the two frames' scenes and indices. Before a sample crosses from one
 * frame to the other its reconnection vertex is posed in the destination frame and its
 * suffix is traced again there (rc_retrace_suffix), so a reused path is a path of the
 * destination scene (the cached x_k and L_k of frame t-1 are not, where objects moved). */
typedef struct {
    const restir_context *ctx[2]; /* [0] frame t, [1] frame t-1 (scenes posed at those frames) */
    int frame[2];
} temporal_frames;

/* The temporal GRIS step. x1_cur: the pixel's primary vertex in frame t; x1_prev: the
 * primary vertex of the reprojected pixel in frame t-1 (x1_prev, prev_r NULL: no history,
 * the output is the current reservoir). u[0], u[1]: selection numbers (RNG_VERTEX_TEMPORAL_RIS,
 * docs/rng.md). mcap > 0 (may be infinite). The workspace holds >= 2 domains. frames:
 * NULL when nothing but the camera moves (a static scene needs no re-tracing). */
void temporal_resample(const restir_context *cur, const restir_context *prev, const temporal_frames *frames,
                       mis_family mis,
                       const path_vertex *x1_cur, const path_vertex *x1_prev, const reservoir *cur_r,
                       const reservoir *prev_r, real mcap, const real *u, reservoir *out, spatial_workspace *w,
                       temporal_stats *st);

/* How the temporal cap C applies (temporal_options.mcap_mode). */
enum temporal_mcap_mode {
    TEMPORAL_MCAP_RELATIVE = 0, /* c_prev <= C c_cur (GRIS §6.2, §6.4, §8.3; default) */
    TEMPORAL_MCAP_ABSOLUTE = 1  /* c_prev <= C (Mutations Algorithm 2, line 3) */
};
extern const char *const temporal_mcap_mode_names[]; /* "relative", "absolute" */

/* The previous confidence after the cap: min(c_prev, C c_cur) or min(c_prev, C); C may be
 * infinite (no cap). */
real temporal_capped_confidence(real c_prev, real c_cur, real mcap, enum temporal_mcap_mode mode);

/* temporal_resample with the cap applied in `mode` (temporal_resample: relative). */
void temporal_resample_mode(const restir_context *cur, const restir_context *prev, const temporal_frames *frames,
                            mis_family mis, const path_vertex *x1_cur, const path_vertex *x1_prev,
                            const reservoir *cur_r, const reservoir *prev_r, real mcap,
                            enum temporal_mcap_mode mode, const real *u, reservoir *out, spatial_workspace *w,
                            temporal_stats *st);

void temporal_stats_add(temporal_stats *acc, const temporal_stats *add);

/* The temporal technique's options (the real-time pipeline's step 2, GRIS §6.3). Where the
 * history of a disoccluded pixel comes from: nowhere (single), or the occluder's motion
 * (dual, Enhanced §6.4 / Zeng et al. 2021; unbiased). */
enum restir_motion_vectors { RESTIR_MV_SINGLE = 0, RESTIR_MV_DUAL = 1 };
extern const char *const restir_motion_vector_names[]; /* "single", "dual" */
typedef struct {
    int enabled;     /* temporal reuse (default 1; sequences only) */
    mis_family mis;  /* of the temporal step (default MIS_TALBOT, GRIS §8.3) */
    double mcap;     /* C > 0: c_prev <= C c_cur (GRIS §6.2, §6.4; default 20; may be inf) */
    enum temporal_mcap_mode mcap_mode; /* relative (default, C c_cur) or absolute (C; Mutations Alg. 2) */
    enum restir_motion_vectors motion_vectors; /* default single */
} temporal_options;

void temporal_options_default(temporal_options *o);
/* 0, or -1 with "temporal: what is wrong". */
int temporal_options_validate(const temporal_options *o, rerror *e);

#endif
