/* Checks that keep the house in order (issue 18); they read the source tree as text
 * (the suite runs from the repository root):
 *   house_layers:        no file of src/render or src/restir includes, directly or through
 *                        other headers, the interface header of a src/bench or src/metrics
 *                        file, and no file of src/render one of src/restir (the layers:
 *                        render < restir < metrics, bench < cli);
 *   house_equations_cited: every function docs/equations.md names as `name` (src/x.c)
 *                        exists, and its comment or body (or the comment of its declaration
 *                        in a header) cites the equation of its row with the paper's name,
 *                        e.g. GRIS Eq. 36 or Stochastic MIS Eqs. 18-19. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "test.h"

/* ---- small text helpers ---- */

typedef struct {
    char (*name)[256];
    int count, cap;
} path_list;

static void list_add(path_list *l, const char *name)
{
    if (l->count == l->cap) {
        int cap = l->cap ? 2 * l->cap : 64;
        char(*grown)[256] = realloc(l->name, (size_t)cap * sizeof *grown);
        if (!grown) return;
        l->name = grown;
        l->cap = cap;
    }
    snprintf(l->name[l->count++], 256, "%s", name);
}

static int list_has(const path_list *l, const char *name)
{
    int i;
    for (i = 0; i < l->count; ++i)
        if (!strcmp(l->name[i], name)) return 1;
    return 0;
}

/* The .c and .h files of directory dir ("src/render") as "dir/file". */
static void list_sources(path_list *l, const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *de;
    char path[256];
    if (!d) return;
    while ((de = readdir(d))) {
        size_t n = strlen(de->d_name);
        if (n < 3 || de->d_name[n - 2] != '.' || (de->d_name[n - 1] != 'c' && de->d_name[n - 1] != 'h')) continue;
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        list_add(l, path);
    }
    closedir(d);
}

/* The path of the n-th `#include "..."` of text (n = 0, 1, ...), resolved against
 * include/ ("restir/x.h") or the including file's directory; 0 when there is none. */
static int nth_include(const char *text, const char *file, int n, char *out, size_t size)
{
    const char *p = text;
    while ((p = strstr(p, "#include \""))) {
        const char *name = p + 10, *end = strchr(name, '"');
        p = name;
        if (!end) return 0;
        if (n-- > 0) continue;
        if (!strncmp(name, "restir/", 7)) {
            snprintf(out, size, "include/%.*s", (int)(end - name), name);
        } else {
            const char *slash = strrchr(file, '/');
            snprintf(out, size, "%.*s/%.*s", (int)(slash ? slash - file : 1), slash ? file : ".", (int)(end - name),
                     name);
        }
        return 1;
    }
    return 0;
}

/* ---- house_layers ---- */

/* The interface header of every .c file in dir: its first #include "restir/...". */
static void interface_headers(path_list *out, const char *dir)
{
    path_list files = {0};
    int i;
    list_sources(&files, dir);
    for (i = 0; i < files.count; ++i) {
        char *text, inc[256];
        if (files.name[i][strlen(files.name[i]) - 1] != 'c') continue; /* a .c file's interface */
        text = test_read_text(files.name[i]);
        if (text && nth_include(text, files.name[i], 0, inc, sizeof inc) && !list_has(out, inc)) list_add(out, inc);
        free(text);
    }
    free(files.name);
}

/* Follows the includes of `file` depth first; 1 (with the chain in `why`) if a forbidden
 * header is reached. */
static int reaches(const char *file, const path_list *forbidden, path_list *seen, char *why, size_t size)
{
    char *text = test_read_text(file);
    char inc[256];
    int i, found = 0;
    if (!text) return 0;
    for (i = 0; !found && nth_include(text, file, i, inc, sizeof inc); ++i) {
        if (list_has(seen, inc)) continue;
        list_add(seen, inc);
        if (list_has(forbidden, inc)) {
            snprintf(why, size, "%s includes %s", file, inc);
            found = 1;
        } else if (reaches(inc, forbidden, seen, why, size)) {
            size_t n = strlen(why);
            snprintf(why + n, size - n, " (via %s)", file);
            found = 1;
        }
    }
    free(text);
    return found;
}

