/* The generated atrium (src/scene/generate_atrium.c; docs/scenes.md section 11). */
#ifndef RESTIR_SCENE_GENERATE_ATRIUM_H
#define RESTIR_SCENE_GENERATE_ATRIUM_H

#include "restir/scene/generate_rooms.h"

/* Fills a zeroed scene with the atrium (docs/scenes.md §11): a generated Sponza-like
 * interior of about a quarter of a million triangles (a courtyard between two-storey
 * arcades of fluted columns, curtains, balusters, planters), lit by a sky panel and a
 * small sun above the open courtyard; the camera stands in the courtyard. The traversal
 * yardstick's interior (issue 17). Metres. */
int generate_atrium(scene *s, rerror *e);

#endif
