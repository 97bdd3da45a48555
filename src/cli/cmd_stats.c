/* restir stats mean-ci [FILE]: the mean of the numbers on stdin (or in FILE) and the
 * half-width of its Student t interval, by the library's stats_mean_ci; restir stats t-table:
 * the two-sided t quantiles for 1..N degrees of freedom, for the awk summaries that compute
 * many intervals in one pass. So the results scripts and the C code report intervals the
 * same way (one implementation instead of an awk t-table per script). */
#include "cmd_stats.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/stats.h"
#include "args.h"

#define DEFAULT_FORMAT "%.4g ± %.2g"

static const char help_notes[] =
    "\nReads whitespace-separated numbers from FILE or stdin (at least two: a variance needs two) and\n"
    "prints their mean and the half-width t_{(1+level)/2, n-1} s / sqrt(n) of the t interval\n"
    "(stats_mean_ci) as FORMAT: text with exactly two conversions %.Ng, %.Nf or %.Ne (N digits,\n"
    "0..17), the mean then the half-width, and %% for a percent sign; a newline follows.\n"
    "t-table prints t_{(1+level)/2, df} for df = 1..--max-dof on one line (stats_t_quantile).\n"
    "exit status: 0 done, 2 bad usage or bad input (no number, one number, not a number).\n";

static int usage_error(const char *what)
{
    fprintf(stderr, "restir stats: %s\n(restir stats --help for usage)\n", what);
    return 2;
}

/* 1 if f is literal text, %% and exactly two conversions %.N[gfe] with N in 0..17: the only
 * printf formats let through to printf (the format comes from the command line). */
static int format_is_safe(const char *f)
{
    int conversions = 0;
    for (; *f; ++f) {
        int digits = 0, n = 0;
        if (*f != '%') continue;
        if (f[1] == '%') {
            ++f;
            continue;
        }
        if (f[1] != '.') return 0;
        f += 2;
        while (isdigit((unsigned char)*f) && digits < 3) n = 10 * n + (*f++ - '0'), ++digits;
        if (digits == 0 || n > 17 || (*f != 'g' && *f != 'f' && *f != 'e')) return 0;
        ++conversions;
    }
    return conversions == 2;
}

/* Appends v to *x (grown here); 2 after a message when memory runs out. */
static int push_number(double v, double **x, long *n, long *cap)
{
    if (*n == *cap) {
        double *grown = realloc(*x, (size_t)(*cap ? 2 * *cap : 64) * sizeof *grown);
        if (!grown) {
            fprintf(stderr, "restir stats: out of memory\n");
            return 2;
        }
        *x = grown;
        *cap = *cap ? 2 * *cap : 64;
    }
    (*x)[(*n)++] = v;
    return 0;
}

/* Every number of `in` (named `name` in messages) into *x (grown here); 2 after a message on
 * a word that is not a finite number. Read word by word, so a line of any length is read
 * whole (a fixed line buffer once split a number at its edge: a false mean, exit 0). */
static int read_numbers(FILE *in, const char *name, double **x, long *n)
{
    char word[128];
    long cap = 0, line_no = 1;
    size_t len = 0;
    int c;
    *x = NULL;
    *n = 0;
    do {
        c = getc(in);
        if (c != EOF && !isspace(c)) {
            if (len + 1 < sizeof word) word[len] = (char)c;
            ++len;
            continue;
        }
        if (len > 0) {
            char *end;
            double v;
            int whole = len < sizeof word;
            word[whole ? len : sizeof word - 1] = '\0';
            v = strtod(word, &end);
            if (!whole || end == word || *end || !isfinite(v)) {
                fprintf(stderr, "restir stats: %s:%ld: '%s%s' is not a finite number\n", name, line_no, word,
                        whole ? "" : "...");
                return 2;
            }
            if (push_number(v, x, n, &cap)) return 2;
            len = 0;
        }
        if (c == '\n') ++line_no;
    } while (c != EOF);
    if (ferror(in)) {
        fprintf(stderr, "restir stats: %s: cannot read: %s\n", name, strerror(errno));
        return 2;
    }
    return 0;
}

static int mean_ci(const char *path, double level, const char *format)
{
    double *x, mean, var, lo, hi;
    long n;
    int status;
    FILE *in = path ? fopen(path, "r") : stdin;
    if (!in) {
        fprintf(stderr, "restir stats: %s: cannot open\n", path);
        return 2;
    }
    status = read_numbers(in, path ? path : "stdin", &x, &n);
    if (path) fclose(in);
    if (status) {
        free(x);
        return 2;
    }
    if (n < 2) {
        free(x);
        fprintf(stderr, "restir stats mean-ci: needs two values or more (a variance needs two), got %s in %s\n",
                n ? "one" : "none", path ? path : "stdin");
        return 2;
    }
    stats_mean_var(x, n, &mean, &var);
    free(x);
    stats_mean_ci(stats_estimate_from_samples(mean, var, (double)n), level, &lo, &hi);
    if (!isfinite(mean) || !isfinite(hi - lo)) {
        /* finite inputs whose sum or spread overflows (1e308 1e308 -1e308): no answer to print */
        fprintf(stderr, "restir stats mean-ci: %s: the mean or its interval overflows the double range (mean %g, "
                        "half-width %g): scale the numbers\n", path ? path : "stdin", mean, 0.5 * (hi - lo));
        return 2;
    }
    printf(format, mean, 0.5 * (hi - lo));
    putchar('\n');
    return 0;
}

/* The two-sided t quantiles of stats_mean_ci for 1..max_dof degrees of freedom. */
static int t_table(double level, int max_dof)
{
    int df;
    for (df = 1; df <= max_dof; ++df)
        printf("%s%.9g", df > 1 ? " " : "", stats_t_quantile(0.5 * (1.0 + level), (double)df));
    putchar('\n');
    return 0;
}

int cmd_stats(int argc, char **argv)
{
    const char *positional[2], *format = DEFAULT_FORMAT;
    double level = 0.95;
    int status, count, max_dof = 1000;
    const cli_option options[] = {
        {"--level", OPT_REAL, &level, "confidence level of the interval, in (0, 1) (default 0.95)", NULL, 0, 1, NULL},
        {"--format", OPT_STRING, &format, "mean-ci: how to print mean and half-width (default '" DEFAULT_FORMAT "')",
         NULL, 0, 0, NULL},
        {"--max-dof", OPT_INT, &max_dof, "t-table: the largest degrees of freedom (default 1000)", NULL, 1, 100000,
         NULL},
        {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
    };
    status = cli_parse("stats", argc, argv, options, positional, 2, &count);
    if (status == 1) {
        cli_print_help(stdout, "stats", "mean-ci [FILE] [options]   (numbers from FILE, else stdin) | t-table [options]",
                       options);
        fputs(help_notes, stdout);
        return 0;
    }
    if (status) return status;
    if (count < 1 || (strcmp(positional[0], "mean-ci") && strcmp(positional[0], "t-table")) ||
        (!strcmp(positional[0], "t-table") && count > 1))
        return usage_error("expected `mean-ci [FILE]` or `t-table`");
    if (!(level > 0.0 && level < 1.0)) return usage_error("--level must lie strictly between 0 and 1");
    if (!strcmp(positional[0], "t-table")) return t_table(level, max_dof);
    if (!format_is_safe(format))
        return usage_error("--format needs exactly two conversions %.Ng, %.Nf or %.Ne (N = 0..17), mean first");
    return mean_ci(count > 1 ? positional[1] : NULL, level, format);
}