static int layer_violation(const char *const *dirs, int ndirs, const path_list *forbidden, char *why, size_t size)
{
    int d, i, found = 0;
    for (d = 0; d < ndirs && !found; ++d) {
        path_list files = {0};
        list_sources(&files, dirs[d]);
        for (i = 0; i < files.count && !found; ++i) {
            path_list seen = {0};
            found = reaches(files.name[i], forbidden, &seen, why, size);
            free(seen.name);
        }
        free(files.name);
    }
    return found;
}

TEST(house_layers)
{
    static const char *const algorithms[] = {"src/render", "src/restir"};
    path_list forbidden = {0};
    char why[2048];
    int bad;
    interface_headers(&forbidden, "src/bench");
    interface_headers(&forbidden, "src/metrics");
    CHECKF(forbidden.count >= 8 && list_has(&forbidden, "include/restir/metrics/metrics.h"),
           "house_layers: found only %d bench/metrics headers (is the suite running from the repository root?)",
           forbidden.count);
    bad = layer_violation(algorithms, 2, &forbidden, why, sizeof why);
    free(forbidden.name);
    CHECKF(!bad, "house_layers: %s, a bench or metrics header (docs/design.md, Layout)", why);
    /* and the path tracer is below ReSTIR: src/render reaches no src/restir header */
    memset(&forbidden, 0, sizeof forbidden);
    interface_headers(&forbidden, "src/restir");
    bad = layer_violation(algorithms, 1, &forbidden, why, sizeof why);
    free(forbidden.name);
    CHECKF(!bad, "house_layers: %s, a restir header (render is below restir)", why);
}

/* The check sees a planted violation: a restir file that includes metrics.h. */
TEST(house_layers_detects_a_violation)
{
    static const char *const planted[] = {RESTIR_TMP "/house-layer"};
    path_list forbidden = {0};
    char why[2048];
    FILE *f;
    int bad;
    interface_headers(&forbidden, "src/metrics");
    CHECK(system("mkdir -p " RESTIR_TMP "/house-layer") == 0);
    f = fopen(RESTIR_TMP "/house-layer/planted.h", "w");
    CHECK(f != NULL);
    fputs("#include \"restir/restir/reservoir.h\"\n#include \"restir/metrics/stats.h\"\n", f);
    fclose(f);
    f = fopen(RESTIR_TMP "/house-layer/planted.c", "w");
    CHECK(f != NULL);
    fputs("#include \"planted.h\"\n", f);
    fclose(f);
    bad = layer_violation(planted, 1, &forbidden, why, sizeof why);
    free(forbidden.name);
    CHECKF(bad && strstr(why, "include/restir/metrics/stats.h"), "planted include not found (%s)", bad ? why : "-");
}

/* ---- house_equations_cited ---- */

/* The paper a citation at `at` belongs to: the last paper name written before it. */
static const char *paper_before(const char *text, const char *at)
{
    static const char *const papers[] = {"GRIS", "Enhanced", "Mutations", "Stochastic"};
    const char *best = NULL, *where = NULL;
    int i;
    for (i = 0; i < 4; ++i) {
        const char *p = text, *last = NULL;
        while ((p = strstr(p, papers[i])) && p < at) last = p++;
        if (last && (!where || last > where)) {
            where = last;
            best = papers[i];
        }
    }
    return best;
}

/* 1 if text[0..n) cites equation eq of `paper`: some "Eq. N" / "Eqs. A-B, C and D" list
 * contains eq, and the last paper name before it is `paper` ("GRIS Eq. 19", "Stochastic
 * MIS Eqs. 9-12", "Mutations App. B Eqs. 31-32"). */
