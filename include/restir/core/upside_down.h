/* The upside-down check of `compare` and `check` (issue 29): some renderers write PFM
 * with the top row first, while PFM stores the bottom row first; read as standard PFM
 * such an image comes out upside down, and every metric against a reference is absurd. */
#ifndef RESTIR_UPSIDE_DOWN_H
#define RESTIR_UPSIDE_DOWN_H

#include "restir/core/image.h"

/* Mean squared error over the finite values of two same-size images, as they are and
 * with `test`'s rows reversed. */
void image_mse_flipped(const image *test, const image *ref, double *mse, double *mse_flipped);
/* If test matches ref far better upside down (flipped MSE below a quarter of the plain
 * one), prints a warning on stderr naming both files and the fix; returns 1 if it did. */
int image_warn_upside_down(const image *test, const char *test_name, const image *ref, const char *ref_name);

#endif
