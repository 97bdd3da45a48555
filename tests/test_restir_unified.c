/* Unified direct + indirect reservoirs (Enhanced §6.1): with --paths all (the default)
 * the candidates of one reservoir include direct-only paths (d = 2) and longer ones, and
 * both kinds are selected; with --paths indirect no d = 2 path is. */
#include <string.h>
#include "restir_util.h"
#include "test.h"
#include "restir/frame/offline.h"
#include "restir/frame/options.h"

static int selections(const scene *s, int paths, uint64_t *direct, uint64_t *longer)
{
    restir_options o;
    restir_result r;
    rerror e;
    int d;
    restir_options_default(&o);
    o.paths = paths;
    o.max_depth = 4;
    o.candidates = 2;
    o.spatial_passes = 1;
    o.threads = 2;
    o.seed = test_seed();
    if (restir_render(s, &o, &r, &e)) {
        test_fail(__FILE__, __LINE__, "restir_render: %s", e.msg);
        return -1;
    }
    *direct = r.stats.initial.length[2];
    *longer = 0;
    for (d = 3; d <= PATH_MAX_LENGTH; ++d) *longer += r.stats.initial.length[d];
    restir_result_free(&r);
    return 0;
}

TEST(restir_unified_direct_and_indirect_selected)
{
    scene s;
    uint64_t direct = 0, longer = 0;
    if (rt_load_scene("scenes/cornell.scene", 16, &s)) return;
    if (selections(&s, RESTIR_PATHS_ALL, &direct, &longer) == 0)
        CHECKF(direct > 0 && longer > 0, "--paths all: %lu direct (d = 2) and %lu longer selections",
               (unsigned long)direct, (unsigned long)longer);
    if (selections(&s, RESTIR_PATHS_INDIRECT, &direct, &longer) == 0)
        CHECKF(direct == 0 && longer > 0, "--paths indirect: %lu direct (d = 2) selections", (unsigned long)direct);
    scene_free(&s);
}
