/* restir diff-dump A B: stage-by-stage comparison of two stage dumps (docs/oracle.md,
 * docs/cli.md). A's manifest gives the frames, the stage order and the dumped stages; every
 * dumped stage file of A must exist in A and in B. Exit 0 if every stage passes the
 * tolerances, 1 if one does not, 2 on bad or incomplete input (a missing frame, stage or
 * record, a run cut short, a file of the wrong frame or stage): never 0 for a comparison
 * that did not happen. */
#include "cmd_diff_dump.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/image.h"
#include "restir/core/json_text.h"
#include "restir/core/pfm.h"
#include "restir/core/png.h"
#include "restir/oracle/dump_diff.h"
#include "restir/oracle/stage_dump.h"
#include "args.h"
#include "collide.h"
#include "diff_dump_runs.h"

typedef struct {
    const char *a, *b, *images, *max_rel, *ignore;
    int json, stat, paired, first;
    double max_rel_w, max_rel_target, max_rel_conf, min_same, z, outliers;
} diff_args;

/* What is known of one side: its manifest (B's is optional) and its region. */
typedef struct {
    stage_manifest m;
    int has_manifest;
    stage_region region; /* the pixels its files hold (whole image: 0, 0, W, H) */
} dump_side;

static const char *const kind_names[] = {"same", "beyond tolerance", "OTHER SAMPLE", "NON-FINITE"};

static void print_pixel_text(const stage_manifest *m, const dump_diff_pixel *d, long frame)
{
    printf("    pixel %ld,%ld: %s", d->x, d->y, kind_names[d->kind]);
    if (d->kind == DUMP_PIXEL_BEYOND) printf(" (%s rel err %.3g)", dump_field_name((dump_field)d->field), d->rel);
    if (d->kind == DUMP_PIXEL_NONFINITE) printf(" in %s", d->nonfinite_in == 3 ? "A and B" : d->nonfinite_in == 1 ? "A" : "B");
    printf("  W %.17g | %.17g  p^ %.17g | %.17g  c %.17g | %.17g\n", d->w[0], d->w[1], d->target[0], d->target[1],
           d->conf[0], d->conf[1]);
    if (d->kind == DUMP_PIXEL_OTHER)
        printf("      ids (pixel %u, sample %u, d %d, tech %d) | (pixel %u, sample %u, d %d, tech %d)\n", d->id_pixel[0],
               d->id_sample[0], d->length[0], d->technique[0], d->id_pixel[1], d->id_sample[1], d->length[1],
               d->technique[1]);
    printf("      reproduce: restir inspect %s --pixel %ld,%ld --seed %ld --first-frame %ld%s\n",
           m->scene[0] ? m->scene : "SCENE", d->x, d->y, m->seed, frame, m->inspect_args);
}

static void put_pair(const char *name, const double *v)
{
    printf(", \"%s\": [", name);
    json_put_number(stdout, v[0]);
    printf(", ");
    json_put_number(stdout, v[1]);
    printf("]");
}

static void print_pixel_json(const stage_manifest *m, const dump_diff_pixel *d, long frame)
{
    char cmd[5300];
    static const char *const kinds[] = {"same", "beyond", "other_sample", "nonfinite"};
    printf("{\"x\": %ld, \"y\": %ld, \"same_sample\": %s, \"kind\": \"%s\"", d->x, d->y,
           d->kind == DUMP_PIXEL_OTHER ? "false" : "true", kinds[d->kind]);
    if (d->kind == DUMP_PIXEL_BEYOND) {
        printf(", \"field\": \"%s\", \"rel_err\": ", dump_field_name((dump_field)d->field));
        json_put_number(stdout, d->rel);
    }
    if (d->kind == DUMP_PIXEL_NONFINITE) printf(", \"nonfinite_in\": \"%s\"", d->nonfinite_in == 3 ? "AB" : d->nonfinite_in == 1 ? "A" : "B");
    put_pair("W", d->w);
    put_pair("target", d->target);
    put_pair("confidence", d->conf);
    snprintf(cmd, sizeof cmd, "%s --pixel %ld,%ld --seed %ld --first-frame %ld%s", m->scene[0] ? m->scene : "SCENE",
             d->x, d->y, m->seed, frame, m->inspect_args);
    printf(", \"inspect_args\": ");
    json_put_string(stdout, cmd);
    printf("}");
}

