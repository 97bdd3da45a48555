/* Text in the tests: the rows of the error tables (a bad input and the message it must
 * give), and numbers read back out of what a command printed (its JSON or text), for the
 * tests that redo a printed computation by hand. */
#ifndef RESTIR_TESTS_TEXT_UTIL_H
#define RESTIR_TESTS_TEXT_UTIL_H

/* A bad input (a file's text, a command's arguments, ...) and a part of the message it
 * must be refused with: the row of the tables of error tests. */
typedef struct {
    const char *input, *expect;
} bad_input;

/* The number after "key": (the JSON member `key`) at or after *from, which is advanced past
 * the key; NAN if absent. */
double json_after(const char **from, const char *key);

#endif
