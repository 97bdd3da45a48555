/* `restir check` statistics (check.h; decision rule in docs/statistics.md, "check"). */
#include "restir/check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/vec.h"

void check_options_default(check_options *o)
{
    o->alpha = 0.01;
    o->correction = CHECK_SIDAK;
    o->margin = 0.01;
    o->block_size = 8;
}

/* ---- building a side ---- */

static void side_clear(check_side *s, enum check_side_kind kind)
{
    memset(s, 0, sizeof *s);
    s->kind = kind;
}

static void side_set_blocks(check_side *s, int width, int height, int block_size)
{
    s->width = width;
    s->height = height;
    s->block_size = block_size;
    s->blocks_x = (width + block_size - 1) / block_size;
    s->blocks_y = (height + block_size - 1) / block_size;
}

int check_side_begin_runs(check_side *s, int width, int height, int block_size, rerror *e)
{
    side_clear(s, CHECK_SIDE_RUNS);
    if (block_size < 1) return rerror_set(e, "block size %d must be at least 1", block_size);
    if (moments_init(&s->acc, width, height, e)) return -1;
    side_set_blocks(s, width, height, block_size);
    return 0;
}

/* Pixels in block (bx, by): edge blocks are smaller. */
static long block_pixel_count(int width, int height, int b, int bx, int by)
{
    int w = width - bx * b < b ? width - bx * b : b;
    int h = height - by * b < b ? height - by * b : b;
    return (long)w * h;
}

int check_side_add_run(check_side *s, const image *run, const char *name, rerror *e)
{
    long blocks = (long)s->blocks_x * s->blocks_y, k, i;
    double *grown, *sums;
    int x, y, c;
    if (moments_add(&s->acc, run, name, e)) return -1;
    k = s->acc.runs - 1;
    grown = realloc(s->block_run_means, (size_t)(k + 1) * (size_t)blocks * 3 * sizeof *grown);
    if (!grown) return rerror_set(e, "out of memory (block means)");
    s->block_run_means = grown;
    sums = grown + (size_t)k * (size_t)blocks * 3;
    memset(sums, 0, (size_t)blocks * 3 * sizeof *sums);
    for (y = 0; y < run->height; ++y)
        for (x = 0; x < run->width; ++x) {
            const float *p = image_pixel(run, x, y);
            double *b = sums + 3 * ((long)(y / s->block_size) * s->blocks_x + x / s->block_size);
            for (c = 0; c < 3; ++c) b[c] += p[c];
        }
    for (i = 0; i < blocks; ++i) {
        double n = (double)block_pixel_count(s->width, s->height, s->block_size, (int)(i % s->blocks_x),
                                             (int)(i / s->blocks_x));
        for (c = 0; c < 3; ++c) sums[3 * i + c] /= n;
    }
    return 0;
}

int check_side_end_runs(check_side *s, rerror *e)
{
    if (s->acc.runs < 2)
        return rerror_set(e, "%ld run(s) given: at least 2 independent runs are needed to estimate a variance",
                          s->acc.runs);
    if (moments_images(&s->acc, &s->mean, &s->var, e)) return -1;
    s->runs = s->acc.runs;
    s->run_means = s->acc.run_means;
    s->acc.run_means = NULL;
    moments_free(&s->acc);
    return 0;
}

int check_side_from_moments(check_side *s, moments_file *f, const char *name, rerror *e)
{
    side_clear(s, CHECK_SIDE_MOMENTS);
    if (f->runs < 2)
        return rerror_at(e, name, 0, "%ld run(s): at least 2 are needed for a variance estimate", f->runs);
    s->width = f->mean.width;
    s->height = f->mean.height;
    s->runs = f->runs;
    s->mean = f->mean;
    s->var = f->var;
    s->run_means = f->run_means;
    memset(f, 0, sizeof *f);
    return 0;
}

int check_side_exact(check_side *s, image *ref, rerror *e)
{
    (void)e;
    side_clear(s, CHECK_SIDE_EXACT);
    s->width = ref->width;
    s->height = ref->height;
    s->mean = *ref;
    memset(ref, 0, sizeof *ref);
    return 0;
}

void check_side_free(check_side *s)
{
    image_free(&s->mean);
    image_free(&s->var);
    free(s->run_means);
    free(s->block_run_means);
    moments_free(&s->acc);
    memset(s, 0, sizeof *s);
}

