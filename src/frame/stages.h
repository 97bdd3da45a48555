/* Private to src/frame. The stages of one ReSTIR PT frame (stages.c), shared by the
 * offline driver (offline.c, independent frames, GRIS §6.5) and the real-time pipeline
 * (pipeline.c, GRIS §6.3 steps 1-4). Every stage is a pass over the image in 16 x 16
 * tiles (deterministic for any thread count); `t` is the stage clock (frame_lap_ms). */
#ifndef RESTIR_SRC_FRAME_STAGES_H
#define RESTIR_SRC_FRAME_STAGES_H

#include "restir/render/camera.h"
#include "restir/render/gbuffer.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"
#include "restir/frame/stage_hook.h"

typedef struct {
    restir_stats st;
    spatial_workspace ws;
    uint32_t *nbr;           /* accepted neighbour pixels of the current pixel */
    const path_vertex **x1;  /* per domain */
    path_vertex *verts;      /* storage of the domains' primary vertices */
    const reservoir **in;    /* per domain */
    real *u;                 /* per domain */
    stochastic_workspace sw; /* stochastic pairwise MIS (stochastic_spatial.h) */
    real up[STOCHASTIC_MAX_PICKS], uc[STOCHASTIC_MAX_PICKS]; /* its pick numbers */
    struct frame_job_s *lazy_job; /* the job of the pixel being resampled (lazy_vertex) */
    int *slot;                    /* pair step: the reuse texture of each accepted neighbour */
    const pair_shift **fwd, **rev; /* pair step: the pre-pass shifts per domain (pair_shifts) */
    char pad[64];            /* keep workers' counters on separate cache lines */
} worker_state;

typedef struct frame_job_s {
    const scene *s;                  /* the frame's (posed) scene */
    const restir_options *o;
    restir_context ctx;
    initial_options io;
    neighbor_options no;
    int max_domains;
    gbuffer g;
    uint32_t frame;
    int pass;
    reservoir *initial, *pong;       /* ping-pong: pass p reads src, writes dst */
    int pss_rows;                    /* the buffers have primary-sample rows (reservoir.h) */
    const reservoir *src;
    reservoir *dst;
    const reservoir *final;          /* what the frame shades */
    int shade_cancelled;             /* frame_stage_shade did not run: the frame was cancelled */
    double *sum;                     /* 3 per pixel */
    rgb *vector_shade;               /* --shading vector: the last spatial pass's Enhanced §6.3
                                        estimate per pixel (NULL: scalar shading) */
    worker_state *workers;
    int temporal;                    /* real-time pipeline with temporal reuse (workspaces >= 2) */
    const frame_stage_hook *hook;    /* NULL, or the stage listener (stage dumps / restart) */
    reuse_cells cells;               /* o->cells: the current pass's reuse cells (reuse_cells.h) */
    reuse_transform placed[PAIRING_MAX_TEXTURES]; /* paired: this pass's placements (no.placements) */
    pair_shift *pair;                /* the pair step (restir_pair_step_active): the pre-pass's
                                        shift of pixel p to its partner in texture k at
                                        pair[k * pixels + p] (pair_step.c) */
    int *pair_n;                     /* pair step: accepted neighbours of pixel p (-1: no hit) */
    uint32_t *pair_nbr;              /* ... their pixels, pair_nbr[p * count + a] */
    unsigned char *pair_slot;        /* ... their textures */
    path_vertex *pair_x1;            /* pair step: x1 of every pixel of the frame (built once) */
} frame_job;

/* Every stage of a frame calls this once its output reservoirs `rs` are complete: their
 * samples take their explicit numbers into rs's own rows (reservoir_buffer_keep_pss; the
 * buffers they were shifted or copied from are intact until the next stage), and it dumps them and/or replaces them by a dump (restart), as j->sio says (stage_dump.h).
 * A new stage plugs into the golden-oracle kit with this one line. */
void pipeline_stage_done(frame_job *j, const char *name, reservoir *rs);
/* Restart from a dump (--from-stage S): 1 if stage `name` is not computed in this frame
 * (S, or an earlier stage the dump holds or nobody needs: stage_io_skips), so that the stage
 * skips its computation (pipeline_stage_done then reads its output from the dump). Every
 * stage runs as `if (!pipeline_stage_skipped(j, "name")) compute;` then pipeline_stage_done. */
int pipeline_stage_skipped(const frame_job *j, const char *name);

/* Milliseconds since *t, and *t reset to now. */
double frame_lap_ms(double *t);

/* GRIS §6.3 step 1: the frame's primary hits into j->g (camera cam, frame j->frame). */
int frame_stage_gbuffer(frame_job *j, const camera *cam, restir_stats *times, double *t, rerror *e);
/* GRIS §6.3 step 1: initial resampling of N path trees per pixel into j->initial. */
void frame_stage_initial(frame_job *j, restir_stats *times, double *t);
/* GRIS §6.3 step 3: K spatial passes starting from a, ping-ponging a -> b -> a ...;
 * returns the buffer that holds the last pass's output (a if K = 0). */
reservoir *frame_stage_spatial(frame_job *j, reservoir *a, reservoir *b, restir_stats *times, double *t);
/* GRIS §6.3 step 4: Le(x1) + F(Y) W_Y of `final` added into j->sum. */
void frame_stage_shade(frame_job *j, const reservoir *final, restir_stats *times, double *t);

int frame_workers_alloc(frame_job *j, rerror *e);
void frame_workers_free(frame_job *j);
/* The workers' counters summed into *st. */
void frame_sum_stats(const frame_job *j, restir_stats *st);

#endif
