/* A region dump as the input of one stage (include/restir/oracle/region_input.h). */
#include "restir/oracle/region_input.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "restir/core/atomic_file.h"
#include "restir/core/json_text.h"
#include "restir/core/le_bytes.h"
#include "restir/render/motion.h"
#include "restir/restir/duplication.h"
#include "restir/restir/boiling_filter.h"
#include "restir/restir/reservoir_dump.h"
#include "restir/restir/reuse_cells.h"
#include "restir/restir/spatial_options.h"

/* The largest |dx|, |dy| of the paired pattern's reuse textures (every placement moves and
 * mirrors the texture, never lengthens an offset: reuse_partner_offset). */
static int paired_reach(const restir_options *o, rerror *e)
{
    neighbor_options no;
    reuse_texture textures[PAIRING_MAX_TEXTURES];
    int k, reach = 0;
    long i;
    spatial_neighbor_options(&no, &o->spatial);
    if (restir_pairing_build(&no, o, textures, e)) return -1;
    for (k = 0; k < no.count; ++k)
        for (i = 0; i < (long)textures[k].size * textures[k].size; ++i) {
            int dx = abs(textures[k].dx[i]), dy = abs(textures[k].dy[i]);
            if (dx > reach) reach = dx;
            if (dy > reach) reach = dy;
        }
    restir_pairing_free(&no);
    return reach;
}

int region_reach_for(region_reach *rr, const restir_options *o, rerror *e)
{
    memset(rr, 0, sizeof *rr);
    rr->dedup = o->correlation.dedup != 0;
    rr->dual = o->temporal.motion_vectors == RESTIR_MV_DUAL;
    rr->cells = o->spatial.cells != 0;
    if (rr->cells) /* reuse_cell_search: radius 30 growing by 1.25 over 12 draws, rounded */
        rr->spatial = (int)ceil(REUSE_SEARCH_RADIUS * pow(REUSE_SEARCH_GROWTH, REUSE_SEARCH_ITERATIONS - 1)) + 1;
    else if (o->spatial.pairing == RESTIR_PAIRING_PAIRED)
        rr->spatial = paired_reach(o, e);
    else if (o->spatial.pattern == NEIGHBOR_BOX)
        rr->spatial = (int)floor(o->spatial.radius);
    else /* neighbor_offset: floor(R p + 0.5) with |p| <= 1 */
        rr->spatial = (int)floor(o->spatial.radius + 0.5);
    return rr->spatial < 0 ? -1 : 0;
}

static pixel_box clip_box(long x0, long y0, long x1, long y1, long w, long h)
{
    pixel_box b;
    b.x0 = x0 < 0 ? 0 : x0;
    b.y0 = y0 < 0 ? 0 : y0;
    b.x1 = x1 >= w ? w - 1 : x1;
    b.y1 = y1 >= h ? h - 1 : y1;
    return b;
}

static long floor_to(long v, long g) { return v >= 0 ? v / g * g : -((-v + g - 1) / g) * g; }