/* ---- estimates of one side ---- */

/* Per-pixel mean: its variance is the single-run variance over K, with K - 1 dof. */
static stats_estimate pixel_estimate(const check_side *s, int x, int y, int c)
{
    if (s->kind == CHECK_SIDE_EXACT) {
        stats_estimate exact = {0.0, 0.0, 0.0};
        exact.mean = image_pixel(&s->mean, x, y)[c];
        return exact;
    }
    return stats_estimate_from_samples(image_pixel(&s->mean, x, y)[c], image_pixel(&s->var, x, y)[c],
                                       (double)s->runs);
}

/* Mean and variance of the mean from K per-run values x[0], x[stride], ... (two-pass). */
static stats_estimate mean_of_runs(const double *x, long stride, long runs)
{
    double sum = 0.0, ss = 0.0, mean;
    long k;
    for (k = 0; k < runs; ++k) sum += x[k * stride];
    mean = sum / (double)runs;
    for (k = 0; k < runs; ++k) ss += (x[k * stride] - mean) * (x[k * stride] - mean);
    return stats_estimate_from_samples(mean, ss / (double)(runs - 1), (double)runs);
}

/* Block mean of channel c. From raw runs the variance comes from the K per-run block
 * means: exact whatever the correlation between the block's pixels. From moments it is
 * sum(var_i) / (n^2 K), which assumes independent pixels (true for a path tracer, not
 * for ReSTIR), with the Welch-Satterthwaite dof of that sum (each term has K - 1). */
static stats_estimate block_estimate(const check_side *s, int b, int bx, int by, int c)
{
    stats_estimate est = {0.0, 0.0, 0.0};
    int x0 = bx * b, y0 = by * b, x1 = x0 + b, y1 = y0 + b, x, y;
    double n, sum = 0.0, sum_var = 0.0, sum_var2 = 0.0;
    if (x1 > s->width) x1 = s->width;
    if (y1 > s->height) y1 = s->height;
    n = (double)(x1 - x0) * (y1 - y0);
    if (s->kind == CHECK_SIDE_RUNS) {
        long blocks = (long)s->blocks_x * s->blocks_y, idx = (long)by * s->blocks_x + bx;
        return mean_of_runs(s->block_run_means + 3 * idx + c, 3 * blocks, s->runs);
    }
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            sum += image_pixel(&s->mean, x, y)[c];
            if (s->kind != CHECK_SIDE_EXACT) {
                double v = image_pixel(&s->var, x, y)[c];
                sum_var += v;
                sum_var2 += v * v;
            }
        }
    est.mean = sum / n;
    if (s->kind == CHECK_SIDE_EXACT || sum_var == 0.0) return est;
    est.var_of_mean = sum_var / (n * n * (double)s->runs);
    est.dof = sum_var * sum_var / sum_var2 * (double)(s->runs - 1);
    return est;
}

/* The Rec. 709 weights of luminance() (vec.h, the one place they are written), as a
 * double weighted sum so the statistics stay in double in the float build too. */
static double lum_of(const double rgb3[3])
{
    return (double)luminance(rgb_make(1, 0, 0)) * rgb3[0] + (double)luminance(rgb_make(0, 1, 0)) * rgb3[1] +
           (double)luminance(rgb_make(0, 0, 1)) * rgb3[2];
}

static double run_luminance(const check_side *s, long k)
{
    return lum_of(s->run_means + 3 * k);
}

/* Luminance image mean. With per-run image means the variance is the sample variance of
 * the K per-run luminance means: exact for any correlation between pixels. Without them
 * (a reference with only a variance image) we bound it assuming independent pixels and
 * perfectly correlated channels: var(lum_i) <= (sum_c w_c sd_ic)^2. */
