/* A region dump as the input of one stage (docs/oracle.md §6, docs/formats.md "What each
 * stage reads"): `restir replay` and `restir inspect --from-dump` on a `--dump-region` dump.
 *
 * A stage of pixel p reads reservoirs of other pixels: the spatial neighbours (within the
 * pattern's reach, or whole reuse cells), the pair partners, the temporal source pixel in
 * frame F-1 and, with --dedup, the 17 x 17 window around it. The oracle recomputes every
 * pixel of the frame, so a replay from a region dump fills the pixels outside the dumped
 * rectangle with empty reservoirs (region_dump_expand) and accepts a pixel only if every
 * pixel its stage can read lies inside the rectangle (region_pixel_reads, checked against
 * the frame's own G-buffer by the stage listener, stage_dump.c): then its output is
 * bit-identical to the whole-image replay's. */
#ifndef RESTIR_ORACLE_REGION_INPUT_H
#define RESTIR_ORACLE_REGION_INPUT_H

#include "restir/core/error.h"
#include "restir/frame/options.h"
#include "restir/oracle/stage_dump.h"
#include "restir/render/gbuffer.h"

/* A rectangle of pixels, bounds inclusive (x1 < x0: empty). */
typedef struct {
    long x0, y0, x1, y1;
} pixel_box;

/* How far a pixel's stage reads, from the options (region_reach_for). */
typedef struct {
    int spatial;     /* a spatial pass reads pixels within this Chebyshev distance */
    int cells;       /* reuse cells (--reuse-cells): whole 8 x 8 tiles around that distance */
    int dedup;       /* --dedup: the cap at the source pixel q reads the window q +- 8 of F-1 */
    int dual;        /* --motion-vectors dual: a disoccluded pixel's source is not bounded */
} region_reach;

/* The reach of the options' stages: disk patterns round(R) (floor(R·|p| + 0.5), |p| <= 1),
 * box floor(R), paired the largest partner offset of the built reuse textures, reuse cells
 * the last search radius (30 · 1.25^11) rounded up plus one, widened to whole tiles. */
int region_reach_for(region_reach *rr, const restir_options *o, rerror *e);

/* What stage `stage` of pixel (x, y) reads from the dump (at most 2 boxes, each clipped to
 * the w x h image): the stage before it in the frame (`what` = "input") and for `temporal`
 * the previous frame's final reservoirs ("history", if history is 1). t: the pixel's texel
 * of the frame's G-buffer (after motion vectors). Returns the number of boxes, or -1 if the
 * reads are not bounded (dual motion vectors at a disoccluded pixel, an unknown stage). */
typedef struct {
    pixel_box box;
    const char *what;
} region_read;
int region_pixel_reads(const region_reach *rr, const char *stage, long w, long h, long x, long y,
                       const gbuffer_texel *t, int history, region_read out[2]);

/* Writes dst: the region file src (a reservoir dump holding rectangle r) as a whole
 * width x height dump, byte for byte inside r, empty records (docs/formats.md "Empty
 * records", confidence 0) outside. Streams: memory is one row. */
int region_dump_expand(const char *src, const stage_region *r, long width, long height, const char *dst, rerror *e);

/* The stage listener's part (stage_dump.c): keeps the texels of io->in_check at the frame's
 * G-buffer, then (at the end of the frame, with the options) refuses the first checked
 * pixel whose reads leave io->in_dumped: "frame F, stage S, pixel (x, y): reads its WHAT
 * at (qx, qy), outside the dumped rectangle ...". */
void region_input_gbuffer(stage_io *io, const gbuffer *g);
int region_input_check(stage_io *io, const restir_options *o, rerror *e);

/* The input directory of a replay of stage `stage` of frame `frame` from the region dump
 * `dir` (manifest m): tmp (an empty directory) gets the stage before it (`prev`) and, with
 * history, frame F-1's last stage expanded to the whole image, and a manifest whose
 * "region_input" asks the listener to check the pixels of `check` (docs/formats.md). */
typedef struct {
    const char *dir, *tmp, *stage, *prev;
    const stage_manifest *m;
    long frame;
    int history;
    stage_region check;
} region_input_plan;
int region_input_dir_make(const region_input_plan *p, rerror *e);
/* Removes what region_input_dir_make wrote, and tmp. */
void region_input_dir_remove(const region_input_plan *p);

#endif
