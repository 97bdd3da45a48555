/* Option parsing for the CLI (the only place that parses arguments, docs/design.md, Layout). */
#include "args.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image.h"

static int parse_number(const char *text, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    return *text && !*end && errno == 0 && isfinite(*out);
}

static int parse_triple(const char *text, double v[3])
{
    char buf[256], *a, *b;
    if (strlen(text) >= sizeof buf) return 0;
    strcpy(buf, text);
    a = strchr(buf, ',');
    if (!a) return 0;
    *a++ = '\0';
    b = strchr(a, ',');
    if (!b) return 0;
    *b++ = '\0';
    return parse_number(buf, &v[0]) && parse_number(a, &v[1]) && parse_number(b, &v[2]);
}

static int parse_size(const char *text, int wh[2])
{
    char *end;
    long w, h;
    w = strtol(text, &end, 10);
    if (end == text || (*end != 'x' && *end != 'X')) return 0;
    h = strtol(end + 1, &end, 10);
    if (*end || w < 1 || h < 1 || w > 65536 || h > 65536 || w * h > IMAGE_MAX_PIXELS) return 0;
    wh[0] = (int)w;
    wh[1] = (int)h;
    return 1;
}

static int in_bounds(const cli_option *o, double v)
{
    return !(o->min < o->max) || (v >= o->min && v <= o->max);
}

static int bad_value(const char *command, const cli_option *o, const char *value, const char *expected)
{
    fprintf(stderr, "restir %s: %s: expected %s, got '%s'\n", command, o->name, expected, value);
    return 2;
}

/* "a whole number from 1 to 256" / "a number from -1 to 1": a range error states the range. */
static int bad_number(const char *command, const cli_option *o, const char *value, int whole)
{
    char expected[128];
    const char *kind = whole ? "a whole number" : "a finite number";
    if (o->min < o->max)
        snprintf(expected, sizeof expected, "%s from %.10g to %.10g", kind, o->min, o->max);
    else if (whole)
        snprintf(expected, sizeof expected, "%s from 0 to 2147483647", kind);
    else
        snprintf(expected, sizeof expected, "%s", kind);
    return bad_value(command, o, value, expected);
}

static int set_choice(const char *command, const cli_option *o, const char *value)
{
    int i;
    for (i = 0; o->choices[i]; ++i) {
        if (!strcmp(o->choices[i], value)) {
            *(int *)o->dest = i;
            return 0;
        }
    }
    fprintf(stderr, "restir %s: %s: '%s' is not one of", command, o->name, value);
    for (i = 0; o->choices[i]; ++i) fprintf(stderr, " %s", o->choices[i]);
    fprintf(stderr, "\n");
    return 2;
}

static int set_value(const char *command, const cli_option *o, const char *value)
{
    double d;
    switch (o->type) {
    case OPT_INT:
        if (!parse_number(value, &d) || d != floor(d) || fabs(d) > 2147483647.0 || !in_bounds(o, d) ||
            (!(o->min < o->max) && d < 0))
            return bad_number(command, o, value, 1);
        *(int *)o->dest = (int)d;
        return 0;
    case OPT_UINT32:
        if (!parse_number(value, &d) || d != floor(d) || d < 0 || d > 4294967295.0)
            return bad_value(command, o, value, "a whole number from 0 to 4294967295");
        *(uint32_t *)o->dest = (uint32_t)d;
        return 0;
    case OPT_REAL:
        if (!parse_number(value, &d) || !in_bounds(o, d)) return bad_number(command, o, value, 0);
        *(double *)o->dest = d;
        return 0;
    case OPT_STRING:
        *(const char **)o->dest = value;
        return 0;
    case OPT_VEC3:
        if (!parse_triple(value, (double *)o->dest)) return bad_value(command, o, value, "x,y,z");
        return 0;
    case OPT_SIZE:
        if (!parse_size(value, (int *)o->dest)) return bad_value(command, o, value, "WxH (e.g. 512x512; W, H <= 65536, W*H <= 8192*8192)");
        return 0;
    case OPT_CHOICE:
        return set_choice(command, o, value);
    case OPT_LIST: {
        cli_list *l = o->dest;
        if (l->count >= l->max) {
            fprintf(stderr, "restir %s: %s: more than %d values\n", command, o->name, l->max);
            return 2;
        }
        l->items[l->count++] = value;
        return 0;
    }
    case OPT_FLAG:
        break;
    }
    return 0;
}

static int is_option(const char *arg)
{
    return arg[0] == '-' && arg[1] != '\0';
}

static const cli_option *find_option(const cli_option *options, const char *name)
{
    for (; options->name; ++options)
        if (!strcmp(options->name, name)) return options;
    return NULL;
}

