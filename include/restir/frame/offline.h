/* Offline ReSTIR PT (GRIS §6.5; docs/restir-pt.md): per frame, initial resampling over N
 * path trees per pixel (initial.h), K spatial passes (GRIS §6.3 step 3: every pixel
 * resamples its own reservoir and n accepted neighbours, neighbors.h + spatial.h, with the
 * MIS family of mis.h; reservoirs ping-pong between passes), and shading
 *     I_frame = Le(x1) + F(Y) W_Y        (emission at x1 is added, never resampled)
 * averaged over independent frames with the explicit mean of GRIS Eq. 47 (GRIS §6.5).
 * With --paths indirect the image holds only paths of length d >= 3 (no Le(x1)).
 *
 * Random numbers (docs/restir-pt.md, "Random numbers"): tree t of frame f uses the path
 * tracer's addresses with sample index f*N + t; the frame's primary rays (jitter) sample
 * f*N; the neighbours of pass p are RNG_NEIGHBOR with sample f*K + p (neighbors.h); the
 * selection number of domain j in pass p is RNG_RIS (sample f*N, RNG_VERTEX_SPATIAL_RIS(p), slot j;
 * initial sampling uses vertices 2..16). The result is byte-identical for any thread count. */
#ifndef RESTIR_FRAME_OFFLINE_H
#define RESTIR_FRAME_OFFLINE_H

#include "restir/core/image.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"

typedef struct {
    image mean;            /* float RGB: the frame average */
    reservoir *reservoirs; /* width * height reservoirs of the last frame (keep_reservoirs), else NULL */
    restir_stats stats;
    double seconds;
} restir_result;

/* Renders s (prepared: BVH built). Deterministic for any thread count. On success fills
 * *out (free with restir_result_free); frees everything on failure. */
int restir_render(const scene *s, const restir_options *o, restir_result *out, rerror *e);
void restir_result_free(restir_result *r);
#endif
