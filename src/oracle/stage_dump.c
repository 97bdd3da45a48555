/* Per-stage dumps, the manifest and restart from a dump (include/restir/oracle/stage_dump.h,
 * docs/oracle.md, docs/formats.md "Stage dumps"). */
#include "restir/oracle/stage_dump.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/atomic_file.h"
#include "restir/core/checksum.h"
#include "restir/core/json_text.h"
#include "restir/core/le_bytes.h"
#include "restir/frame/options.h"
#include "restir/oracle/region_input.h"

void stage_dump_path(char *buf, size_t size, const char *dir, uint32_t frame, const char *name, const char *ext)
{
    snprintf(buf, size, "%s/frame_%04u/%s.%s", dir, (unsigned)frame, name, ext);
}

static int make_dir(const char *dir, rerror *e)
{
    struct stat st;
    if (stat(dir, &st) == 0) return S_ISDIR(st.st_mode) ? 0 : rerror_set(e, "%s: not a directory", dir);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return rerror_set(e, "%s: cannot create directory: %s", dir, strerror(errno));
    return 0;
}

static int valid_name(const char *s)
{
    size_t i, n = strlen(s);
    if (n == 0 || n >= STAGE_NAME_SIZE) return 0;
    for (i = 0; i < n; ++i)
        if (!((s[i] >= 'a' && s[i] <= 'z') || (s[i] >= '0' && s[i] <= '9') || s[i] == '-' || s[i] == '_')) return 0;
    return 1;
}

int stage_io_set_stages(stage_io *io, const char *list, rerror *e)
{
    const char *p = list;
    io->n_want = 0;
    while (*p) {
        const char *comma = strchr(p, ',');
        size_t n = comma ? (size_t)(comma - p) : strlen(p);
        char name[64];
        if (n >= sizeof name || io->n_want >= STAGE_MAX)
            return rerror_set(e, "--dump-stages: too long or too many names in '%s'", list);
        memcpy(name, p, n);
        name[n] = '\0';
        if (!valid_name(name))
            return rerror_set(e, "--dump-stages: '%s' is not a stage name (lower-case letters, digits, '-', '_'; "
                                 "at most %d characters)", name, STAGE_NAME_SIZE - 1);
        strcpy(io->want[io->n_want++], name);
        p += n;
        if (*p == ',') ++p;
    }
    if (io->n_want == 0) return rerror_set(e, "--dump-stages: empty list");
    return 0;
}

int stage_region_parse(const char *text, stage_region *r, rerror *e)
{
    long v[4];
    int n = 0;
    const char *p = text;
    while (n < 4) {
        char *end;
        v[n] = strtol(p, &end, 10);
        if (end == p || v[n] < 0 || v[n] > 65536) break;
        ++n;
        p = end;
        if (n < 4 && *p++ != ',') break;
    }
    if (n != 4 || *p || v[2] == 0 || v[3] == 0)
        return rerror_set(e, "--dump-region: '%s' is not X,Y,W,H (pixels; W, H > 0)", text);
    r->x = v[0];
    r->y = v[1];
    r->width = v[2];
    r->height = v[3];
    return 0;
}

/* A region dump cannot restart a run: the pixels outside it have no input (docs/oracle.md). */
static int refuse_region_restart(const stage_io *io, const stage_manifest *m, rerror *e)
{
    if (!m->region.width) return 0;
    return rerror_set(e, "--from-dump %s: a region dump (--dump-region %ld,%ld,%ld,%ld) cannot restart a run: the "
                         "stages after --from-stage read every pixel's reservoir and its neighbours'; dump the whole "
                         "image to restart",
                      io->from_dir, m->region.x, m->region.y, m->region.width, m->region.height);
}

int stage_io_begin(stage_io *io, int first, int last, rerror *e)
{
    io->first_frame = first;
    io->last_frame = last;
    io->n_order = io->frames_done = io->failed = io->restarted = 0;
    io->rc_missing = io->rc_nonempty = 0;
    if (io->from_dir && !valid_name(io->from_stage))
        return rerror_set(e, "--from-stage: '%s' is not a stage name", io->from_stage);
    if (io->from_dir) {
        stage_manifest m;
        int i;
        if (stage_manifest_read(io->from_dir, &m, e) || refuse_region_restart(io, &m, e)) return -1;
        for (i = 0; i < m.n_order; ++i) strcpy(io->from_order[i], m.order[i]);
        io->n_from_order = m.n_order;
        /* written by restir replay / inspect for a region dump (region_input.h) */
        io->in_dumped = m.in_dumped;
        io->in_check = m.in_check;
        strcpy(io->in_stage, m.in_stage);
        io->in_history = (int)m.in_history;
    }
    if (io->dump_dir) {
        struct stat st;
        io->created_dir = stat(io->dump_dir, &st) != 0;
        if (make_dir(io->dump_dir, e)) return -1;
    }
    return 0;
}

/* Index of name in the restart dump's stage order, -1 if absent. */
static int from_index(const stage_io *io, const char *name)
{
    int i;
    for (i = 0; i < io->n_from_order; ++i)
        if (!strcmp(io->from_order[i], name)) return i;
    return -1;
}

