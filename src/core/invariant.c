/* The failure path of the debug build's invariants (include/restir/core/invariant.h). */
#include "restir/core/invariant.h"

#include <stdio.h>
#include <stdlib.h>

void restir_invariant_failed(const char *file, int line, const char *what)
{
    fprintf(stderr, "%s:%d: invariant failed: %s\n", file, line, what);
    fflush(stderr);
    abort();
}
