/* Golden test vectors (docs/oracle.md "Golden vectors"): the library reproduces the
 * checked-in files tests/vectors/FAMILY.jsonl bit for bit (double build), regenerating them gives the
 * same bytes, a changed output is caught, and every row of docs/equations.md that computes
 * something has a vector or is listed, with its reason, in docs/oracle.md's table of rows
 * without vectors. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/oracle/vectors.h"
#include "test.h"

static char out[65536];

/* Regenerated twice: byte-identical; every file re-evaluates; in the double build the
 * checked-in golden files are reproduced exactly (the float build rounds differently:
 * docs/oracle.md lists its tolerance, and it only checks its own files). */
TEST(oracle_vectors_reproduce)
{
    const char *const *fam = vectors_families();
    char a[1200], b[1200], golden[1200];
    rerror e;
    int i;
    snprintf(a, sizeof a, "%s/vec1", test_tmpdir());
    snprintf(b, sizeof b, "%s/vec2", test_tmpdir());
    CHECKF(vectors_write(a, &e) == 0, "%s", e.msg);
    CHECKF(test_cli(out, sizeof out, "vectors -o %s", b) == 0, "%s", out);
    for (i = 0; fam[i]; ++i) {
        char fa[1300], fb[1300];
        long lines, bad;
        snprintf(fa, sizeof fa, "%s/%s.jsonl", a, fam[i]);
        snprintf(fb, sizeof fb, "%s/%s.jsonl", b, fam[i]);
        CHECKF(test_files_equal(fa, fb), "%s: two generations differ", fam[i]);
        CHECKF(vectors_check_file(fa, &lines, &bad, &e) == 0 && lines > 0, "%s: %ld bad of %ld: %s", fa, bad, lines,
               e.msg);
        snprintf(golden, sizeof golden, "tests/vectors/%s.jsonl", fam[i]);
#ifndef RESTIR_REAL_FLOAT
        CHECKF(vectors_check_file(golden, &lines, &bad, &e) == 0, "%s: %ld of %ld lines do not reproduce: %s", golden,
               bad, lines, e.msg);
        CHECKF(test_files_equal(fa, golden), "%s differs from a fresh generation: run `restir vectors -o tests/vectors` "
               "after a deliberate change", golden);
#endif
    }
}

/* A vector whose output was changed in its last digit is reported with file and line. */
TEST(oracle_vectors_detect_changed_output)
{
    char path[1200], line[8192];
    const char *p;
    FILE *in, *fo;
    long lines, bad;
    rerror e;
    int n = 0;
    snprintf(path, sizeof path, "%s/vec1", test_tmpdir());
    CHECKF(vectors_write(path, &e) == 0, "%s", e.msg);
    snprintf(path, sizeof path, "%s/vec1/mis.jsonl", test_tmpdir());
    in = fopen(path, "rb");
    fo = fopen(test_tmp_path("mis-changed.jsonl"), "wb");
    CHECK(in && fo);
    if (!in || !fo) return;
    while (fgets(line, sizeof line, in)) {
        if (++n == 5 && (p = strstr(line, "\"out\": [")) != NULL) {
            /* 0.xxx...d -> change the last digit of the first output */
            char *q = strchr(p + 8, ',');
            if (!q) q = strchr(p + 8, ']');
            if (q && isdigit((unsigned char)q[-1])) q[-1] = q[-1] == '9' ? '8' : (char)(q[-1] + 1);
        }
        fputs(line, fo);
    }
    fclose(in);
    fclose(fo);
    CHECK(vectors_check_file(test_tmp_path("mis-changed.jsonl"), &lines, &bad, &e) == 1 && bad == 1);
    CHECKF(strstr(e.msg, "mis-changed.jsonl:5: mis_weights") != NULL, "%s", e.msg);
    CHECK(test_cli(out, sizeof out, "vectors --check %s", test_tmp_path("mis-changed.jsonl")) == 1);
    CHECK(test_cli(out, sizeof out, "vectors") == 2);
}

/* ---- coverage of docs/equations.md ----------------------------------------------------- */