static int wanted(const stage_io *io, const char *name)
{
    int i;
    if (!io->dump_dir) return 0;
    if (io->n_want == 0) return 1;
    for (i = 0; i < io->n_want; ++i)
        if (!strcmp(io->want[i], name)) return 1;
    return 0;
}

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    fclose(f);
    return 1;
}

int stage_io_skips(const stage_io *io, const char *name)
{
    char path[4200];
    int n, s;
    if (!io || !io->from_dir) return 0;
    n = from_index(io, name);
    s = from_index(io, io->from_stage);
    if (n < 0 || s < 0 || n > s) return 0;
    if (n == s) return 1;
    /* an earlier stage: read from the dump if it has the file; else computed only if this
     * run dumps it (nothing after S reads it) */
    stage_dump_path(path, sizeof path, io->from_dir, io->frame, name, "resv");
    return file_exists(path) || !wanted(io, name);
}

void stage_io_frame_begin(stage_io *io, uint32_t frame)
{
    char dir[4200];
    io->frame = frame;
    if (!io->dump_dir || io->failed) return;
    snprintf(dir, sizeof dir, "%s/frame_%04u", io->dump_dir, (unsigned)frame);
    if (make_dir(dir, &io->err)) io->failed = 1;
}


static void note_order(stage_io *io, const char *name)
{
    int i;
    if (io->frames_done > 0) return;
    for (i = 0; i < io->n_order; ++i)
        if (!strcmp(io->order[i], name)) return;
    if (io->n_order < STAGE_MAX && strlen(name) < STAGE_NAME_SIZE) strcpy(io->order[io->n_order++], name);
}

/* A read reservoir must be usable as input: W, wsum and c finite (the reader lets +inf
 * through, a format check only; an infinite W would poison every later stage). Counts the
 * non-empty records without usable reconnection data: rc_k = 0, or rc_k set with a zero
 * Jacobian source term (docs/formats.md). A GPU build that leaves these fields 0 makes
 * every hybrid or reconnection shift of its samples fail (the offset path reconnects where
 * the sample does not: rc_offset_reconnects), so spatial reuse would stop without a word;
 * stage_io_frame_end refuses such a dump once it knows the shift. */
static int restart_records_check(stage_io *io, const char *path, const reservoir *in, size_t n)
{
    size_t i;
    long missing = 0, nonempty = 0;
    for (i = 0; i < n; ++i) {
        const path_sample *s = &in[i].y;
        if (!isfinite((double)in[i].W) || !isfinite((double)in[i].wsum) || !isfinite((double)in[i].confidence))
            return rerror_at(&io->err, path, 0, "record %lu (pixel %lu,%lu): W, wsum and confidence must be finite to "
                             "restart from them (W %g, wsum %g, c %g)", (unsigned long)i, (unsigned long)(i % (size_t)io->width),
                             (unsigned long)(i / (size_t)io->width), (double)in[i].W, (double)in[i].wsum,
                             (double)in[i].confidence);
        if (!path_sample_is_valid(s)) continue;
        nonempty++;
        if (s->rc_k == PATH_RC_NONE || !(s->rc_pdf_prev > 0) || !(s->rc_geom > 0) || !(s->rc_pdf > 0)) missing++;
    }
    if (nonempty > 0 && (double)missing / (double)nonempty > (io->rc_nonempty ? (double)io->rc_missing / (double)io->rc_nonempty : -1)) {
        io->rc_missing = missing;
        io->rc_nonempty = nonempty;
        snprintf(io->rc_missing_path, sizeof io->rc_missing_path, "%s", path);
    }
    return 0;
}

/* Refuses a restart whose input lacks the reconnection data the shift needs: more than
 * half of its non-empty samples (our own dumps: at most 21% on every shipped scene, most 0%;
 * hall-glossy-far with its mirror-like floor is the 21%) with rc_k = 0 or a zero Jacobian
 * source term, under a shift that reconnects. */
static int restart_rc_verdict(const stage_io *io, const restir_options *o, rerror *e)
{
    if (!io->from_dir || o->shift == RESTIR_SHIFT_REPLAY || io->rc_nonempty < 16 ||
        2 * io->rc_missing <= io->rc_nonempty)
        return 0;
    return rerror_at(e, io->rc_missing_path, 0,
                     "%ld of %ld non-empty records have no usable reconnection data (rc_k = 0, or rc_pdf_prev, rc_geom "
                     "or rc_pdf = 0); with --shift %s every shift of such a sample fails (the offset path reconnects "
                     "where the sample does not), which would silently stop spatial reuse. Fill the reconnection "
                     "fields (docs/formats.md \"Record\") or restart with --shift replay",
                     io->rc_missing, io->rc_nonempty, restir_shift_names[o->shift]);
}

