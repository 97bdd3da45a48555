/* Per-pixel moments of K runs and the moments file set (moments.h,
 * docs/statistics.md "Moments files"). */
#include "restir/moments.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "restir/atomic_file.h"
#include "restir/json_text.h"
#include "restir/output_set.h"

int moments_init(moments *m, int width, int height, rerror *e)
{
    size_t n;
    memset(m, 0, sizeof *m);
    if (width <= 0 || height <= 0) return rerror_set(e, "moments: image size %d x %d is not positive", width, height);
    n = (size_t)width * (size_t)height * 3;
    m->mean = rcalloc(n, sizeof *m->mean, e);
    m->m2 = rcalloc(n, sizeof *m->m2, e);
    if (!m->mean || !m->m2) {
        moments_free(m);
        return -1;
    }
    m->width = width;
    m->height = height;
    return 0;
}

void moments_free(moments *m)
{
    free(m->mean);
    free(m->m2);
    free(m->run_means);
    memset(m, 0, sizeof *m);
}

static int check_finite(const image *run, const char *name, rerror *e)
{
    size_t i, n = (size_t)run->width * (size_t)run->height * 3;
    for (i = 0; i < n; ++i)
        if (!isfinite(run->px[i])) {
            long pixel = (long)(i / 3);
            return rerror_at(e, name ? name : "run", 0, "pixel (%ld, %ld) channel %d is not finite",
                             pixel % run->width, pixel / run->width, (int)(i % 3));
        }
    return 0;
}

/* Welford (1962): one pass, numerically stable, in double. */
int moments_add(moments *m, const image *run, const char *name, rerror *e)
{
    size_t i, n = (size_t)m->width * (size_t)m->height * 3;
    double sum[3] = {0.0, 0.0, 0.0}, count;
    if (run->width != m->width || run->height != m->height)
        return rerror_at(e, name ? name : "run", 0, "image is %d x %d, the other runs are %d x %d", run->width,
                         run->height, m->width, m->height);
    if (check_finite(run, name, e)) return -1;
    if (m->runs == m->run_capacity) {
        long cap = m->run_capacity ? 2 * m->run_capacity : 16;
        double *grown = realloc(m->run_means, (size_t)cap * 3 * sizeof *grown);
        if (!grown) return rerror_set(e, "out of memory (per-run means)");
        m->run_means = grown;
        m->run_capacity = cap;
    }
    m->runs++;
    count = (double)m->runs;
    for (i = 0; i < n; ++i) {
        double x = run->px[i];
        double delta = x - m->mean[i];
        m->mean[i] += delta / count;
        m->m2[i] += delta * (x - m->mean[i]);
        sum[i % 3] += x;
    }
    for (i = 0; i < 3; ++i) m->run_means[3 * (m->runs - 1) + i] = sum[i] / (double)(n / 3);
    return 0;
}

int moments_images(const moments *m, image *mean, image *var, rerror *e)
{
    size_t i, n = (size_t)m->width * (size_t)m->height * 3;
    if (image_alloc(mean, m->width, m->height, e)) return -1;
    if (image_alloc(var, m->width, m->height, e)) {
        image_free(mean);
        return -1;
    }
    for (i = 0; i < n; ++i) {
        mean->px[i] = (float)m->mean[i];
        var->px[i] = m->runs > 1 ? (float)(m->m2[i] / (double)(m->runs - 1)) : 0.0f;
    }
    return 0;
}

int moments_write(const char *prefix, const moments *m, rerror *e)
{
    image mean, var;
    int status;
    if (moments_images(m, &mean, &var, e)) return -1;
    status = moments_write_images(prefix, &mean, &var, m->runs, m->run_means, e);
    image_free(&mean);
    image_free(&var);
    return status;
}

