/* Undoing a failed run's stage dump (stage_dump.h, stage_io_remove_written): issue 27,
 * `--dump-stages initial,bogus` left frame 0's files without a manifest behind. The stage
 * names are only known once the pipeline has run a frame, so the refusal comes after that
 * frame, and what it wrote is removed here. */
#include "restir/oracle/stage_dump_undo.h"

#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>
#include "restir/oracle/stage_dump.h"

static int remove_file(const char *path)
{
    return remove(path) == 0;
}

static int same_directory(const char *a, const char *b)
{
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int stage_io_remove_written(const stage_io *io)
{
    char path[4400];
    long f;
    int i, removed = 0;
    if (!io || !io->dump_dir) return 0;
    if (io->from_dir && same_directory(io->from_dir, io->dump_dir)) return 0;
    for (f = io->first_frame; f <= (long)io->frame; ++f) {
        stage_dump_path(path, sizeof path, io->dump_dir, (uint32_t)f, "gbuffer", "gbuf");
        removed += remove_file(path);
        for (i = 0; i < io->n_order; ++i) {
            stage_dump_path(path, sizeof path, io->dump_dir, (uint32_t)f, io->order[i], "resv");
            removed += remove_file(path);
        }
        for (i = 0; i < io->n_want; ++i) {
            stage_dump_path(path, sizeof path, io->dump_dir, (uint32_t)f, io->want[i], "resv");
            removed += remove_file(path);
        }
        snprintf(path, sizeof path, "%s/frame_%04u", io->dump_dir, (unsigned)f);
        rmdir(path); /* only if empty */
    }
    snprintf(path, sizeof path, "%s/manifest.json", io->dump_dir);
    removed += remove_file(path);
    if (io->created_dir) rmdir(io->dump_dir);
    return removed;
}