/* Replaces rs by the dumped output of stage `name` of the current frame. */
static int restart_load(stage_io *io, const char *name, reservoir *rs, int width, int height)
{
    char path[4200];
    reservoir_dump_info info;
    reservoir *in;
    stage_dump_path(path, sizeof path, io->from_dir, io->frame, name, "resv");
    if (reservoir_dump_read(path, &in, &info, &io->err)) return -1;
    if (info.width != (uint32_t)width || info.height != (uint32_t)height || info.frame != io->frame ||
        strcmp(info.tag, name)) {
        free(in);
        return rerror_at(&io->err, path, 0, "is %ux%u, frame %u, stage '%s'; the run needs %dx%d, frame %u, stage '%s'",
                         info.width, info.height, info.frame, info.tag, width, height, (unsigned)io->frame, name);
    }
    memcpy(rs, in, (size_t)width * (size_t)height * sizeof *rs);
    if (io->pss_rows) {
        reservoir_buffer_keep_pss(rs, (size_t)width * (size_t)height, 1); /* before in's rows are freed */
    } else if (info.flags & RESERVOIR_DUMP_FLAG_PSS) {
        free(in);
        return rerror_at(&io->err, path, 0, "holds primary-sample vectors, the run has no rows for them");
    }
    if (restart_records_check(io, path, in, (size_t)width * (size_t)height)) {
        free(in);
        return -1;
    }
    free(in);
    io->restarted++;
    return 0;
}

/* The region must lie inside the image (known from the first stage). --dump-halo grows it
 * once, clipped to the image; the rectangle asked for is kept as the core. */
static int region_check(stage_io *io, int width, int height)
{
    stage_region *r = &io->region;
    if (!r->width) return 0;
    if (r->x + r->width <= width && r->y + r->height <= height) {
        if (io->halo > 0 && !io->core.width) {
            long x0 = r->x - io->halo < 0 ? 0 : r->x - io->halo, y0 = r->y - io->halo < 0 ? 0 : r->y - io->halo;
            long x1 = r->x + r->width + io->halo > width ? width : r->x + r->width + io->halo;
            long y1 = r->y + r->height + io->halo > height ? height : r->y + r->height + io->halo;
            io->core = *r;
            r->x = x0;
            r->y = y0;
            r->width = x1 - x0;
            r->height = y1 - y0;
        }
        return 0;
    }
    rerror_set(&io->err, "--dump-region %ld,%ld,%ld,%ld does not lie inside the %dx%d image", r->x, r->y, r->width,
               r->height, width, height);
    io->failed = 1;
    return -1;
}

void stage_io_reservoirs(stage_io *io, const char *name, reservoir *rs, int width, int height)
{
    char path[4200];
    reservoir_dump_info info;
    if (!io || io->failed) return;
    io->width = width;
    io->height = height;
    note_order(io, name);
    if (stage_io_skips(io, name)) {
        /* not computed: S's output comes from the dump, an earlier stage's where it has it */
        if (strcmp(name, io->from_stage)) {
            stage_dump_path(path, sizeof path, io->from_dir, io->frame, name, "resv");
            if (!file_exists(path)) return; /* not dumped either (stage_io_skips) */
        }
        if (restart_load(io, name, rs, width, height)) {
            io->failed = 1;
            return;
        }
    } else if (io->from_dir && !strcmp(name, io->from_stage) && restart_load(io, name, rs, width, height)) {
        io->failed = 1; /* S is not in the dump's manifest order: computed, then replaced */
        return;
    }
    if (!wanted(io, name)) return;
    if (region_check(io, width, height)) return;
    memset(&info, 0, sizeof info);
    info.width = (uint32_t)(io->region.width ? io->region.width : width);
    info.height = (uint32_t)(io->region.width ? io->region.height : height);
    info.frame = io->frame;
    strcpy(info.tag, name);
    stage_dump_path(path, sizeof path, io->dump_dir, io->frame, name, "resv");
    if (io->region.width) {
        /* only the rectangle's records, row-major within it (shallow copies: the samples'
           primary-sample rows stay where they are, reservoir_dump_write reads them there) */
        size_t n = (size_t)info.width * info.height, i;
        reservoir *sub = rmalloc(n, sizeof *sub, &io->err);
        if (!sub) {
            io->failed = 1;
            return;
        }
        for (i = 0; i < n; ++i)
            sub[i] = rs[(size_t)(io->region.y + (long)(i / info.width)) * (size_t)width + (size_t)io->region.x +
                        i % info.width];
        if (reservoir_dump_write(path, sub, &info, &io->err)) io->failed = 1;
        free(sub);
        return;
    }
    if (reservoir_dump_write(path, rs, &info, &io->err)) io->failed = 1;
}