/* Splits a table row on unescaped '|' into trimmed cells; returns the count. */
static int split_row(char *row, char *cells[], int max)
{
    int n = 0;
    char *p = row, *start;
    if (*p != '|') return 0;
    start = ++p;
    for (; *p && n < max; ++p) {
        if (*p == '|' && p[-1] != '\\') {
            char *end = p;
            *end = '\0';
            while (*start == ' ') ++start;
            while (end > start && end[-1] == ' ') *--end = '\0';
            cells[n++] = start;
            start = p + 1;
        }
    }
    return n;
}

/* The rows of docs/oracle.md's "Rows without vectors" table: "| GRIS 47 | exempt | why |". */
static int listed_without_vector(const char *eq, char *reason, size_t size)
{
    FILE *fp = fopen("docs/oracle.md", "rb");
    char line[2048];
    int in_table = 0, found = 0;
    if (!fp) return 0;
    while (!found && fgets(line, sizeof line, fp)) {
        char *cells[8];
        int n;
        line[strcspn(line, "\r\n")] = '\0';
        if (!strncmp(line, "#", 1)) in_table = strstr(line, "Rows without vectors") != NULL;
        if (!in_table || (n = split_row(line, cells, 8)) < 3) continue;
        if (!strcmp(cells[0], eq) && (!strcmp(cells[1], "exempt") || !strcmp(cells[1], "pending")) && cells[2][0]) {
            snprintf(reason, size, "%s: %s", cells[1], cells[2]);
            found = 1;
        }
    }
    fclose(fp);
    return found;
}

TEST(oracle_vectors_cover_equations)
{
    FILE *fp = fopen("docs/equations.md", "rb");
    char line[8192], reason[2048], missing[16384] = "";
    const char *paper = NULL;
    int lineno = 0, computing = 0, covered = 0, listed = 0;
    CHECK(fp != NULL);
    if (!fp) return;
    while (fgets(line, sizeof line, fp)) {
        char *cells[12], eq[64];
        int n;
        ++lineno;
        line[strcspn(line, "\r\n")] = '\0';
        if (!strncmp(line, "## ", 3)) {
            /* the four paper sections; the section-level maps below them have other columns */
            paper = !strncmp(line, "## GRIS", 7)             ? "GRIS"
                    : !strncmp(line, "## Enhanced", 11)      ? "Enhanced"
                    : !strncmp(line, "## Mutations", 12)     ? "Mutations"
                    : !strncmp(line, "## Stochastic MIS", 17) ? "Stochastic MIS"
                                                              : NULL;
            continue;
        }
        if (!paper || (n = split_row(line, cells, 12)) < 6 || !isdigit((unsigned char)cells[0][0])) continue;
        /* computes something: an estimator or metric with an implementation ("—" = none yet) */
        if (strcmp(cells[3], "estimator") && strcmp(cells[3], "metric")) continue;
        if (!cells[4][0] || !strncmp(cells[4], "—", strlen("—"))) continue;
        ++computing;
        snprintf(eq, sizeof eq, "%s %s", paper, cells[0]);
        if (vectors_cover(eq)) {
            ++covered;
            CHECKF(!listed_without_vector(eq, reason, sizeof reason),
                   "docs/oracle.md lists '%s' among the rows without vectors, but it has vectors now: remove it", eq);
        } else if (listed_without_vector(eq, reason, sizeof reason))
            ++listed;
        else {
            size_t used = strlen(missing);
            snprintf(missing + used, sizeof missing - used,
                     "\n  docs/equations.md:%d: row '%s' (%s, implemented in %.60s) has no golden vector", lineno, eq,
                     cells[3], cells[4]);
        }
    }
    fclose(fp);
    CHECKF(!missing[0],
           "rows of docs/equations.md that compute something but have no golden vector:%s\n  add cases tagged "
           "with the row (e.g. \"GRIS 19\") in src/oracle/vectors.c, then `restir vectors -o tests/vectors`, or list "
           "the row with a reason under \"Rows without vectors\" in docs/oracle.md",
           missing);
    CHECKF(computing >= 30 && covered >= 25, "parsed %d computing rows, %d covered: has the table format changed?",
           computing, covered);
    (void)listed;
}
