/* Memory per pixel (issue 17, docs/performance.md "Memory per pixel"): the primary-sample
 * vector of MCMC mutations lives out of line (path_sample.h: pss points into the rows of a
 * reservoir buffer, reservoir.h), which must not change a bit of any output.
 *
 * The checksums below were recorded with main at 288619d, BEFORE the vector left the
 * struct (pss[45] inside every path_sample), for the double and the float build. They
 * cover every place a mutated sample is copied: temporal and spatial reuse (shifts copy
 * samples by value), the paired spatial step's pre-pass records, the mutation stages
 * after initial, temporal and spatial resampling, the stage dumps (whose records carry the
 * 45 numbers: the dump format is unchanged), a checkpoint and its resume, and a restart
 * from a stage dump (--from-dump). Fixed seed 3 on purpose (SEED= does not apply). */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include "restir/core/checksum.h"
#include "restir/frame/options.h"
#include "restir/frame/frame_stats.h"
#include "restir/restir/reservoir.h"
#include "test.h"

/* CRC-32 of the files' bytes, concatenated in the order given (space-separated names
 * relative to dir); 0 and *missing set if one cannot be read. */
static uint32_t files_crc(const char *dir, const char *names, int *missing)
{
    char list[1024], path[2048], *name, *save = NULL;
    unsigned char buf[4096];
    uint32_t crc = 0;
    snprintf(list, sizeof list, "%s", names);
    for (name = strtok_r(list, " ", &save); name; name = strtok_r(NULL, " ", &save)) {
        FILE *f;
        size_t n;
        snprintf(path, sizeof path, "%s/%s", dir, name);
        if (!(f = fopen(path, "rb"))) {
            *missing = 1;
            return 0;
        }
        while ((n = fread(buf, 1, sizeof buf, f)) > 0) crc = crc32_update(crc, buf, n);
        fclose(f);
    }
    return crc;
}

typedef struct {
    const char *name, *scene, *args, *files;
    uint32_t crc_double, crc_float; /* recorded on main before the change, per PRECISION */
} recorded_sequence;

#define FRAMES3 "img.0000.pfm img.0001.pfm img.0002.pfm"
/* Issue 26 made every mutation pass a dump stage of its own (mutate-initial, -temporal,
 * -spatial): `temporal.resv` now holds the reservoirs before the chains and the old
 * post-mutation dump is `mutate-temporal.resv`, equal to the recorded one but for its 16-byte
 * tag. The two dump cases (rv, fp) were therefore re-recorded with the new stage files after
 * checking, against the binary before that change, that every frame is byte-identical and
 * each mutate-X.resv differs from the old X.resv in the tag bytes only; the other cases
 * (frames, checkpoint, resume, restart) keep the checksums recorded at 288619d. */
#define DUMPS(f)                                                                                                      \
    "dump/frame_000" f "/initial.resv dump/frame_000" f "/temporal.resv dump/frame_000" f                              \
    "/mutate-temporal.resv dump/frame_000" f "/spatial1.resv"
#define FP_DUMPS(f)                                                                                                   \
    "dump/frame_000" f "/initial.resv dump/frame_000" f "/mutate-initial.resv dump/frame_000" f                        \
    "/spatial1.resv dump/frame_000" f "/mutate-spatial.resv"

