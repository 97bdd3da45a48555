/* FLIP image-difference evaluator:
 *   LDR-FLIP: Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild,
 *             "FLIP: A Difference Evaluator for Alternating Images", HPG 2020 (PACMCGIT 3(2)).
 *   HDR-FLIP: Andersson, Nilsson, Shirley, Akenine-Möller, "Visualizing Errors in Rendered
 *             High Dynamic Range Images", EG 2021, and Andersson, Nilsson, Akenine-Möller,
 *             "Visualizing and Communicating Errors in Rendered Images", Ray Tracing Gems II, 2021.
 * Our own C99 implementation from the published definitions and constants; docs/metrics.md
 * lists the formulas and the (small) known deviations from NVIDIA's reference code.
 * Arguments are (test, reference) as everywhere in metrics.h. Per-pixel errors are in [0, 1]. */
#ifndef RESTIR_FLIP_H
#define RESTIR_FLIP_H

#include "restir/core/error.h"
#include "restir/core/image.h"

/* Pixels per degree of visual angle for an observer at distance_m from a monitor
 * monitor_width_m wide showing resolution_x pixels across. */
double flip_pixels_per_degree(double distance_m, double resolution_x, double monitor_width_m);

typedef struct {
    double ppd;            /* pixels per degree; default: 0.7 m from a 0.7 m wide 3840-pixel monitor (~67.02) */
    int threads;           /* worker threads, 0 = one per core (results do not depend on it) */
    int auto_exposure;     /* HDR: 1 = exposure range from the reference (the published default) */
    double start_exposure; /* HDR, when auto_exposure == 0: exposures in stops */
    double stop_exposure;
    int exposure_count;    /* HDR, when auto_exposure == 0: >= 1 */
} flip_params;

void flip_default_params(flip_params *p);

/* The published automatic HDR exposure range for a reference image: start = log2(x_max / Y_max),
 * stop = log2(x_max / Y_median), count = max(2, ceil(stop - start)), with x_max the input at
 * which the ACES curve reaches 0.85 and Y the Rec. 709 luminance of the reference.
 * An all-black reference gives start = stop = 0, count = 2. */
int flip_auto_exposure(const image *ref, double *start, double *stop, int *count, rerror *e);

/* The ACES filmic fit (Narkowicz 2016) with FLIP's 0.6 pre-exposure folded in; input clipped
 * to >= 0 first, output clamped to [0,1]. */
double flip_tonemap_aces(double x);

/* LDR-FLIP of two linear-RGB images shown on a display: values are clamped to [0, 1]
 * (so the sRGB-encoded display image is what is compared, without 8-bit quantisation).
 * map (width*height floats) may be NULL; *mean receives the mean error. */
int flip_ldr(const image *test, const image *ref, const flip_params *p, float *map, double *mean, rerror *e);

/* HDR-FLIP: for each exposure, 2^exposure * max(value, 0) -> ACES -> LDR-FLIP; the per-pixel
 * maximum over exposures. If used_start/stop/count are non-NULL they receive the range used. */
int flip_hdr(const image *test, const image *ref, const flip_params *p, float *map, double *mean, double *used_start,
             double *used_stop, int *used_count, rerror *e);

#endif