void stage_io_gbuffer(stage_io *io, const gbuffer *g)
{
    char path[4200];
    if (io && !io->failed) region_input_gbuffer(io, g); /* a region dump as input: the reads' texels */
    if (!io || io->failed || !io->dump_dir) return;
    stage_dump_path(path, sizeof path, io->dump_dir, io->frame, "gbuffer", "gbuf");
    if (io->region.width) {
        gbuffer sub;
        long i, n;
        if (region_check(io, g->width, g->height)) return; /* grows the region by --dump-halo */
        n = io->region.width * io->region.height;
        sub.width = (int)io->region.width;
        sub.height = (int)io->region.height;
        sub.texels = rmalloc((size_t)n, sizeof *sub.texels, &io->err);
        if (!sub.texels) {
            io->failed = 1;
            return;
        }
        for (i = 0; i < n; ++i)
            sub.texels[i] = g->texels[(io->region.y + i / io->region.width) * g->width + io->region.x + i % io->region.width];
        if (gbuffer_dump_write(path, &sub, io->frame, &io->err)) io->failed = 1;
        free(sub.texels);
        return;
    }
    if (gbuffer_dump_write(path, g, io->frame, &io->err)) io->failed = 1;
}

/* ---- manifest ---- */

/* CRC-32 and size of a file (the scene file; the OBJ/MTL it names are not hashed). */
static int file_crc(const char *path, uint32_t *crc, long *bytes)
{
    unsigned char buf[65536];
    size_t n;
    FILE *fp = fopen(path, "rb");
    *crc = 0;
    *bytes = 0;
    if (!fp) return -1;
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0) {
        *crc = crc32_update(*crc, buf, n);
        *bytes += (long)n;
    }
    fclose(fp);
    return 0;
}

void stage_names_put(FILE *fp, char names[][STAGE_NAME_SIZE], int n)
{
    int i;
    fputc('[', fp);
    for (i = 0; i < n; ++i) {
        if (i) fputs(", ", fp);
        json_put_string(fp, names[i]);
    }
    fputc(']', fp);
}

static int write_manifest(stage_io *io, const restir_options *o, rerror *e)
{
    char path[4200];
    atomic_file f;
    uint32_t crc = 0;
    long bytes = 0;
    int have_scene = io->scene_path && file_crc(io->scene_path, &crc, &bytes) == 0, i;
    snprintf(path, sizeof path, "%s/manifest.json", io->dump_dir);
    if (atomic_file_open(&f, path, e)) return -1;
    fprintf(f.fp, "{\n  \"format\": \"restir-stage-dump\",\n  \"format_version\": %u,\n", STAGE_DUMP_FORMAT_VERSION);
    fprintf(f.fp, "  \"reservoir_dump_version\": %u,\n  \"gbuffer_dump_version\": %u,\n  \"rng_spec_version\": %u,\n",
            RESERVOIR_DUMP_VERSION, GBUFFER_DUMP_VERSION, RNG_SPEC_VERSION);
    fprintf(f.fp, "  \"real_bits\": %u,\n  \"scene\": {\"path\": ", (unsigned)(8 * sizeof(real)));
    json_put_string(f.fp, io->scene_path ? io->scene_path : "");
    if (have_scene) fprintf(f.fp, ", \"crc32\": \"%08x\", \"bytes\": %ld},\n", (unsigned)crc, bytes);
    else fprintf(f.fp, ", \"crc32\": null, \"bytes\": null},\n");
    fprintf(f.fp, "  \"image\": {\"width\": %d, \"height\": %d},\n", io->width, io->height);
    fprintf(f.fp, "  \"seed\": %u,\n  \"frames\": {\"first\": %d, \"last\": %d, \"written\": %d},\n", o->seed,
            io->first_frame, io->last_frame, io->frames_done);
    fprintf(f.fp, "  \"command_line\": [");
    for (i = 0; io->argv && i < io->argc; ++i) {
        if (i) fputs(", ", f.fp);
        json_put_string(f.fp, io->argv[i]);
    }
    fprintf(f.fp, "],\n");
    fprintf(f.fp, "  \"stage_order\": ");
    stage_names_put(f.fp, io->order, io->n_order);
    fprintf(f.fp, ",\n  \"dumped_stages\": ");
    if (io->n_want) stage_names_put(f.fp, io->want, io->n_want);
    else stage_names_put(f.fp, io->order, io->n_order);
    fprintf(f.fp, ",\n  \"restart\": ");
    if (io->from_dir) {
        fprintf(f.fp, "{\"from_dump\": ");
        json_put_string(f.fp, io->from_dir);
        fprintf(f.fp, ", \"from_stage\": ");
        json_put_string(f.fp, io->from_stage);
        fprintf(f.fp, "}");
    } else
        fprintf(f.fp, "null");
    if (io->region.width) /* absent: the whole image (so whole-image manifests keep their bytes) */
        fprintf(f.fp, ",\n  \"region\": {\"x\": %ld, \"y\": %ld, \"width\": %ld, \"height\": %ld}", io->region.x,
                io->region.y, io->region.width, io->region.height);
    if (io->region.width && io->core.width) /* --dump-halo: absent without one */
        fprintf(f.fp, ",\n  \"halo\": {\"pixels\": %ld, \"core\": {\"x\": %ld, \"y\": %ld, \"width\": %ld, \"height\": %ld}}",
                io->halo, io->core.x, io->core.y, io->core.width, io->core.height);
    fprintf(f.fp, ",\n  \"files\": \"frame_NNNN/STAGE.resv, frame_NNNN/gbuffer.gbuf\",\n  \"options\": ");
    restir_options_write_json(f.fp, o, "  ");
    fprintf(f.fp, "\n}\n");
    return atomic_file_commit(&f, e);
}

