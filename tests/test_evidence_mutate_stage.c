/* Mutation as a dump stage of its own (issue 26; src/frame/pipeline.c stage_mutate): with
 * mutations on, each mutation pass reports "mutate-initial", "mutate-temporal" or
 * "mutate-spatial" after the stage it mutates, so the dumps hold the reservoirs before and
 * after the chains; restart from a mutation stage is byte-identical to the uninterrupted
 * run, and diff-dump locates a broken mutation (the deliberately biased `--ablate
 * mutation-w`, W kept on acceptance) at that stage, the stages before it identical. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "dump_util.h"
#include "test.h"

static char out[262144];

/* pillars: animated camera, 3 frames, temporal + 1 spatial pass, rv mutations after the
 * temporal and the spatial pass */
#define MS_COMMON                                                                                               \
    "scenes/pillars.scene --method restir --preset gris-realtime --spatial-passes 1 --size 32x24 --sequence 0..2 " \
    "--mutations 2 --mutate-after temporal,spatial --quiet --no-png --threads 2"

static const char *ms_dir(const char *name) { return dump_scratch("mstage_", name); }

static int ms_reference(void)
{
    dump_once(MS_COMMON, ms_dir("a.pfm"), ms_dir("A"));
    return !test_has_failed();
}

TEST(evidence_mutate_stage_order_and_restart)
{
    char path[1200], fa[1200], fb[1200], *manifest;
    static const char *const stages[] = {"mutate-temporal", "mutate-spatial"};
    int i, f;
    if (!ms_reference()) return;
    snprintf(path, sizeof path, "%s/manifest.json", ms_dir("A"));
    manifest = test_read_text(path);
    CHECKF(manifest && strstr(manifest, "\"stage_order\": [\"initial\", \"temporal\", \"mutate-temporal\", "
                                        "\"spatial1\", \"mutate-spatial\"]"),
           "%s", manifest ? manifest : "(no manifest)");
    free(manifest);
    for (i = 0; i < 2; ++i) {
        char name[64];
        snprintf(name, sizeof name, "R_%s", stages[i]);
        CHECKF(test_cli(out, sizeof out, "render " MS_COMMON " -o %s.pfm --from-dump %s --from-stage %s --dump-dir %s",
                        ms_dir(name), ms_dir("A"), stages[i], ms_dir(name)) == 0,
               "%s", out);
        for (f = 0; f <= 2; ++f) {
            snprintf(fa, sizeof fa, "%s.%04d.pfm", ms_dir("a"), f);
            snprintf(fb, sizeof fb, "%s.%04d.pfm", ms_dir(name), f);
            CHECKF(test_files_equal(fa, fb), "restart from %s: frame %d differs", stages[i], f);
        }
        CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", ms_dir("A"), ms_dir(name)) == 0, "restart from %s:\n%s",
               stages[i], out);
    }
}

/* A broken mutation (no Eq. 16 W update) run with the same seed: the first difference is
 * frame 0, stage mutate-temporal; initial and temporal are identical in every frame
 * (frame 0's temporal has no history; frames 1, 2 read the broken frame's output, so only
 * frame 0's pre-mutation stages are guaranteed equal). */
TEST(evidence_mutate_stage_diff_dump_locates_broken_mutation)
{
    if (!ms_reference()) return;
    CHECKF(test_cli(out, sizeof out, "render " MS_COMMON " --ablate mutation-w -o %s.pfm --dump-dir %s", ms_dir("w"),
                    ms_dir("W")) == 0,
           "%s", out);
    CHECKF(test_cli(out, sizeof out, "diff-dump %s %s", ms_dir("A"), ms_dir("W")) == 1, "%s", out);
    CHECKF(strstr(out, "first difference: frame 0, stage mutate-temporal") != NULL, "%s", out);
    CHECKF(strstr(out, "frame    0 initial      same 1.000000") && strstr(out, "frame    0 temporal     same 1.000000"),
           "%s", out);
}
