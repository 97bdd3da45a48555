/* In-process output capture for tests that call a command or library function which
 * prints: a passing test must not print error-looking lines into `make test`'s log
 * (issue 27), and the message is worth checking anyway. */
#ifndef RESTIR_TEST_CAPTURE_H
#define RESTIR_TEST_CAPTURE_H

#include <stddef.h>

/* Redirects stdout and stderr to a scratch file until capture_end. Not nested. */
void capture_begin(void);
/* Restores them and copies what was printed into out (NUL-terminated, truncated). */
void capture_end(char *out, size_t size);

#endif