/* "--opt=value": name "--opt" and *value "value"; otherwise the whole argument and NULL. */
static int split_inline_value(const char *arg, char *name, size_t size, const char **value)
{
    const char *eq = arg[0] == '-' && arg[1] == '-' ? strchr(arg, '=') : NULL;
    size_t n = eq ? (size_t)(eq - arg) : strlen(arg);
    *value = eq ? eq + 1 : NULL;
    if (n >= size) return -1;
    memcpy(name, arg, n);
    name[n] = '\0';
    return 0;
}

int cli_parse(const char *command, int argc, char **argv, const cli_option *options, const char **positional,
              int max_positional, int *positional_count)
{
    int i, status;
    *positional_count = 0;
    for (i = 1; i < argc; ++i) {
        const char *arg = argv[i], *inline_value;
        char name[64];
        const cli_option *o;
        if (!is_option(arg)) {
            if (*positional_count >= max_positional) {
                fprintf(stderr, "restir %s: unexpected argument '%s'\n", command, arg);
                return 2;
            }
            positional[(*positional_count)++] = arg;
            continue;
        }
        if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) return 1;
        if (split_inline_value(arg, name, sizeof name, &inline_value)) {
            fprintf(stderr, "restir %s: option name too long: '%s'\n", command, arg);
            return 2;
        }
        o = find_option(options, name);
        if (!o) {
            fprintf(stderr, "restir %s: unknown option '%s' (see restir %s --help)\n", command, name, command);
            return 2;
        }
        if (o->seen) *o->seen = 1;
        if (o->type == OPT_FLAG) {
            if (inline_value) {
                fprintf(stderr, "restir %s: %s takes no value (got '%s')\n", command, name, arg);
                return 2;
            }
            *(int *)o->dest = 1;
            continue;
        }
        if (!inline_value && i + 1 >= argc) {
            fprintf(stderr, "restir %s: %s needs a value\n", command, name);
            return 2;
        }
        status = set_value(command, o, inline_value ? inline_value : argv[++i]);
        while (!status && o->type == OPT_LIST && i + 1 < argc && !is_option(argv[i + 1]))
            status = set_value(command, o, argv[++i]);
        if (status) return status;
    }
    return 0;
}

static size_t value_size(enum cli_option_type type)
{
    switch (type) {
    case OPT_FLAG:
    case OPT_INT:
    case OPT_CHOICE: return sizeof(int);
    case OPT_UINT32: return sizeof(uint32_t);
    case OPT_REAL: return sizeof(double);
    case OPT_STRING: return sizeof(const char *);
    case OPT_VEC3: return 3 * sizeof(double);
    case OPT_SIZE: return 2 * sizeof(int);
    case OPT_LIST: return sizeof(cli_list);
    }
    return 0;
}

void cli_take_unset(const cli_option *options, const int *given, void *to, const void *from, size_t size)
{
    int i;
    for (i = 0; options[i].name; ++i) {
        uintptr_t dest = (uintptr_t)options[i].dest, base = (uintptr_t)to;
        size_t n = value_size(options[i].type);
        if (given[i] || dest < base || dest + n > base + size) continue;
        memcpy(options[i].dest, (const char *)from + (dest - base), n);
    }
}

void cli_track_given(cli_option *options, int *given)
{
    int i;
    for (i = 0; options[i].name; ++i) {
        given[i] = 0;
        if (!options[i].seen) options[i].seen = &given[i];
    }
}

int cli_given(const cli_option *options, const int *given, const char *name)
{
    int i;
    for (i = 0; options[i].name; ++i)
        if (!strcmp(options[i].name, name)) return options[i].seen ? *options[i].seen : given[i];
    return 0;
}

static const char *type_hint(const cli_option *o)
{
    switch (o->type) {
    case OPT_FLAG: return "";
    case OPT_INT: return " N";
    case OPT_UINT32: return " N";
    case OPT_REAL: return " X";
    case OPT_STRING: return " VALUE";
    case OPT_VEC3: return " x,y,z";
    case OPT_SIZE: return " WxH";
    case OPT_CHOICE: return " CHOICE";
    case OPT_LIST: return " FILE...";
    }
    return "";
}

void cli_print_help(FILE *out, const char *command, const char *usage, const cli_option *options)
{
    fprintf(out, "usage: restir %s %s\n\noptions:\n", command, usage);
    for (; options->name; ++options) {
        char left[64];
        snprintf(left, sizeof left, "%s%s", options->name, type_hint(options));
        fprintf(out, "  %-22s %s", left, options->help);
        if (options->type == OPT_CHOICE) {
            int i;
            fprintf(out, " (");
            for (i = 0; options->choices[i]; ++i) fprintf(out, "%s%s", i ? "|" : "", options->choices[i]);
            fprintf(out, ")");
        }
        fputc('\n', out);
    }
    fprintf(out, "  %-22s %s\n", "--help", "show this help");
}