static stats_estimate luminance_estimate(const check_side *s, int *from_runs)
{
    stats_estimate est = {0.0, 0.0, 0.0};
    double npx = (double)s->width * s->height, sum = 0.0, sum_var = 0.0, sum_var2 = 0.0;
    long i, k;
    *from_runs = 0;
    if (s->kind != CHECK_SIDE_EXACT && s->run_means) {
        double lum_sum = 0.0, ss = 0.0, mean;
        for (k = 0; k < s->runs; ++k) lum_sum += run_luminance(s, k);
        mean = lum_sum / (double)s->runs;
        for (k = 0; k < s->runs; ++k) ss += (run_luminance(s, k) - mean) * (run_luminance(s, k) - mean);
        *from_runs = 1;
        return stats_estimate_from_samples(mean, ss / (double)(s->runs - 1), (double)s->runs);
    }
    for (i = 0; i < (long)npx; ++i) {
        const float *m = s->mean.px + 3 * i;
        double mean3[3], sd3[3];
        mean3[0] = m[0];
        mean3[1] = m[1];
        mean3[2] = m[2];
        sum += lum_of(mean3);
        if (s->kind != CHECK_SIDE_EXACT) {
            const float *v = s->var.px + 3 * i;
            double sd;
            sd3[0] = sqrt(v[0]);
            sd3[1] = sqrt(v[1]);
            sd3[2] = sqrt(v[2]);
            sd = lum_of(sd3);
            sum_var += sd * sd;
            sum_var2 += sd * sd * sd * sd;
        }
    }
    est.mean = sum / npx;
    if (s->kind == CHECK_SIDE_EXACT || sum_var == 0.0) return est;
    est.var_of_mean = sum_var / (npx * npx * (double)s->runs);
    est.dof = sum_var * sum_var / sum_var2 * (double)(s->runs - 1);
    return est;
}

/* ---- the comparison ---- */

static double saturate_z(double z)
{
    if (z > CHECK_Z_MAX) return CHECK_Z_MAX;
    if (z < -CHECK_Z_MAX) return -CHECK_Z_MAX;
    return z;
}

/* Normal-equivalent z of a Welch result (0 when there is no evidence either way). */
static double welch_z(stats_welch w)
{
    if (w.se == 0.0) return w.diff == 0.0 ? 0.0 : (w.diff > 0.0 ? CHECK_Z_MAX : -CHECK_Z_MAX);
    return saturate_z(stats_t_to_z(w.t, w.dof));
}

static int validate(const check_side *a, const check_side *b, const check_options *o, rerror *e)
{
    if (!(o->alpha > 0.0 && o->alpha < 1.0)) return rerror_set(e, "alpha %g must be in (0, 1)", o->alpha);
    if (!(o->margin > 0.0 && o->margin < 1.0)) return rerror_set(e, "margin %g must be in (0, 1)", o->margin);
    if (o->block_size < 1) return rerror_set(e, "block size %d must be at least 1", o->block_size);
    if (a->width != b->width || a->height != b->height)
        return rerror_set(e, "A is %d x %d but B is %d x %d", a->width, a->height, b->width, b->height);
    if (a->kind == CHECK_SIDE_EXACT && b->kind == CHECK_SIDE_EXACT)
        return rerror_set(e, "both sides are exact: at least one needs runs or a variance");
    if ((a->kind == CHECK_SIDE_RUNS && a->block_size != o->block_size) ||
        (b->kind == CHECK_SIDE_RUNS && b->block_size != o->block_size))
        return rerror_set(e, "runs were accumulated with a different block size");
    return 0;
}

static int block_tests(const check_side *a, const check_side *b, const check_options *o, check_result *r, rerror *e)
{
    int b_size = o->block_size, bx, by, c;
    long i = 0;
    double *p;
    unsigned char *reject = NULL;
    double level = 0.5 * o->alpha;
    r->blocks_x = (a->width + b_size - 1) / b_size;
    r->blocks_y = (a->height + b_size - 1) / b_size;
    r->tests = 3L * r->blocks_x * r->blocks_y;
    if (image_alloc(&r->block_z, r->blocks_x, r->blocks_y, e)) return -1;
    p = rmalloc((size_t)r->tests, sizeof *p, e);
    if (!p) return -1;
    r->worst.test.p = 2.0;
    for (by = 0; by < r->blocks_y; ++by)
        for (bx = 0; bx < r->blocks_x; ++bx)
            for (c = 0; c < 3; ++c, ++i) {
                stats_welch w = stats_welch_test(block_estimate(a, b_size, bx, by, c),
                                                 block_estimate(b, b_size, bx, by, c));
                double z = welch_z(w);
                p[i] = w.p;
                image_pixel(&r->block_z, bx, by)[c] = (float)z;
                if (w.p < r->worst.test.p || (w.p == r->worst.test.p && fabs(z) > fabs(r->worst.z))) {
                    r->worst.x = bx;
                    r->worst.y = by;
                    r->worst.channel = c;
                    r->worst.test = w;
                    r->worst.z = z;
                }
            }
    if (o->correction == CHECK_BH) {
        r->rejected = stats_benjamini_hochberg(p, r->tests, level, reject, &r->block_threshold, e);
        if (r->rejected < 0) {
            free(p);
            return -1;
        }
    } else {
        r->block_threshold = stats_sidak_level(level, r->tests);
        r->rejected = 0;
        for (i = 0; i < r->tests; ++i) r->rejected += p[i] <= r->block_threshold;
    }
    free(p);
    return 0;
}

