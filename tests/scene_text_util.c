/* scene_text_util.h: scenes from strings, bad-line tables. */
#include "scene_text_util.h"

#include <stdio.h>
#include <string.h>
#include "test.h"

int scene_from_text(scene *s, const char *name, const char *text, rerror *e)
{
    char path[1024];
    snprintf(path, sizeof path, "%s", test_write_file(name, text));
    return scene_load(s, path, e);
}

const material *find_material(const scene *s, const char *name)
{
    size_t i;
    for (i = 0; i < s->material_count; ++i)
        if (!strcmp(s->materials[i].name, name)) return &s->materials[i];
    return NULL;
}

int error_at(const char *msg, const char *name, long line, const char *what)
{
    char prefix[1200];
    if (line > 0) snprintf(prefix, sizeof prefix, "%s:%ld: ", test_tmp_path(name), line);
    else snprintf(prefix, sizeof prefix, "%s: ", test_tmp_path(name));
    return !strncmp(msg, prefix, strlen(prefix)) && strstr(msg, what) != NULL && !strchr(msg, '\n');
}

int expect_bad_lines(const bad_line *cases, size_t n, const char *name, scene_text_loader load)
{
    size_t i;
    for (i = 0; i < n; ++i) {
        scene s;
        rerror e;
        if (load(&s, cases[i].text, &e) == 0) {
            scene_free(&s);
            test_fail(__FILE__, __LINE__, "case %zu loaded: %s", i, cases[i].text);
            return -1;
        }
        if (!error_at(e.msg, name, cases[i].line, cases[i].what)) {
            test_fail(__FILE__, __LINE__, "case %zu: '%s' is not %s:%ld: ...%s", i, e.msg, name, cases[i].line,
                      cases[i].what);
            return -1;
        }
    }
    return 0;
}
