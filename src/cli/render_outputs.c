/* The collision check of every file `restir render` writes (render_outputs.h). */
#include "render_outputs.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image_io.h"
#include "collide.h"
#include "output.h"

/* The files one frame (or one --runs set) writes after PREFIX (render_sequence_runs.c,
 * render_runs.c, cmd_render.c's write_frame). */
static const char *const run_suffixes[2][4] = {{".mean.pfm", ".var.pfm", ".moments.json", ".blocks.bin"},
                                               {".mean.exr", ".var.exr", ".moments.json", ".blocks.bin"}};
static const char *const frame_suffixes[2][2] = {{".pfm", ".png"}, {".exr", ".png"}}; /* -o x.pfm, -o x.exr */

/* If `path` is one of the files frame F of the sequence writes (PREFIX.NNNN + a suffix, F
 * in first..last), its frame number; else -1. Only the name's shape is parsed, then the
 * frame's own path is built and compared, so "./s.0001.pfm" is caught too. */
static int sequence_frame_of(const char *path, const char *prefix, int first, int last,
                             const char *const *suffixes, int n_suffixes)
{
    const char *name = strrchr(path, '/'), *stem = strrchr(prefix, '/'), *p;
    char *end, built[4400];
    long frame;
    int i;
    name = name ? name + 1 : path;
    stem = stem ? stem + 1 : prefix;
    if (strncmp(name, stem, strlen(stem)) || name[strlen(stem)] != '.') return -1;
    p = name + strlen(stem) + 1;
    if (*p < '0' || *p > '9') return -1;
    frame = strtol(p, &end, 10);
    if (frame < first || frame > last) return -1;
    for (i = 0; i < n_suffixes; ++i) {
        snprintf(built, sizeof built, "%s.%04ld%s", prefix, frame, suffixes[i]);
        if (same_file(path, built)) return (int)frame;
    }
    return -1;
}

/* Another output (PNG, --stats, --checkpoint) that is one of the sequence's frame files. */
static int against_frames(const render_args *a, const char *prefix, int exr, const named_file *f)
{
    int frame;
    if (!f->path || !f->path[0]) return 0;
    frame = a->runs > 0 ? sequence_frame_of(f->path, prefix, a->seq.first, a->seq.last, run_suffixes[exr], 4)
                        : sequence_frame_of(f->path, prefix, a->seq.first, a->seq.last, frame_suffixes[exr],
                                            a->no_png ? 1 : 2);
    if (frame < 0) return 0;
    fprintf(stderr, "restir render: %s %s is a file of frame %d of --sequence %d..%d (-o %s.%s writes %s.%04d.*): one "
                    "would overwrite the other\n", f->role, f->path, frame, a->seq.first, a->seq.last, prefix,
            exr ? "exr" : "pfm", prefix, frame);
    return 2;
}

/* An output that is one of the --dump-dir tree's own files (DIR/manifest.json, anything in
 * DIR/frame_NNNN/ or DIR/run_KK/; a file directly in DIR is fine: replay writes its frame
 * there), or a dump directory overlapping --from-dump DIR (the stages being read). */
static int against_dump(const render_args *a, const named_file *f, int n)
{
    char manifest[4200], dir[4200];
    int i;
    if (!a->sio.dump_dir) return 0;
    snprintf(manifest, sizeof manifest, "%s/manifest.json", a->sio.dump_dir);
    for (i = 0; i < n; ++i) {
        const char *slash;
        if (!f[i].path || !f[i].path[0] || !path_within(f[i].path, a->sio.dump_dir)) continue;
        slash = strrchr(f[i].path, '/');
        snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - f[i].path) : 1, slash ? f[i].path : ".");
        if (same_file(f[i].path, manifest) || same_file(f[i].path, a->sio.dump_dir) || !same_file(dir, a->sio.dump_dir)) {
            fprintf(stderr, "restir render: %s %s is a file of --dump-dir %s (its manifest.json, frame_NNNN/, "
                            "run_KK/): one would overwrite the other\n", f[i].role, f[i].path, a->sio.dump_dir);
            return 2;
        }
    }
    if (a->sio.from_dir && (path_within(a->sio.dump_dir, a->sio.from_dir) || path_within(a->sio.from_dir, a->sio.dump_dir))) {
        fprintf(stderr, "restir render: --dump-dir %s and --from-dump %s overlap: the new dump would overwrite the "
                        "stages it reads\n", a->sio.dump_dir, a->sio.from_dir);
        return 2;
    }
    return 0;
}

int render_outputs_distinct(const render_args *a, const char *out, const char *png)
{
    char prefix[4096], runs[4][4200];
    named_file outs[8], ins[2];
    int n = 0, i, exr = image_path_is(out, "exr");
    output_prefix(prefix, sizeof prefix, out);
    if (a->runs > 0 && !a->sequence)
        for (i = 0; i < 4; ++i) {
            snprintf(runs[i], sizeof runs[i], "%s%s", prefix, run_suffixes[exr][i]);
            outs[n].path = runs[i], outs[n++].role = "-o";
        }
    else if (!a->sequence)
        outs[n].path = out, outs[n++].role = "-o";
    outs[n].path = png, outs[n++].role = "the PNG preview";
    outs[n].path = a->stats, outs[n++].role = "--stats";
    outs[n].path = a->pt.o.checkpoint_path, outs[n++].role = "--checkpoint";
    ins[0].path = a->sio.scene_path, ins[0].role = "the scene";
    ins[1].path = a->pt.o.resume_path, ins[1].role = "--resume";
    if (outputs_distinct("render", outs, n, ins, 2, a->pt.o.resume_path)) return 2;
    if (a->sequence)
        for (i = 0; i < n; ++i)
            if (against_frames(a, prefix, exr, &outs[i])) return 2;
    if (a->sequence) { /* the frames themselves must not land in the dump either */
        char frame0[4200];
        named_file f;
        snprintf(frame0, sizeof frame0, "%s.%04d%s", prefix, a->seq.first, a->runs > 0 ? run_suffixes[exr][0] : frame_suffixes[exr][0]);
        f.path = frame0, f.role = "the frame";
        if (against_dump(a, &f, 1)) return 2;
    }
    return against_dump(a, outs, n);
}
