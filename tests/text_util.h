/* Numbers read back out of what a command printed (its JSON or text), for the tests that
 * redo a printed computation by hand. */
#ifndef RESTIR_TESTS_TEXT_UTIL_H
#define RESTIR_TESTS_TEXT_UTIL_H

/* The number after "key": (the JSON member `key`) at or after *from, which is advanced past
 * the key; NAN if absent. */
double json_after(const char **from, const char *key);

#endif
