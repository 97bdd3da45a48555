/* FLIP (HPG 2020) and HDR-FLIP (EG 2021 / Ray Tracing Gems II ch. 19), written from the
 * published definitions; constants as published (and as in NVIDIA's reference code).
 *
 * Per pixel, for test image T and reference R (both linear RGB in [0,1]):
 *   colour:  RGB -> YCxCz opponent space -> contrast-sensitivity (CSF) filter per channel
 *            -> back to linear RGB, clamp to [0,1] -> CIE L*a*b* -> Hunt adjustment
 *            -> HyAB distance -> power q_c -> redistribution to [0,1] with c_max, p_c, p_t.
 *   feature: normalised luminance -> edge (1st derivative of Gaussian) and point
 *            (2nd derivative) detectors -> max of |edge difference|, |point difference|,
 *            scaled by 1/sqrt(2), power q_f.
 *   FLIP = dE_c ^ (1 - dE_f).
 * Both the CSF filters and the detectors are separable (the blue-yellow CSF, a sum of
 * two Gaussians, as a sum of two separable filters), which gives exactly the sampled
 * 2-D kernels of the paper. Borders clamp to the edge. Images are float planes; all
 * filter sums are accumulated in double. */
#include "restir/metrics/flip.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/threads.h"

/* ---- published constants ---- */

#define FLIP_QC 0.7    /* colour-difference exponent q_c */
#define FLIP_PC 0.4    /* fraction p_c of c_max mapped to [0, p_t] */
#define FLIP_PT 0.95   /* p_t */
#define FLIP_W 0.082   /* edge detector peak-to-trough width (degrees); std dev = w/2 */
#define FLIP_QF 0.5    /* feature-difference exponent q_f */
#define FLIP_T_TONE 0.85 /* tone-mapped value that defines the automatic exposure range */

/* CSF of each opponent channel (HPG 2020, colour pipeline): in the spatial domain
 *   s(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2),
 * x in degrees. b2 = 1e-5 for A and RG only avoids a division by zero (a2 = 0 there). */
typedef struct {
    double a1, b1, a2, b2;
} csf_params;

static const csf_params CSF_ACHROMATIC = {1.0, 0.0047, 0.0, 1e-5};
static const csf_params CSF_RED_GREEN = {1.0, 0.0053, 0.0, 1e-5};
static const csf_params CSF_BLUE_YELLOW = {34.1, 0.04, 13.5, 0.025};

/* ACES fit (Narkowicz 2016) y = x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14) applied to 0.6x:
 * y = (k0 x^2 + k1 x) / (k3 x^2 + k4 x + k5). */
static const double ACES_K0 = 0.6 * 0.6 * 2.51, ACES_K1 = 0.6 * 0.03, ACES_K3 = 0.6 * 0.6 * 2.43,
                    ACES_K4 = 0.6 * 0.59, ACES_K5 = 0.14;

/* Linear sRGB (Rec. 709 primaries, D65) to CIE XYZ, the exact rational matrix FLIP uses. */
static const double RGB_TO_XYZ[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0},
};

double flip_pixels_per_degree(double distance_m, double resolution_x, double monitor_width_m)
{
    return distance_m * (resolution_x / monitor_width_m) * (3.14159265358979323846 / 180.0);
}

void flip_default_params(flip_params *p)
{
    p->ppd = flip_pixels_per_degree(0.7, 3840.0, 0.7);
    p->threads = 0;
    p->auto_exposure = 1;
    p->start_exposure = 0;
    p->stop_exposure = 0;
    p->exposure_count = 1;
}

/* ---- colour spaces ---- */

typedef struct {
    double xyz_to_rgb[3][3];
    double white[3]; /* XYZ of RGB (1,1,1): the D65 reference white of the matrix */
    double cmax;     /* HyAB(green, blue)^q_c in Hunt-adjusted L*a*b*: the largest colour difference */
} colour_space;

static void mat3_apply(const double m[3][3], const double in[3], double out[3])
{
    int i;
    for (i = 0; i < 3; ++i) out[i] = m[i][0] * in[0] + m[i][1] * in[1] + m[i][2] * in[2];
}

