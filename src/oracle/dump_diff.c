/* Comparison of two reservoir images of one stage (include/restir/oracle/dump_diff.h). */
#include "restir/oracle/dump_diff.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void dump_diff_tolerance_default(dump_diff_tolerance *t)
{
    /* the defaults ask for a bit-identical build (same RNG, same precision): docs/oracle.md */
    t->max_rel_w = t->max_rel_target = t->max_rel_conf = 0;
    t->min_same = 1;
    t->first = 5;
}

int dump_same_sample(const path_sample *a, const path_sample *b)
{
    int ea = !path_sample_is_valid(a), eb = !path_sample_is_valid(b);
    if (ea || eb) return ea && eb;
    return a->seed == b->seed && a->pixel == b->pixel && a->sample == b->sample && a->length == b->length &&
           a->technique == b->technique;
}

double dump_rel_error(double a, double b)
{
    double m = fabs(a) > fabs(b) ? fabs(a) : fabs(b);
    if (isnan(a) || isnan(b)) return isnan(a) && isnan(b) ? 0 : 1;
    if (a == b) return 0;
    return fabs(a - b) / m;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Quantiles 0.5, 0.9, 0.99 (nearest rank) and the maximum of v[0..n-1] (sorted in place). */
static void quantiles(double *v, long n, double q[4])
{
    static const double p[3] = {0.5, 0.9, 0.99};
    int i;
    if (n == 0) {
        q[0] = q[1] = q[2] = q[3] = 0;
        return;
    }
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    for (i = 0; i < 3; ++i) {
        long k = (long)ceil(p[i] * (double)n) - 1;
        q[i] = v[k < 0 ? 0 : k];
    }
    q[3] = v[n - 1];
}

static void note_pixel(dump_diff_result *r, const dump_diff_tolerance *t, const reservoir *a, const reservoir *b,
                       long p, long width, int same)
{
    dump_diff_pixel *d;
    if (r->n_first >= t->first || r->n_first >= DUMP_DIFF_MAX_FIRST) return;
    d = &r->firsts[r->n_first++];
    d->x = p % width;
    d->y = p / width;
    d->same_sample = same;
    d->w[0] = (double)a->W;
    d->w[1] = (double)b->W;
    d->target[0] = (double)a->y.target;
    d->target[1] = (double)b->y.target;
    d->conf[0] = (double)a->confidence;
    d->conf[1] = (double)b->confidence;
    d->id_sample[0] = a->y.sample;
    d->id_sample[1] = b->y.sample;
    d->id_pixel[0] = a->y.pixel;
    d->id_pixel[1] = b->y.pixel;
    d->length[0] = a->y.length;
    d->length[1] = b->y.length;
    d->technique[0] = a->y.technique;
    d->technique[1] = b->y.technique;
}

/* One per-pixel quantity of the statistical mode. */
enum image_quantity { Q_FW, Q_CONFIDENCE, Q_NONEMPTY };

static double quantity(const reservoir *r, enum image_quantity q)
{
    if (q == Q_CONFIDENCE) return (double)r->confidence;
    if (q == Q_NONEMPTY) return r->W > 0 ? 1.0 : 0.0;
    return (double)r->y.target * (double)r->W; /* p̂ = luminance(F) */
}

/* Mean and standard error of a quantity over the image. */
static void image_mean(const reservoir *rs, long n, enum image_quantity q, double *mean, double *se)
{
    double s = 0, s2 = 0;
    long p;
    for (p = 0; p < n; ++p) {
        double v = quantity(&rs[p], q);
        s += v;
        s2 += v * v;
    }
    *mean = s / (double)n;
    *se = n > 1 ? sqrt(fmax(s2 / (double)n - *mean * *mean, 0) / (double)(n - 1)) : 0;
}

int dump_diff(const reservoir *a, const reservoir *b, long width, long height, const dump_diff_tolerance *t,
              dump_diff_result *r, rerror *e)
{
    long n = width * height, p, k = 0;
    double *ew = rmalloc((size_t)n + 1, sizeof *ew, e), *et = rmalloc((size_t)n + 1, sizeof *et, e),
           *ec = rmalloc((size_t)n + 1, sizeof *ec, e);
    memset(r, 0, sizeof *r);
    if (!ew || !et || !ec) {
        free(ew);
        free(et);
        free(ec);
        return -1;
    }
    r->pixels = n;
    for (p = 0; p < n; ++p) {
        int same = dump_same_sample(&a[p].y, &b[p].y);
        int differs = !same;
        if (same) {
            ew[k] = dump_rel_error((double)a[p].W, (double)b[p].W);
            et[k] = dump_rel_error((double)a[p].y.target, (double)b[p].y.target);
            ec[k] = dump_rel_error((double)a[p].confidence, (double)b[p].confidence);
            r->same++;
            if (et[k] <= t->max_rel_target) r->target_agree++;
            differs = ew[k] > t->max_rel_w || et[k] > t->max_rel_target || ec[k] > t->max_rel_conf;
            k++;
        }
        if (differs) {
            r->differing++;
            note_pixel(r, t, &a[p], &b[p], p, width, same);
        }
    }
    quantiles(ew, k, r->q_w);
    quantiles(et, k, r->q_target);
    quantiles(ec, k, r->q_conf);
    image_mean(a, n, Q_FW, &r->mean_fw[0], &r->se_fw[0]);
    image_mean(b, n, Q_FW, &r->mean_fw[1], &r->se_fw[1]);
    image_mean(a, n, Q_CONFIDENCE, &r->mean_c[0], &r->se_c[0]);
    image_mean(b, n, Q_CONFIDENCE, &r->mean_c[1], &r->se_c[1]);
    image_mean(a, n, Q_NONEMPTY, &r->mean_full[0], &r->se_full[0]);
    image_mean(b, n, Q_NONEMPTY, &r->mean_full[1], &r->se_full[1]);
    free(ew);
    free(et);
    free(ec);
    return 0;
}

int dump_diff_pass(const dump_diff_result *r, const dump_diff_tolerance *t)
{
    double same = r->pixels ? (double)r->same / (double)r->pixels : 1;
    return same >= t->min_same && r->q_w[3] <= t->max_rel_w && r->q_target[3] <= t->max_rel_target &&
           r->q_conf[3] <= t->max_rel_conf;
}

static double two_sample_z(const double *mean, const double *se)
{
    double s = sqrt(se[0] * se[0] + se[1] * se[1]);
    if (s == 0) return mean[0] == mean[1] ? 0 : INFINITY;
    return (mean[0] - mean[1]) / s;
}

double dump_diff_mean_z(const dump_diff_result *r) { return two_sample_z(r->mean_fw, r->se_fw); }
double dump_diff_confidence_z(const dump_diff_result *r) { return two_sample_z(r->mean_c, r->se_c); }
double dump_diff_nonempty_z(const dump_diff_result *r) { return two_sample_z(r->mean_full, r->se_full); }