static void put_q(const char *name, const double *q)
{
    int i;
    printf("\"%s\": [", name);
    for (i = 0; i < 4; ++i) {
        if (i) printf(", ");
        json_put_number(stdout, q[i]);
    }
    printf("]");
}

/* ", "name": [a, b], "zname": z */
static void put_means(const char *name, const double *v, const char *zname, double z)
{
    put_pair(name, v);
    printf(", \"%s\": ", zname);
    json_put_number(stdout, z);
}

static void put_fields_json(const dump_diff_result *r)
{
    int f;
    printf(", \"fields\": {");
    for (f = 0; f < DF_COUNT; ++f) {
        printf("%s\"%s\": {\"max_rel_err\": ", f ? ", " : "", dump_field_name((dump_field)f));
        json_put_number(stdout, r->field_max[f]);
        printf(", \"beyond\": %ld}", r->field_beyond[f]);
    }
    printf("}");
}

/* The fields with pixels beyond their tolerance, as text. */
static void print_fields_text(const dump_diff_result *r)
{
    int f, any = 0;
    for (f = 0; f < DF_COUNT; ++f)
        if (r->field_beyond[f]) {
            printf("%s%s %ld (max %.3g)", any ? ", " : "    beyond tolerance: ", dump_field_name((dump_field)f),
                   r->field_beyond[f], r->field_max[f]);
            any = 1;
        }
    if (any) printf("\n");
}