static void mat3_inverse(const double m[3][3], double inv[3][3])
{
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    int i, j;
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            /* cofactor of m[j][i] (transposed) */
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            inv[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
}

/* CIE 1976 L*a*b* of XYZ relative to the white point. */
static void xyz_to_lab(const colour_space *cs, const double xyz[3], double lab[3])
{
    const double delta = 6.0 / 29.0;
    double f[3];
    int i;
    for (i = 0; i < 3; ++i) {
        double t = xyz[i] / cs->white[i];
        f[i] = t > delta * delta * delta ? cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
    }
    lab[0] = 116.0 * f[1] - 16.0;
    lab[1] = 500.0 * (f[0] - f[1]);
    lab[2] = 200.0 * (f[1] - f[2]);
}

/* Hunt effect (chroma grows with luminance): a, b scaled by 0.01 L (HPG 2020, colour pipeline). */
static void hunt_adjust(double lab[3])
{
    lab[1] *= 0.01 * lab[0];
    lab[2] *= 0.01 * lab[0];
}

/* HyAB distance (Abasi et al. 2020): city-block in L, Euclidean in (a, b). */
static double hyab(const double p[3], const double q[3])
{
    return fabs(p[0] - q[0]) + sqrt((p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

static void linear_rgb_to_hunt_lab(const colour_space *cs, const double rgb[3], double out[3])
{
    double xyz[3];
    mat3_apply(RGB_TO_XYZ, rgb, xyz);
    xyz_to_lab(cs, xyz, out);
    hunt_adjust(out);
}

static void colour_space_init(colour_space *cs)
{
    static const double one[3] = {1, 1, 1}, green[3] = {0, 1, 0}, blue[3] = {0, 0, 1};
    double g[3], b[3];
    mat3_inverse(RGB_TO_XYZ, cs->xyz_to_rgb);
    mat3_apply(RGB_TO_XYZ, one, cs->white);
    linear_rgb_to_hunt_lab(cs, green, g);
    linear_rgb_to_hunt_lab(cs, blue, b);
    cs->cmax = pow(hyab(g, b), FLIP_QC);
}

/* YCxCz (Johnson & Fairchild's linearised opponent space, HPG 2020): L*a*b* without the cube root. */
static void linear_rgb_to_ycxcz(const colour_space *cs, const double rgb[3], double out[3])
{
    double xyz[3], n[3];
    int i;
    mat3_apply(RGB_TO_XYZ, rgb, xyz);
    for (i = 0; i < 3; ++i) n[i] = xyz[i] / cs->white[i];
    out[0] = 116.0 * n[1] - 16.0;
    out[1] = 500.0 * (n[0] - n[1]);
    out[2] = 200.0 * (n[1] - n[2]);
}

static void ycxcz_to_linear_rgb(const colour_space *cs, const double ycxcz[3], double rgb[3])
{
    double ny = (ycxcz[0] + 16.0) / 116.0, xyz[3];
    xyz[0] = (ny + ycxcz[1] / 500.0) * cs->white[0];
    xyz[1] = ny * cs->white[1];
    xyz[2] = (ny - ycxcz[2] / 200.0) * cs->white[2];
    mat3_apply(cs->xyz_to_rgb, xyz, rgb);
}

/* Error redistribution (HPG 2020): [0, p_c c_max) -> [0, p_t), [p_c c_max, c_max] -> [p_t, 1]. */
static double redistribute_colour_error(double powered_hyab, double cmax)
{
    double pccmax = FLIP_PC * cmax;
    if (powered_hyab < pccmax) return (FLIP_PT / pccmax) * powered_hyab;
    return FLIP_PT + (powered_hyab - pccmax) / (cmax - pccmax) * (1.0 - FLIP_PT);
}

/* ---- filters ---- */

typedef struct {
    int radius;
    double *w; /* 2*radius + 1 weights */
} kernel1d;

typedef struct {
    kernel1d achromatic, red_green, blue_yellow_1, blue_yellow_2; /* CSF, separable */
    kernel1d gauss, edge, point;                                  /* feature detectors, separable */
} flip_filters;

static int kernel_alloc(kernel1d *k, int radius, rerror *e)
{
    k->radius = radius;
    k->w = rcalloc((size_t)(2 * radius + 1), sizeof(double), e);
    return k->w ? 0 : -1;
}

static void filters_free(flip_filters *f)
{
    free(f->achromatic.w);
    free(f->red_green.w);
    free(f->blue_yellow_1.w);
    free(f->blue_yellow_2.w);
    free(f->gauss.w);
    free(f->edge.w);
    free(f->point.w);
}

/* Radius of the CSF filters: 3 standard deviations of the widest Gaussian (largest b). */
static int csf_radius(double ppd)
{
    double bmax = fmax(fmax(CSF_ACHROMATIC.b1, CSF_RED_GREEN.b1), fmax(CSF_BLUE_YELLOW.b1, CSF_BLUE_YELLOW.b2));
    const double pi = 3.14159265358979323846;
    return (int)ceil(3.0 * sqrt(bmax / (2.0 * pi * pi)) * ppd);
}

/* One factor sqrt(a sqrt(pi/b)) exp(-pi^2 x^2 / b) of a separable 2-D CSF Gaussian term. */
static double csf_factor(double a, double b, double x_degrees)
{
    const double pi = 3.14159265358979323846;
    return sqrt(a * sqrt(pi / b)) * exp(-pi * pi * x_degrees * x_degrees / b);
}

/* Single-Gaussian CSF (achromatic, red-green): normalised to sum 1 (in 1-D, hence in 2-D). */
static void csf_single(kernel1d *k, const csf_params *c, double ppd)
{
    double sum = 0;
    int i;
    for (i = -k->radius; i <= k->radius; ++i) sum += k->w[i + k->radius] = csf_factor(c->a1, c->b1, i / ppd);
    for (i = 0; i <= 2 * k->radius; ++i) k->w[i] /= sum;
}

/* Blue-yellow CSF = g1(x)g1(y) + g2(x)g2(y); scaling both factors by 1/sqrt(S1^2 + S2^2)
 * (S = 1-D sums) makes the 2-D kernel sum to 1, as the paper's normalised 2-D kernel. */
static void csf_double(kernel1d *k1, kernel1d *k2, const csf_params *c, double ppd)
{
    double s1 = 0, s2 = 0, norm;
    int i;
    for (i = -k1->radius; i <= k1->radius; ++i) {
        s1 += k1->w[i + k1->radius] = csf_factor(c->a1, c->b1, i / ppd);
        s2 += k2->w[i + k2->radius] = csf_factor(c->a2, c->b2, i / ppd);
    }
    norm = 1.0 / sqrt(s1 * s1 + s2 * s2);
    for (i = 0; i <= 2 * k1->radius; ++i) {
        k1->w[i] *= norm;
        k2->w[i] *= norm;
    }
}

/* Scales positive weights to sum 1 and negative weights to sum -1 (HPG 2020, feature pipeline). */
static void balance_signed(kernel1d *k)
{
    double pos = 0, neg = 0;
    int i;
    for (i = 0; i <= 2 * k->radius; ++i) {
        if (k->w[i] > 0) pos += k->w[i];
        else neg -= k->w[i];
    }
    for (i = 0; i <= 2 * k->radius; ++i) k->w[i] /= k->w[i] > 0 ? pos : neg;
}

/* Feature detectors: Gaussian with std sd = 0.5 * w * ppd pixels, radius ceil(3 sd);
 * edge = -x g(x) (1st derivative), point = (x^2/sd^2 - 1) g(x) (2nd derivative). The 2-D
 * detectors are edge(x) gauss(y) (and transposed): since gauss sums to 1, their positive
 * and negative parts sum to +1 and -1 in 2-D exactly as in the paper. */
static void feature_filters(flip_filters *f, double ppd)
{
    double sd = 0.5 * FLIP_W * ppd, sum = 0;
    int r = f->gauss.radius, i;
    for (i = -r; i <= r; ++i) {
        double g = exp(-(double)i * i / (2.0 * sd * sd));
        f->gauss.w[i + r] = g;
        f->edge.w[i + r] = -(double)i * g;
        f->point.w[i + r] = ((double)i * i / (sd * sd) - 1.0) * g;
        sum += g;
    }
    for (i = 0; i <= 2 * r; ++i) f->gauss.w[i] /= sum;
    balance_signed(&f->edge);
    balance_signed(&f->point);
}

static int filters_init(flip_filters *f, double ppd, rerror *e)
{
    int rc = csf_radius(ppd), rf = (int)ceil(3.0 * 0.5 * FLIP_W * ppd);
    memset(f, 0, sizeof *f);
    if (kernel_alloc(&f->achromatic, rc, e) || kernel_alloc(&f->red_green, rc, e) ||
        kernel_alloc(&f->blue_yellow_1, rc, e) || kernel_alloc(&f->blue_yellow_2, rc, e) ||
        kernel_alloc(&f->gauss, rf, e) || kernel_alloc(&f->edge, rf, e) || kernel_alloc(&f->point, rf, e)) {
        filters_free(f);
        return -1;
    }
    csf_single(&f->achromatic, &CSF_ACHROMATIC, ppd);
    csf_single(&f->red_green, &CSF_RED_GREEN, ppd);
    csf_double(&f->blue_yellow_1, &f->blue_yellow_2, &CSF_BLUE_YELLOW, ppd);
    feature_filters(f, ppd);
    return 0;
}

/* ---- planes and row-parallel passes ---- */

typedef struct {
    int width, height, threads;
    double *row_scratch; /* threads * width doubles */
} grid;

/* One separable convolution pass (clamp-to-edge), one row per work item. */
typedef struct {
    const grid *g;
    const float *src;
    float *dst;
    const kernel1d *k;
    int vertical;
    double *acc; /* vertical pass: one row of double accumulators per worker */
} convolve_job;

static int clamp_index(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

static void convolve_row_horizontal(const convolve_job *j, int y)
{
    const int w = j->g->width, r = j->k->radius;
    const float *src = j->src + (size_t)y * w;
    const double *k = j->k->w + r; /* k[i], i in [-r, r] */
    int x, i;
    for (x = 0; x < w; ++x) {
        double sum = 0;
        if (x - r >= 0 && x + r < w) {
            for (i = -r; i <= r; ++i) sum += k[i] * src[x + i];
        } else {
            for (i = -r; i <= r; ++i) sum += k[i] * src[clamp_index(x + i, w)];
        }
        j->dst[(size_t)y * w + x] = (float)sum;
    }
}

static void convolve_row_vertical(const convolve_job *j, int y, double *acc)
{
    const int w = j->g->width, h = j->g->height, r = j->k->radius;
    int x, i;
    for (x = 0; x < w; ++x) acc[x] = 0;
    for (i = -r; i <= r; ++i) {
        const float *src = j->src + (size_t)clamp_index(y + i, h) * w;
        const double k = j->k->w[i + r];
        for (x = 0; x < w; ++x) acc[x] += k * src[x];
    }
    for (x = 0; x < w; ++x) j->dst[(size_t)y * w + x] = (float)acc[x];
}

static void convolve_row(void *ctx, long row, int worker)
{
    const convolve_job *j = ctx;
    if (j->vertical) convolve_row_vertical(j, (int)row, j->acc + (size_t)worker * j->g->width);
    else convolve_row_horizontal(j, (int)row);
}

static void convolve(const grid *g, const float *src, float *dst, const kernel1d *k, int vertical)
{
    convolve_job j;
    j.g = g;
    j.src = src;
    j.dst = dst;
    j.k = k;
    j.vertical = vertical;
    j.acc = g->row_scratch;
    parallel_items(g->height, g->threads, convolve_row, &j);
}

/* Planes of one image during the evaluation. */
typedef struct {
    float *c[3];       /* YCxCz, later the filtered Hunt-adjusted L*a*b* */
    float *edge, *point;
} image_planes;

/* Scratch planes shared by both images. */
typedef struct {
    float *s1, *s2, *s3;
} scratch_planes;

typedef enum { INPUT_CLAMP, INPUT_ACES } input_transform;

typedef struct {
    const grid *g;
    const colour_space *cs;
    const image *img;
    image_planes *out;
    input_transform transform;
    double gain; /* 2^exposure (HDR) */
} load_job;

double flip_tonemap_aces(double x)
{
    double y;
    if (!(x > 0)) return 0;    /* negative (and NaN) input is clipped to 0 first */
    if (x > 1e30) return 1;    /* the curve tends to k0/k3 > 1: clamped (and x^2 cannot overflow) */
    y = (ACES_K0 * x * x + ACES_K1 * x) / (ACES_K3 * x * x + ACES_K4 * x + ACES_K5);
    return y > 1 ? 1 : y;
}

static void load_row(void *ctx, long row, int worker)
{
    const load_job *j = ctx;
    int x, c;
    (void)worker;
    for (x = 0; x < j->g->width; ++x) {
        const float *p = image_pixel(j->img, x, (int)row);
        double rgb[3], ycc[3];
        size_t i = (size_t)row * j->g->width + x;
        for (c = 0; c < 3; ++c) {
            if (j->transform == INPUT_ACES) {
                rgb[c] = flip_tonemap_aces(p[c] * j->gain);
            } else {
                rgb[c] = p[c] < 0 ? 0.0 : (p[c] > 1 ? 1.0 : p[c]);
            }
        }
        linear_rgb_to_ycxcz(j->cs, rgb, ycc);
        for (c = 0; c < 3; ++c) j->out->c[c][i] = (float)ycc[c];
    }
}

/* Normalised luminance (Y + 16)/116 in [0,1], the feature detectors' input. */
static void normalised_luminance(const grid *g, const float *y, float *out)
{
    size_t i, n = (size_t)g->width * g->height;
    for (i = 0; i < n; ++i) out[i] = (float)((y[i] + 16.0) / 116.0);
}

/* Edge and point strengths |(d/dx, d/dy)| of the normalised luminance. */
static void detect_features(const grid *g, const flip_filters *f, image_planes *p, scratch_planes *s)
{
    size_t i, n = (size_t)g->width * g->height;
    float *gx = s->s1, *lum = s->s2, *tmp = s->s3;
    normalised_luminance(g, p->c[0], lum);
    convolve(g, lum, gx, &f->gauss, 0);
    convolve(g, lum, p->edge, &f->edge, 0);   /* d/dx along rows */
    convolve(g, lum, p->point, &f->point, 0); /* d2/dx2 along rows */
    /* edge: x-part = gauss_y * (d/dx), y-part = d/dy * gauss_x */
    convolve(g, p->edge, lum, &f->gauss, 1);
    convolve(g, gx, tmp, &f->edge, 1);
    for (i = 0; i < n; ++i) p->edge[i] = (float)sqrt((double)lum[i] * lum[i] + (double)tmp[i] * tmp[i]);
    convolve(g, p->point, lum, &f->gauss, 1);
    convolve(g, gx, tmp, &f->point, 1);
    for (i = 0; i < n; ++i) p->point[i] = (float)sqrt((double)lum[i] * lum[i] + (double)tmp[i] * tmp[i]);
}

/* CSF-filters the three opponent channels in place. */
static void csf_filter(const grid *g, const flip_filters *f, image_planes *p, scratch_planes *s)
{
    size_t i, n = (size_t)g->width * g->height;
    convolve(g, p->c[0], s->s1, &f->achromatic, 0);
    convolve(g, s->s1, p->c[0], &f->achromatic, 1);
    convolve(g, p->c[1], s->s1, &f->red_green, 0);
    convolve(g, s->s1, p->c[1], &f->red_green, 1);
    convolve(g, p->c[2], s->s1, &f->blue_yellow_1, 0);
    convolve(g, s->s1, s->s2, &f->blue_yellow_1, 1);
    convolve(g, p->c[2], s->s1, &f->blue_yellow_2, 0);
    convolve(g, s->s1, p->c[2], &f->blue_yellow_2, 1);
    for (i = 0; i < n; ++i) p->c[2][i] += s->s2[i];
}

typedef struct {
    const grid *g;
    const colour_space *cs;
    image_planes *p;
} lab_job;

/* Filtered YCxCz -> linear RGB clamped to [0,1] -> Hunt-adjusted L*a*b*, in place. */
static void to_hunt_lab_row(void *ctx, long row, int worker)
{
    const lab_job *j = ctx;
    int x, c;
    (void)worker;
    for (x = 0; x < j->g->width; ++x) {
        size_t i = (size_t)row * j->g->width + x;
        double ycc[3], rgb[3], lab[3];
        for (c = 0; c < 3; ++c) ycc[c] = j->p->c[c][i];
        ycxcz_to_linear_rgb(j->cs, ycc, rgb);
        for (c = 0; c < 3; ++c) rgb[c] = rgb[c] < 0 ? 0 : (rgb[c] > 1 ? 1 : rgb[c]);
        linear_rgb_to_hunt_lab(j->cs, rgb, lab);
        for (c = 0; c < 3; ++c) j->p->c[c][i] = (float)lab[c];
    }
}

/* Everything that depends on one image alone: features, CSF filtering, L*a*b*. */
static void prepare_image(const grid *g, const colour_space *cs, const flip_filters *f, const image *img,
                          input_transform t, double gain, image_planes *p, scratch_planes *s)
{
    load_job lj;
    lab_job hj;
    lj.g = g;
    lj.cs = cs;
    lj.img = img;
    lj.out = p;
    lj.transform = t;
    lj.gain = gain;
    parallel_items(g->height, g->threads, load_row, &lj);
    detect_features(g, f, p, s); /* before filtering: the detectors see the unfiltered luminance */
    csf_filter(g, f, p, s);
    hj.g = g;
    hj.cs = cs;
    hj.p = p;
    parallel_items(g->height, g->threads, to_hunt_lab_row, &hj);
}

/* Per-pixel FLIP from the prepared planes of test and reference. */
static void combine(const grid *g, const colour_space *cs, const image_planes *t, const image_planes *r, float *map)
{
    size_t i, n = (size_t)g->width * g->height;
    int c;
    for (i = 0; i < n; ++i) {
        double lt[3], lr[3], colour, feature;
        for (c = 0; c < 3; ++c) {
            lt[c] = t->c[c][i];
            lr[c] = r->c[c][i];
        }
        colour = redistribute_colour_error(pow(hyab(lr, lt), FLIP_QC), cs->cmax);
        feature = fmax(fabs((double)r->edge[i] - t->edge[i]), fabs((double)r->point[i] - t->point[i]));
        feature = pow(feature / sqrt(2.0), FLIP_QF);
        map[i] = (float)pow(colour, 1.0 - feature);
    }
}

/* ---- evaluation ---- */

typedef struct {
    grid g;
    colour_space cs;
    flip_filters f;
    image_planes test, ref;
    scratch_planes s;
    float *block; /* one allocation for all planes */
} flip_workspace;

static void workspace_free(flip_workspace *w)
{
    filters_free(&w->f);
    free(w->block);
    free(w->g.row_scratch);
}

static int workspace_init(flip_workspace *w, const image *test, const image *ref, const flip_params *p, rerror *e)
{
    size_t n;
    float *q;
    int i;
    memset(w, 0, sizeof *w);
    if (test->width != ref->width || test->height != ref->height)
        return rerror_set(e, "FLIP: image sizes differ (%d x %d vs %d x %d)", test->width, test->height, ref->width,
                          ref->height);
    if (!(p->ppd > 0) || !isfinite(p->ppd)) return rerror_set(e, "FLIP: pixels per degree must be positive");
    w->g.width = ref->width;
    w->g.height = ref->height;
    w->g.threads = p->threads > 0 ? p->threads : threads_default();
    /* Each pass starts its threads anew: not worth it for small images. */
    if ((size_t)ref->width * ref->height < ((size_t)1 << 16)) w->g.threads = 1;
    colour_space_init(&w->cs);
    if (filters_init(&w->f, p->ppd, e)) return -1;
    n = (size_t)ref->width * ref->height;
    w->block = rmalloc(n * 13, sizeof(float), e);
    w->g.row_scratch = rmalloc((size_t)w->g.threads * (size_t)w->g.width, sizeof(double), e);
    if (!w->block || !w->g.row_scratch) {
        workspace_free(w);
        return -1;
    }
    q = w->block;
    for (i = 0; i < 3; ++i, q += n) w->test.c[i] = q;
    for (i = 0; i < 3; ++i, q += n) w->ref.c[i] = q;
    w->test.edge = q, q += n;
    w->test.point = q, q += n;
    w->ref.edge = q, q += n;
    w->ref.point = q, q += n;
    w->s.s1 = q, q += n;
    w->s.s2 = q, q += n;
    w->s.s3 = q;
    return 0;
}

static double map_mean(const float *map, size_t n)
{
    double sum = 0;
    size_t i;
    for (i = 0; i < n; ++i) sum += map[i];
    return sum / (double)n;
}

int flip_ldr(const image *test, const image *ref, const flip_params *p, float *map, double *mean, rerror *e)
{
    flip_workspace w;
    size_t n = (size_t)ref->width * ref->height;
    float *out = map;
    if (workspace_init(&w, test, ref, p, e)) return -1;
    if (!out && !(out = rmalloc(n, sizeof(float), e))) {
        workspace_free(&w);
        return -1;
    }
    prepare_image(&w.g, &w.cs, &w.f, ref, INPUT_CLAMP, 1.0, &w.ref, &w.s);
    prepare_image(&w.g, &w.cs, &w.f, test, INPUT_CLAMP, 1.0, &w.test, &w.s);
    combine(&w.g, &w.cs, &w.test, &w.ref, out);
    if (mean) *mean = map_mean(out, n);
    if (out != map) free(out);
    workspace_free(&w);
    return 0;
}

/* The larger root of (k0 - t k3) x^2 + (k1 - t k4) x - t k5 = 0: the input at which ACES reaches t. */
static double aces_input_for(double t)
{
    double a = ACES_K0 - t * ACES_K3, b = ACES_K1 - t * ACES_K4, c = -t * ACES_K5;
    return (-b + sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
}

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

int flip_auto_exposure(const image *ref, double *start, double *stop, int *count, rerror *e)
{
    size_t n = (size_t)ref->width * ref->height, i;
    float *lum = rmalloc(n, sizeof(float), e);
    double x_max = aces_input_for(FLIP_T_TONE), y_max = 0, y_median, y_min_positive = HUGE_VAL;
    *start = *stop = 0;
    *count = 2;
    if (!lum) return -1;
    for (i = 0; i < n; ++i) {
        const float *p = ref->px + 3 * i;
        double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; /* Rec. 709, as vec.h luminance() */
        lum[i] = (float)y;
        if (y > y_max) y_max = y;
        if (y > 0 && y < y_min_positive) y_min_positive = y;
    }
    if (y_max > 0) {
        qsort(lum, n, sizeof(float), compare_floats);
        y_median = (n % 2) ? lum[n / 2] : 0.5 * ((double)lum[n / 2 - 1] + lum[n / 2]);
        /* Deviation: a median of 0 (mostly black reference) would give an infinite stop;
         * the smallest positive luminance is used instead. */
        if (!(y_median > 0)) y_median = y_min_positive;
        *start = log2(x_max / y_max);
        *stop = log2(x_max / y_median);
        *count = (int)ceil(*stop - *start);
        if (*count < 2) *count = 2;
    }
    free(lum);
    return 0;
}

int flip_hdr(const image *test, const image *ref, const flip_params *p, float *map, double *mean, double *used_start,
             double *used_stop, int *used_count, rerror *e)
{
    flip_workspace w;
    size_t n = (size_t)ref->width * ref->height, i;
    double start, stop, step;
    int count, k;
    float *out = map, *one = NULL;
    if (workspace_init(&w, test, ref, p, e)) return -1;
    if (p->auto_exposure) {
        if (flip_auto_exposure(ref, &start, &stop, &count, e)) {
            workspace_free(&w);
            return -1;
        }
    } else {
        start = p->start_exposure;
        stop = p->stop_exposure;
        count = p->exposure_count;
    }
    if (count < 1 || !(stop >= start) || !isfinite(start) || !isfinite(stop)) {
        workspace_free(&w);
        return rerror_set(e, "HDR-FLIP: bad exposure range %g..%g (%d exposures)", start, stop, count);
    }
    one = rmalloc(n, sizeof(float), e);
    if (!one || (!out && !(out = rmalloc(n, sizeof(float), e)))) {
        free(one);
        workspace_free(&w);
        return -1;
    }
    for (i = 0; i < n; ++i) out[i] = 0;
    step = count > 1 ? (stop - start) / (count - 1) : 0;
    for (k = 0; k < count; ++k) {
        double gain = pow(2.0, start + k * step);
        prepare_image(&w.g, &w.cs, &w.f, ref, INPUT_ACES, gain, &w.ref, &w.s);
        prepare_image(&w.g, &w.cs, &w.f, test, INPUT_ACES, gain, &w.test, &w.s);
        combine(&w.g, &w.cs, &w.test, &w.ref, one);
        for (i = 0; i < n; ++i)
            if (one[i] > out[i]) out[i] = one[i];
    }
    if (mean) *mean = map_mean(out, n);
    if (used_start) *used_start = start;
    if (used_stop) *used_stop = stop;
    if (used_count) *used_count = count;
    free(one);
    if (out != map) free(out);
    workspace_free(&w);
    return 0;
}
