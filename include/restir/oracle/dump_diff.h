/* Pixel-by-pixel comparison of two reservoir images of the same stage (restir diff-dump,
 * docs/oracle.md). Two reservoirs hold the SAME SAMPLE when their selected samples have
 * the same initial-candidate id: the replay identity (seed, pixel, sample) of the path
 * tree that produced it plus its (length d, technique), which names one candidate of that
 * tree (GRIS Eq. 50: one candidate per integrand and tree). Shifts and mutations keep the
 * id, so it follows a sample through every stage. Two empty reservoirs hold the same
 * (null) sample.
 *
 * Every documented record field (docs/formats.md "Record") is compared, each with its own
 * tolerance (dump_field below; default 0 = bit identity). A value that is not finite
 * (NaN, +-inf) in either record is always a difference: no tolerance and no outlier
 * allowance admits it (a NaN compares false with everything, so a test written as
 * `err > tol` would let it pass). */
#ifndef RESTIR_DUMP_DIFF_H
#define RESTIR_DUMP_DIFF_H

#include <stddef.h>
#include "restir/restir/reservoir.h"

/* The compared fields, in record order (docs/formats.md "Record"). The id fields (seed,
 * pixel, sample, length, technique) decide "same sample" and are not in this list. Integer
 * fields compare exactly; real fields by relative error |a - b| / max(|a|, |b|). The x_k
 * fields (rc_triangle .. rc_radiance) are compared only when rc_k != 0 (the format leaves
 * them unspecified otherwise); pss only for the first n_pss entries. */
typedef enum {
    DF_WSUM,
    DF_W,
    DF_CONFIDENCE,
    DF_N_INVALID,
    DF_RC_K,
    DF_N_PSS,
    DF_LOBE,
    DF_RC_TRIANGLE,
    DF_RC_BARY,
    DF_RC_POSITION,
    DF_RC_NORMAL,
    DF_RC_FLAGS,
    DF_RC_WO,
    DF_RC_PDF_PREV,
    DF_RC_GEOM,
    DF_RC_PDF,
    DF_RC_RADIANCE,
    DF_LIGHT_PDF,
    DF_F,
    DF_TARGET,
    DF_PSS,
    DF_COUNT
} dump_field;

/* "wsum", "W", "confidence", ... (the names of docs/formats.md "Record"); NULL past the end. */
const char *dump_field_name(dump_field f);
/* 1 for the integer fields (compared exactly: n_invalid, rc_k, n_pss, lobe, rc_triangle, rc_flags). */
int dump_field_is_integer(dump_field f);
/* The field called name (case-sensitive), or -1. */
int dump_field_parse(const char *name);

/* Per-pixel class (dump_diff_result.mask). */
enum {
    DUMP_PIXEL_SAME = 0,      /* same sample, every field within its tolerance */
    DUMP_PIXEL_BEYOND = 1,    /* same sample, some field beyond its tolerance */
    DUMP_PIXEL_OTHER = 2,     /* another sample */
    DUMP_PIXEL_NONFINITE = 3  /* a non-finite value in A or B */
};

typedef struct {
    double max_rel[DF_COUNT]; /* tolerance per real field (integer fields: exact) */
    int ignore[DF_COUNT];     /* 1: the field is not compared */
    double min_same;          /* fraction of pixels with the same sample */
    double max_outlier_fraction; /* fraction of the pixels that may be DUMP_PIXEL_BEYOND (default 0) */
    long first;               /* how many differing pixels to list (no cap) */
} dump_diff_tolerance;

typedef struct {
    long x, y;  /* pixel in the compared image's coordinates (the caller adds a region's origin) */
    int kind;   /* DUMP_PIXEL_* */
    int field;  /* the first field beyond its tolerance (dump_field), -1 for OTHER */
    double rel; /* its relative error */
    int nonfinite_in; /* NONFINITE: 1 = A, 2 = B, 3 = both */
    double w[2], target[2], conf[2];
    uint32_t id_sample[2], id_pixel[2];
    int length[2], technique[2];
} dump_diff_pixel;