/* One (frame, stage) row; returns 1 if it passes. */
static int report_row(const diff_args *a, const stage_manifest *m, long frame, const char *stage, const dump_diff_result *r,
                      const dump_diff_tolerance *t, int *first_row)
{
    double same = (double)r->same / (double)r->pixels, z = dump_diff_mean_z(r), zc = dump_diff_confidence_z(r),
           zn = dump_diff_nonempty_z(r), zrgb[3], zp[4];
    static const char *const ch[] = {"R", "G", "B"};
    int pass, c;
    long i;
    for (c = 0; c < 4; ++c) zp[c] = dump_diff_paired_z(r, c);
    for (c = 0; c < 3; ++c) zrgb[c] = dump_diff_channel_z(r, c);
    /* a NaN z (non-finite values) fails: |NaN| <= bound is false. F W is judged per channel
     * R, G, B and in luminance: unpaired, or with --paired by the per-pixel differences */
    pass = a->stat ? r->nonfinite == 0 && fabs(a->paired ? zp[3] : z) <= a->z && fabs(zc) <= a->z && fabs(zn) <= a->z
                   : dump_diff_pass(r, t);
    for (c = 0; c < 3 && a->stat; ++c) pass = pass && fabs(a->paired ? zp[c] : zrgb[c]) <= a->z;
    if (a->json) {
        printf("%s\n  {\"frame\": %ld, \"stage\": ", *first_row ? "" : ",", frame);
        json_put_string(stdout, stage);
        printf(", \"pixels\": %ld, \"same_sample\": ", r->pixels);
        json_put_number(stdout, same);
        printf(", \"differing\": %ld, \"beyond\": %ld, \"other_sample\": %ld, \"nonfinite\": %ld, \"target_agreement\": ",
               r->differing, r->beyond, r->other, r->nonfinite);
        json_put_number(stdout, r->same ? (double)r->target_agree / (double)r->same : 1.0);
        printf(", ");
        put_q("rel_err_W", r->q_w);
        printf(", ");
        put_q("rel_err_target", r->q_target);
        printf(", ");
        put_q("rel_err_confidence", r->q_conf);
        put_fields_json(r);
        put_means("mean_FW", r->mean_fw, "z", z);
        put_means("mean_confidence", r->mean_c, "z_confidence", zc);
        put_means("nonempty", r->mean_full, "z_nonempty", zn);
        for (c = 0; c < 3; ++c) {
            char mn[16], zn_[16];
            double v[2];
            v[0] = r->mean_rgb[0][c];
            v[1] = r->mean_rgb[1][c];
            snprintf(mn, sizeof mn, "mean_FW_%s", ch[c]);
            snprintf(zn_, sizeof zn_, "z_%s", ch[c]);
            put_means(mn, v, zn_, zrgb[c]);
        }
        printf(", \"z_paired\": [");
        for (c = 0; c < 4; ++c) {
            if (c) printf(", ");
            json_put_number(stdout, zp[c]);
        }
        printf("]");
        printf(", \"pass\": %s, \"first_differing\": [", pass ? "true" : "false");
        for (i = 0; i < r->n_first; ++i) {
            if (i) printf(", ");
            print_pixel_json(m, &r->firsts[i], frame);
        }
        printf("]}");
    } else {
        printf("frame %4ld %-12s same %.6f  W rel err p50 %.3g p99 %.3g max %.3g  p^ max %.3g  c max %.3g  "
               "mean F*W %.6g | %.6g (z %+.2f)  %s\n",
               frame, stage, same, r->q_w[0], r->q_w[2], r->q_w[3], r->q_target[3], r->q_conf[3], r->mean_fw[0],
               r->mean_fw[1], z, pass ? "ok" : "DIFFERS");
        if (r->nonfinite) printf("    %ld pixels with a non-finite value (never within a tolerance)\n", r->nonfinite);
        if (r->beyond) printf("    %ld same-sample pixels beyond a tolerance (allowed: %.0f)\n", r->beyond,
                              floor(t->max_outlier_fraction * (double)r->pixels));
        if (a->stat) {
            printf("    mean c %.6g | %.6g (z %+.2f)  non-empty %.6f | %.6f (z %+.2f)\n", r->mean_c[0], r->mean_c[1], zc,
                   r->mean_full[0], r->mean_full[1], zn);
            printf("    F*W");
            for (c = 0; c < 3; ++c) printf(" %s %.6g | %.6g (z %+.2f) ", ch[c], r->mean_rgb[0][c], r->mean_rgb[1][c], zrgb[c]);
            printf(" paired z R %+.2f G %+.2f B %+.2f lum %+.2f%s\n", zp[0], zp[1], zp[2], zp[3],
                   a->paired ? " (judged)" : "");
        } else {
            print_fields_text(r);
            for (i = 0; i < r->n_first; ++i) print_pixel_text(m, &r->firsts[i], frame);
        }
    }
    *first_row = 0;
    return pass;
}

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Reads one side's stage file and checks its header against the frame, stage and region. */
static int read_side(const char *path, const char *which, long frame, const char *stage, const stage_region *rg,
                     reservoir **rs, rerror *e)
{
    reservoir_dump_info info;
    if (!file_exists(path))
        return rerror_set(e, "%s: missing: %s's manifest lists stage %s of frame %ld as dumped (or %s lacks it)", path,
                          which, stage, frame, which);
    if (reservoir_dump_read(path, rs, &info, e)) return -1;
    if ((long)info.frame != frame || strcmp(info.tag, stage) || (long)info.width != rg->width ||
        (long)info.height != rg->height) {
        free(*rs);
        *rs = NULL;
        return rerror_at(e, path, 0, "holds frame %u, stage '%s', %ux%u records; expected frame %ld, stage '%s', %ldx%ld",
                         info.frame, info.tag, info.width, info.height, frame, stage, rg->width, rg->height);
    }
    return 0;
}

static int region_inside(const stage_region *in, const stage_region *out)
{
    return in->x >= out->x && in->y >= out->y && in->x + in->width <= out->x + out->width &&
           in->y + in->height <= out->y + out->height;
}

/* The records of rectangle c out of rs, which holds rectangle from (row-major), into a new array. */
static reservoir *crop(const reservoir *rs, const stage_region *from, const stage_region *c, rerror *e)
{
    long i, n = c->width * c->height;
    reservoir *out = rmalloc((size_t)n, sizeof *out, e);
    if (!out) return NULL;
    for (i = 0; i < n; ++i)
        out[i] = rs[(c->y - from->y + i / c->width) * from->width + c->x - from->x + i % c->width];
    return out;
}

