/* Private to src/oracle. The JSON form of restir inspect (src/oracle/inspect_json.c): the same
 * numbers as the text, at 17 significant digits. */
#ifndef RESTIR_SRC_ORACLE_INSPECT_JSON_H
#define RESTIR_SRC_ORACLE_INSPECT_JSON_H

#include "inspect_step.h"

/* The whole inspection as one JSON object (xa, xb, g, tg may be NULL: absent). */
void inspect_print_json(FILE *out, const restir_context *c, const restir_options *o, int x, int y, int nx, int ny,
                        const path_vertex *xa, const path_vertex *xb, const reservoir *r, const inspect_step *g,
                        const inspect_step *tg);

#endif