static int known_stage(const stage_io *io, const char *name)
{
    int i;
    for (i = 0; i < io->n_order; ++i)
        if (!strcmp(io->order[i], name)) return 1;
    return 0;
}

static void order_text(const stage_io *io, char *buf, size_t size)
{
    int i;
    buf[0] = '\0';
    for (i = 0; i < io->n_order; ++i) {
        if (i) strncat(buf, ",", size - strlen(buf) - 1);
        strncat(buf, io->order[i], size - strlen(buf) - 1);
    }
}

int stage_io_frame_end(stage_io *io, const void *restir_opts, rerror *e)
{
    char stages[STAGE_MAX * STAGE_NAME_SIZE + STAGE_MAX];
    int i;
    if (!io) return 0;
    if (io->failed) {
        *e = io->err;
        free(io->in_texels);
        io->in_texels = NULL;
        return -1;
    }
    if (region_input_check(io, (const restir_options *)restir_opts, e)) return -1;
    order_text(io, stages, sizeof stages);
    if (io->frames_done == 0) {
        for (i = 0; io->dump_dir && i < io->n_want; ++i)
            if (!known_stage(io, io->want[i]))
                return rerror_set(e, "--dump-stages: this pipeline has no stage '%s' (its stages: %s)", io->want[i],
                                  stages);
        if (io->from_dir && !known_stage(io, io->from_stage))
            return rerror_set(e, "--from-stage: this pipeline has no stage '%s' (its stages: %s)", io->from_stage,
                              stages);
    }
    if (restart_rc_verdict(io, (const restir_options *)restir_opts, e)) return -1;
    io->frames_done++;
    if (io->dump_dir) return write_manifest(io, (const restir_options *)restir_opts, e);
    return 0;
}

/* ---- reading a manifest (diff-dump, restart) ----------------------------------------- */

/* An integer of the manifest (frames, pixels, seed): refused beyond +-2^53 before the
 * conversion, which is undefined for a double outside long's range (the fuzzer's finding:
 * "y": 1e33, tests/data/fuzz/dump/crash-manifest-huge-y.json). */
static int read_long(json_reader *r, long *v)
{
    double d;
    if (json_read_number(r, &d)) return -1;
    if (!(fabs(d) <= 9007199254740992.0))
        return rerror_at(r->e, r->path, r->line, "number %g is out of range (a manifest's integers are below 2^53)", d);
    *v = (long)d;
    return 0;
}

static int read_names(json_reader *r, char names[][STAGE_NAME_SIZE], int *n)
{
    *n = 0;
    if (json_expect(r, '[')) return -1;
    if (json_peek(r) == ']') return json_expect(r, ']');
    for (;;) {
        if (*n >= STAGE_MAX) return rerror_at(r->e, r->path, r->line, "more than %d stages", STAGE_MAX);
        if (json_read_string(r, names[(*n)++], STAGE_NAME_SIZE)) return -1;
        if (json_peek(r) != ',') break;
        r->pos++;
    }
    return json_expect(r, ']');
}

static int read_order(json_reader *r, stage_manifest *m) { return read_names(r, m->order, &m->n_order); }

int stage_manifest_dumped(const stage_manifest *m, const char *name)
{
    int i;
    if (m->n_dumped < 0) return 1;
    for (i = 0; i < m->n_dumped; ++i)
        if (!strcmp(m->dumped[i], name)) return 1;
    return 0;
}

/* The options `restir inspect` needs to reproduce a pixel's initial sample: manifest key
 * -> command-line option (booleans: the flag when true). */
static const char *const inspect_options[][2] = {
    {"shift", "--shift"},         {"mis", "--mis"},
    {"candidates", "--candidates"}, {"max_depth", "--max-depth"},
    {"roughness_threshold", "--roughness-threshold"}, {"distance_threshold", "--distance-threshold"},
    {"paths", "--paths"},         {"rc_criterion", "--rc-criterion"},
    {"footprint_c", "--footprint-c"}, {"force_nee_reconnection", "--force-nee-reconnection"},
    {"russian_roulette", "--russian-roulette"}, {"jitter", "--jitter"},
    {"pairwise_confidence", "--pairwise-confidence"}};

