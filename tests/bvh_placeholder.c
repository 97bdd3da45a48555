/* TEMPORARY, for the sceneio branch alone: scene_free() calls bvh_free(), which the BVH
 * branch provides. This weak no-op lets the tests link before that branch is merged; a
 * real bvh_free (strong symbol) replaces it automatically. Delete after the merge. */
#include "restir/bvh.h"

#ifdef __GNUC__
__attribute__((weak)) void bvh_free(bvh *b) { (void)b; }
#endif