int region_pixel_reads(const region_reach *rr, const char *stage, long w, long h, long x, long y,
                       const gbuffer_texel *t, int history, region_read out[2])
{
    int n = 0;
    if (!strcmp(stage, "initial")) return 0; /* the scene's path trees only */
    out[n].what = "input";
    if (!t->valid && strcmp(stage, "boiling")) return 0; /* no primary hit: an empty output, nothing read */
    if (!strncmp(stage, "mutate-", 7)) { /* Mutations Alg. 3: the pixel's own reservoir */
        out[n++].box = clip_box(x, y, x, y, w, h);
        return n;
    }
    if (!strcmp(stage, "boiling")) { /* the filter's statistic is one of the 16 x 16 group */
        long gx = x / BOILING_GROUP * BOILING_GROUP, gy = y / BOILING_GROUP * BOILING_GROUP;
        out[n++].box = clip_box(gx, gy, gx + BOILING_GROUP - 1, gy + BOILING_GROUP - 1, w, h);
        return n;
    }
    if (!strncmp(stage, "spatial", 7)) {
        long r = rr->spatial;
        if (rr->cells) /* a cell is a set of pixels of one 8 x 8 tile */
            out[n++].box = clip_box(floor_to(x - r, REUSE_TILE), floor_to(y - r, REUSE_TILE),
                                    floor_to(x + r, REUSE_TILE) + REUSE_TILE - 1,
                                    floor_to(y + r, REUSE_TILE) + REUSE_TILE - 1, w, h);
        else
            out[n++].box = clip_box(x - r, y - r, x + r, y + r, w, h);
        return n;
    }
    if (strcmp(stage, "temporal")) return -1;
    out[n++].box = clip_box(x, y, x, y, w, h); /* the pixel's initial reservoir */
    if (history && t->valid) {
        int qx, qy;
        if (t->prev_valid) {
            gbuffer_previous_pixel(t, &qx, &qy); /* floor(x + 0.5 + mv): pipeline.c reproject */
            if (qx >= 0 && qy >= 0 && qx < w && qy < h) {
                long d = rr->dedup ? DUPLICATION_RADIUS : 0; /* the cap's duplication score */
                out[n].what = "history";
                out[n++].box = clip_box(qx - d, qy - d, qx + d, qy + d, w, h);
            }
        } else if (rr->dual)
            return -1; /* the occluder's motion decides the source pixel */
    }
    return n;
}

/* ---- the stage listener's check ---------------------------------------------------------- */

void region_input_gbuffer(stage_io *io, const gbuffer *g)
{
    const stage_region *c = &io->in_check;
    long i, n = c->width * c->height;
    if (!c->width || io->in_texels || io->frames_done > 0) return;
    io->in_image_w = g->width;
    io->in_image_h = g->height;
    if (c->x + c->width > g->width || c->y + c->height > g->height) {
        rerror_set(&io->err, "region input: the checked rectangle %ld,%ld,%ld,%ld is not inside the %dx%d image", c->x,
                   c->y, c->width, c->height, g->width, g->height);
        io->failed = 1;
        return;
    }
    if (!(io->in_texels = rmalloc((size_t)n, sizeof(gbuffer_texel), &io->err))) {
        io->failed = 1;
        return;
    }
    for (i = 0; i < n; ++i)
        ((gbuffer_texel *)io->in_texels)[i] = g->texels[(c->y + i / c->width) * g->width + c->x + i % c->width];
}

static int inside(const pixel_box *b, const stage_region *r)
{
    return b->x0 >= r->x && b->y0 >= r->y && b->x1 < r->x + r->width && b->y1 < r->y + r->height;
}

/* A pixel of b outside r (b is not inside r). */
static void outside_pixel(const pixel_box *b, const stage_region *r, long *x, long *y)
{
    *x = b->x0 < r->x ? b->x0 : b->x1 >= r->x + r->width ? b->x1 : b->x0;
    *y = b->y0 < r->y ? b->y0 : b->y1 >= r->y + r->height ? b->y1 : b->y0;
}

