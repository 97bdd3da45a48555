/* The render command's option table (src/cli/render_table.h). */
#include "render_table.h"

#include <string.h>
#include "restir/core/progress.h"

/* Appends the ReSTIR rows. --max-depth, --time-limit, --checkpoint and --resume exist for
 * more than one method: the path tracer's rows stay (with help for both), restir's copies
 * are dropped and apply_shared_options() hands the values over. */
static int add_restir_rows(cli_option *options, int n, render_args *a)
{
    cli_option rows[RENDER_RESTIR_OPTION_ROWS];
    int i, j, count = render_restir_options(rows, &a->restir, &a->restir_flags);
    for (i = 0; i < n; ++i) {
        if (!strcmp(options[i].name, "--max-depth"))
            options[i].help = "maximum path length d in segments (2 = direct light; pt: 1..255, restir: 2..16; default 10)";
        if (!strcmp(options[i].name, "--checkpoint"))
            options[i].help = "pt: write the accumulation state here at the end and on SIGINT/SIGTERM; restir "
                              "--sequence: the previous-frame state after every frame";
        if (!strcmp(options[i].name, "--resume"))
            options[i].help = "pt: continue this checkpoint up to --spp; restir --sequence: continue after its frame";
        if (!strcmp(options[i].name, "--time-limit"))
            options[i].help = "pt: whole 1-spp passes, restir: whole frames until SECONDS have passed (restir: --frames ignored)";
    }
    for (j = 0; j < count; ++j) {
        int duplicate = 0;
        for (i = 0; i < n; ++i) duplicate |= !strcmp(options[i].name, rows[j].name);
        if (!duplicate) options[n++] = rows[j];
    }
    return n;
}