/* --images DIR: per row the difference mask (PNG: black same, yellow beyond a tolerance,
 * red another sample, magenta non-finite; PFM: the same classes 0..3) and F W of A and B
 * (PFM, and PNG previews). */
static int write_images(const char *dir, long frame, const char *stage, const reservoir *ra, const reservoir *rb,
                        const dump_diff_result *r, long w, long h, rerror *e)
{
    static const unsigned char colours[4][3] = {{0, 0, 0}, {255, 220, 0}, {230, 0, 0}, {255, 0, 255}};
    char path[4300];
    unsigned char *rgb8 = rmalloc((size_t)(w * h), 3, e);
    image mask, fw[2];
    long p;
    int i, status = -1;
    memset(&mask, 0, sizeof mask);
    memset(fw, 0, sizeof fw);
    if (!rgb8 || image_alloc(&mask, (int)w, (int)h, e) || image_alloc(&fw[0], (int)w, (int)h, e) ||
        image_alloc(&fw[1], (int)w, (int)h, e))
        goto done;
    for (p = 0; p < w * h; ++p) {
        const reservoir *s[2];
        s[0] = &ra[p];
        s[1] = &rb[p];
        memcpy(rgb8 + 3 * p, colours[r->mask[p]], 3);
        for (i = 0; i < 3; ++i) mask.px[3 * p + i] = (float)r->mask[p];
        for (i = 0; i < 2; ++i) {
            fw[i].px[3 * p + 0] = (float)(s[i]->y.F.r * s[i]->W);
            fw[i].px[3 * p + 1] = (float)(s[i]->y.F.g * s[i]->W);
            fw[i].px[3 * p + 2] = (float)(s[i]->y.F.b * s[i]->W);
        }
    }
    snprintf(path, sizeof path, "%s/frame_%04ld_%s_mask.png", dir, frame, stage);
    if (png_write_rgb8(path, (int)w, (int)h, rgb8, e)) goto done;
    snprintf(path, sizeof path, "%s/frame_%04ld_%s_mask.pfm", dir, frame, stage);
    if (pfm_write(path, &mask, e)) goto done;
    for (i = 0; i < 2; ++i) {
        snprintf(path, sizeof path, "%s/frame_%04ld_%s_%c_FW.pfm", dir, frame, stage, "AB"[i]);
        if (pfm_write(path, &fw[i], e)) goto done;
        snprintf(path, sizeof path, "%s/frame_%04ld_%s_%c_FW.png", dir, frame, stage, "AB"[i]);
        if (png_write_preview(path, &fw[i], 0, e)) goto done;
    }
    status = 0;
done:
    free(rgb8);
    image_free(&mask);
    image_free(&fw[0]);
    image_free(&fw[1]);
    return status;
}

/* Compares one (frame, stage); returns 1 (passes), 0 (differs), -1 (bad input: e),
 * 2 (not dumped by A: no row). */
