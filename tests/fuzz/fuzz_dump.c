/* Fuzz target: the reservoir-dump reader (src/restir/reservoir_dump.c, docs/formats.md). */
#include <stdlib.h>
#include "fuzz.h"
#include "restir/restir/reservoir_dump.h"

FUZZ_TARGET(dump)
{
    const char *path = fuzz_write_file("input.rsv", data, size);
    reservoir *rs;
    reservoir_dump_info info;
    rerror e;
    if (!path || reservoir_dump_read(path, &rs, &info, &e)) return 0;
    free(rs);
    return 0;
}
