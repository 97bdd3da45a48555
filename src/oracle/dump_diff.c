/* Comparison of two reservoir images of one stage (include/restir/oracle/dump_diff.h). */
#include "restir/oracle/dump_diff.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const field_names[DF_COUNT] = {
    "wsum",     "W",           "confidence",  "n_invalid", "rc_k",          "n_pss",   "lobe",
    "rc_triangle", "rc_bary",  "rc_position", "rc_normal", "rc_flags",      "rc_wo",   "rc_pdf_prev",
    "rc_geom",  "rc_pdf",      "rc_radiance", "light_pdf", "F",             "target",  "pss"};

const char *dump_field_name(dump_field f) { return (int)f >= 0 && f < DF_COUNT ? field_names[f] : NULL; }

int dump_field_is_integer(dump_field f)
{
    return f == DF_N_INVALID || f == DF_RC_K || f == DF_N_PSS || f == DF_LOBE || f == DF_RC_TRIANGLE ||
           f == DF_RC_FLAGS;
}

int dump_field_parse(const char *name)
{
    int f;
    for (f = 0; f < DF_COUNT; ++f)
        if (!strcmp(name, field_names[f])) return f;
    return -1;
}

void dump_diff_tolerance_default(dump_diff_tolerance *t)
{
    /* the defaults ask for a bit-identical build (same RNG, same precision): docs/oracle.md */
    memset(t, 0, sizeof *t);
    t->min_same = 1;
    t->max_outlier_fraction = 0;
    t->first = 5;
}

void dump_diff_tolerance_all(dump_diff_tolerance *t, double v)
{
    int f;
    for (f = 0; f < DF_COUNT; ++f)
        if (!dump_field_is_integer((dump_field)f)) t->max_rel[f] = v;
}

/* Calls item(t, name, value) for each comma-separated "name[=value]" of list. */
static int each_item(dump_diff_tolerance *t, const char *list, const char *option, int with_value, rerror *e)
{
    const char *p = list;
    if (!*p) return rerror_set(e, "%s: empty list", option);
    while (*p) {
        char item[64], *eq, *end;
        size_t n = strcspn(p, ",");
        int f;
        double v = 0;
        if (n == 0 || n >= sizeof item) return rerror_set(e, "%s: bad item in '%s'", option, list);
        memcpy(item, p, n);
        item[n] = '\0';
        eq = strchr(item, '=');
        if (with_value) {
            if (!eq) return rerror_set(e, "%s: '%s' is not FIELD=VALUE", option, item);
            *eq = '\0';
            v = strtod(eq + 1, &end);
            if (end == eq + 1 || *end || !(v >= 0) || !isfinite(v))
                return rerror_set(e, "%s: '%s' is not a finite number >= 0", option, eq + 1);
        } else if (eq)
            return rerror_set(e, "%s: '%s' takes no value", option, item);
        f = dump_field_parse(item);
        if (f < 0 && !(with_value && !strcmp(item, "all")))
            return rerror_set(e, "%s: unknown field '%s' (docs/formats.md \"Record\": wsum, W, confidence, n_invalid, "
                                 "rc_k, n_pss, lobe, rc_triangle, rc_bary, rc_position, rc_normal, rc_flags, rc_wo, "
                                 "rc_pdf_prev, rc_geom, rc_pdf, rc_radiance, light_pdf, F, target, pss)", option, item);
        if (!with_value)
            t->ignore[f] = 1;
        else if (f < 0)
            dump_diff_tolerance_all(t, v);
        else if (dump_field_is_integer((dump_field)f))
            return rerror_set(e, "%s: %s is an integer field, compared exactly (use --ignore to skip it)", option,
                              item);
        else
            t->max_rel[f] = v;
        p += n;
        if (*p == ',') ++p;
    }
    return 0;
}

int dump_diff_tolerance_parse(dump_diff_tolerance *t, const char *list, rerror *e)
{
    return each_item(t, list, "--max-rel", 1, e);
}