static int diff_stage(const diff_args *a, const dump_side *sa, const dump_side *sb, long frame, const char *stage,
                      const dump_diff_tolerance *t, int *first_row, int *first_fail_reported, rerror *e)
{
    char pa[4200], pb[4200];
    reservoir *ra = NULL, *rb = NULL, *ca = NULL, *cb = NULL;
    dump_diff_result r;
    stage_region c;
    int pass = -1;
    long i;
    stage_dump_path(pa, sizeof pa, a->a, (uint32_t)frame, stage, "resv");
    stage_dump_path(pb, sizeof pb, a->b, (uint32_t)frame, stage, "resv");
    if (!stage_manifest_dumped(&sa->m, stage) && !file_exists(pa)) return 2; /* --dump-stages left it out */
    if (read_side(pa, "A", frame, stage, &sa->region, &ra, e) || read_side(pb, "B", frame, stage, &sb->region, &rb, e))
        goto done;
    /* the compared rectangle: the smaller region, which must lie in the other */
    if (region_inside(&sa->region, &sb->region)) c = sa->region;
    else if (region_inside(&sb->region, &sa->region)) c = sb->region;
    else {
        rerror_set(e, "the regions of A (%ld,%ld,%ld,%ld) and B (%ld,%ld,%ld,%ld) do not nest", sa->region.x,
                   sa->region.y, sa->region.width, sa->region.height, sb->region.x, sb->region.y, sb->region.width,
                   sb->region.height);
        goto done;
    }
    if (!(ca = crop(ra, &sa->region, &c, e)) || !(cb = crop(rb, &sb->region, &c, e))) goto done;
    if (dump_diff(ca, cb, c.width, c.height, t, &r, e)) goto done;
    for (i = 0; i < r.n_first; ++i) { /* image coordinates */
        r.firsts[i].x += c.x;
        r.firsts[i].y += c.y;
    }
    if (a->images && write_images(a->images, frame, stage, ca, cb, &r, c.width, c.height, e)) {
        dump_diff_result_free(&r);
        goto done;
    }
    pass = report_row(a, &sa->m, frame, stage, &r, t, first_row);
    if (!pass && !*first_fail_reported && !a->json) {
        fprintf(stderr, "restir diff-dump: first difference: frame %ld, stage %s", frame, stage);
        if (r.n_first > 0 && !a->stat) fprintf(stderr, ", pixel %ld,%ld", r.firsts[0].x, r.firsts[0].y);
        fprintf(stderr, "\n");
        *first_fail_reported = 1;
    }
    dump_diff_result_free(&r);
done:
    free(ra);
    free(rb);
    free(ca);
    free(cb);
    return pass;
}

/* Reads a side's manifest (required for A) and decides its region. */
static int load_side(const char *dir, int required, const dump_side *other, dump_side *s, rerror *e)
{
    char path[4200];
    memset(s, 0, sizeof *s);
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    if (!file_exists(dir)) return rerror_set(e, "%s: no such dump directory", dir);
    if (required || file_exists(path)) {
        if (stage_manifest_read(dir, &s->m, e)) return -1;
        s->has_manifest = 1;
    } else {
        s->m = other->m; /* B without a manifest: A's frames and stages, A's region */
        s->region = other->region;
        return 0;
    }
    if (s->m.region.width) s->region = s->m.region;
    else if (s->m.width <= 0 && other) /* B's manifest without "image": A's image and region */
        s->region = other->region;
    else {
        s->region.width = s->m.width;
        s->region.height = s->m.height;
    }
    return 0;
}

/* Structural checks before any row: both runs complete, the same image, frames covered. */
static int check_sides(const diff_args *a, const dump_side *sa, const dump_side *sb, rerror *e)
{
    long frames = sa->m.last - sa->m.first + 1;
    if (sa->m.width <= 0 || sa->m.height <= 0) return rerror_set(e, "%s/manifest.json: missing \"image\" {width, height}", a->a);
    if (sa->m.written >= 0 && sa->m.written < frames)
        return rerror_set(e, "%s: the run was cut short: its manifest says %ld of the %ld frames %ld..%ld were written",
                          a->a, sa->m.written, frames, sa->m.first, sa->m.last);
    if (!sb->has_manifest) return 0;
    if (sb->m.width > 0 && (sb->m.width != sa->m.width || sb->m.height != sa->m.height))
        return rerror_set(e, "A's image is %ldx%ld, B's %ldx%ld", sa->m.width, sa->m.height, sb->m.width, sb->m.height);
    if (sb->m.first > sa->m.first || sb->m.last < sa->m.last)
        return rerror_set(e, "B holds frames %ld..%ld, A %ld..%ld", sb->m.first, sb->m.last, sa->m.first, sa->m.last);
    if (sb->m.written >= 0 && sb->m.written < sb->m.last - sb->m.first + 1)
        return rerror_set(e, "%s: the run was cut short: its manifest says %ld of the %ld frames %ld..%ld were written",
                          a->b, sb->m.written, sb->m.last - sb->m.first + 1, sb->m.first, sb->m.last);
    return 0;
}

