/* Per-pixel moments of K runs and the moments file set (moments.h,
 * docs/statistics.md "Moments files"). */
#include "restir/metrics/moments.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/json_text.h"
#include "restir/core/image_io.h"
#include "restir/metrics/output_set.h"

const int moments_default_block_sizes[4] = {4, 8, 16, 32};

long moments_block_count(int width, int height, int b)
{
    return (long)((width + b - 1) / b) * (long)((height + b - 1) / b);
}

void moments_block_means(const image *img, int b, double *out)
{
    int blocks_x = (img->width + b - 1) / b, blocks_y = (img->height + b - 1) / b, x, y, c, bx, by;
    memset(out, 0, (size_t)blocks_x * (size_t)blocks_y * 3 * sizeof *out);
    for (y = 0; y < img->height; ++y)
        for (x = 0; x < img->width; ++x) {
            const float *p = image_pixel(img, x, y);
            double *o = out + 3 * ((long)(y / b) * blocks_x + x / b);
            for (c = 0; c < 3; ++c) o[c] += p[c];
        }
    for (by = 0; by < blocks_y; ++by)
        for (bx = 0; bx < blocks_x; ++bx) {
            int w = img->width - bx * b < b ? img->width - bx * b : b;
            int h = img->height - by * b < b ? img->height - by * b : b;
            double *o = out + 3 * ((long)by * blocks_x + bx);
            for (c = 0; c < 3; ++c) o[c] /= (double)w * (double)h;
        }
}

