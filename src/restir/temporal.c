/* Temporal reuse at one pixel (include/restir/restir/temporal.h). */
#include "restir/restir/temporal.h"

#include <math.h>
#include "restir/core/invariant.h"
#include "restir/restir/temporal_check.h"
#include "restir/scene/animation.h"

/* domain_refresh for two frames: x (of frame `from`) re-expressed in frame `to`'s scene, its
 * reconnection vertex moved by its object's motion between the two frames. */
static enum shift_failure refresh_between_frames(const void *user, int from, int to, const path_sample *x,
                                                 path_sample *out)
{
    const temporal_frames *tf = user;
    const restir_context *dest = tf->ctx[to];
    const scene *s = dest->path.scene;
    double mf[3][3], mt[3][3], tv[3], rot[3][3];
    int i, j, l, moved = 0;
    if (path_sample_is_valid(x) && x->rc_k != PATH_RC_NONE && x->rc_triangle < s->triangle_count) {
        uint32_t object = s->triangles[x->rc_triangle].object;
        scene_object_transform_at_d(s, object, tf->frame[from], mf, tv);
        scene_object_transform_at_d(s, object, tf->frame[to], mt, tv);
        for (i = 0; i < 3; ++i)
            for (j = 0; j < 3; ++j) {
                rot[i][j] = 0; /* R = M_to M_from^T */
                for (l = 0; l < 3; ++l) rot[i][j] += mt[i][l] * mf[j][l];
                moved |= mf[i][j] != mt[i][j];
            }
    }
    return rc_retrace_suffix(dest, x, moved ? (const double(*)[3])rot : NULL, out);
}

const char *const temporal_mcap_mode_names[] = {"relative", "absolute", NULL};

/* GRIS §6.2 M_c, §6.4 (relative: the history counts at most C times the new samples) or
 * Mutations Algorithm 2 line 3 (absolute: at most C). */
real temporal_capped_confidence(real c_prev, real c_cur, real mcap, enum temporal_mcap_mode mode)
{
    real cap;
    if (!isfinite((double)mcap)) return c_prev;
    cap = mode == TEMPORAL_MCAP_ABSOLUTE ? mcap : mcap * c_cur;
    return c_prev > cap ? cap : c_prev;
}

void temporal_resample(const restir_context *cur, const restir_context *prev, const temporal_frames *frames,
                       mis_family mis,
                       const path_vertex *x1_cur, const path_vertex *x1_prev, const reservoir *cur_r,
                       const reservoir *prev_r, real mcap, const real *u, reservoir *out, spatial_workspace *w,
                       temporal_stats *st)
{
    temporal_resample_mode(cur, prev, frames, mis, x1_cur, x1_prev, cur_r, prev_r, mcap, TEMPORAL_MCAP_RELATIVE, u, out,
                           w, st);
}

void temporal_resample_mode(const restir_context *cur, const restir_context *prev, const temporal_frames *frames,
                            mis_family mis, const path_vertex *x1_cur, const path_vertex *x1_prev,
                            const reservoir *cur_r, const reservoir *prev_r, real mcap,
                            enum temporal_mcap_mode mode, const real *u, reservoir *out, spatial_workspace *w,
                            temporal_stats *st)
{
    const path_vertex *x1[2];
    const reservoir *in[2];
    reservoir capped, cur_capped;
    domain_refresh rf;
    st->pixels++;
    if (!x1_prev || !prev_r) {
        st->no_history++;
        *out = *cur_r;
        return;
    }
    /* GRIS §6.2 M_c, §6.4 (relative) or Mutations Algorithm 2 line 3 (absolute) */
    capped = *prev_r;
    in[0] = cur_r;
    if (isfinite((double)mcap) && cur->ablation == RESTIR_ABLATE_MCAP_CURRENT) {
        /* the planted GPU bug: the cap lands on the current reservoir */
        cur_capped = *cur_r;
        reservoir_cap_confidence(&cur_capped, mcap * prev_r->confidence);
        in[0] = &cur_capped;
    } else if (isfinite((double)mcap)) {
        real cap = temporal_capped_confidence(capped.confidence, cur_r->confidence, mcap, mode);
        if (capped.confidence > cap) st->capped++;
        reservoir_cap_confidence(&capped, cap);
    }
    x1[0] = x1_cur;
    x1[1] = x1_prev;
    in[1] = &capped;
    /* domain 1's MIS shifts run in the previous frame (GRIS App. B) */
    rf.fn = refresh_between_frames;
    rf.user = frames;
    gris_resample(cur, prev, frames ? &rf : NULL, mis, 2, x1, in, u, out, w, &st->step);
    /* the deliberately biased ablations evaluate frame t-1 with frame t's camera / scene, or
     * take another pixel's x1 for the history */
    if (RESTIR_DEBUG_ENABLED && cur->ablation != RESTIR_ABLATE_TEMPORAL_TARGET &&
        cur->ablation != RESTIR_ABLATE_TEMPORAL_SUFFIX && cur->ablation != RESTIR_ABLATE_DUAL_MV_VERTEX) {
        char why[512];
        if (temporal_check_round_trip(prev, frames ? &rf : NULL, x1_prev, &prev_r->y, w, why, sizeof why, NULL))
            restir_invariant_failed(__FILE__, __LINE__, why);
    }
}

void temporal_stats_add(temporal_stats *acc, const temporal_stats *add)
{
    acc->pixels += add->pixels;
    acc->no_history += add->no_history;
    acc->capped += add->capped;
    acc->dual += add->dual;
    acc->dedup_lowered += add->dedup_lowered;
    spatial_stats_add(&acc->step, &add->step);
}

const char *const restir_motion_vector_names[] = {"single", "dual", NULL};

void temporal_options_default(temporal_options *o)
{
    o->enabled = 1;
    o->mis = MIS_TALBOT;
    o->mcap = 20;
    o->mcap_mode = TEMPORAL_MCAP_RELATIVE;
    o->motion_vectors = RESTIR_MV_SINGLE;
}

int temporal_options_validate(const temporal_options *o, rerror *e)
{
    if ((int)o->mis < 0 || (int)o->mis >= MIS_FAMILY_COUNT)
        return rerror_set(e, "temporal: unknown MIS family %d", (int)o->mis);
    if (!(o->mcap > 0)) return rerror_set(e, "temporal: M-cap %g (must be > 0, or inf)", o->mcap);
    if (o->mcap_mode != TEMPORAL_MCAP_RELATIVE && o->mcap_mode != TEMPORAL_MCAP_ABSOLUTE)
        return rerror_set(e, "temporal: unknown M-cap mode %d", (int)o->mcap_mode);
    if (o->motion_vectors != RESTIR_MV_SINGLE && o->motion_vectors != RESTIR_MV_DUAL)
        return rerror_set(e, "temporal: unknown motion vectors %d", (int)o->motion_vectors);
    return 0;
}