/* The file name part of a path (the sidecar refers to its images relative to itself). */
static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static int write_sidecar(const char *staged, const char *mean_name, const char *var_name, const image *mean,
                         long runs, const double *run_means, rerror *e)
{
    atomic_file f;
    long k;
    if (atomic_file_open(&f, staged, e)) return -1;
    fprintf(f.fp, "{\n  \"format\": \"restir-moments\",\n  \"version\": 1,\n  \"runs\": %ld,\n", runs);
    fprintf(f.fp, "  \"width\": %d,\n  \"height\": %d,\n  \"mean\": ", mean->width, mean->height);
    json_put_string(f.fp, mean_name);
    fprintf(f.fp, ",\n  \"var\": ");
    json_put_string(f.fp, var_name);
    if (run_means) {
        fprintf(f.fp, ",\n  \"run_means\": [");
        for (k = 0; k < runs; ++k) {
            fprintf(f.fp, "%s\n    [", k ? "," : "");
            json_put_number(f.fp, run_means[3 * k]);
            fputs(", ", f.fp);
            json_put_number(f.fp, run_means[3 * k + 1]);
            fputs(", ", f.fp);
            json_put_number(f.fp, run_means[3 * k + 2]);
            fputc(']', f.fp);
        }
        fprintf(f.fp, "\n  ]");
    }
    fprintf(f.fp, "\n}\n");
    return atomic_file_commit(&f, e);
}

int moments_write_images(const char *prefix, const image *mean, const image *var, long runs,
                         const double *run_means, rerror *e)
{
    char mean_path[4096], var_path[4096], json_path[4096];
    const char *staged;
    output_set out;
    if (runs < 1) return rerror_set(e, "%s: moments need at least one run", prefix);
    if (mean->width != var->width || mean->height != var->height)
        return rerror_set(e, "%s: mean and variance images differ in size", prefix);
    if (snprintf(mean_path, sizeof mean_path, "%s.mean.pfm", prefix) >= (int)sizeof mean_path ||
        snprintf(var_path, sizeof var_path, "%s.var.pfm", prefix) >= (int)sizeof var_path ||
        snprintf(json_path, sizeof json_path, "%s.moments.json", prefix) >= (int)sizeof json_path)
        return rerror_set(e, "%s: path too long", prefix);
    output_set_init(&out);
    if (!(staged = output_set_stage(&out, mean_path, e)) || pfm_write(staged, mean, e)) goto fail;
    if (!(staged = output_set_stage(&out, var_path, e)) || pfm_write(staged, var, e)) goto fail;
    if (!(staged = output_set_stage(&out, json_path, e)) ||
        write_sidecar(staged, base_name(mean_path), base_name(var_path), mean, runs, run_means, e))
        goto fail;
    return output_set_commit(&out, e);
fail:
    output_set_abort(&out);
    return -1;
}

/* ---- reading ---- */

typedef struct {
    long runs, width, height, version;
    char format[64], mean[4096], var[4096];
    double *run_means;
    long run_means_count;
} sidecar;

static int read_integer(json_reader *r, const char *key, long lo, long *out)
{
    double v;
    if (json_read_number(r, &v)) return -1;
    if (v != floor(v) || v < (double)lo || v > 2147483647.0)
        return rerror_at(r->e, r->path, r->line, "\"%s\" must be an integer >= %ld", key, lo);
    *out = (long)v;
    return 0;
}

static int read_run_means(json_reader *r, sidecar *s)
{
    long cap = 0;
    if (json_expect(r, '[')) return -1;
    if (json_peek(r) == ']') return json_expect(r, ']');
    for (;;) {
        int c;
        if (s->run_means_count == cap) {
            double *grown;
            cap = cap ? 2 * cap : 64;
            grown = realloc(s->run_means, (size_t)cap * 3 * sizeof *grown);
            if (!grown) return rerror_at(r->e, r->path, r->line, "out of memory");
            s->run_means = grown;
        }
        if (json_expect(r, '[')) return -1;
        for (c = 0; c < 3; ++c)
            if ((c && json_expect(r, ',')) || json_read_number(r, &s->run_means[3 * s->run_means_count + c]))
                return -1;
        if (json_expect(r, ']')) return -1;
        s->run_means_count++;
        if (json_peek(r) != ',') break;
        r->pos++;
    }
    return json_expect(r, ']');
}