/* One member of "options": appended to m->inspect_args if inspect needs it. */
static int read_inspect_option(json_reader *r, stage_manifest *m, const char *key)
{
    size_t i, n = strlen(m->inspect_args);
    char value[64];
    for (i = 0; i < sizeof inspect_options / sizeof inspect_options[0]; ++i)
        if (!strcmp(key, inspect_options[i][0])) break;
    if (i == sizeof inspect_options / sizeof inspect_options[0]) return json_skip_value(r);
    if (json_peek(r) == '"') {
        if (json_read_string(r, value, sizeof value)) return -1;
    } else if (json_peek(r) == 't' || json_peek(r) == 'f') {
        int on = json_peek(r) == 't';
        if (json_skip_value(r)) return -1;
        if (on) snprintf(m->inspect_args + n, sizeof m->inspect_args - n, " %s", inspect_options[i][1]);
        return 0;
    } else {
        double d;
        if (json_read_number(r, &d)) return -1;
        snprintf(value, sizeof value, "%.15g", d); /* the shortest that reads back exactly */
        if (strtod(value, NULL) != d) snprintf(value, sizeof value, "%.17g", d);
    }
    snprintf(m->inspect_args + n, sizeof m->inspect_args - n, " %s %s", inspect_options[i][1], value);
    return 0;
}

/* An object's members: frames {first, last}, scene {path}, image {width, height}, halo
 * {pixels, core}, region_input {dumped, check, stage, history} or the options inspect
 * needs; other keys skipped. */
static int read_object(json_reader *r, stage_manifest *m, const char *outer, stage_region *rect);

/* {"x", "y", "width", "height"} into *out (other keys skipped). */
static int read_rect(json_reader *r, stage_manifest *m, stage_region *out) { return read_object(r, m, "rect", out); }

static int read_object(json_reader *r, stage_manifest *m, const char *outer, stage_region *rect)
{
    if (json_expect(r, '{')) return -1;
    if (json_peek(r) == '}') return json_expect(r, '}');
    for (;;) {
        char key[64];
        int status;
        if (json_read_string(r, key, sizeof key) || json_expect(r, ':')) return -1;
        if (!strcmp(outer, "frames") && !strcmp(key, "first")) status = read_long(r, &m->first);
        else if (!strcmp(outer, "frames") && !strcmp(key, "last")) status = read_long(r, &m->last);
        else if (!strcmp(outer, "frames") && !strcmp(key, "written")) status = read_long(r, &m->written);
        else if (!strcmp(outer, "rect") && !strcmp(key, "x")) status = read_long(r, &rect->x);
        else if (!strcmp(outer, "rect") && !strcmp(key, "y")) status = read_long(r, &rect->y);
        else if (!strcmp(outer, "rect") && !strcmp(key, "width")) status = read_long(r, &rect->width);
        else if (!strcmp(outer, "rect") && !strcmp(key, "height")) status = read_long(r, &rect->height);
        else if (!strcmp(outer, "scene") && !strcmp(key, "path") && json_peek(r) == '"')
            status = json_read_string(r, m->scene, sizeof m->scene);
        else if (!strcmp(outer, "image") && !strcmp(key, "width")) status = read_long(r, &m->width);
        else if (!strcmp(outer, "image") && !strcmp(key, "height")) status = read_long(r, &m->height);
        else if (!strcmp(outer, "options")) status = read_inspect_option(r, m, key);
        else if (!strcmp(outer, "halo") && !strcmp(key, "pixels")) status = read_long(r, &m->halo);
        else if (!strcmp(outer, "halo") && !strcmp(key, "core")) status = read_rect(r, m, &m->core);
        else if (!strcmp(outer, "region_input") && !strcmp(key, "dumped")) status = read_rect(r, m, &m->in_dumped);
        else if (!strcmp(outer, "region_input") && !strcmp(key, "check")) status = read_rect(r, m, &m->in_check);
        else if (!strcmp(outer, "region_input") && !strcmp(key, "stage"))
            status = json_read_string(r, m->in_stage, sizeof m->in_stage);
        else if (!strcmp(outer, "region_input") && !strcmp(key, "history")) status = read_long(r, &m->in_history);
        else status = json_skip_value(r);
        if (status) return -1;
        if (json_peek(r) != ',') break;
        r->pos++;
    }
    return json_expect(r, '}');
}

