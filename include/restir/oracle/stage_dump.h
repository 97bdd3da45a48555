/* Per-stage dumps of the real-time pipeline and restart from them: the golden-oracle kit
 * (docs/oracle.md; file layout in docs/formats.md "Stage dumps").
 *
 *   DIR/manifest.json                    what produced the dump (format version, scene file
 *                                        and its CRC-32, every effective option, seed, frames,
 *                                        stage order, RNG spec version)
 *   DIR/frame_NNNN/gbuffer.gbuf          the frame's G-buffer (docs/formats.md)
 *   DIR/frame_NNNN/STAGE.resv            the reservoirs after stage STAGE (reservoir dump,
 *                                        tag STAGE, frame NNNN)
 *
 * Stages are named by the pipeline itself: every stage calls pipeline_stage_done(job,
 * "name", reservoirs) once its output is complete (src/frame/stages.h), so a new stage (mutate,
 * paired spatial, ...) plugs into dumps, restart and diff-dump with that one line. The
 * stage order in the manifest is the order of those calls in the first frame.
 *
 * Restart (--from-dump DIR --from-stage S): stage S and the stages before it (in DIR's
 * manifest order) are not computed (stage_io_skips); S's output is DIR/frame_f/S.resv, so
 * every later stage runs on the dumped reservoirs.
 * All RNG is addressed (docs/rng.md), so restarting from our own dump is bit-identical to
 * the uninterrupted run; a GPU build hands its pass-S output to the oracle the same way. */
#ifndef RESTIR_STAGE_DUMP_H
#define RESTIR_STAGE_DUMP_H

#include <stdio.h>
#include "restir/frame/stage_hook.h"
#include "restir/render/gbuffer.h"
#include "restir/restir/reservoir_dump.h"

#define STAGE_DUMP_FORMAT_VERSION 1u
#define RNG_SPEC_VERSION 1u /* docs/rng.md as of this format; bump when an address or the hash changes */
#define STAGE_MAX 40                            /* stages per frame */
#define STAGE_NAME_SIZE (RESERVOIR_DUMP_TAG_SIZE + 1) /* a stage name is a dump tag */
#define GBUFFER_DUMP_MAGIC "RSTRGBUF"
#define GBUFFER_DUMP_VERSION 1u
#define GBUFFER_DUMP_HEADER_SIZE 32u
#define GBUFFER_DUMP_RECORD_SIZE 108u

/* A rectangle of pixels (--dump-region X,Y,W,H): a region dump holds only these pixels'
 * records, row-major within the rectangle (docs/formats.md "Stage dumps"). */
typedef struct {
    long x, y, width, height; /* width = 0: no region (the whole image) */
} stage_region;

/* Parses "X,Y,W,H" (W, H > 0). */
int stage_region_parse(const char *text, stage_region *r, rerror *e);

typedef struct stage_io_s {
    /* configuration (the CLI fills these) */
    const char *dump_dir;                  /* NULL: no dumps */
    char want[STAGE_MAX][STAGE_NAME_SIZE]; /* --dump-stages; n_want = 0: every stage */
    int n_want;
    const char *from_dir;                  /* NULL: no restart */
    char from_stage[STAGE_NAME_SIZE];
    char from_order[STAGE_MAX][STAGE_NAME_SIZE]; /* the stage order of from_dir's manifest */
    int n_from_order;
    const char *scene_path;                /* for the manifest (hashed) */
    int argc;                              /* the command line, for the manifest (argv may be NULL) */
    char **argv;
    /* state */
    char order[STAGE_MAX][STAGE_NAME_SIZE]; /* stage order seen in the first frame */
    int n_order, frames_done, first_frame, last_frame, restarted;
    int width, height;                     /* image size (from the first stage) */
    uint32_t frame;                        /* the frame in progress */
    int failed;
    rerror err;                            /* the first failure (sticky) */
    int created_dir;                       /* stage_io_begin created dump_dir (stage_io_remove_written) */
    int pss_rows;                          /* set by the pipeline: its reservoir buffers have
                                              primary-sample rows (reservoir.h) */
    stage_region region;                   /* --dump-region (width 0: the whole image) */
    /* restart: the read stage file whose records most lack reconnection data (rc_k = 0 or a
       zero Jacobian source term), checked against the shift at the frame's end */
    long rc_missing, rc_nonempty;
    char rc_missing_path[4200];
    /* --dump-halo N: the files hold `region` grown by N pixels on each side (clipped to the
       image); `core` is the rectangle asked for (region_input.h, docs/oracle.md §6) */
    long halo;
    stage_region core;
    /* a region dump as the input of one stage (restir replay / inspect --from-dump, from the
       restart dump's manifest "region_input"; region_input.h): the pixels of in_check must
       read only pixels of in_dumped in stage in_stage (in_history: with frame F-1's state) */
    stage_region in_dumped, in_check;
    char in_stage[STAGE_NAME_SIZE];
    int in_history, in_image_w, in_image_h;
    void *in_texels; /* gbuffer_texel[in_check]: kept from the frame's G-buffer until its end */
} stage_io;