int moments_set_block_sizes(moments *m, const int *sizes, int count, rerror *e)
{
    int i, j;
    if (m->runs > 0) return rerror_set(e, "moments: block sizes must be set before the first run");
    if (count < 0 || count > MOMENTS_MAX_BLOCK_SIZES)
        return rerror_set(e, "moments: %d block sizes (at most %d)", count, MOMENTS_MAX_BLOCK_SIZES);
    for (i = 0; i < count; ++i) {
        if (sizes[i] < 1 || sizes[i] > 4096) return rerror_set(e, "moments: block size %d is not 1..4096", sizes[i]);
        for (j = 0; j < i; ++j)
            if (sizes[j] == sizes[i]) return rerror_set(e, "moments: block size %d given twice", sizes[i]);
    }
    for (i = 0; i < count; ++i) m->block_sizes[i] = sizes[i];
    m->block_size_count = count;
    return 0;
}

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
    int i;
    free(m->run_means);
    for (i = 0; i < m->block_size_count; ++i) free(m->block_means[i]);
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
        int j;
        double *grown = realloc(m->run_means, (size_t)cap * 3 * sizeof *grown);
        if (!grown) return rerror_set(e, "out of memory (per-run means)");
        m->run_means = grown;
        for (j = 0; j < m->block_size_count; ++j) {
            long blocks = moments_block_count(m->width, m->height, m->block_sizes[j]);
            grown = realloc(m->block_means[j], (size_t)cap * (size_t)blocks * 3 * sizeof *grown);
            if (!grown) return rerror_set(e, "out of memory (per-run block means)");
            m->block_means[j] = grown;
        }
        m->run_capacity = cap;
    }
    for (i = 0; i < (size_t)m->block_size_count; ++i) {
        long blocks = moments_block_count(m->width, m->height, m->block_sizes[i]);
        moments_block_means(run, m->block_sizes[i], m->block_means[i] + (size_t)m->runs * (size_t)blocks * 3);
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

static int write_set(const char *prefix, const image *mean, const image *var, long runs, const double *run_means,
                     const moments *blocks, const moments_meta *meta, rerror *e);

int moments_write(const char *prefix, const moments *m, rerror *e)
{
    return moments_write_meta(prefix, m, NULL, e);
}

int moments_write_meta(const char *prefix, const moments *m, const moments_meta *meta, rerror *e)
{
    image mean, var;
    int status;
    if (moments_images(m, &mean, &var, e)) return -1;
    status = write_set(prefix, &mean, &var, m->runs, m->run_means, m->block_size_count > 0 ? m : NULL, meta, e);
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

/* The per-run block means file (docs/statistics.md, "Per-run block means"): the magic
 * MOMENTS_BLOCKS_MAGIC, then IEEE-754 binary64 little-endian values, per block size in
 * the sidecar's order, per run, per block row (top first), block column, channel. */
#define MOMENTS_BLOCKS_MAGIC "RSBLOCK1"

static void put_f64le(FILE *fp, double v)
{
    unsigned char b[8];
    uint64_t u;
    int i;
    memcpy(&u, &v, sizeof u);
    for (i = 0; i < 8; ++i) b[i] = (unsigned char)(u >> (8 * i));
    fwrite(b, 1, 8, fp);
}

static int write_blocks(const char *staged, const moments *m, rerror *e)
{
    atomic_file f;
    int j;
    size_t i;
    if (atomic_file_open(&f, staged, e)) return -1;
    fwrite(MOMENTS_BLOCKS_MAGIC, 1, 8, f.fp);
    for (j = 0; j < m->block_size_count; ++j) {
        size_t n = (size_t)m->runs * (size_t)moments_block_count(m->width, m->height, m->block_sizes[j]) * 3;
        for (i = 0; i < n; ++i) put_f64le(f.fp, m->block_means[j][i]);
    }
    return atomic_file_commit(&f, e);
}

static void write_meta(FILE *fp, const char *blocks_name, const moments *blocks, const moments_meta *meta)
{
    int j;
    if (meta && meta->method) {
        fprintf(fp, ",\n  \"method\": ");
        json_put_string(fp, meta->method);
    }
    if (meta && meta->correlation != MOMENTS_CORRELATION_UNKNOWN)
        fprintf(fp, ",\n  \"correlated_pixels\": %s", meta->correlation == MOMENTS_CORRELATED ? "true" : "false");
    if (meta && meta->write_config) {
        fprintf(fp, ",\n  \"renderer\": ");
        meta->write_config(fp, meta->ctx, "  ");
    }
    if (blocks) {
        fprintf(fp, ",\n  \"block_sizes\": [");
        for (j = 0; j < blocks->block_size_count; ++j) fprintf(fp, "%s%d", j ? ", " : "", blocks->block_sizes[j]);
        fprintf(fp, "],\n  \"block_means\": ");
        json_put_string(fp, blocks_name);
    }
}

static int write_sidecar(const char *staged, const char *mean_name, const char *var_name, const image *mean,
                         long runs, const double *run_means, const char *blocks_name, const moments *blocks,
                         const moments_meta *meta, rerror *e)
{
    atomic_file f;
    long k;
    if (atomic_file_open(&f, staged, e)) return -1;
    fprintf(f.fp, "{\n  \"format\": \"restir-moments\",\n  \"version\": 1,\n  \"runs\": %ld,\n", runs);
    fprintf(f.fp, "  \"width\": %d,\n  \"height\": %d,\n  \"mean\": ", mean->width, mean->height);
    json_put_string(f.fp, mean_name);
    fprintf(f.fp, ",\n  \"var\": ");
    json_put_string(f.fp, var_name);
    write_meta(f.fp, blocks_name, blocks, meta);
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

static int write_set(const char *prefix, const image *mean, const image *var, long runs, const double *run_means,
                     const moments *blocks, const moments_meta *meta, rerror *e)
{
    char mean_path[4096], var_path[4096], json_path[4096], blocks_path[4096];
    const char *staged;
    output_set out;
    if (runs < 1) return rerror_set(e, "%s: moments need at least one run", prefix);
    if (mean->width != var->width || mean->height != var->height)
        return rerror_set(e, "%s: mean and variance images differ in size", prefix);
    const char *ext = meta && meta->image_ext ? meta->image_ext : "pfm";
    if (snprintf(mean_path, sizeof mean_path, "%s.mean.%s", prefix, ext) >= (int)sizeof mean_path ||
        snprintf(var_path, sizeof var_path, "%s.var.%s", prefix, ext) >= (int)sizeof var_path ||
        snprintf(json_path, sizeof json_path, "%s.moments.json", prefix) >= (int)sizeof json_path ||
        snprintf(blocks_path, sizeof blocks_path, "%s.blocks.bin", prefix) >= (int)sizeof blocks_path)
        return rerror_set(e, "%s: path too long", prefix);
    output_set_init(&out);
    if (!(staged = output_set_stage(&out, mean_path, e)) || image_write_as(staged, mean_path, mean, e)) goto fail;
    if (!(staged = output_set_stage(&out, var_path, e)) || image_write_as(staged, var_path, var, e)) goto fail;
    if (blocks && (!(staged = output_set_stage(&out, blocks_path, e)) || write_blocks(staged, blocks, e))) goto fail;
    if (!(staged = output_set_stage(&out, json_path, e)) ||
        write_sidecar(staged, base_name(mean_path), base_name(var_path), mean, runs, run_means,
                      base_name(blocks_path), blocks, meta, e))
        goto fail;
    return output_set_commit(&out, e);
fail:
    output_set_abort(&out);
    return -1;
}

/* ---- reading ---- */

typedef struct {
    long runs, width, height, version;
    char format[64], mean[4096], var[4096], blocks[4096], method[64];
    double *run_means;
    long run_means_count;
    int block_size_count;
    int block_sizes[MOMENTS_MAX_BLOCK_SIZES];
    enum moments_correlation correlation;
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

static int read_block_sizes(json_reader *r, sidecar *s)
{
    if (json_expect(r, '[')) return -1;
    if (json_peek(r) == ']') return json_expect(r, ']');
    for (;;) {
        long b;
        int j;
        if (s->block_size_count == MOMENTS_MAX_BLOCK_SIZES)
            return rerror_at(r->e, r->path, r->line, "\"block_sizes\" has more than %d entries",
                             MOMENTS_MAX_BLOCK_SIZES);
        if (read_integer(r, "block_sizes", 1, &b)) return -1;
        if (b > 4096) return rerror_at(r->e, r->path, r->line, "block size %ld is larger than 4096", b);
        for (j = 0; j < s->block_size_count; ++j)
            if (s->block_sizes[j] == b) return rerror_at(r->e, r->path, r->line, "block size %ld given twice", b);
        s->block_sizes[s->block_size_count++] = (int)b;
        if (json_peek(r) != ',') break;
        r->pos++;
    }
    return json_expect(r, ']');
}

static int read_bool(json_reader *r, const char *key, enum moments_correlation *out)
{
    json_peek(r); /* skips white space */
    if (!strncmp(r->text + r->pos, "true", 4)) {
        r->pos += 4;
        *out = MOMENTS_CORRELATED;
        return 0;
    }
    if (!strncmp(r->text + r->pos, "false", 5)) {
        r->pos += 5;
        *out = MOMENTS_INDEPENDENT;
        return 0;
    }
    return rerror_at(r->e, r->path, r->line, "\"%s\" must be true or false", key);
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
            else if (!strcmp(key, "block_sizes"))
                status = read_block_sizes(&r, s);
            else if (!strcmp(key, "block_means"))
                status = json_read_string(&r, s->blocks, sizeof s->blocks);
            else if (!strcmp(key, "correlated_pixels"))
                status = read_bool(&r, key, &s->correlation);
            else if (!strcmp(key, "method"))
                status = json_read_string(&r, s->method, sizeof s->method);
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
    if ((s->block_size_count > 0) != (s->blocks[0] != '\0')) {
        rerror_at(e, path, 0, "\"block_sizes\" and \"block_means\" go together");
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

static double get_f64le(const unsigned char *b)
{
    uint64_t u = 0;
    double v;
    int i;
    for (i = 7; i >= 0; --i) u = (u << 8) | b[i];
    memcpy(&v, &u, sizeof v);
    return v;
}

/* PREFIX.blocks.bin (see write_blocks): the exact size the sidecar implies, finite values. */
static int read_blocks(const char *path, const sidecar *s, moments_file *out, rerror *e)
{
    FILE *fp = fopen(path, "rb");
    unsigned char magic[8], b[8];
    long expected = 8, size;
    int j;
    for (j = 0; j < s->block_size_count; ++j)
        expected += 8L * 3 * s->runs * moments_block_count((int)s->width, (int)s->height, s->block_sizes[j]);
    if (!fp) return rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
    if (fseek(fp, 0, SEEK_END) != 0 || (size = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) != 0) {
        fclose(fp);
        return rerror_at(e, path, 0, "cannot read: %s", strerror(errno));
    }
    if (fread(magic, 1, 8, fp) != 8 || memcmp(magic, MOMENTS_BLOCKS_MAGIC, 8) != 0) {
        fclose(fp);
        return rerror_at(e, path, 0, "not a per-run block means file (no \"" MOMENTS_BLOCKS_MAGIC "\" at the start)");
    }
    if (size != expected) {
        fclose(fp);
        return rerror_at(e, path, 0, "%ld bytes, but %ld runs of %d x %d pixels at the given block sizes need %ld",
                         size, s->runs, (int)s->width, (int)s->height, expected);
    }
    for (j = 0; j < s->block_size_count; ++j) {
        size_t i, n = (size_t)s->runs * (size_t)moments_block_count((int)s->width, (int)s->height, s->block_sizes[j]) * 3;
        double *v = rmalloc(n, sizeof *v, e);
        out->block_means[j] = v;
        out->block_sizes[j] = s->block_sizes[j];
        out->block_size_count = j + 1;
        if (!v) break;
        for (i = 0; i < n; ++i) {
            if (fread(b, 1, 8, fp) != 8) {
                fclose(fp);
                return rerror_at(e, path, 0, "read failed");
            }
            v[i] = get_f64le(b);
            if (!isfinite(v[i])) {
                fclose(fp);
                return rerror_at(e, path, 0, "block size %d: value %zu is not finite", s->block_sizes[j], i);
            }
        }
    }
    fclose(fp);
    return j < s->block_size_count ? -1 : 0;
}

int moments_read(const char *path, moments_file *out, rerror *e)
{
    char json_path[4096], mean_path[4096], var_path[4096], blocks_path[4096];
    sidecar s;
    memset(out, 0, sizeof *out);
    if (snprintf(json_path, sizeof json_path, has_suffix(path, ".moments.json") ? "%s" : "%s.moments.json", path) >=
        (int)sizeof json_path)
        return rerror_set(e, "%s: path too long", path);
    if (read_sidecar(json_path, &s, e)) return -1;
    if (sibling_path(mean_path, sizeof mean_path, json_path, s.mean) ||
        sibling_path(var_path, sizeof var_path, json_path, s.var) ||
        sibling_path(blocks_path, sizeof blocks_path, json_path, s.blocks)) {
        free(s.run_means);
        return rerror_at(e, json_path, 0, "image path too long");
    }
    if (image_read(mean_path, &out->mean, NULL, e) || check_image(json_path, mean_path, &out->mean, &s, 0, e) ||
        image_read(var_path, &out->var, NULL, e) || check_image(json_path, var_path, &out->var, &s, 1, e) ||
        (s.block_size_count > 0 && read_blocks(blocks_path, &s, out, e))) {
        free(s.run_means);
        moments_file_free(out);
        return -1;
    }
    out->runs = s.runs;
    out->run_means = s.run_means;
    out->correlation = s.correlation;
    memcpy(out->method, s.method, sizeof out->method);
    return 0;
}

void moments_file_free(moments_file *f)
{
    int j;
    for (j = 0; j < f->block_size_count; ++j) free(f->block_means[j]);
    f->block_size_count = 0;
    image_free(&f->mean);
    image_free(&f->var);
    free(f->run_means);
    f->run_means = NULL;
    f->runs = 0;
}