int stage_manifest_read(const char *dir, stage_manifest *m, rerror *e)
{
    char path[4200], format[64] = "";
    json_reader r;
    memset(m, 0, sizeof *m);
    m->first = m->last = m->written = -1;
    m->n_dumped = -1;
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    if (json_reader_open(&r, path, e)) return -1;
    if (json_expect(&r, '{')) goto fail;
    for (;;) {
        char key[64];
        int status;
        if (json_read_string(&r, key, sizeof key) || json_expect(&r, ':')) goto fail;
        if (!strcmp(key, "format")) status = json_read_string(&r, format, sizeof format);
        else if (!strcmp(key, "stage_order")) status = read_order(&r, m);
        else if (!strcmp(key, "seed")) status = read_long(&r, &m->seed);
        else if (!strcmp(key, "dumped_stages")) status = read_names(&r, m->dumped, &m->n_dumped);
        else if (!strcmp(key, "region") && json_peek(&r) == '{') status = read_rect(&r, m, &m->region);
        else if (!strcmp(key, "frames") || !strcmp(key, "scene") || !strcmp(key, "image") || !strcmp(key, "options") ||
                 ((!strcmp(key, "halo") || !strcmp(key, "region_input")) && json_peek(&r) == '{'))
            status = read_object(&r, m, key, NULL);
        else status = json_skip_value(&r);
        if (status) goto fail;
        if (json_peek(&r) != ',') break;
        r.pos++;
    }
    if (json_expect(&r, '}') || json_expect_end(&r)) goto fail;
    json_reader_close(&r);
    if (strcmp(format, "restir-stage-dump"))
        return rerror_at(e, path, 0, "\"format\" must be \"restir-stage-dump\"");
    if (m->first < 0 || m->last < m->first || m->n_order == 0)
        return rerror_at(e, path, 0, "missing \"frames\" {first, last} or \"stage_order\"");
    /* A sequence has at most 10^8 frames (--sequence); a larger range is a corrupt manifest,
     * not 2e9 frames to look for (issue 27: diff-dump hung). */
    if (m->last >= 100000000L || m->written > m->last - m->first + 1)
        return rerror_at(e, path, 0, "\"frames\" {first %ld, last %ld, written %ld}: out of range (frames < 10^8, "
                                     "written <= last - first + 1)", m->first, m->last, m->written);
    if (m->region.width < 0 || m->region.height < 0 || m->region.x < 0 || m->region.y < 0 ||
        (m->region.width == 0) != (m->region.height == 0) ||
        (m->region.width && m->width > 0 &&
         (m->region.x + m->region.width > m->width || m->region.y + m->region.height > m->height)))
        return rerror_at(e, path, 0, "\"region\" is not a rectangle inside \"image\"");
    if (m->width > 0 && m->height > 0) { /* --size first: inspect's pixel is in this image */
        char size[64];
        size_t n = (size_t)snprintf(size, sizeof size, " --size %ldx%ld", m->width, m->height),
               len = strlen(m->inspect_args);
        if (len + n < sizeof m->inspect_args) {
            memmove(m->inspect_args + n, m->inspect_args, len + 1);
            memcpy(m->inspect_args, size, n);
        }
    }
    return 0;
fail:
    json_reader_close(&r);
    return -1;
}

/* ---- G-buffer dump: little-endian, docs/formats.md "G-buffer dump" ---- */

static void encode_texel(const gbuffer_texel *t, unsigned char *buf)
{
    unsigned char *p = buf;
    le_put_u32(&p, (uint32_t)t->valid);
    le_put_u32(&p, t->hit.triangle);
    le_put_u32(&p, t->hit.material);
    le_put_u32(&p, t->hit.object);
    le_put_f32(&p, t->hit.b1);
    le_put_f32(&p, t->hit.b2);
    le_put_f32(&p, t->hit.t);
    le_put_vec3f(&p, t->hit.position);
    le_put_vec3f(&p, t->hit.ng);
    le_put_vec3f(&p, t->hit.ns);
    le_put_vec3f(&p, t->view_dir);
    le_put_f32(&p, t->distance);
    le_put_f32(&p, t->cos_theta);
    le_put_f32(&p, t->depth);
    le_put_f32(&p, t->pixel[0]);
    le_put_f32(&p, t->pixel[1]);
    le_put_f32(&p, t->motion[0]);
    le_put_f32(&p, t->motion[1]);
    le_put_u32(&p, (uint32_t)t->prev_valid);
}

static void decode_texel(const unsigned char *buf, gbuffer_texel *t)
{
    const unsigned char *p = buf;
    memset(t, 0, sizeof *t);
    t->valid = (int)le_get_u32(&p);
    t->hit.triangle = le_get_u32(&p);
    t->hit.material = le_get_u32(&p);
    t->hit.object = le_get_u32(&p);
    t->hit.b1 = le_get_f32(&p);
    t->hit.b2 = le_get_f32(&p);
    t->hit.t = le_get_f32(&p);
    t->hit.position = le_get_vec3f(&p);
    t->hit.ng = le_get_vec3f(&p);
    t->hit.ns = le_get_vec3f(&p);
    t->view_dir = le_get_vec3f(&p);
    t->distance = le_get_f32(&p);
    t->cos_theta = le_get_f32(&p);
    t->depth = le_get_f32(&p);
    t->pixel[0] = le_get_f32(&p);
    t->pixel[1] = le_get_f32(&p);
    t->motion[0] = le_get_f32(&p);
    t->motion[1] = le_get_f32(&p);
    t->prev_valid = (int)le_get_u32(&p);
}

int gbuffer_dump_write(const char *path, const gbuffer *g, uint32_t frame, rerror *e)
{
    unsigned char head[GBUFFER_DUMP_HEADER_SIZE], rec[GBUFFER_DUMP_RECORD_SIZE], *p = head;
    size_t i, n = (size_t)g->width * (size_t)g->height;
    atomic_file f;
    memcpy(p, GBUFFER_DUMP_MAGIC, 8);
    p += 8;
    le_put_u32(&p, GBUFFER_DUMP_VERSION);
    le_put_u32(&p, GBUFFER_DUMP_HEADER_SIZE);
    le_put_u32(&p, GBUFFER_DUMP_RECORD_SIZE);
    le_put_u32(&p, (uint32_t)g->width);
    le_put_u32(&p, (uint32_t)g->height);
    le_put_u32(&p, frame);
    if (atomic_file_open(&f, path, e)) return -1;
    if (fwrite(head, 1, sizeof head, f.fp) != sizeof head) goto failed;
    for (i = 0; i < n; ++i) {
        encode_texel(&g->texels[i], rec);
        if (fwrite(rec, 1, sizeof rec, f.fp) != sizeof rec) goto failed;
    }
    return atomic_file_commit(&f, e);
failed:
    atomic_file_abort(&f);
    return rerror_at(e, path, 0, "write failed: %s", strerror(errno));
}

