/* SVG plots (src/metrics/plot_svg.c) and their CSV input (src/metrics/plot_csv.c).
 * The SVG must be well-formed XML: a small checker below verifies balanced tags,
 * quoted attributes without duplicates, and that every '&' starts an entity. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/plot.h"
#include "test.h"
#include "restir/metrics/plot_svg.h"
#include "restir/metrics/plot_csv.h"

/* ---- a minimal XML well-formedness checker ---- */

static int is_name_start(int c) { return isalpha(c) || c == '_' || c == ':'; }
static int is_name_char(int c) { return isalnum(c) || c == '_' || c == ':' || c == '.' || c == '-'; }

/* '&' at s must start &name; or &#digits; or &#xhex; with a predefined name. */
static int entity_length(const char *s)
{
    static const char *const names[] = {"amp;", "lt;", "gt;", "quot;", "apos;"};
    size_t i;
    if (s[1] == '#') {
        const char *p = s + 2;
        int hex = *p == 'x';
        if (hex) p++;
        if (!(hex ? isxdigit((unsigned char)*p) : isdigit((unsigned char)*p))) return 0;
        while (hex ? isxdigit((unsigned char)*p) : isdigit((unsigned char)*p)) p++;
        return *p == ';' ? (int)(p - s + 1) : 0;
    }
    for (i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (!strncmp(s + 1, names[i], strlen(names[i]))) return 1 + (int)strlen(names[i]);
    return 0;
}

/* Character data between tags: no '<' (the caller stops there), valid entities. */
static const char *check_text(const char *s, const char **why)
{
    while (*s && *s != '<') {
        if (*s == '&') {
            int n = entity_length(s);
            if (!n) {
                *why = "bare '&' in text";
                return NULL;
            }
            s += n;
        } else {
            s++;
        }
    }
    return s;
}

static int read_name(const char **s, char *name, size_t size)
{
    size_t n = 0;
    if (!is_name_start((unsigned char)**s)) return -1;
    while (is_name_char((unsigned char)**s)) {
        if (n + 1 < size) name[n++] = **s;
        (*s)++;
    }
    name[n] = '\0';
    return 0;
}

/* Returns NULL if well-formed, else the reason. */
static const char *xml_problem(const char *doc)
{
    static char stack[64][64];
    int depth = 0, roots = 0;
    const char *s = doc, *why = NULL;
    if (!strncmp(s, "<?xml", 5)) {
        s = strstr(s, "?>");
        if (!s) return "unterminated XML declaration";
        s += 2;
    }
    for (;;) {
        s = check_text(s, &why);
        if (!s) return why;
        if (depth == 0) { /* only whitespace outside the root */
            const char *p;
            for (p = s; p > doc && p[-1] != '>'; --p)
                if (!isspace((unsigned char)p[-1])) return "text outside the root element";
        }
        if (!*s) break;
        if (!strncmp(s, "<!--", 4)) {
            s = strstr(s + 4, "-->");
            if (!s) return "unterminated comment";
            s += 3;
        } else if (s[1] == '/') {
            char name[64];
            s += 2;
            if (read_name(&s, name, sizeof name)) return "bad end tag name";
            while (isspace((unsigned char)*s)) s++;
            if (*s != '>') return "end tag not closed";
            s++;
            if (depth == 0 || strcmp(stack[depth - 1], name)) return "mismatched end tag";
            depth--;
        } else {
            char name[64], attrs[32][64];
            int attr_count = 0, i;
            s++;
            if (read_name(&s, name, sizeof name)) return "bad start tag name";
            if (depth == 0 && ++roots > 1) return "more than one root element";
            for (;;) {
                const char *before = s;
                char quote;
                while (isspace((unsigned char)*s)) s++;
                if (*s == '>' || (*s == '/' && s[1] == '>')) break;
                if (s == before) return "no space before an attribute";
                if (attr_count == 32 || read_name(&s, attrs[attr_count], sizeof attrs[0])) return "bad attribute name";
                for (i = 0; i < attr_count; ++i)
                    if (!strcmp(attrs[i], attrs[attr_count])) return "duplicate attribute";
                attr_count++;
                if (*s++ != '=') return "attribute without '='";
                quote = *s++;
                if (quote != '"' && quote != '\'') return "unquoted attribute value";
                while (*s != quote) {
                    if (!*s || *s == '<') return "'<' or end of input inside an attribute value";
                    if (*s == '&') {
                        int n = entity_length(s);
                        if (!n) return "bare '&' in an attribute value";
                        s += n;
                    } else {
                        s++;
                    }
                }
                s++;
            }
            if (*s == '/') {
                s += 2;
            } else {
                s++;
                if (depth == 64) return "nested too deeply";
                strcpy(stack[depth++], name);
            }
        }
    }
    if (depth) return "unclosed element";
    if (roots != 1) return "no root element";
    return NULL;
}

/* The checker itself must reject what is not well-formed. */
TEST(plot_xml_checker_rejects_bad_documents)
{
    CHECK(xml_problem("<a><b x=\"1\" y='2'/>t &amp; &#60; &#x3c;</a>") == NULL);
    CHECK(xml_problem("<?xml version=\"1.0\"?>\n<a/>\n") == NULL);
    CHECK(xml_problem("<a><b></a></b>") != NULL);
    CHECK(xml_problem("<a>x & y</a>") != NULL);
    CHECK(xml_problem("<a>x < y</a>") != NULL);
    CHECK(xml_problem("<a x=1/>") != NULL);
    CHECK(xml_problem("<a x=\"a<b\"/>") != NULL);
    CHECK(xml_problem("<a x=\"1\" x=\"2\"/>") != NULL);
    CHECK(xml_problem("<a x=\"1\"y=\"2\"/>") != NULL);
    CHECK(xml_problem("<a/><b/>") != NULL);
    CHECK(xml_problem("<a>") != NULL);
    CHECK(xml_problem("<a title=\"&foo;\"/>") != NULL);
}

TEST(plot_svg_wellformed_and_escaped)
{
    static const double x[6] = {1, 3, 10, 30, 100, 1000};
    static const double y1[6] = {0.5, 0.2, 0.05, 0.02, 0.005, 0.0005};
    static const double y2[6] = {0.1, NAN, 0.01, -1.0, 0.001, 0.0001}; /* a gap and a non-positive value */
    plot_series s[2];
    plot_options o;
    const char *path = test_tmp_path("escape.svg");
    char *svg;
    const char *problem;
    long skipped = -1;
    rerror e;
    plot_options_default(&o);
    o.title = "Error <relMSE> & \"time\" 'quoted'";
    o.xlabel = "time (s) \x01 bad\xff byte";
    o.ylabel = "caf\xc3\xa9 & <y>";
    s[0].name = "PT & <NEE>";
    s[0].x = x;
    s[0].y = y1;
    s[0].count = 6;
    s[1].name = "ReSTIR \"PT\"";
    s[1].x = x;
    s[1].y = y2;
    s[1].count = 6;
    CHECK(plot_svg_write(path, &o, s, 2, &skipped, &e) == 0);
    CHECK(skipped == 1); /* -1 on the log axis; the NaN is a missing cell, not counted */
    svg = test_read_text(path);
    CHECK(svg != NULL);
    problem = xml_problem(svg);
    CHECKF(problem == NULL, "SVG not well-formed: %s", problem);
    CHECK(strstr(svg, "Error &lt;relMSE&gt; &amp; &quot;time&quot; &apos;quoted&apos;"));
    CHECK(strstr(svg, "PT &amp; &lt;NEE&gt;"));
    CHECK(strstr(svg, "ReSTIR &quot;PT&quot;"));
    CHECK(strstr(svg, "caf\xc3\xa9 &amp; &lt;y&gt;")); /* valid UTF-8 passes through */
    CHECK(strstr(svg, "time (s) ? bad? byte"));         /* control and invalid bytes replaced */
    CHECK(!strstr(svg, "<relMSE>") && !strstr(svg, "\x01"));
    /* Decade labels 10^0 .. 10^3 on x and 10^-4 .. 10^0 on y, 8 minor ticks per decade. */
    CHECK(strstr(svg, "10<tspan dy=\"-6\" font-size=\"9\">3</tspan>"));
    CHECK(strstr(svg, "10<tspan dy=\"-6\" font-size=\"9\">-4</tspan>"));
    CHECK(!strstr(svg, "font-size=\"9\">4</tspan>") && !strstr(svg, "font-size=\"9\">-5</tspan>"));
    {
        int minor = 0;
        const char *p = svg;
        while ((p = strstr(p, "y2=\"379.00\"")) != NULL) { /* x minor ticks are 3 px long from y = 382 */
            minor++;
            p++;
        }
        CHECKF(minor == 3 * 8, "%d minor x ticks", minor);
    }
    /* Distinct styles: two colours, one dashed. */
    CHECK(strstr(svg, "stroke=\"#0072B2\"") && strstr(svg, "stroke=\"#D55E00\" stroke-width=\"1.8\" stroke-dasharray"));
    free(svg);
}

TEST(plot_linear_axes_and_errors)
{
    static const double x[4] = {-2, 0, 1.5, 3}, y[4] = {-0.3, 0.1, 0.25, 0.2};
    static const double zero[2] = {0, -1};
    plot_series s;
    plot_options o;
    const char *path = test_tmp_path("linear.svg");
    char *svg;
    const char *problem;
    rerror e;
    plot_options_default(&o);
    o.x_scale = o.y_scale = PLOT_LINEAR;
    s.name = "series";
    s.x = x;
    s.y = y;
    s.count = 4;
    CHECK(plot_svg_write(path, &o, &s, 1, NULL, &e) == 0);
    svg = test_read_text(path);
    CHECK(svg != NULL);
    problem = xml_problem(svg);
    CHECKF(problem == NULL, "%s", problem);
    /* x: step 1 from -2 to 3; y: step 0.2 from -0.4 to 0.4 ("0", not "-5.55e-17"). */
    CHECK(strstr(svg, ">-2</text>") && strstr(svg, ">3</text>") && strstr(svg, ">0.4</text>"));
    CHECK(strstr(svg, ">-0.4</text>") && strstr(svg, ">0</text>") && !strstr(svg, "e-17"));
    free(svg);
    /* Nothing drawable on log axes: an error, and no file. */
    o.x_scale = o.y_scale = PLOT_LOG;
    s.x = zero;
    s.y = zero;
    s.count = 2;
    remove(test_tmp_path("none.svg"));
    CHECK(plot_svg_write(test_tmp_path("none.svg"), &o, &s, 1, NULL, &e) != 0);
    CHECK(!test_file_exists(test_tmp_path("none.svg")));
}

TEST(plot_csv_reader)
{
    plot_table t;
    rerror e;
    const char *path = test_write_file("table.csv", "# a comment\n"
                                                    "spp,\"PT, NEE\",\"say \"\"hi\"\"\" , plain\r\n"
                                                    "1, 0.5 ,0.25,\n"
                                                    "\n"
                                                    "2,0.125,,3e-2\n");
    CHECKF(plot_csv_read(path, &t, &e) == 0, "%s", e.msg);
    CHECK(t.columns == 4 && t.rows == 2);
    CHECK(!strcmp(t.names[0], "spp") && !strcmp(t.names[1], "PT, NEE") && !strcmp(t.names[2], "say \"hi\"") &&
          !strcmp(t.names[3], "plain"));
    CHECK(t.values[0] == 1 && t.values[1] == 2);           /* x */
    CHECK(t.values[2] == 0.5 && t.values[3] == 0.125);     /* PT, NEE */
    CHECK(t.values[4] == 0.25 && isnan(t.values[5]));      /* say "hi" */
    CHECK(isnan(t.values[6]) && t.values[7] == 0.03);      /* plain */
    plot_table_free(&t);
    path = test_write_file("bad1.csv", "x,y\n1,2\n2,abc\n");
    CHECK(plot_csv_read(path, &t, &e) != 0);
    CHECKF(strstr(e.msg, "bad1.csv:3:") && strstr(e.msg, "abc"), "%s", e.msg);
    path = test_write_file("bad2.csv", "x,y\n1,2,3\n");
    CHECK(plot_csv_read(path, &t, &e) != 0 && strstr(e.msg, "bad2.csv:2:"));
    path = test_write_file("bad3.csv", "x,y\n,2\n");
    CHECK(plot_csv_read(path, &t, &e) != 0 && strstr(e.msg, "x value"));
    path = test_write_file("bad4.csv", "x,\"y\n1,2\n");
    CHECK(plot_csv_read(path, &t, &e) != 0 && strstr(e.msg, "bad4.csv:1:"));
    path = test_write_file("bad5.csv", "x,y\n");
    CHECK(plot_csv_read(path, &t, &e) != 0 && strstr(e.msg, "no data"));
    /* Many rows (storage growth). */
    {
        FILE *f = fopen(test_tmp_path("big.csv"), "w");
        int i;
        CHECK(f != NULL);
        fprintf(f, "x,a,b\n");
        for (i = 0; i < 1000; ++i) fprintf(f, "%d,%d,%d\n", i + 1, 2 * i, 3 * i);
        fclose(f);
        CHECK(plot_csv_read(test_tmp_path("big.csv"), &t, &e) == 0);
        CHECK(t.rows == 1000 && t.values[999] == 1000 && t.values[1000 + 999] == 1998 && t.values[2000 + 500] == 1500);
        plot_table_free(&t);
    }
}

TEST(plot_cli)
{
    char out[4096], svg_path[1100];
    char *svg;
    const char *csv = test_write_file("cli.csv", "spp,a & b,c\n1,1,0.5\n10,0.1,0.05\n100,0.01,0\n");
    int status;
    snprintf(svg_path, sizeof svg_path, "%s", test_tmp_path("cli.svg"));
    remove(svg_path);
    status = test_cli(out, sizeof out, "plot %s -o %s --title 'T <1>' --ylabel 'rel. MSE'", csv, svg_path);
    CHECKF(status == 0, "%d %s", status, out);
    CHECK(strstr(out, "1 point(s) not drawn")); /* the 0 on the log axis */
    svg = test_read_text(svg_path);
    CHECK(svg != NULL && xml_problem(svg) == NULL);
    CHECK(strstr(svg, "T &lt;1&gt;") && strstr(svg, ">spp</text>") && strstr(svg, "a &amp; b"));
    free(svg);
    status = test_cli(out, sizeof out, "plot %s -o %s --linear", test_write_file("bad.csv", "x,y\n1,z\n"),
                      test_tmp_path("bad.svg"));
    CHECK(status == 2 && strstr(out, "bad.csv:2:") && !test_file_exists(test_tmp_path("bad.svg")));
    CHECK(test_cli(out, sizeof out, "plot %s", csv) == 2);
    CHECK(test_cli(out, sizeof out, "plot %s -o x.svg --bogus", csv) == 2);
}