TEST(mutation_sequences_bit_identical_to_recorded)
{
    /* @D is the case's output directory; the cases run in this order (ckpt before resume,
     * rv's dump before restart). */
    static const recorded_sequence cases[] = {
        {"rv", "cornell", "--mutations 3 --sequence 0..2 --dump-dir @D/dump",
         FRAMES3 " " DUMPS("0") " " DUMPS("1") " " DUMPS("2"), 0xcd9288beu, 0x6a31e66bu},
        {"pp-all", "cornell-glossy", "--mutations 2 --mutation pp --mutate-after initial,temporal,spatial "
                   "--sequence 0..2",
         FRAMES3, 0x1f290017u, 0x035366a1u},
        {"fp", "glass", "--mutations 2 --mutation fp --mutate-after initial,spatial --sequence 0..2 "
               "--dump-dir @D/dump",
         FRAMES3 " " FP_DUMPS("1"), 0x53aa24ffu, 0x11787ceau},
        {"paired", "cornell-glossy", "--mutations 2 --pairing paired --spatial-passes 2 --sequence 0..2",
         FRAMES3, 0x61e714c0u, 0x34ca95aeu},
        {"ckpt", "cornell", "--mutations 3 --sequence 0..1 --checkpoint @D/c.ckpt",
         "img.0000.pfm img.0001.pfm c.ckpt", 0x0f36c9ddu, 0x262cd767u},
        {"resume", "cornell", "--mutations 3 --sequence 0..2 --resume @P/ckpt/c.ckpt", "img.0002.pfm", 0x46a44109u,
         0xf8eea1b9u},
        {"restart", "cornell", "--mutations 3 --sequence 0..2 --from-dump @P/rv/dump --from-stage temporal",
         FRAMES3, 0x1281f1abu, 0x589f674du},
    };
    char out[4096], args[2048], dir[1100], parent[1024];
    size_t i;
    snprintf(parent, sizeof parent, "%s", test_tmp_path("memory-mutations"));
    for (i = 0; i < sizeof cases / sizeof cases[0] && !test_has_failed(); ++i) {
        const recorded_sequence *c = &cases[i];
        uint32_t want = sizeof(real) == sizeof(double) ? c->crc_double : c->crc_float, got;
        const char *a;
        size_t n = 0;
        int missing = 0;
        snprintf(dir, sizeof dir, "%s/%s", parent, c->name);
        for (a = c->args; *a && n + 1100 < sizeof args; ++a) /* @D: this case's directory, @P: the parent */
            if (a[0] == '@' && (a[1] == 'D' || a[1] == 'P')) {
                n += (size_t)snprintf(args + n, sizeof args - n, "%s", a[1] == 'D' ? dir : parent);
                ++a;
            } else {
                args[n++] = *a;
            }
        args[n] = '\0';
        CHECKF(mkdir(parent, 0777) == 0 || errno == EEXIST, "%s: %s", parent, strerror(errno));
        CHECKF(mkdir(dir, 0777) == 0 || errno == EEXIST, "%s: %s", dir, strerror(errno));
        CHECKF(test_cli(out, sizeof out, "render scenes/%s.scene --method restir --preset gris-realtime %s --size 40x32 "
                                         "--seed 3 --threads 2 --no-png -o '%s/img.pfm'",
                        c->scene, args, dir) == 0,
               "%s: %s", c->name, out);
        got = files_crc(dir, c->files, &missing);
        CHECKF(!missing, "%s: an output of %s is missing", c->name, c->files);
        CHECKF(got == want, "%s: outputs' CRC-32 %08x, recorded before the vector left the struct %08x", c->name,
               (unsigned)got, (unsigned)want);
    }
}

/* Issue 17: the reservoir state of the real-time configuration is at most 256 B per pixel
 * (224 B double, 152 B float; room for a field or two more), and only mutation runs pay
 * for the primary-sample rows (--stats bytes_per_pixel). */
TEST(reservoir_state_at_most_256_bytes)
{
    restir_options o;
    restir_memory m;
    CHECKF(sizeof(reservoir) <= 256, "sizeof(reservoir) = %u", (unsigned)sizeof(reservoir));
    restir_options_default(&o);
    restir_options_preset_gris_realtime(&o);
    restir_memory_per_pixel(&o, 1, &m);
    CHECK(m.reservoir == sizeof(reservoir) && m.reservoir_pss == 0);
    CHECK(m.reservoirs_initial == m.reservoir && m.reservoirs_spatial == m.reservoir && m.reservoirs_previous == m.reservoir);
    o.mutation.count = 1;
    restir_memory_per_pixel(&o, 1, &m);
    CHECK(m.reservoir_pss == PATH_MAX_PSS * sizeof(real) && m.reservoirs_previous == m.reservoir + m.reservoir_pss);
}
