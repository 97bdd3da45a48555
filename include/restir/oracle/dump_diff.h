/* Pixel-by-pixel comparison of two reservoir images of the same stage (restir diff-dump,
 * docs/oracle.md). Two reservoirs hold the SAME SAMPLE when their selected samples have
 * the same initial-candidate id: the replay identity (seed, pixel, sample) of the path
 * tree that produced it plus its (length d, technique), which names one candidate of that
 * tree (GRIS Eq. 50: one candidate per integrand and tree). Shifts and mutations keep the
 * id, so it follows a sample through every stage. Two empty reservoirs hold the same
 * (null) sample. */
#ifndef RESTIR_DUMP_DIFF_H
#define RESTIR_DUMP_DIFF_H

#include <stddef.h>
#include "restir/restir/reservoir.h"

#define DUMP_DIFF_MAX_FIRST 32

typedef struct {
    double max_rel_w, max_rel_target, max_rel_conf; /* a pixel differs beyond these */
    double min_same;                                /* fraction of pixels with the same sample */
    int first;                                      /* how many differing pixels to list */
} dump_diff_tolerance;

typedef struct {
    long x, y;
    int same_sample;
    double w[2], target[2], conf[2];
    uint32_t id_sample[2], id_pixel[2];
    int length[2], technique[2];
} dump_diff_pixel;

typedef struct {
    long pixels, same, differing;       /* differing: other sample, or beyond a tolerance */
    long target_agree;                  /* same sample and p̂ within max_rel_target */
    double q_w[4], q_target[4], q_conf[4]; /* relative-error quantiles 0.5, 0.9, 0.99, max
                                             over pixels with the same sample */
    double mean_fw[2], se_fw[2];        /* image mean of luminance(F) W and its standard error */
    double mean_c[2], se_c[2];          /* image mean of the confidence c and its standard error */
    double mean_full[2], se_full[2];    /* fraction of non-empty reservoirs (W > 0) and its s.e. */
    int n_first;
    dump_diff_pixel firsts[DUMP_DIFF_MAX_FIRST];
} dump_diff_result;

void dump_diff_tolerance_default(dump_diff_tolerance *t);
/* 1 if the two samples have the same initial-candidate id (see above). */
int dump_same_sample(const path_sample *a, const path_sample *b);
/* |a - b| / max(|a|, |b|), 0 when both are 0 (1 when one is NaN). */
double dump_rel_error(double a, double b);
/* Compares a[] and b[] (width x height). Returns -1 only when out of memory. */
int dump_diff(const reservoir *a, const reservoir *b, long width, long height, const dump_diff_tolerance *t,
              dump_diff_result *r, rerror *e);
/* 1 if r passes the tolerances (fraction same >= min_same and no pixel beyond a tolerance). */
int dump_diff_pass(const dump_diff_result *r, const dump_diff_tolerance *t);
/* Two-sample z of the image means of luminance(F) W (the statistical mode; pixels are
 * treated as independent, which spatial reuse makes optimistic: docs/oracle.md). */
double dump_diff_mean_z(const dump_diff_result *r);
/* The same two-sample z for the mean confidence and for the fraction of non-empty
 * reservoirs: a build that gets W right on average but the confidences (an M-cap, a
 * confidence sum) or the support (a shift that fails too often) wrong. */
double dump_diff_confidence_z(const dump_diff_result *r);
double dump_diff_nonempty_z(const dump_diff_result *r);

#endif