static int pixel_tests(const check_side *a, const check_side *b, const check_options *o, check_result *r, rerror *e)
{
    int x, y, c;
    if (image_alloc(&r->pixel_z, a->width, a->height, e)) return -1;
    r->pixel_tests = 3L * a->width * a->height;
    for (y = 0; y < a->height; ++y)
        for (x = 0; x < a->width; ++x)
            for (c = 0; c < 3; ++c) {
                stats_welch w = stats_welch_test(pixel_estimate(a, x, y, c), pixel_estimate(b, x, y, c));
                image_pixel(&r->pixel_z, x, y)[c] = (float)welch_z(w);
                r->pixels_p_below_alpha += w.p < o->alpha;
            }
    return 0;
}

int check_compare(const check_side *a, const check_side *b, const check_options *o, check_result *r, rerror *e)
{
    memset(r, 0, sizeof *r);
    if (validate(a, b, o, e)) return -1;

    /* Part 1: the image mean (luminance), level alpha / 2. */
    r->lum_a = luminance_estimate(a, &r->lum_a_exact_runs);
    r->lum_b = luminance_estimate(b, &r->lum_b_exact_runs);
    r->global = stats_welch_test(r->lum_a, r->lum_b);
    r->global_reject = r->global.p < 0.5 * o->alpha;

    /* Part 2: blocks x channels with the family correction, level alpha / 2. */
    if (block_tests(a, b, o, r, e) || pixel_tests(a, b, o, r, e)) {
        check_result_free(r);
        return -1;
    }
    r->different = r->global_reject || r->rejected > 0;

    /* Equivalence (TOST at alpha) and the relative bias with its (1 - alpha) interval. */
    r->tost = stats_tost_ratio(r->lum_a, r->lum_b, o->margin, o->alpha);
    r->bias = r->lum_b.mean != 0.0 ? r->lum_a.mean / r->lum_b.mean - 1.0 : NAN;
    r->bias_ci_bounded = stats_ratio_ci(r->lum_a, r->lum_b, 1.0 - o->alpha, &r->bias_lo, &r->bias_hi);
    r->bias_lo -= 1.0;
    r->bias_hi -= 1.0;
    return 0;
}

/* ---- the paired comparison (check.h, check_compare_paired) ---- */

static int validate_paired(const check_side *a, const check_side *b, const check_options *o, rerror *e)
{
    if (validate(a, b, o, e)) return -1;
    if (!a->run_means || !b->run_means || !a->block_run_means || !b->block_run_means)
        return rerror_set(e, "paired: both sides need K runs with per-run image and block means");
    if (a->runs != b->runs)
        return rerror_set(e, "paired: A has %ld runs but B has %ld (run k of A is paired with run k of B)", a->runs,
                          b->runs);
    if (a->blocks_x != b->blocks_x || a->blocks_y != b->blocks_y)
        return rerror_set(e, "paired: the sides were accumulated with different blocks");
    return 0;
}

/* One-sample t-test of the K differences x_a[k*stride] - x_b[k*stride] against 0, as a
 * Welch result against an exact zero. */
static stats_welch paired_test(const double *x_a, const double *x_b, long stride, long runs, double *d)
{
    stats_estimate zero = {0.0, 0.0, 0.0};
    long k;
    for (k = 0; k < runs; ++k) d[k] = x_a[k * stride] - x_b[k * stride];
    return stats_welch_test(mean_of_runs(d, 1, runs), zero);
}

