/* Fuzz target: the readers of a stage dump (docs/formats.md "Stage dumps"), picked by the
 * input's first bytes: a reservoir dump (magic RSTRRESV, src/restir/reservoir_dump.c), a
 * G-buffer dump (RSTRGBUF, gbuffer_dump_read) and otherwise the dump's manifest.json
 * (stage_manifest_read: region, halo, region_input, stage lists). One target for the three
 * because they are read together (diff-dump, --from-dump, replay) and the magic decides
 * which reader sees a file; the committed inputs of the .resv-only target stay valid. */
#include <stdlib.h>
#include <string.h>
#include "fuzz.h"
#include "restir/oracle/stage_dump.h"
#include "restir/restir/reservoir_dump.h"

static void read_reservoirs(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("input.rsv", data, size);
    reservoir *rs;
    reservoir_dump_info info;
    rerror e;
    if (!path || reservoir_dump_read(path, &rs, &info, &e)) return;
    free(rs);
}

static void read_gbuffer(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("input.gbuf", data, size);
    gbuffer g;
    uint32_t frame;
    rerror e;
    if (!path || gbuffer_dump_read(path, &g, &frame, &e)) return;
    gbuffer_free(&g);
}

/* stage_manifest_read takes the dump directory: the fuzz directory's manifest.json. */
static void read_manifest(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("manifest.json", data, size);
    char dir[128];
    const char *slash;
    stage_manifest *m;
    rerror e;
    if (!path || !(slash = strrchr(path, '/')) || (size_t)(slash - path) >= sizeof dir) return;
    memcpy(dir, path, (size_t)(slash - path));
    dir[slash - path] = '\0';
    m = malloc(sizeof *m); /* about 7 KB: off the stack */
    if (m) stage_manifest_read(dir, m, &e);
    free(m);
}

FUZZ_TARGET(dump)
{
    if (size >= 8 && !memcmp(data, RESERVOIR_DUMP_MAGIC, 8))
        read_reservoirs(data, size);
    else if (size >= 8 && !memcmp(data, GBUFFER_DUMP_MAGIC, 8))
        read_gbuffer(data, size);
    else
        read_manifest(data, size);
    return 0;
}
