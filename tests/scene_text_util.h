/* Scenes built from strings (the text written as a scratch file, then scene_load) and the
 * table runner of the loaders' error tests: each bad text must be refused with a one-line
 * message that names the file and line. */
#ifndef RESTIR_TESTS_SCENE_TEXT_UTIL_H
#define RESTIR_TESTS_SCENE_TEXT_UTIL_H

#include <stddef.h>
#include "restir/core/error.h"
#include "restir/scene/scene.h"

/* Writes text as the scratch file `name` (test_write_file) and loads it; returns
 * scene_load's status (e filled on failure). */
int scene_from_text(scene *s, const char *name, const char *text, rerror *e);

/* The material called name in s, or NULL. */
const material *find_material(const scene *s, const char *name);

/* 1 if msg is one line that starts with "<scratch dir>/<name>:<line>: " (line 0:
 * "<scratch dir>/<name>: ", the file as a whole) and contains `what`. */
int error_at(const char *msg, const char *name, long line, const char *what);

/* A bad file text, the line its error must name (0: none) and a part of the message. */
typedef struct {
    const char *text;
    long line;
    const char *what;
} bad_line;

/* Loads one case's text (writing whatever companion files the loader needs). */
typedef int (*scene_text_loader)(scene *s, const char *text, rerror *e);

/* Every case must fail to load, with error_at(message, name, line, what); records a test
 * failure naming the first case that does not. Returns 0 if every case holds. */
int expect_bad_lines(const bad_line *cases, size_t n, const char *name, scene_text_loader load);

#endif