static int paired_block_tests(const check_side *a, const check_side *b, const check_options *o, check_result *r,
                              double *d, rerror *e)
{
    long blocks = (long)a->blocks_x * a->blocks_y, i;
    double *p;
    int c;
    r->blocks_x = a->blocks_x;
    r->blocks_y = a->blocks_y;
    r->tests = 3L * blocks;
    if (image_alloc(&r->block_z, r->blocks_x, r->blocks_y, e)) return -1;
    p = rmalloc((size_t)r->tests, sizeof *p, e);
    if (!p) return -1;
    r->worst.test.p = 2.0;
    for (i = 0; i < blocks; ++i)
        for (c = 0; c < 3; ++c) {
            stats_welch w = paired_test(a->block_run_means + 3 * i + c, b->block_run_means + 3 * i + c, 3 * blocks,
                                        a->runs, d);
            double z = welch_z(w);
            p[3 * i + c] = w.p;
            image_pixel(&r->block_z, (int)(i % a->blocks_x), (int)(i / a->blocks_x))[c] = (float)z;
            if (w.p < r->worst.test.p || (w.p == r->worst.test.p && fabs(z) > fabs(r->worst.z))) {
                r->worst.x = (int)(i % a->blocks_x);
                r->worst.y = (int)(i / a->blocks_x);
                r->worst.channel = c;
                r->worst.test = w;
                r->worst.z = z;
            }
        }
    if (o->correction == CHECK_BH) {
        r->rejected = stats_benjamini_hochberg(p, r->tests, 0.5 * o->alpha, NULL, &r->block_threshold, e);
    } else {
        r->block_threshold = stats_sidak_level(0.5 * o->alpha, r->tests);
        r->rejected = 0;
        for (i = 0; i < r->tests; ++i) r->rejected += p[i] <= r->block_threshold;
    }
    free(p);
    return r->rejected < 0 ? -1 : 0;
}

/* Bias and TOST of the paired luminance difference relative to B's mean. */
static void paired_bias(const check_options *o, check_result *r)
{
    double mb = r->lum_b.mean, se = r->global.se, dof = r->global.dof, q;
    r->bias = mb != 0.0 ? r->global.diff / mb : NAN;
    r->tost.margin = o->margin;
    r->bias_ci_bounded = mb != 0.0 && se > 0.0;
    if (!r->bias_ci_bounded) {
        r->bias_lo = -INFINITY;
        r->bias_hi = INFINITY;
        r->tost.p_lower = r->tost.p_upper = r->tost.p = 1.0;
        return;
    }
    q = stats_t_quantile(1.0 - 0.5 * o->alpha, dof);
    r->bias_lo = (r->global.diff - q * se) / fabs(mb);
    r->bias_hi = (r->global.diff + q * se) / fabs(mb);
    r->tost.p_lower = stats_t_sf((r->global.diff + o->margin * fabs(mb)) / se, dof); /* H0: d <= -margin |m_B| */
    r->tost.p_upper = stats_t_cdf((r->global.diff - o->margin * fabs(mb)) / se, dof); /* H0: d >= +margin |m_B| */
    r->tost.p = fmax(r->tost.p_lower, r->tost.p_upper);
    r->tost.equivalent = r->tost.p < o->alpha;
}

int check_compare_paired(const check_side *a, const check_side *b, const check_options *o, check_result *r,
                         rerror *e)
{
    double *la, *lb, *d;
    long k;
    int status = 0;
    memset(r, 0, sizeof *r);
    if (validate_paired(a, b, o, e)) return -1;
    r->paired = 1;
    la = rmalloc((size_t)a->runs, sizeof *la, e);
    lb = rmalloc((size_t)a->runs, sizeof *lb, e);
    d = rmalloc((size_t)a->runs, sizeof *d, e);
    if (!la || !lb || !d) {
        free(la);
        free(lb);
        free(d);
        return -1;
    }
    r->lum_a = luminance_estimate(a, &r->lum_a_exact_runs);
    r->lum_b = luminance_estimate(b, &r->lum_b_exact_runs);
    for (k = 0; k < a->runs; ++k) {
        la[k] = run_luminance(a, k);
        lb[k] = run_luminance(b, k);
    }
    r->global = paired_test(la, lb, 1, a->runs, d);
    r->global_reject = r->global.p < 0.5 * o->alpha;
    if (paired_block_tests(a, b, o, r, d, e) || pixel_tests(a, b, o, r, e)) {
        check_result_free(r);
        status = -1;
    } else {
        r->different = r->global_reject || r->rejected > 0;
        paired_bias(o, r);
    }
    free(la);
    free(lb);
    free(d);
    return status;
}

void check_result_free(check_result *r)
{
    image_free(&r->block_z);
    image_free(&r->pixel_z);
}