static int read_sidecar(const char *path, sidecar *s, rerror *e)
{
    json_reader r;
    memset(s, 0, sizeof *s);
    s->runs = s->width = s->height = s->version = -1;
    if (json_reader_open(&r, path, e)) return -1;
    if (json_expect(&r, '{')) goto fail;
    if (json_peek(&r) != '}')
        for (;;) {
            char key[64];
            int status;
            if (json_read_string(&r, key, sizeof key) || json_expect(&r, ':')) goto fail;
            if (!strcmp(key, "format"))
                status = json_read_string(&r, s->format, sizeof s->format);
            else if (!strcmp(key, "version"))
                status = read_integer(&r, key, 1, &s->version);
            else if (!strcmp(key, "runs"))
                status = read_integer(&r, key, 1, &s->runs);
            else if (!strcmp(key, "width"))
                status = read_integer(&r, key, 1, &s->width);
            else if (!strcmp(key, "height"))
                status = read_integer(&r, key, 1, &s->height);
            else if (!strcmp(key, "mean"))
                status = json_read_string(&r, s->mean, sizeof s->mean);
            else if (!strcmp(key, "var"))
                status = json_read_string(&r, s->var, sizeof s->var);
            else if (!strcmp(key, "run_means"))
                status = read_run_means(&r, s);
            else
                status = json_skip_value(&r); /* unknown keys are allowed (forward compatible) */
            if (status) goto fail;
            if (json_peek(&r) != ',') break;
            r.pos++;
        }
    if (json_expect(&r, '}') || json_expect_end(&r)) goto fail;
    if (strcmp(s->format, "restir-moments") != 0) {
        rerror_at(e, path, 0, "\"format\" must be \"restir-moments\"");
        goto fail;
    }
    if (s->version != 1) {
        rerror_at(e, path, 0, "unsupported moments version (expected 1)");
        goto fail;
    }
    if (s->runs < 1 || s->width < 1 || s->height < 1 || !s->mean[0] || !s->var[0]) {
        rerror_at(e, path, 0, "missing one of \"runs\", \"width\", \"height\", \"mean\", \"var\"");
        goto fail;
    }
    if (s->run_means && s->run_means_count != s->runs) {
        rerror_at(e, path, 0, "\"run_means\" has %ld entries, \"runs\" is %ld", s->run_means_count, s->runs);
        goto fail;
    }
    json_reader_close(&r);
    return 0;
fail:
    json_reader_close(&r);
    free(s->run_means);
    s->run_means = NULL;
    return -1;
}

/* `name` relative to the directory of `json_path` (absolute names stay as they are). */
static int sibling_path(char *out, size_t size, const char *json_path, const char *name)
{
    const char *slash = strrchr(json_path, '/');
    int n;
    if (name[0] == '/' || !slash)
        n = snprintf(out, size, "%s", name);
    else
        n = snprintf(out, size, "%.*s/%s", (int)(slash - json_path), json_path, name);
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && !strcmp(s + n - k, suffix);
}

static int check_image(const char *json_path, const char *path, const image *img, const sidecar *s, int is_var,
                       rerror *e)
{
    size_t i, n;
    if (img->width != s->width || img->height != s->height)
        return rerror_at(e, path, 0, "image is %d x %d, %s says %ld x %ld", img->width, img->height, json_path,
                         s->width, s->height);
    n = (size_t)img->width * (size_t)img->height * 3;
    for (i = 0; i < n; ++i)
        if (!isfinite(img->px[i]) || (is_var && img->px[i] < 0.0f))
            return rerror_at(e, path, 0, "pixel (%ld, %ld) channel %d is %s", (long)(i / 3) % img->width,
                             (long)(i / 3) / img->width, (int)(i % 3),
                             isfinite(img->px[i]) ? "a negative variance" : "not finite");
    return 0;
}

int moments_read(const char *path, moments_file *out, rerror *e)
{
    char json_path[4096], mean_path[4096], var_path[4096];
    sidecar s;
    memset(out, 0, sizeof *out);
    if (snprintf(json_path, sizeof json_path, has_suffix(path, ".moments.json") ? "%s" : "%s.moments.json", path) >=
        (int)sizeof json_path)
        return rerror_set(e, "%s: path too long", path);
    if (read_sidecar(json_path, &s, e)) return -1;
    if (sibling_path(mean_path, sizeof mean_path, json_path, s.mean) ||
        sibling_path(var_path, sizeof var_path, json_path, s.var)) {
        free(s.run_means);
        return rerror_at(e, json_path, 0, "image path too long");
    }
    if (pfm_read(mean_path, &out->mean, NULL, e) || check_image(json_path, mean_path, &out->mean, &s, 0, e) ||
        pfm_read(var_path, &out->var, NULL, e) || check_image(json_path, var_path, &out->var, &s, 1, e)) {
        free(s.run_means);
        moments_file_free(out);
        return -1;
    }
    out->runs = s.runs;
    out->run_means = s.run_means;
    return 0;
}

void moments_file_free(moments_file *f)
{
    image_free(&f->mean);
    image_free(&f->var);
    free(f->run_means);
    f->run_means = NULL;
    f->runs = 0;
}