typedef struct {
    long pixels, same, differing;       /* differing: other sample, non-finite, or beyond a tolerance */
    long beyond, other, nonfinite;      /* the three kinds of differing pixels */
    long field_beyond[DF_COUNT];        /* same-sample pixels with this field beyond its tolerance */
    double field_max[DF_COUNT];         /* largest relative error of the field (finite pixels) */
    long target_agree;                  /* same sample and p̂ within max_rel[DF_TARGET] */
    double q_w[4], q_target[4], q_conf[4]; /* relative-error quantiles 0.5, 0.9, 0.99, max
                                             over finite pixels with the same sample */
    double mean_fw[2], se_fw[2];        /* image mean of luminance(F) W and its standard error */
    double mean_c[2], se_c[2];          /* image mean of the confidence c and its standard error */
    double mean_full[2], se_full[2];    /* fraction of non-empty reservoirs (W > 0) and its s.e. */
    double mean_rgb[2][3], se_rgb[2][3]; /* image mean of F_c W per channel c = R, G, B and its s.e. */
    double paired_mean[4], paired_se[4]; /* mean over pixels of (A - B) of F_c W (c = R, G, B) and of
                                            luminance(F) W (index 3), and its s.e. */
    long n_first;
    dump_diff_pixel *firsts;            /* the first t->first differing pixels (malloc'ed) */
    unsigned char *mask;                /* DUMP_PIXEL_* per pixel (malloc'ed) */
} dump_diff_result;

void dump_diff_tolerance_default(dump_diff_tolerance *t);
/* Sets every real field's tolerance to v (the --max-rel-all option). */
void dump_diff_tolerance_all(dump_diff_tolerance *t, double v);
/* Parses "FIELD=V[,FIELD=V...]" (FIELD a dump_field name or "all") into t->max_rel. */
int dump_diff_tolerance_parse(dump_diff_tolerance *t, const char *list, rerror *e);
/* Parses "FIELD[,FIELD...]" into t->ignore. */
int dump_diff_ignore_parse(dump_diff_tolerance *t, const char *list, rerror *e);
/* 1 if the two samples have the same initial-candidate id (see above). */
int dump_same_sample(const path_sample *a, const path_sample *b);
/* |a - b| / max(|a|, |b|), 0 when both are 0 or equal; +inf when either is not finite
 * and they differ, NaN when either is NaN (callers test non-finite inputs first). */
double dump_rel_error(double a, double b);
/* 1 if every real field of r is finite. */
int dump_record_finite(const reservoir *r);
/* Compares a[] and b[] (width x height). Returns -1 only when out of memory;
 * free r with dump_diff_result_free. */
int dump_diff(const reservoir *a, const reservoir *b, long width, long height, const dump_diff_tolerance *t,
              dump_diff_result *r, rerror *e);
void dump_diff_result_free(dump_diff_result *r);
/* 1 if r passes the tolerances: no non-finite pixel, fraction same >= min_same, and at
 * most max_outlier_fraction of the pixels beyond a tolerance. */
int dump_diff_pass(const dump_diff_result *r, const dump_diff_tolerance *t);
/* Two-sample z of the image means of luminance(F) W (the statistical mode; pixels are
 * treated as independent, which spatial reuse makes optimistic: docs/oracle.md). */
double dump_diff_mean_z(const dump_diff_result *r);
/* The same two-sample z for the mean confidence and for the fraction of non-empty
 * reservoirs: a build that gets W right on average but the confidences (an M-cap, a
 * confidence sum) or the support (a shift that fails too often) wrong. */
double dump_diff_confidence_z(const dump_diff_result *r);
double dump_diff_nonempty_z(const dump_diff_result *r);
/* Per colour channel c (0 R, 1 G, 2 B): the two-sample z of the image means of F_c W. The
 * target is luminance, so a bug that moves colour and keeps luminance (an MH acceptance
 * without its target ratio keeps luminance(F) W of every pixel exact, Mutations Eq. 23) is
 * invisible to dump_diff_mean_z and visible here (issue 26). */
double dump_diff_channel_z(const dump_diff_result *r, int c);
/* The paired z of channel c (0..2 R, G, B; 3 luminance): mean(d)/se(d) over the pixels of
 * d = A - B. Valid for independent runs too, and far stronger when A and B share the RNG
 * (a port with the oracle's RNG, a planted bug): the pixels that agree add no noise. */
double dump_diff_paired_z(const dump_diff_result *r, int c);

#endif