static int cites(const char *text, size_t n, const char *paper, int eq)
{
    const char *p, *end = text + n;
    for (p = text; p + 4 <= end; ++p) {
        const char *q, *owner;
        if (strncmp(p, "Eq.", 3) && strncmp(p, "Eqs.", 4)) continue;
        owner = paper_before(text, p);
        if (!owner || strcmp(owner, paper)) continue;
        q = p + (p[2] == 's' ? 4 : 3);
        for (;;) {
            long a, b;
            char *after;
            while (q < end && *q == ' ') ++q;
            if (q >= end || *q < '0' || *q > '9') break;
            a = b = strtol(q, &after, 10);
            q = after;
            while (q < end && *q == ' ') ++q;
            if (q < end && (*q == '-' || !strncmp(q, "\xe2\x80\x93", 3))) { /* "-" or an en dash */
                q += *q == '-' ? 1 : 3;
                while (q < end && *q == ' ') ++q;
                b = strtol(q, &after, 10);
                if (after == q) break;
                q = after;
            }
            if (a <= eq && eq <= b) return 1;
            while (q < end && *q == ' ') ++q;
            if (q < end && (*q == ',' || *q == '&')) ++q;
            else if (q + 3 <= end && !strncmp(q, "and", 3)) q += 3;
            else break;
        }
    }
    return 0;
}

/* The first line of text that starts a definition or declaration of `name`: it begins with
 * a lower-case letter (a type) and holds "name(" after a non-identifier character. */
static const char *find_definition(const char *text, const char *name)
{
    size_t n = strlen(name);
    const char *p = text;
    while ((p = strstr(p, name))) {
        const char *line = p;
        while (line > text && line[-1] != '\n') --line;
        if (p[n] == '(' && p > text && !(p[-1] == '_' || (p[-1] >= 'a' && p[-1] <= 'z') || (p[-1] >= '0' && p[-1] <= '9')) &&
            *line >= 'a' && *line <= 'z' && !memchr(line, ';', (size_t)(p - line)))
            return p;
        p += n;
    }
    return NULL;
}

static const char *last_before(const char *text, const char *at, const char *what)
{
    const char *best = NULL, *p = text;
    while ((p = strstr(p, what)) && p < at) best = p++;
    return best;
}

/* The comment and body of a definition in a .c file, or the comment of a declaration. */
static int definition_cites(const char *text, const char *name, const char *paper, int eq, int is_header)
{
    const char *def = find_definition(text, name), *start, *end, *alt;
    if (!def) return -1;
    start = last_before(text, def, "\n}\n");
    if (is_header) {
        alt = last_before(text, def, ";\n");
        if (alt && (!start || alt > start)) start = alt;
        alt = last_before(text, def, "\n\n");
        if (alt && (!start || alt > start)) start = alt;
        end = strchr(def, ';');
    } else {
        end = strstr(def, "\n}\n");
    }
    if (!start) start = text;
    if (!end) end = def + strlen(def);
    return cites(start, (size_t)(end - start), paper, eq);
}

static int header_cites(const path_list *headers, const char *name, const char *paper, int eq)
{
    int i;
    for (i = 0; i < headers->count; ++i) {
        char *text;
        int ok;
        if (headers->name[i][strlen(headers->name[i]) - 1] != 'h') continue;
        text = test_read_text(headers->name[i]);
        ok = text && definition_cites(text, name, paper, eq, 1) == 1;
        free(text);
        if (ok) return 1;
    }
    return 0;
}

/* Checks one "implemented in" cell; returns the number of functions checked, or -1 with
 * the failure in why. */
static int check_cell(const char *cell, const char *paper, int eq, const path_list *headers, char *why, size_t size)
{
    char names[16][128];
    int pending = 0, checked = 0;
    const char *p = cell;
    while (*p) {
        if (*p == '`') {
            const char *end = strchr(p + 1, '`');
            if (!end) break;
            if (pending < 16) snprintf(names[pending++], sizeof names[0], "%.*s", (int)(end - p - 1), p + 1);
            p = end + 1;
            while (*p == ',' || *p == ' ') ++p;
            if (*p == '`') continue;
            if (!strncmp(p, "(src/", 5)) {
                char path[200];
                const char *close = strchr(p, ')');
                char *text;
                int i;
                if (!close) break;
                snprintf(path, sizeof path, "%.*s", (int)(close - p - 1), p + 1);
                text = test_read_text(path);
                if (!text) {
                    snprintf(why, size, "%s Eq. %d: %s does not exist", paper, eq, path);
                    return -1;
                }
                for (i = 0; i < pending; ++i) {
                    int r = definition_cites(text, names[i], paper, eq, 0);
                    if (r == 1 || (r == 0 && header_cites(headers, names[i], paper, eq))) {
                        ++checked;
                        continue;
                    }
                    snprintf(why, size, "%s Eq. %d: %s (%s) %s", paper, eq, names[i], path,
                             r < 0 ? "is not defined there" : "does not cite the equation");
                    free(text);
                    return -1;
                }
                free(text);
                p = close + 1;
            }
            pending = 0;
            continue;
        }
        ++p;
    }
    return checked;
}