/* --images DIR: never inside either dump (its files would sit among the stage files the
 * next diff reads), created if missing. */
static int make_images_dir(const diff_args *a, rerror *e)
{
    struct stat st;
    if (path_within(a->images, a->a) || path_within(a->images, a->b))
        return rerror_set(e, "--images %s lies inside dump %s: choose a directory outside both dumps", a->images,
                          path_within(a->images, a->a) ? a->a : a->b);
    if (mkdir(a->images, 0777) != 0 && errno != EEXIST)
        return rerror_set(e, "%s: cannot create directory: %s", a->images, strerror(errno));
    if (stat(a->images, &st) != 0 || !S_ISDIR(st.st_mode))
        return rerror_set(e, "%s: not a directory (--images names the directory the images go to)", a->images);
    return 0;
}

/* An exit 2 after images were written says what it kept (issue 27: exit != 0 leaves nothing
 * or says exactly what it kept). */
static int failed_after_images(const diff_args *a)
{
    if (a->images)
        fprintf(stderr, "restir diff-dump: stopped by the error below; the images of the rows before it are kept in %s\n",
                a->images);
    return 2;
}

/* The tolerances from the options (--max-rel-w/-target/-confidence, then --max-rel, --ignore). */
static int tolerances(const diff_args *a, dump_diff_tolerance *t, rerror *e)
{
    dump_diff_tolerance_default(t);
    t->max_rel[DF_W] = a->max_rel_w;
    t->max_rel[DF_TARGET] = a->max_rel_target;
    t->max_rel[DF_CONFIDENCE] = a->max_rel_conf;
    t->min_same = a->min_same;
    t->first = a->first;
    t->max_outlier_fraction = a->outliers;
    if (a->max_rel && dump_diff_tolerance_parse(t, a->max_rel, e)) return -1;
    if (a->ignore && dump_diff_ignore_parse(t, a->ignore, e)) return -1;
    return 0;
}

static int run(const diff_args *a, rerror *e)
{
    dump_side sa, sb;
    dump_diff_tolerance t;
    int i, all_pass = 1, first_row = 1, reported = 0, rows = 0;
    long f;
    if (tolerances(a, &t, e) || load_side(a->a, 1, NULL, &sa, e) || load_side(a->b, 0, &sa, &sb, e) ||
        check_sides(a, &sa, &sb, e) || (a->images && make_images_dir(a, e)))
        return 2;
    if (a->json) {
        printf("{\"a\": ");
        json_put_string(stdout, a->a);
        printf(", \"b\": ");
        json_put_string(stdout, a->b);
        printf(", \"mode\": \"%s\", \"region\": [%ld, %ld, %ld, %ld], \"rows\": [", a->stat ? "stat" : "identity",
               sa.region.x, sa.region.y, sa.region.width, sa.region.height);
    }
    if (!a->json && (sa.region.width != sa.m.width || sa.region.height != sa.m.height ||
                     sb.region.width != sa.m.width || sb.region.height != sa.m.height)) {
        const stage_region *c = region_inside(&sa.region, &sb.region) ? &sa.region : &sb.region;
        printf("region %ld,%ld,%ld,%ld of the %ldx%ld image (%ld pixels per row; pixels in image coordinates)\n", c->x,
               c->y, c->width, c->height, sa.m.width, sa.m.height, c->width * c->height);
    }
    for (f = sa.m.first; f <= sa.m.last; ++f)
        for (i = 0; i < sa.m.n_order; ++i) {
            int pass = diff_stage(a, &sa, &sb, f, sa.m.order[i], &t, &first_row, &reported, e);
            if (pass < 0) {
                if (a->json) printf("\n]}\n");
                return failed_after_images(a);
            }
            if (pass == 2) continue;
            rows++;
            if (!pass) all_pass = 0;
        }
    if (rows == 0) {
        if (a->json) printf("\n]}\n");
        rerror_set(e, "%s: no stage file to compare (its manifest lists no dumped stage)", a->a);
        return 2;
    }
    if (a->json) printf("\n], \"pass\": %s}\n", all_pass ? "true" : "false");
    return all_pass ? 0 : 1;
}