int dump_diff_ignore_parse(dump_diff_tolerance *t, const char *list, rerror *e)
{
    return each_item(t, list, "--ignore", 0, e);
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
    if (isnan(a) || isnan(b)) return NAN;
    if (a == b) return 0;
    if (!isfinite(a) || !isfinite(b)) return INFINITY;
    return fabs(a - b) / (fabs(a) > fabs(b) ? fabs(a) : fabs(b));
}

static int finite3(double x, double y, double z) { return isfinite(x) && isfinite(y) && isfinite(z); }

int dump_record_finite(const reservoir *r)
{
    const path_sample *s = &r->y;
    int i;
    if (!finite3((double)r->wsum, (double)r->W, (double)r->confidence)) return 0;
    if (!finite3(s->rc_bary[0], s->rc_bary[1], 0) || !finite3(s->rc_position.x, s->rc_position.y, s->rc_position.z) ||
        !finite3(s->rc_normal.x, s->rc_normal.y, s->rc_normal.z) ||
        !finite3((double)s->rc_wo.x, (double)s->rc_wo.y, (double)s->rc_wo.z) ||
        !finite3((double)s->rc_pdf_prev, (double)s->rc_geom, (double)s->rc_pdf) ||
        !finite3((double)s->rc_radiance.r, (double)s->rc_radiance.g, (double)s->rc_radiance.b) ||
        !finite3((double)s->light_pdf, (double)s->target, 0) || !finite3((double)s->F.r, (double)s->F.g, (double)s->F.b))
        return 0;
    for (i = 0; s->pss && i < s->n_pss; ++i)
        if (!isfinite((double)s->pss[i])) return 0;
    return 1;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Quantiles 0.5, 0.9, 0.99 (nearest rank) and the maximum of v[0..n-1] (sorted in place;
 * every entry is finite or +inf, never NaN, so the order is total). */
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

/* The relative error of a field of n components: max_i |a_i - b_i| / max_i max(|a_i|, |b_i|).
 * One scale for the whole vector, so that a coordinate near 0 of a position, a normal or an
 * RGB triple does not turn a rounding difference into a relative error of 1 (a per-component
 * relative error did: binary32 builds showed rc_position "errors" above 1e-2). For n = 1 it
 * is dump_rel_error. */
static double rel_max(const double *a, const double *b, int n)
{
    double diff = 0, scale = 0;
    int i;
    for (i = 0; i < n; ++i) {
        double d = fabs(a[i] - b[i]);
        if (d > diff) diff = d;
        if (fabs(a[i]) > scale) scale = fabs(a[i]);
        if (fabs(b[i]) > scale) scale = fabs(b[i]);
    }
    return diff == 0 ? 0 : diff / scale;
}

/* Relative error of one real field of two same-sample finite records (0 if equal). */
static double field_error(dump_field f, const reservoir *ra, const reservoir *rb)
{
    const path_sample *a = &ra->y, *b = &rb->y;
    double x[PATH_MAX_PSS], y[PATH_MAX_PSS];
    int i, n = 0;
    switch (f) {
    case DF_WSUM: x[0] = (double)ra->wsum, y[0] = (double)rb->wsum, n = 1; break;
    case DF_W: x[0] = (double)ra->W, y[0] = (double)rb->W, n = 1; break;
    case DF_CONFIDENCE: x[0] = (double)ra->confidence, y[0] = (double)rb->confidence, n = 1; break;
    case DF_RC_BARY: x[0] = a->rc_bary[0], x[1] = a->rc_bary[1], y[0] = b->rc_bary[0], y[1] = b->rc_bary[1], n = 2; break;
    case DF_RC_POSITION:
        x[0] = a->rc_position.x, x[1] = a->rc_position.y, x[2] = a->rc_position.z;
        y[0] = b->rc_position.x, y[1] = b->rc_position.y, y[2] = b->rc_position.z, n = 3;
        break;
    case DF_RC_NORMAL:
        x[0] = a->rc_normal.x, x[1] = a->rc_normal.y, x[2] = a->rc_normal.z;
        y[0] = b->rc_normal.x, y[1] = b->rc_normal.y, y[2] = b->rc_normal.z, n = 3;
        break;
    case DF_RC_WO:
        x[0] = (double)a->rc_wo.x, x[1] = (double)a->rc_wo.y, x[2] = (double)a->rc_wo.z;
        y[0] = (double)b->rc_wo.x, y[1] = (double)b->rc_wo.y, y[2] = (double)b->rc_wo.z, n = 3;
        break;
    case DF_RC_PDF_PREV: x[0] = (double)a->rc_pdf_prev, y[0] = (double)b->rc_pdf_prev, n = 1; break;
    case DF_RC_GEOM: x[0] = (double)a->rc_geom, y[0] = (double)b->rc_geom, n = 1; break;
    case DF_RC_PDF: x[0] = (double)a->rc_pdf, y[0] = (double)b->rc_pdf, n = 1; break;
    case DF_RC_RADIANCE:
        x[0] = (double)a->rc_radiance.r, x[1] = (double)a->rc_radiance.g, x[2] = (double)a->rc_radiance.b;
        y[0] = (double)b->rc_radiance.r, y[1] = (double)b->rc_radiance.g, y[2] = (double)b->rc_radiance.b, n = 3;
        break;
    case DF_LIGHT_PDF: x[0] = (double)a->light_pdf, y[0] = (double)b->light_pdf, n = 1; break;
    case DF_F:
        x[0] = (double)a->F.r, x[1] = (double)a->F.g, x[2] = (double)a->F.b;
        y[0] = (double)b->F.r, y[1] = (double)b->F.g, y[2] = (double)b->F.b, n = 3;
        break;
    case DF_TARGET: x[0] = (double)a->target, y[0] = (double)b->target, n = 1; break;
    case DF_PSS:
        n = a->n_pss < b->n_pss ? a->n_pss : b->n_pss; /* n_pss itself is compared exactly */
        for (i = 0; i < n; ++i) {
            x[i] = a->pss ? (double)a->pss[i] : 0;
            y[i] = b->pss ? (double)b->pss[i] : 0;
        }
        break;
    default: break;
    }
    return rel_max(x, y, n);
}

/* 1 if an integer field differs. */
static int field_int_differs(dump_field f, const reservoir *ra, const reservoir *rb)
{
    const path_sample *a = &ra->y, *b = &rb->y;
    switch (f) {
    case DF_N_INVALID: return ra->n_invalid != rb->n_invalid;
    case DF_RC_K: return a->rc_k != b->rc_k;
    case DF_N_PSS: return a->n_pss != b->n_pss;
    case DF_LOBE: return memcmp(a->lobe, b->lobe, sizeof a->lobe) != 0;
    case DF_RC_TRIANGLE: return a->rc_triangle != b->rc_triangle;
    case DF_RC_FLAGS: return a->rc_flags != b->rc_flags;
    default: return 0;
    }
}

/* The x_k fields: meaningful only when rc_k != 0 (docs/formats.md). */
static int is_rc_field(dump_field f) { return f >= DF_RC_TRIANGLE && f <= DF_RC_RADIANCE; }

/* Compares every field of two finite same-sample records: the first field beyond its
 * tolerance (-1 if none) and its error; records the per-field statistics in r. */
static int compare_fields(const reservoir *a, const reservoir *b, const dump_diff_tolerance *t, dump_diff_result *r,
                          double *worst)
{
    int f, first = -1;
    for (f = 0; f < DF_COUNT; ++f) {
        double err;
        int beyond;
        if (t->ignore[f]) continue;
        if (is_rc_field((dump_field)f) && (a->y.rc_k == PATH_RC_NONE || a->y.rc_k != b->y.rc_k)) continue;
        if (dump_field_is_integer((dump_field)f)) {
            err = field_int_differs((dump_field)f, a, b) ? 1 : 0;
            beyond = err > 0;
        } else {
            err = field_error((dump_field)f, a, b);
            beyond = !(err <= t->max_rel[f]);
        }
        if (err > r->field_max[f]) r->field_max[f] = err;
        if (beyond) {
            r->field_beyond[f]++;
            if (first < 0) {
                first = f;
                *worst = err;
            }
        }
    }
    return first;
}

static void note_pixel(dump_diff_result *r, const dump_diff_tolerance *t, const reservoir *a, const reservoir *b,
                       long p, long width, int kind, int field, double rel)
{
    dump_diff_pixel *d;
    if (r->n_first >= t->first) return;
    d = &r->firsts[r->n_first++];
    d->x = p % width;
    d->y = p / width;
    d->kind = kind;
    d->field = field;
    d->rel = rel;
    d->nonfinite_in = kind == DUMP_PIXEL_NONFINITE ? (!dump_record_finite(a)) + 2 * (!dump_record_finite(b)) : 0;
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

/* Mean and standard error of a quantity over the image (non-finite if a value is). */
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

/* F_c W of channel c = 0, 1, 2 (R, G, B), or luminance(F) W for c = 3. */
static double channel_fw(const reservoir *r, int c)
{
    real f = c == 0 ? r->y.F.r : c == 1 ? r->y.F.g : r->y.F.b;
    return c == 3 ? quantity(r, Q_FW) : (double)f * (double)r->W;
}

/* Per channel: the image means of F_c W of one side and their standard errors. */
static void image_mean_rgb(const reservoir *rs, long n, double *mean, double *se)
{
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    long p;
    int c;
    for (p = 0; p < n; ++p)
        for (c = 0; c < 3; ++c) {
            double v = channel_fw(&rs[p], c);
            s[c] += v;
            s2[c] += v * v;
        }
    for (c = 0; c < 3; ++c) {
        mean[c] = s[c] / (double)n;
        se[c] = n > 1 ? sqrt(fmax(s2[c] / (double)n - mean[c] * mean[c], 0) / (double)(n - 1)) : 0;
    }
}

/* The paired differences A - B of F_c W (c = 0..2) and of luminance(F) W (c = 3): mean and
 * standard error over the pixels (two passes: the differences are often tiny). */
static void paired_means(const reservoir *a, const reservoir *b, long n, double *mean, double *se)
{
    long p;
    int c;
    for (c = 0; c < 4; ++c) {
        double s = 0, s2 = 0;
        for (p = 0; p < n; ++p)
            s += channel_fw(&a[p], c) - channel_fw(&b[p], c);
        mean[c] = s / (double)n;
        for (p = 0; p < n; ++p) {
            double d = channel_fw(&a[p], c) - channel_fw(&b[p], c) - mean[c];
            s2 += d * d;
        }
        se[c] = n > 1 ? sqrt(s2 / (double)(n - 1) / (double)n) : 0;
    }
}

void dump_diff_result_free(dump_diff_result *r)
{
    free(r->firsts);
    free(r->mask);
    r->firsts = NULL;
    r->mask = NULL;
}

/* Classifies pixel p (DUMP_PIXEL_*) and adds it to the statistics. */
static int classify(const reservoir *a, const reservoir *b, long p, long width, const dump_diff_tolerance *t,
                    dump_diff_result *r, double *ew, double *et, double *ec, long *k)
{
    int field = -1, kind;
    double rel = 0;
    if (!dump_record_finite(a) || !dump_record_finite(b)) {
        kind = DUMP_PIXEL_NONFINITE; /* never within a tolerance (dump_diff.h) */
        r->nonfinite++;
        if (dump_same_sample(&a->y, &b->y)) r->same++;
    } else if (!dump_same_sample(&a->y, &b->y)) {
        kind = DUMP_PIXEL_OTHER;
        r->other++;
    } else {
        ew[*k] = dump_rel_error((double)a->W, (double)b->W);
        et[*k] = dump_rel_error((double)a->y.target, (double)b->y.target);
        ec[*k] = dump_rel_error((double)a->confidence, (double)b->confidence);
        ++*k;
        r->same++;
        if (et[*k - 1] <= t->max_rel[DF_TARGET]) r->target_agree++;
        field = compare_fields(a, b, t, r, &rel);
        kind = field < 0 ? DUMP_PIXEL_SAME : DUMP_PIXEL_BEYOND;
        if (field >= 0) r->beyond++;
    }
    if (kind != DUMP_PIXEL_SAME) {
        r->differing++;
        note_pixel(r, t, a, b, p, width, kind, field, rel);
    }
    return kind;
}

int dump_diff(const reservoir *a, const reservoir *b, long width, long height, const dump_diff_tolerance *t,
              dump_diff_result *r, rerror *e)
{
    long n = width * height, p, k = 0, nf = t->first < n ? t->first : n;
    double *ew, *et, *ec;
    memset(r, 0, sizeof *r);
    ew = rmalloc((size_t)n + 1, sizeof *ew, e);
    et = rmalloc((size_t)n + 1, sizeof *et, e);
    ec = rmalloc((size_t)n + 1, sizeof *ec, e);
    r->mask = rmalloc((size_t)n, 1, e);
    r->firsts = rmalloc((size_t)nf + 1, sizeof *r->firsts, e);
    if (!ew || !et || !ec || !r->mask || !r->firsts) {
        free(ew);
        free(et);
        free(ec);
        dump_diff_result_free(r);
        return -1;
    }
    r->pixels = n;
    for (p = 0; p < n; ++p) r->mask[p] = (unsigned char)classify(&a[p], &b[p], p, width, t, r, ew, et, ec, &k);
    quantiles(ew, k, r->q_w);
    quantiles(et, k, r->q_target);
    quantiles(ec, k, r->q_conf);
    image_mean(a, n, Q_FW, &r->mean_fw[0], &r->se_fw[0]);
    image_mean(b, n, Q_FW, &r->mean_fw[1], &r->se_fw[1]);
    image_mean(a, n, Q_CONFIDENCE, &r->mean_c[0], &r->se_c[0]);
    image_mean(b, n, Q_CONFIDENCE, &r->mean_c[1], &r->se_c[1]);
    image_mean(a, n, Q_NONEMPTY, &r->mean_full[0], &r->se_full[0]);
    image_mean(b, n, Q_NONEMPTY, &r->mean_full[1], &r->se_full[1]);
    image_mean_rgb(a, n, r->mean_rgb[0], r->se_rgb[0]);
    image_mean_rgb(b, n, r->mean_rgb[1], r->se_rgb[1]);
    paired_means(a, b, n, r->paired_mean, r->paired_se);
    free(ew);
    free(et);
    free(ec);
    return 0;
}

int dump_diff_pass(const dump_diff_result *r, const dump_diff_tolerance *t)
{
    double same = r->pixels ? (double)r->same / (double)r->pixels : 1;
    /* the allowance is a count of pixels, floor(fraction x pixels): 0 allows none */
    double allowed = floor(t->max_outlier_fraction * (double)r->pixels);
    return r->pixels > 0 && r->nonfinite == 0 && same >= t->min_same && (double)r->beyond <= allowed;
}

static double two_sample_z(const double *mean, const double *se)
{
    double s = sqrt(se[0] * se[0] + se[1] * se[1]);
    if (!isfinite(mean[0]) || !isfinite(mean[1]) || !isfinite(s)) return NAN; /* fails every |z| <= bound */
    if (s == 0) return mean[0] == mean[1] ? 0 : INFINITY;
    return (mean[0] - mean[1]) / s;
}

double dump_diff_mean_z(const dump_diff_result *r) { return two_sample_z(r->mean_fw, r->se_fw); }
double dump_diff_confidence_z(const dump_diff_result *r) { return two_sample_z(r->mean_c, r->se_c); }
double dump_diff_nonempty_z(const dump_diff_result *r) { return two_sample_z(r->mean_full, r->se_full); }

double dump_diff_channel_z(const dump_diff_result *r, int c)
{
    double m[2], se[2];
    if (c < 0 || c > 2) return NAN;
    m[0] = r->mean_rgb[0][c];
    m[1] = r->mean_rgb[1][c];
    se[0] = r->se_rgb[0][c];
    se[1] = r->se_rgb[1][c];
    return two_sample_z(m, se);
}

double dump_diff_paired_z(const dump_diff_result *r, int c)
{
    double m, s;
    if (c < 0 || c > 3) return NAN;
    m = r->paired_mean[c];
    s = r->paired_se[c];
    if (!isfinite(m) || !isfinite(s)) return NAN;
    if (s == 0) return m == 0 ? 0 : (m > 0 ? INFINITY : -INFINITY);
    return m / s;
}