/* *hook calls io's functions below at the frame's stage boundaries (frame/stage_hook.h);
 * io must outlive the sequence. */
void stage_io_hook(stage_io *io, frame_stage_hook *hook);

/* What restart and diff-dump read of a dump's manifest.json. */
typedef struct {
    char order[STAGE_MAX][STAGE_NAME_SIZE]; /* "stage_order" */
    int n_order;
    long first, last, seed;                 /* "frames" {first, last}, "seed" */
    long written;                           /* "frames" {written}: frames dumped (-1 if absent) */
    char scene[4096];                       /* "scene" {path} ("" if absent) */
    long width, height;                     /* "image" (0 if absent) */
    char inspect_args[1024];                /* " --size WxH --shift hybrid --mis ...": what
                                               `restir inspect` needs besides --pixel, --seed
                                               and --first-frame to print a pixel's initial sample */
    char dumped[STAGE_MAX][STAGE_NAME_SIZE]; /* "dumped_stages" */
    int n_dumped;                           /* -1: the key is absent (then every stage is dumped) */
    stage_region region;                    /* "region" (width 0: absent or null: the whole image) */
    long halo;                              /* "halo" {"pixels"} (0 if absent) */
    stage_region core;                      /* "halo" {"core"}: the rectangle asked for (width 0: absent) */
    stage_region in_dumped, in_check;       /* "region_input" {"dumped", "check"} (width 0: absent) */
    char in_stage[STAGE_NAME_SIZE];         /* "region_input" {"stage"} */
    long in_history;                        /* "region_input" {"history"} */
} stage_manifest;

/* 1 if the manifest lists stage `name` as dumped (every stage when "dumped_stages" is absent). */
int stage_manifest_dumped(const stage_manifest *m, const char *name);

/* Reads DIR/manifest.json ("format" must be "restir-stage-dump"; other keys are skipped). */
int stage_manifest_read(const char *dir, stage_manifest *m, rerror *e);

/* Restart: 1 if stage `name` of the current frame is not computed. The dump's stage order
 * (its manifest) decides: S = --from-stage is read from the dump; an earlier stage is read
 * from the dump if it has the file, else computed only if this run dumps it (so that its
 * own dump is complete; nothing after S reads it); later stages run. */
int stage_io_skips(const stage_io *io, const char *name);

/* Parses a comma-separated stage list ("initial,spatial1") into io->want. */
int stage_io_set_stages(stage_io *io, const char *list, rerror *e);
/* Before the first frame: creates the dump directory. */
int stage_io_begin(stage_io *io, int first, int last, rerror *e);
/* The frame in progress (called by the pipeline at the start of each frame). */
void stage_io_frame_begin(stage_io *io, uint32_t frame);
/* After each frame: reports a sticky failure of the frame's hooks, checks that the
 * requested stages exist, and (re)writes the manifest (o: the effective options). */
int stage_io_frame_end(stage_io *io, const void *restir_opts, rerror *e);
/* The hook of each stage (see above): dump and/or restart. Failures are sticky in io. */
void stage_io_reservoirs(stage_io *io, const char *name, reservoir *rs, int width, int height);
/* The G-buffer of the frame in progress (after motion vectors). */
void stage_io_gbuffer(stage_io *io, const gbuffer *g);

/* G-buffer dump files (docs/formats.md). */
int gbuffer_dump_write(const char *path, const gbuffer *g, uint32_t frame, rerror *e);
int gbuffer_dump_read(const char *path, gbuffer *g, uint32_t *frame, rerror *e);

/* A JSON array of the n stage names (a manifest's stage_order, dumped_stages). */
void stage_names_put(FILE *fp, char names[][STAGE_NAME_SIZE], int n);

/* Path of DIR/frame_NNNN/NAME.EXT into buf. */
void stage_dump_path(char *buf, size_t size, const char *dir, uint32_t frame, const char *name, const char *ext);

#endif