int cmd_diff_dump(int argc, char **argv)
{
    diff_args a;
    cli_option options[20];
    const char *positional[2];
    int count, status, n;
    rerror e;
    memset(&a, 0, sizeof a);
    a.first = 5;
    a.min_same = 1;
    a.z = -1; /* not given: 4, or the t quantile for paired runs */
    {
        const cli_option rows[] = {
            {"--json", OPT_FLAG, &a.json, "one JSON object with a row per frame and stage", NULL, 0, 0, NULL},
            {"--max-rel-w", OPT_REAL, &a.max_rel_w, "relative error of W a same-sample pixel may have (default 0)", NULL, 0, 1e300, NULL},
            {"--max-rel-target", OPT_REAL, &a.max_rel_target, "relative error of the target p^ (default 0)", NULL, 0, 1e300, NULL},
            {"--max-rel-confidence", OPT_REAL, &a.max_rel_conf, "relative error of the confidence c (default 0)", NULL, 0, 1e300, NULL},
            {"--max-rel", OPT_STRING, &a.max_rel, "per-field relative tolerances FIELD=V[,FIELD=V...] (fields of docs/formats.md \"Record\", or all=V for every real field; default 0: bit identity)", NULL, 0, 0, NULL},
            {"--ignore", OPT_STRING, &a.ignore, "fields not compared, FIELD[,FIELD...] (e.g. n_invalid for a build that does not count invalid weights)", NULL, 0, 0, NULL},
            {"--min-same", OPT_REAL, &a.min_same, "fraction of pixels that must hold the same sample (default 1)", NULL, 0, 1, NULL},
            {"--max-outlier-fraction", OPT_REAL, &a.outliers, "fraction of the pixels that may be beyond a tolerance (same sample; never a non-finite value) (default 0)", NULL, 0, 1, NULL},
            {"--first", OPT_INT, &a.first, "differing pixels listed per stage (default 5, no upper limit)", NULL, 0, 0, NULL},
            {"--images", OPT_STRING, &a.images, "write per frame and stage the difference mask (PNG, PFM) and F W of A and B (PFM, PNG) into this directory", NULL, 0, 0, NULL},
            {"--stat", OPT_FLAG, &a.stat, "statistical mode for builds with another RNG: compare the image means of F W per channel R, G, B and in luminance, of c and of the non-empty fraction per stage", NULL, 0, 0, NULL},
            {"--paired", OPT_FLAG, &a.paired, "with --stat (implied): judge F W (R, G, B, luminance) by the per-pixel differences A - B, far stronger when both share the oracle's RNG (a port with the same RNG, a planted bug)", NULL, 0, 0, NULL},
            {"--z", OPT_REAL, &a.z, "with --stat: largest |z| that passes (default 4; paired runs: |t|, default the t quantile of a 1e-3 two-sided false alarm over all rows and channels)", NULL, 0, 1e300, NULL},
        };
        for (n = 0; n < (int)(sizeof rows / sizeof rows[0]); ++n) options[n] = rows[n];
    }
    memset(&options[n], 0, sizeof options[n]);
    status = cli_parse("diff-dump", argc, argv, options, positional, 2, &count);
    if (status == 1) {
        cli_print_help(stdout, "diff-dump", "A B [options]  (two --dump-dir directories)", options);
        return 0;
    }
    if (status) return status;
    if (count != 2) {
        fprintf(stderr, "restir diff-dump: expected two dump directories A B (see restir diff-dump --help)\n");
        return 2;
    }
    a.a = positional[0];
    a.b = positional[1];
    if (a.paired) a.stat = 1;
    if (a.stat && diff_dump_has_runs(a.a)) /* K runs per side: the paired per-channel test */
        return diff_dump_runs(a.a, a.b, a.z < 0 ? 0 : a.z, a.json);
    if (a.z < 0) a.z = 4.0;
    status = run(&a, &e);
    if (status == 2) fprintf(stderr, "restir diff-dump: %s\n", e.msg);
    return status;
}