int region_input_check(stage_io *io, const restir_options *o, rerror *e)
{
    const stage_region *c = &io->in_check, *d = &io->in_dumped;
    const gbuffer_texel *texels = io->in_texels;
    region_reach rr;
    long i, n = c->width * c->height;
    int status = 0;
    if (!c->width || !texels) return 0;
    if (region_reach_for(&rr, o, e)) status = -1;
    for (i = 0; !status && i < n; ++i) {
        long x = c->x + i % c->width, y = c->y + i / c->width, qx, qy;
        region_read reads[2];
        int k, m = region_pixel_reads(&rr, io->in_stage, io->in_image_w, io->in_image_h, x, y, &texels[i],
                                      io->in_history, reads);
        if (m < 0) {
            status = rerror_set(e, "frame %u, stage %s, pixel (%ld, %ld): its reads are not bounded (%s); a region "
                                   "dump cannot be its input", (unsigned)io->frame, io->in_stage, x, y,
                                strcmp(io->in_stage, "temporal") ? "unknown stage"
                                                                 : "--motion-vectors dual at a disoccluded pixel");
            break;
        }
        for (k = 0; k < m; ++k) {
            if (inside(&reads[k].box, d)) continue;
            outside_pixel(&reads[k].box, d, &qx, &qy);
            status = rerror_set(e, "frame %u, stage %s, pixel (%ld, %ld): missing input: it reads %s at pixel (%ld, "
                                   "%ld) (pixels %ld..%ld x %ld..%ld), outside the dumped rectangle %ld,%ld,%ld,%ld; "
                                   "choose pixels farther from the edge or dump a larger --dump-halo (docs/oracle.md §6)",
                                (unsigned)io->frame, io->in_stage, x, y,
                                !strcmp(reads[k].what, "history") ? "the previous frame's final reservoir"
                                                                  : "the previous stage's reservoir",
                                qx, qy, reads[k].box.x0, reads[k].box.x1, reads[k].box.y0, reads[k].box.y1, d->x, d->y,
                                d->width, d->height);
            break;
        }
    }
    free(io->in_texels);
    io->in_texels = NULL;
    return status;
}

/* ---- expanding a region file to the whole image ---------------------------------------- */

int region_dump_expand(const char *src, const stage_region *r, long width, long height, const char *dst, rerror *e)
{
    unsigned char head[RESERVOIR_DUMP_HEADER_SIZE], *p, *row = NULL, empty_rec[RESERVOIR_DUMP_RECORD_PSS];
    const unsigned char *q;
    uint32_t flags, rw, rh;
    size_t size;
    long x, y;
    reservoir empty;
    atomic_file f;
    FILE *in = fopen(src, "rb");
    if (!in) return rerror_at(e, src, 0, "cannot open: %s", strerror(errno));
    if (fread(head, 1, sizeof head, in) != sizeof head || memcmp(head, RESERVOIR_DUMP_MAGIC, 8)) {
        fclose(in);
        return rerror_at(e, src, 0, "not a reservoir dump");
    }
    q = head + 20;
    flags = le_get_u32(&q);
    rw = le_get_u32(&q);
    rh = le_get_u32(&q);
    if (rw != (uint32_t)r->width || rh != (uint32_t)r->height) {
        fclose(in);
        return rerror_at(e, src, 0, "holds %ux%u records, the manifest's region is %ldx%ld", rw, rh, r->width, r->height);
    }
    size = reservoir_record_size(flags);
    reservoir_init(&empty);
    reservoir_record_encode(&empty, flags, empty_rec);
    p = head + 24; /* the whole image's width, height and count; the rest of the header stays */
    le_put_u32(&p, (uint32_t)width);
    le_put_u32(&p, (uint32_t)height);
    p = head + 40;
    le_put_u64(&p, (uint64_t)width * (uint64_t)height);
    if (!(row = rmalloc((size_t)r->width, size, e)) || atomic_file_open(&f, dst, e)) {
        free(row);
        fclose(in);
        return -1;
    }
    if (fwrite(head, 1, sizeof head, f.fp) != sizeof head) goto failed;
    for (y = 0; y < height; ++y) {
        int in_rows = y >= r->y && y < r->y + r->height;
        if (in_rows && fread(row, size, (size_t)r->width, in) != (size_t)r->width) {
            atomic_file_abort(&f);
            free(row);
            fclose(in);
            return rerror_at(e, src, 0, "file is short (row %ld of the region)", y - r->y);
        }
        for (x = 0; x < width; ++x) {
            const unsigned char *rec = in_rows && x >= r->x && x < r->x + r->width ? row + (size_t)(x - r->x) * size
                                                                                    : empty_rec;
            if (fwrite(rec, 1, size, f.fp) != size) goto failed;
        }
    }
    free(row);
    fclose(in);
    return atomic_file_commit(&f, e);
failed:
    atomic_file_abort(&f);
    free(row);
    fclose(in);
    return rerror_at(e, dst, 0, "write failed: %s", strerror(errno));
}

