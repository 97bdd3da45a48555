/* The domains of the golden-vector functions (src/oracle/vectors_domain.c): vectors --check
 * refuses inputs outside a function's domain with a message instead of aborting. */
#ifndef RESTIR_ORACLE_VECTORS_DOMAIN_H
#define RESTIR_ORACLE_VECTORS_DOMAIN_H

#include <stddef.h>

/* 1 (and why, one line) if an input of a vector for fn lies outside the function's domain:
 * a seed or RNG word that is not a whole number in [0, 2^32), an RNG address beyond
 * docs/rng.md's ranges, an index or lobe out of range, a pick's random number outside
 * [0, 1] (vectors_domain.c). */
int vectors_input_problem(const char *fn, const double *in, int n_in, char *why, size_t size);
/* The scene of the shift vectors: scenes/cornell.scene in the working directory if it is
 * there, else next to the executable's directory (build/restir -> scenes/, via
 * /proc/self/exe), so `restir vectors` works from any directory (vectors_domain.c). */
const char *vectors_shift_scene_path(void);

#endif
