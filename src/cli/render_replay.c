/* --history-from-dump and the pixel trace of inspect --from-dump (render_replay.h). */
#include "render_replay.h"

#include <stdio.h>
#include <string.h>
#include "restir/restir/mutate.h"

const render_trace_request *render_trace = NULL;

/* The previous frame's final state as the dump has it: DIR/frame_{A-1}/LAST.resv. */
static int history_file(render_args *a)
{
    stage_manifest m;
    rerror e;
    const char *last;
    FILE *fp;
    if (!a->sio.from_dir) {
        fprintf(stderr, "restir render: --history-from-dump needs --from-dump DIR\n");
        return 2;
    }
    if (a->seq.resume) {
        fprintf(stderr, "restir render: --history-from-dump and --resume both give the previous frame's state\n");
        return 2;
    }
    if (stage_manifest_read(a->sio.from_dir, &m, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    last = m.order[m.n_order - 1];
    if (a->seq.first < 1 || a->seq.first - 1 < m.first || a->seq.first - 1 > m.last) {
        fprintf(stderr, "restir render: --history-from-dump: %s/manifest.json has frames %ld..%ld, not frame %d (the one before --sequence %d..)\n",
                a->sio.from_dir, m.first, m.last, a->seq.first - 1, a->seq.first);
        return 2;
    }
    if (a->restir.mutation.count > 0 && (a->restir.mutation.stages & MUTATE_AFTER_SPATIAL)) {
        /* the shaded reservoirs are mutated after the last dumped stage: no dump holds them */
        fprintf(stderr, "restir render: --history-from-dump: with --mutate-after spatial the final reservoirs are "
                        "not in any dump (the mutation after '%s' is not a stage)\n", last);
        return 2;
    }
    if (!stage_manifest_dumped(&m, last)) {
        fprintf(stderr, "restir render: --history-from-dump: %s/manifest.json: the last stage '%s' (the previous frame's final state) is not dumped\n",
                a->sio.from_dir, last);
        return 2;
    }
    stage_dump_path(a->history_path, sizeof a->history_path, a->sio.from_dir, (uint32_t)(a->seq.first - 1), last, "resv");
    fp = fopen(a->history_path, "rb");
    if (!fp) {
        fprintf(stderr, "restir render: --history-from-dump: %s: cannot open (frame %d's final state)\n", a->history_path,
                a->seq.first - 1);
        return 2;
    }
    fclose(fp);
    a->seq.resume = a->history_path;
    a->seq.resume_foreign = 1;
    return 0;
}

/* The frame hands the trace to the hook's user (the stage_io): pass it on to the request. */
static void trace_adapter(void *user, const pixel_trace *t)
{
    (void)user;
    if (render_trace) render_trace->fn(render_trace->user, t);
}

/* The stage listener's own `reservoirs` (the stage_io's), wrapped to see the traced pixel's
 * record of each complete stage output. */
static void (*listener_reservoirs)(void *user, const char *stage, reservoir *rs, int width, int height);

static void reservoirs_adapter(void *user, const char *stage, reservoir *rs, int width, int height)
{
    if (listener_reservoirs) listener_reservoirs(user, stage, rs, width, height);
    if (render_trace && render_trace->stage_output && render_trace->pixel < (long)width * height)
        render_trace->stage_output(render_trace->user, stage, &rs[render_trace->pixel]);
}

int apply_replay_options(render_args *a)
{
    int status;
    if (a->history_from_dump && (status = history_file(a)) != 0) return status;
    if (render_trace) {
        a->hook.pixel = trace_adapter;
        a->hook.trace_pixel = render_trace->pixel;
        listener_reservoirs = a->hook.reservoirs;
        a->hook.reservoirs = reservoirs_adapter;
    }
    return 0;
}