/* ---- the whole-image input directory of a replay from a region dump ------------------ */

static void put_rect(FILE *fp, const char *key, const stage_region *r)
{
    fprintf(fp, "\"%s\": {\"x\": %ld, \"y\": %ld, \"width\": %ld, \"height\": %ld}", key, r->x, r->y, r->width, r->height);
}

static int expand_stage(const char *dir, const stage_manifest *m, const char *tmp, long frame, const char *stage, rerror *e)
{
    char src[4200], dst[4200];
    snprintf(dst, sizeof dst, "%s/frame_%04ld", tmp, frame);
    if (mkdir(dst, 0700) != 0 && errno != EEXIST) return rerror_set(e, "%s: cannot create: %s", dst, strerror(errno));
    stage_dump_path(src, sizeof src, dir, (uint32_t)frame, stage, "resv");
    stage_dump_path(dst, sizeof dst, tmp, (uint32_t)frame, stage, "resv");
    return region_dump_expand(src, &m->region, m->width, m->height, dst, e);
}

int region_input_dir_make(const region_input_plan *p, rerror *e)
{
    const stage_manifest *m = p->m;
    char path[4200], dumped[2][STAGE_NAME_SIZE];
    atomic_file f;
    int n = 0;
    if (expand_stage(p->dir, m, p->tmp, p->frame, p->prev, e)) return -1;
    snprintf(dumped[n++], STAGE_NAME_SIZE, "%s", p->prev);
    if (p->history) {
        const char *last = m->order[m->n_order - 1];
        if (expand_stage(p->dir, m, p->tmp, p->frame - 1, last, e)) return -1;
        if (strcmp(last, p->prev)) snprintf(dumped[n++], STAGE_NAME_SIZE, "%s", last);
    }
    snprintf(path, sizeof path, "%s/manifest.json", p->tmp);
    if (atomic_file_open(&f, path, e)) return -1;
    fprintf(f.fp, "{\"format\": \"restir-stage-dump\", \"format_version\": %u, \"image\": {\"width\": %ld, "
                  "\"height\": %ld},\n \"frames\": {\"first\": %ld, \"last\": %ld, \"written\": %ld},\n \"stage_order\": ",
            STAGE_DUMP_FORMAT_VERSION, m->width, m->height, m->first, m->last, m->last - m->first + 1);
    stage_names_put(f.fp, (char(*)[STAGE_NAME_SIZE])m->order, m->n_order);
    fprintf(f.fp, ",\n \"dumped_stages\": ");
    stage_names_put(f.fp, dumped, n);
    fprintf(f.fp, ",\n \"region_input\": {");
    put_rect(f.fp, "dumped", &m->region);
    fprintf(f.fp, ", ");
    put_rect(f.fp, "check", &p->check);
    fprintf(f.fp, ", \"stage\": ");
    json_put_string(f.fp, p->stage);
    fprintf(f.fp, ", \"history\": %d}}\n", p->history);
    return atomic_file_commit(&f, e);
}

void region_input_dir_remove(const region_input_plan *p)
{
    char path[4200];
    stage_dump_path(path, sizeof path, p->tmp, (uint32_t)p->frame, p->prev, "resv");
    remove(path);
    snprintf(path, sizeof path, "%s/frame_%04ld", p->tmp, p->frame);
    rmdir(path);
    if (p->history) {
        stage_dump_path(path, sizeof path, p->tmp, (uint32_t)(p->frame - 1), p->m->order[p->m->n_order - 1], "resv");
        remove(path);
        snprintf(path, sizeof path, "%s/frame_%04ld", p->tmp, p->frame - 1);
        rmdir(path);
    }
    snprintf(path, sizeof path, "%s/manifest.json", p->tmp);
    remove(path);
    rmdir(p->tmp);
}
