/* `restir check` statistics (check.h; decision rule in docs/statistics.md, "check"). */
#include "restir/metrics/check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/vec.h"

void check_options_default(check_options *o)
{
    o->alpha = 0.01;
    o->correction = CHECK_SIDAK;
    o->margin = 0.01;
    o->block_size = 8;
    o->skew_correction = 1;
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

int check_side_add_run(check_side *s, const image *run, const char *name, rerror *e)
{
    long blocks = (long)s->blocks_x * s->blocks_y, k;
    double *grown;
    if (moments_add(&s->acc, run, name, e)) return -1;
    k = s->acc.runs - 1;
    grown = realloc(s->block_run_means, (size_t)(k + 1) * (size_t)blocks * 3 * sizeof *grown);
    if (!grown) return rerror_set(e, "out of memory (block means)");
    s->block_run_means = grown;
    /* The same function as `render --runs` uses for PREFIX.blocks.bin: bit-identical means. */
    moments_block_means(run, s->block_size, grown + (size_t)k * (size_t)blocks * 3);
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
    s->run_block_count = f->block_size_count;
    memcpy(s->run_block_sizes, f->block_sizes, sizeof s->run_block_sizes);
    memcpy(s->run_block_means, f->block_means, sizeof s->run_block_means);
    s->correlation = f->correlation;
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
    int i;
    image_free(&s->mean);
    image_free(&s->var);
    free(s->run_means);
    free(s->block_run_means);
    for (i = 0; i < s->run_block_count; ++i) free(s->run_block_means[i]);
    moments_free(&s->acc);
    memset(s, 0, sizeof *s);
}

static void scale_values(double *v, size_t n, double factor)
{
    size_t i;
    if (v)
        for (i = 0; i < n; ++i) v[i] *= factor;
}

void check_side_scale(check_side *s, double factor)
{
    size_t i, npx = (size_t)s->width * (size_t)s->height * 3;
    int j;
    for (i = 0; i < npx; ++i) {
        s->mean.px[i] = (float)(s->mean.px[i] * factor);
        if (s->kind != CHECK_SIDE_EXACT) s->var.px[i] = (float)(s->var.px[i] * factor * factor);
    }
    if (s->kind == CHECK_SIDE_EXACT) return;
    scale_values(s->run_means, 3 * (size_t)s->runs, factor);
    if (s->kind == CHECK_SIDE_RUNS)
        scale_values(s->block_run_means, 3 * (size_t)s->runs * (size_t)s->blocks_x * (size_t)s->blocks_y, factor);
    for (j = 0; j < s->run_block_count; ++j)
        scale_values(s->run_block_means[j],
                     3 * (size_t)s->runs * (size_t)moments_block_count(s->width, s->height, s->run_block_sizes[j]),
                     factor);
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

/* The per-run block means of a moments side at block size b, or NULL if the file set
 * has none at that size. */
static const double *moments_run_blocks(const check_side *s, int b)
{
    int i;
    if (s->kind != CHECK_SIDE_MOMENTS) return NULL;
    for (i = 0; i < s->run_block_count; ++i)
        if (s->run_block_sizes[i] == b) return s->run_block_means[i];
    return NULL;
}

/* Block mean of channel c. From raw runs, or from a moments file set that kept per-run
 * block means at this block size, the variance comes from the K per-run block means:
 * exact whatever the correlation between the block's pixels. Otherwise it is
 * sum(var_i) / (n^2 K), which assumes independent pixels (true for a path tracer, not
 * for ReSTIR's spatial reuse), with the Welch-Satterthwaite dof of that sum (each term
 * has K - 1). */
static stats_estimate block_estimate(const check_side *s, int b, int bx, int by, int c)
{
    const double *run_blocks = moments_run_blocks(s, b);
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
    if (run_blocks) {
        long blocks = moments_block_count(s->width, s->height, b), idx = (long)by * ((s->width + b - 1) / b) + bx;
        return mean_of_runs(run_blocks + 3 * idx + c, 3 * blocks, s->runs);
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

/* The per-run block means of a side at block size b (raw runs or a moments file set that
 * has them), or NULL. */
static const double *side_run_blocks(const check_side *s, int b)
{
    if (s->kind == CHECK_SIDE_RUNS) return s->block_run_means;
    return moments_run_blocks(s, b);
}

/* Pooled standardized skewness of a side's per-run block means: the average over the
 * blocks and channels with a nonzero variance of g = m3 / s^3, m3 = (1/K) sum (x - m)^3,
 * s^2 = 1/(K-1) sum (x - m)^2. One block's g from K = 8 runs is too noisy to use (and a
 * run set without a firefly shows little skew exactly when its mean is low), so the
 * whole family's blocks share one value. 0 without per-run block means. */
static double pooled_block_skewness(const check_side *s, int b)
{
    const double *x = side_run_blocks(s, b);
    long blocks = moments_block_count(s->width, s->height, b), i, k, used = 0;
    double sum_g = 0.0;
    if (!x || s->runs < 3) return 0.0;
    for (i = 0; i < 3 * blocks; ++i) {
        double mean = 0.0, m2 = 0.0, m3 = 0.0, var;
        for (k = 0; k < s->runs; ++k) mean += x[k * 3 * blocks + i];
        mean /= (double)s->runs;
        for (k = 0; k < s->runs; ++k) {
            double d = x[k * 3 * blocks + i] - mean;
            m2 += d * d;
            m3 += d * d * d;
        }
        var = m2 / (double)(s->runs - 1);
        if (!(var > 0.0)) continue;
        sum_g += m3 / (double)s->runs / (var * sqrt(var));
        used++;
    }
    return used ? sum_g / (double)used : 0.0;
}

/* Hall's (1992) transformation of a Studentized mean, g(t) = t + a t^2 + a^2 t^3 / 3 + a / 2
 * with a = gamma_d / 3 (monotone: g' = (1 + a t)^2), removes the first-order Edgeworth
 * term of a statistic whose estimate has skewness gamma_d; here gamma_d is that of
 * d = mean_A - mean_B, from the pooled skewness of each side: third cumulant
 * gamma_A s_A^3 / K_A^2 - gamma_B s_B^3 / K_B^2 over v^(3/2). Right-skewed runs make a low
 * mean come with a low variance, so t is too often very negative: g moves that tail in.
 * Applied only where it makes |t| smaller (the other tail is already conservative),
 * so the correction can never add a rejection. */
static void judge_tails(const check_side *a, const check_side *b, const check_options *o, check_result *r);

static stats_welch skew_adjust(stats_welch w, stats_estimate ea, stats_estimate eb, double skew_a, double skew_b)
{
    double v = ea.var_of_mean + eb.var_of_mean, k3, a, g;
    if (!(w.se > 0.0) || !isfinite(w.t)) return w;
    /* var_of_mean = s^2 / K, so s^3 / K^2 = var_of_mean^(3/2) / sqrt(K), K = dof + 1. */
    k3 = skew_a * ea.var_of_mean * sqrt(ea.var_of_mean) / sqrt(ea.dof + 1.0) -
         skew_b * eb.var_of_mean * sqrt(eb.var_of_mean) / sqrt(eb.dof + 1.0);
    a = k3 / (v * sqrt(v)) / 3.0;
    g = w.t + a * w.t * w.t + a * a * w.t * w.t * w.t / 3.0 + 0.5 * a;
    if (fabs(g) < fabs(w.t)) {
        w.t = g;
        w.p = stats_t_two_sided_p(g, w.dof);
    }
    return w;
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
                stats_estimate ea = block_estimate(a, b_size, bx, by, c), eb = block_estimate(b, b_size, bx, by, c);
                stats_welch w = stats_welch_test(ea, eb);
                double z;
                if (o->skew_correction) w = skew_adjust(w, ea, eb, r->skew_a, r->skew_b);
                z = welch_z(w);
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

    if (o->skew_correction) {
        r->skew_a = pooled_block_skewness(a, o->block_size);
        r->skew_b = pooled_block_skewness(b, o->block_size);
    }

    /* Part 1: the image mean (luminance), level alpha / 2. Plain Welch: the image mean
     * of a run is far less skewed than its block means, and borrowing the blocks'
     * skewness cost power without a measurable gain in calibration (docs/statistics.md,
     * "Skewed per-run means"). */
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
    r->blocks_a_from_runs = a->kind == CHECK_SIDE_RUNS || moments_run_blocks(a, o->block_size) != NULL;
    r->blocks_b_from_runs = b->kind == CHECK_SIDE_RUNS || moments_run_blocks(b, o->block_size) != NULL;
    r->correlated_warning_a = a->kind == CHECK_SIDE_MOMENTS && a->correlation == MOMENTS_CORRELATED &&
                              (!r->blocks_a_from_runs || !r->lum_a_exact_runs);
    r->correlated_warning_b = b->kind == CHECK_SIDE_MOMENTS && b->correlation == MOMENTS_CORRELATED &&
                              (!r->blocks_b_from_runs || !r->lum_b_exact_runs);

    /* Equivalence (TOST at alpha) and the relative bias with its (1 - alpha) interval. */
    r->tost = stats_tost_ratio(r->lum_a, r->lum_b, o->margin, o->alpha);
    r->bias = r->lum_b.mean != 0.0 ? r->lum_a.mean / r->lum_b.mean - 1.0 : NAN;
    r->bias_ci_bounded = stats_ratio_ci(r->lum_a, r->lum_b, 1.0 - o->alpha, &r->bias_lo, &r->bias_hi);
    r->bias_lo -= 1.0;
    r->bias_hi -= 1.0;
    judge_tails(a, b, o, r);
    return 0;
}

/* The tail of one side's runs (check_tail.h): per-run luminance image means and per-run
 * block means at the check's block size. */
static void side_tail(const check_side *s, int block_size, check_tail *t)
{
    const double *blocks = s->kind == CHECK_SIDE_EXACT ? NULL : side_run_blocks(s, block_size);
    long nblocks = moments_block_count(s->width, s->height, block_size), k;
    double *lum = s->run_means && s->runs > 0 ? malloc((size_t)s->runs * sizeof *lum) : NULL;
    for (k = 0; lum && k < s->runs; ++k) lum[k] = run_luminance(s, k);
    check_tail_measure(t, blocks, s->runs, 3 * nblocks, 3 * nblocks, lum,
                       blocks ? pooled_block_skewness(s, block_size) : 0.0);
    free(lum);
}

/* A heavy-tailed side makes the verdict untrustworthy whichever way it went. */
static void judge_tails(const check_side *a, const check_side *b, const check_options *o, check_result *r)
{
    long need_a, need_b;
    side_tail(a, o->block_size, &r->tail_a);
    side_tail(b, o->block_size, &r->tail_b);
    r->inconclusive = r->tail_a.heavy || r->tail_b.heavy;
    need_a = r->tail_a.heavy ? check_tail_runs_needed(&r->tail_a, a->runs) : 0;
    need_b = r->tail_b.heavy ? check_tail_runs_needed(&r->tail_b, b->runs) : 0;
    r->runs_needed = need_a > need_b ? need_a : need_b;
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
        judge_tails(a, b, o, r);
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