int gbuffer_dump_read(const char *path, gbuffer *g, uint32_t *frame, rerror *e)
{
    unsigned char head[GBUFFER_DUMP_HEADER_SIZE], rec[GBUFFER_DUMP_RECORD_SIZE];
    const unsigned char *p = head + 8;
    uint32_t version, hsize, rsize, w, h;
    size_t i, n;
    struct stat st;
    FILE *fp = fopen(path, "rb");
    memset(g, 0, sizeof *g);
    if (!fp) return rerror_at(e, path, 0, "cannot open: %s", strerror(errno));
    if (fread(head, 1, sizeof head, fp) != sizeof head || memcmp(head, GBUFFER_DUMP_MAGIC, 8)) {
        fclose(fp);
        return rerror_at(e, path, 0, "not a G-buffer dump (magic is not \"%s\")", GBUFFER_DUMP_MAGIC);
    }
    version = le_get_u32(&p);
    hsize = le_get_u32(&p);
    rsize = le_get_u32(&p);
    w = le_get_u32(&p);
    h = le_get_u32(&p);
    *frame = le_get_u32(&p);
    if (version != GBUFFER_DUMP_VERSION || hsize != GBUFFER_DUMP_HEADER_SIZE || rsize != GBUFFER_DUMP_RECORD_SIZE ||
        w == 0 || h == 0 || w > 65536 || h > 65536) {
        fclose(fp);
        return rerror_at(e, path, 0, "unsupported G-buffer dump (version %u, sizes %u/%u, %ux%u; expected version %u)",
                         version, hsize, rsize, w, h, GBUFFER_DUMP_VERSION);
    }
    n = (size_t)w * h;
    /* The length before allocating: a 32-byte header claiming 8000 x 8000 texels made this
     * allocate 7 GB (the fuzzer's finding, tests/data/fuzz/dump/crash-gbuffer-huge.gbuf). */
    if (fstat(fileno(fp), &st) == 0 && S_ISREG(st.st_mode) &&
        (uint64_t)st.st_size != GBUFFER_DUMP_HEADER_SIZE + (uint64_t)n * GBUFFER_DUMP_RECORD_SIZE) {
        fclose(fp);
        return rerror_at(e, path, 0, "file has %lld bytes, the header implies %llu (%ux%u texels)",
                         (long long)st.st_size,
                         (unsigned long long)(GBUFFER_DUMP_HEADER_SIZE + (uint64_t)n * GBUFFER_DUMP_RECORD_SIZE), w, h);
    }
    g->width = (int)w;
    g->height = (int)h;
    g->texels = rmalloc(n, sizeof *g->texels, e);
    if (!g->texels) {
        fclose(fp);
        return -1;
    }
    for (i = 0; i < n; ++i) {
        if (fread(rec, 1, sizeof rec, fp) != sizeof rec) {
            fclose(fp);
            gbuffer_free(g);
            return rerror_at(e, path, 0, "file is short: texel %lu of %lu is missing", (unsigned long)i,
                             (unsigned long)n);
        }
        decode_texel(rec, &g->texels[i]);
    }
    fclose(fp);
    return 0;
}

/* ---- the frame's stage hook (frame/stage_hook.h) ---- */

static int hook_begin(void *user, int first, int last, int pss_rows, rerror *e)
{
    stage_io *io = user;
    io->pss_rows = pss_rows;
    return stage_io_begin(io, first, last, e);
}
static void hook_frame_begin(void *user, uint32_t frame) { stage_io_frame_begin(user, frame); }
static void hook_gbuffer(void *user, const gbuffer *g) { stage_io_gbuffer(user, g); }
static int hook_skips(void *user, const char *stage) { return stage_io_skips(user, stage); }
static void hook_reservoirs(void *user, const char *stage, reservoir *rs, int width, int height)
{
    stage_io_reservoirs(user, stage, rs, width, height);
}
static int hook_frame_end(void *user, const void *o, rerror *e) { return stage_io_frame_end(user, o, e); }

void stage_io_hook(stage_io *io, frame_stage_hook *hook)
{
    memset(hook, 0, sizeof *hook);
    hook->user = io;
    hook->restarts = io->from_dir != NULL;
    hook->begin = hook_begin;
    hook->frame_begin = hook_frame_begin;
    hook->gbuffer = hook_gbuffer;
    hook->skips = hook_skips;
    hook->reservoirs = hook_reservoirs;
    hook->frame_end = hook_frame_end;
}
