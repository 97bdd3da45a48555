/* The temporal reverse shift's round trip (include/restir/temporal_check.h). */
#include "restir/restir/temporal_check.h"

#include <math.h>
#include <stdio.h>

static int close_rel(double a, double b, double tol)
{
    double scale = fabs(a) > fabs(b) ? fabs(a) : fabs(b);
    return fabs(a - b) <= tol * scale;
}

int temporal_check_round_trip(const restir_context *prev, const domain_refresh *rf, const path_vertex *x1_prev,
                              const path_sample *x, const spatial_workspace *w, char *why, size_t why_size,
                              long *checked)
{
    /* float geometry: a round trip moves p̂ by up to ~1e-5 relative in static scenes of
     * rough surfaces, but x_k is stored in float, so the reconnection direction carries
     * ~1e-7 relative rounding, which a near-specular lobe at y_{k-1} turns into up to 1.6e-3
     * (measured: the courtyard's glossy metal box, d 3, k 2, scenes/courtyard.scene); in
     * animated ones the suffix is traced again twice (into frame t and back), from a posed
     * x_k that is rounded anew, and a suffix vertex's NEE moves p̂ by up to ~1e-2 (measured
     * over the temporal suite: median 2e-5, max 1.03e-2). The planted 2% errors of
     * evidence_temporal_round_trip_exact stay well outside both. */
    double tol = sizeof(real) == 4 ? (rf ? 1e-1 : 2e-2) : (rf ? 5e-2 : 5e-3);
    path_sample tmp, back;
    const path_sample *y = w->cand[1];
    real jacobian;
    double diag, stored;
    if (w->max_domains < 2 || !w->valid[1]) return 0;
    if (rf) { /* y_1 re-expressed in frame t-1's scene, as the MIS shifts out of frame t do */
        if (rf->fn(rf->user, 0, 1, y, &tmp) != SHIFT_OK) return 0;
        y = &tmp;
    }
    /* the reverse shift T_{t -> t-1}(y_1) from the previous pixel (GRIS Eq. 35, App. B) */
    if (shift_path(prev, x1_prev, y, &back, &jacobian, NULL) != SHIFT_OK) return 0;
    if (prev->ablation == RESTIR_ABLATE_JACOBIAN && jacobian > 0) jacobian = 1;
    if (checked) ++*checked;
    diag = (double)w->ptarget[1 * 2 + 1];
    stored = (double)x->target;
    if (!close_rel((double)back.target, stored, tol)) {
        snprintf(why, why_size,
                 "temporal round trip: p̂_{t-1}(T^-1(T(X))) = %.9g, the stored p̂_{t-1}(X) = %.9g (d %d, k %d, %s, %s)",
                 (double)back.target, stored, x->length, x->rc_k, x->technique == PATH_TECH_NEE ? "NEE" : "BSDF",
                 rf ? "animated" : "static");
        return 1;
    }
    if (!close_rel((double)back.target * (double)jacobian, diag, tol)) {
        snprintf(why, why_size,
                 "temporal round trip: the history candidate's MIS term is %.9g, the reverse shift gives "
                 "p̂_{t-1} |dT^-1/dy| = %.9g (GRIS Eq. 35)",
                 diag, (double)back.target * (double)jacobian);
        return 1;
    }
    return 0;
}
