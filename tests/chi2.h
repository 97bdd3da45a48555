/* Chi-square goodness-of-fit of a direction sampler against its pdf
 * (in the style of pbrt-v4's and Mitsuba's BSDF tests; docs/materials.md §Chi-square).
 *
 * The sphere is binned in ZOOMED polar coordinates around a centre direction c:
 *     a = r^2 / (r^2 + k^2),  r = tan(theta'/2),  theta' = angle(w, c),  phi' = azimuth about c,
 * n_a equal bins in a in [0,1) and n_phi equal bins in phi' in [0, 2 pi).
 * k = 1 gives a = (1 - cos theta')/2: the standard equal-solid-angle (cos-theta
 * uniform) histogram. k < 1 puts half of the a-bins inside the cone of half-angle
 * 2 atan(k), so a lobe of angular width ~k is resolved at any scale (the near-delta
 * GGX lobes). The map covers the whole sphere, so no sample is lost.
 * Expected counts: N times the pdf integrated over each cell by nested adaptive
 * Simpson quadrature; a "failure" cell holds the samples the sampler rejected
 * (expected N (1 - integral of the pdf)). Cells with expected count < 5 are
 * pooled into one. The statistic has (cells - 1) degrees of freedom. */
#ifndef RESTIR_TEST_CHI2_H
#define RESTIR_TEST_CHI2_H

#include <stdint.h>
#include "restir/core/vec.h"
#include "restir/core/warp.h"

typedef struct {
    /* The sampler under test: 1 and *w for a valid sample, 0 for a rejection. */
    int (*sample)(void *ctx, vec2 u, vec3 *w);
    /* Its claimed density (solid angle), 0 where it never samples. */
    double (*pdf)(void *ctx, vec3 w);
    void *ctx;
    vec3 center;     /* unit; the histogram's pole */
    double zoom;     /* k in (0, 1] */
    int n_a, n_phi;  /* histogram resolution */
    long samples;    /* N */
    uint32_t seed;   /* run seed (test_seed()) */
    uint32_t stream; /* distinguishes the tests' random numbers */
} chi2_config;

typedef struct {
    double chi2;
    int dof;
    double p_value;
    long rejected;             /* sampler returned 0 */
    double expected_rejected;  /* N (1 - integral of pdf) */
    double pdf_integral;       /* integral of the pdf over the sphere */
    int pooled_cells;          /* cells merged into the pool */
} chi2_result;

/* Runs the test; returns 0 on success, nonzero if out of memory. */
int chi2_run(const chi2_config *cfg, chi2_result *res);

/* Upper tail Q(dof/2, x/2) of the chi-square distribution. */
double chi2_survival(double x, int dof);
/* Per-test significance for a family of m tests at overall level alpha (Sidak). */
double chi2_sidak(double alpha, int m);

#endif
