/* Invariants of the estimator checked in the debug build (`make DEBUG=1`, which defines
 * RESTIR_DEBUG; docs/statistics.md "Debug invariants"). A failed invariant prints
 * "file:line: invariant failed: what" on stderr and aborts. Without RESTIR_DEBUG the
 * checks compile to nothing (zero cost); the check functions themselves (e.g.
 * spatial_check_step in spatial.h) exist in every build so tests can drive them. */
#ifndef RESTIR_INVARIANT_H
#define RESTIR_INVARIANT_H

#ifdef RESTIR_DEBUG
#define RESTIR_DEBUG_ENABLED 1
#else
#define RESTIR_DEBUG_ENABLED 0
#endif

/* Prints "file:line: invariant failed: what" to stderr and calls abort(). */
void restir_invariant_failed(const char *file, int line, const char *what);

#endif