/* Checks every row of an equations.md text; returns the number of functions checked, or
 * -1 with the first failure in why. */
static int check_equations(const char *doc, char *why, size_t size)
{
    path_list headers = {0};
    char paper[64] = "";
    const char *line = doc;
    int total = 0;
    list_sources(&headers, "include/restir");
    list_sources(&headers, "src/restir");
    list_sources(&headers, "src/render");
    for (; *line; line = strchr(line, '\n') ? strchr(line, '\n') + 1 : line + strlen(line)) {
        const char *eol = strchr(line, '\n');
        size_t len = eol ? (size_t)(eol - line) : strlen(line);
        char row[8192];
        int eq, col, r;
        char *cell;
        if (!strncmp(line, "## ", 3)) { /* "## GRIS — ...": the paper's name is the first word */
            sscanf(line + 3, "%63s", paper);
            continue;
        }
        if (len >= sizeof row || sscanf(line, "| %d |", &eq) != 1 || !paper[0]) continue;
        memcpy(row, line, len);
        row[len] = '\0';
        for (cell = row, col = 0; cell && col < 4; ++col) { /* | Eq. | § | what | kind | implemented in | */
            cell = strstr(cell, " | ");
            if (cell) cell += 3;
        }
        if (!cell) continue;
        if (strstr(cell, " | ")) *strstr(cell, " | ") = '\0';
        r = check_cell(cell, paper, eq, &headers, why, size);
        if (r < 0) {
            free(headers.name);
            return -1;
        }
        total += r;
    }
    free(headers.name);
    return total;
}

TEST(house_equations_cited)
{
    char *doc = test_read_text("docs/equations.md");
    char why[4096] = "";
    int n;
    CHECKF(doc != NULL, "docs/equations.md not found (the suite runs from the repository root)");
    n = check_equations(doc, why, sizeof why);
    free(doc);
    CHECKF(n >= 0, "docs/equations.md: %s", why);
    CHECKF(n >= 60, "docs/equations.md: only %d functions checked (parser out of step with the table?)", n);
}

/* The check rejects a row whose function does not exist, one whose function does not
 * cite the row's equation, and one that cites it without the paper's name. */
TEST(house_equations_check_detects_stale_rows)
{
    char why[4096];
    CHECK(check_equations("## GRIS — x\n| 19 | 4.4 | w | estimator | `gris_resampling_weight` (src/restir/reservoir.c) | t |\n",
                          why, sizeof why) == 1);
    CHECK(check_equations("## GRIS — x\n| 19 | 4.4 | w | estimator | `merge_two_domains` (src/restir/merge.c) | t |\n", why,
                          sizeof why) < 0);
    CHECK(strstr(why, "does not exist") != NULL);
    CHECK(check_equations("## GRIS — x\n| 36 | 4.4 | w | estimator | `spatial_resample` (src/restir/spatial.c) | t |\n",
                          why, sizeof why) < 0);
    CHECK(strstr(why, "does not cite") != NULL);
    CHECK(check_equations("## GRIS — x\n| 36 | 4.4 | w | estimator | `no_such_function` (src/restir/spatial.c) | t |\n",
                          why, sizeof why) < 0);
    CHECK(strstr(why, "not defined") != NULL);
    CHECK(check_equations("## Mutations — x\n| 19 | 4.4 | w | estimator | `gris_resampling_weight` (src/restir/reservoir.c) | t |\n",
                          why, sizeof why) < 0);
    CHECK(check_equations("## GRIS — x\n| 20 | 4.4 | w | estimator | `gris_resampling_weight` (src/restir/reservoir.c) | t |\n",
                          why, sizeof why) < 0);
}