int render_table_build(cli_option *options, render_args *a, method_rows *methods)
{
    int n = 0, count;
    {
        const cli_option rows[] = {
            {"-o", OPT_STRING, &a->output, "output image, PFM or .exr (OpenEXR, float, ZIP) (default out/<scene>.pfm)", NULL, 0, 0, NULL},
            {"--png", OPT_STRING, &a->png, "PNG preview path (default: the PFM path with .png)", NULL, 0, 0, NULL},
            {"--no-png", OPT_FLAG, &a->no_png, "do not write the PNG preview", NULL, 0, 0, NULL},
            {"--exposure", OPT_REAL, &a->exposure, "preview exposure in stops (default 0)", NULL, -64, 64, NULL},
            {"--method", OPT_CHOICE, &a->method, "rendering method", method_names, 0, 0, NULL},
            {"--aov", OPT_CHOICE, &a->aov, "G-buffer channel for --method aov (encodings: docs/cli.md); --method restir: duplicates, per pixel the copies of its sample in its 17x17 window (PNG: heat map, black 0 .. red >= 20%), or age (--sequence): frames of temporal history per pixel (0: none)", aov_choices, 0, 0, NULL},
            {"--seed", OPT_UINT32, &a->seed, "run seed of the addressed RNG (default 1)", NULL, 0, 0, NULL},
            {"--threads", OPT_INT, &a->threads, "worker threads (default: online cores; 1 = no threads)", NULL, 1, 256,
             NULL},
            {"--frame", OPT_INT, &a->frame, "frame index (camera keyframes)", NULL, 0, 1e9, NULL},
            {"--jitter", OPT_FLAG, &a->jitter, "jittered sub-pixel primary rays (default: pixel centres)", NULL, 0, 0,
             NULL},
            {"--runs", OPT_INT, &a->runs, "K >= 2 independent runs (seeds seed..seed+K-1; a variance needs two): writes PREFIX.mean.pfm, PREFIX.var.pfm, PREFIX.moments.json for restir check", NULL, 2, 1e6, NULL},
            {"--sequence", OPT_STRING, &a->sequence, "A..B: the real-time pipeline (restir) over frames A..B inclusive, one -o NAME.pfm -> NAME.0000.pfm ... per frame (NAME.0000.exr ... for -o NAME.exr)", NULL, 0, 0, NULL},
            {"--accumulate", OPT_FLAG, &a->accumulate, "with --sequence: frame f's file holds the average of frames A..f (a still camera, GRIS 6.4)", NULL, 0, 0, NULL},
            {"--mcap", OPT_STRING, &a->mcap, "with --sequence: cap the previous frame's confidence at C x the current one's (C > 0 or inf; default 20, GRIS 6.2)", NULL, 0, 0, NULL},
            {"--no-temporal", OPT_FLAG, &a->no_temporal, "with --sequence: no temporal reuse (independent frames through the same pipeline)", NULL, 0, 0, NULL},
            {"--dump-dir", OPT_STRING, &a->sio.dump_dir, "with --sequence: write DIR/manifest.json and per frame the G-buffer and the reservoirs after each stage (docs/oracle.md)", NULL, 0, 0, NULL},
            {"--dump-stages", OPT_STRING, &a->dump_stages, "with --dump-dir: only these stages, e.g. initial,temporal,spatial1 (default: all)", NULL, 0, 0, NULL},
            {"--dump-region", OPT_STRING, &a->dump_region, "with --dump-dir: dump only the pixels of the rectangle X,Y,W,H (docs/oracle.md)", NULL, 0, 0, NULL},
            {"--dump-halo", OPT_INT, &a->dump_halo, "with --dump-region: also dump N pixels around it (clipped to the image), so that restir replay and inspect --from-dump can recompute the rectangle's stages from the dump (docs/oracle.md section 6)", NULL, 0, 4096, NULL},
            {"--from-dump", OPT_STRING, &a->sio.from_dir, "with --sequence: restart from this stage dump (needs --from-stage)", NULL, 0, 0, NULL},
            {"--from-stage", OPT_STRING, &a->from_stage, "with --from-dump: replace stage S's output of every frame by the dumped one; later stages run on it", NULL, 0, 0, NULL},
            {"--history-from-dump", OPT_FLAG, &a->history_from_dump, "with --from-dump: the previous frame's final reservoirs come from the dump (frame A-1's last stage), not from this run (docs/oracle.md)", NULL, 0, 0, NULL},
            {"--stats", OPT_STRING, &a->stats, "write timings and counters as JSON", NULL, 0, 0, NULL},
            {"--quiet", OPT_FLAG, &a->quiet, "no progress or messages on stderr", NULL, 0, 0, NULL},
            {"--progress", OPT_CHOICE, &a->progress, "auto (default: a bar on a terminal, plain lines with the ETA otherwise), none, bar or lines", progress_mode_names, 0, 0, NULL},
            {"--progress-every", OPT_REAL, &a->progress_every, "seconds between two progress lines (default 5)", NULL, 0.01, 3600, NULL},
            {"--ablate", OPT_STRING, &a->ablate, "a deliberately broken estimator: pt: light-pdf|mis-sum|mis-lobe|light-ris-pdf, restir: jacobian|light-pdf|...", NULL, 0, 0, NULL},
        };
        for (n = 0; n < (int)(sizeof rows / sizeof rows[0]); ++n) options[n] = rows[n];
    }
    n += scene_override_options(options + n, &a->overrides);
    methods[0].first = n;
    methods[0].method = METHOD_PT;
    n += render_pt_options(options + n, &a->pt);
    methods[0].end = n;
    options[n++] = render_restir_preset_row(&a->preset);
    methods[1].first = n - 1;
    methods[1].method = METHOD_RESTIR;
    n = add_restir_rows(options, n, a);
    methods[1].end = n;
    memset(&options[n], 0, sizeof options[n]);
    for (count = 0; count < n; ++count)
        if (!strcmp(options[count].name, "--aov")) methods[2].first = count, methods[2].end = count + 1;
    methods[2].method = METHOD_AOV;
    return n;
}
