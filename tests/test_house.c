/* Checks that keep the house in order (issue 18); they read the source tree as text
 * (the suite runs from the repository root):
 *   house_layers:        no file of a module includes, directly or through other headers,
 *                        a header of a module of higher rank (core < scene < render <
 *                        restir < frame < {oracle, metrics, bench} < cli), and the modules'
 *                        include graph has no circle;
 *   house_headers_show_their_module: every src/M/X.c begins with its interface header
 *                        include/restir/M/X.h (or a private src/M/X.h marked as such);
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

/* The wings in order (docs/design.md, Layout): a file may include headers of its own
 * module and of lower ranks only; oracle, metrics and bench share a rank, and the module
 * graph must have no circle among them either. */
static const struct {
    const char *name;
    int rank;
} house_modules[] = {{"core", 0},   {"scene", 1},   {"render", 2}, {"restir", 3}, {"frame", 4},
                     {"oracle", 5}, {"metrics", 5}, {"bench", 5},  {"cli", 6}};
#define HOUSE_MODULES ((int)(sizeof house_modules / sizeof house_modules[0]))

/* The module (index into house_modules) a path belongs to: include/restir/M/... or src/M/...;
 * -1 for anything else (tests, a planted file). */
static int module_of(const char *path)
{
    int m;
    for (m = 0; m < HOUSE_MODULES; ++m) {
        char a[64], b[64];
        snprintf(a, sizeof a, "include/restir/%s/", house_modules[m].name);
        snprintf(b, sizeof b, "src/%s/", house_modules[m].name);
        if (!strncmp(path, a, strlen(a)) || !strncmp(path, b, strlen(b))) return m;
    }
    return -1;
}

/* Follows the includes of `file` depth first; 1 (with the chain in `why`) if a header of a
 * module ranked above `rank` is reached. edges[m] gets bit n for every module n that a
 * file of module m includes directly. */
static int reaches_above(const char *file, int rank, path_list *seen, unsigned *edges, char *why, size_t size)
{
    char *text = test_read_text(file);
    char inc[256];
    int i, found = 0, from = module_of(file);
    if (!text) return 0;
    for (i = 0; !found && nth_include(text, file, i, inc, sizeof inc); ++i) {
        int m = module_of(inc);
        if (from >= 0 && m >= 0 && m != from) edges[from] |= 1u << m;
        if (list_has(seen, inc)) continue;
        list_add(seen, inc);
        if (m >= 0 && house_modules[m].rank > rank) {
            snprintf(why, size, "%s (%s) includes %s (%s)", file, from >= 0 ? house_modules[from].name : "-", inc,
                     house_modules[m].name);
            found = 1;
        } else if (reaches_above(inc, rank, seen, edges, why, size)) {
            size_t n = strlen(why);
            snprintf(why + n, size - n, " (via %s)", file);
            found = 1;
        }
    }
    free(text);
    return found;
}

/* Every file of dir, checked against rank. */
static int layer_violation(const char *dir, int rank, unsigned *edges, char *why, size_t size)
{
    path_list files = {0};
    int i, found = 0;
    list_sources(&files, dir);
    for (i = 0; i < files.count && !found; ++i) {
        path_list seen = {0};
        found = reaches_above(files.name[i], rank, &seen, edges, why, size);
        free(seen.name);
    }
    free(files.name);
    return found;
}

/* 1 if the module graph has a circle (depth-first search with colours). */
static int module_circle(const unsigned *edges, int m, int *colour, char *why, size_t size)
{
    int n;
    colour[m] = 1;
    for (n = 0; n < HOUSE_MODULES; ++n) {
        if (!(edges[m] & (1u << n))) continue;
        if (colour[n] == 1 || (colour[n] == 0 && module_circle(edges, n, colour, why, size))) {
            size_t k = strlen(why);
            snprintf(why + k, size - k, "%s%s -> %s", k ? ", " : "", house_modules[m].name, house_modules[n].name);
            return 1;
        }
    }
    colour[m] = 2;
    return 0;
}

TEST(house_layers)
{
    unsigned edges[HOUSE_MODULES] = {0};
    int colour[HOUSE_MODULES] = {0};
    char why[2048] = "", dir[64];
    int m, bad = 0, files = 0;
    for (m = 0; m < HOUSE_MODULES && !bad; ++m) {
        path_list l = {0};
        snprintf(dir, sizeof dir, "src/%s", house_modules[m].name);
        list_sources(&l, dir);
        files += l.count;
        free(l.name);
        bad = layer_violation(dir, house_modules[m].rank, edges, why, sizeof why);
        snprintf(dir, sizeof dir, "include/restir/%s", house_modules[m].name);
        if (!bad) bad = layer_violation(dir, house_modules[m].rank, edges, why, sizeof why);
    }
    CHECKF(files >= 100, "house_layers: found only %d source files (is the suite running from the repository root?)",
           files);
    CHECKF(!bad, "house_layers: %s, a module of a higher rank (docs/design.md, Layout)", why);
    for (m = 0; m < HOUSE_MODULES && !bad; ++m)
        if (!colour[m]) bad = module_circle(edges, m, colour, why, sizeof why);
    CHECKF(!bad, "house_layers: the modules include each other in a circle: %s", why);
}

/* The check sees planted violations: a restir file that reaches metrics through a header,
 * and a circle between two modules of the same rank. */
TEST(house_layers_detects_a_violation)
{
    unsigned edges[HOUSE_MODULES] = {0};
    int colour[HOUSE_MODULES] = {0};
    char why[2048] = "";
    FILE *f;
    int bad, m;
    CHECK(system("mkdir -p " RESTIR_TMP "/house-layer") == 0);
    f = fopen(RESTIR_TMP "/house-layer/planted.h", "w");
    CHECK(f != NULL);
    fputs("#include \"restir/restir/reservoir.h\"\n#include \"restir/metrics/stats.h\"\n", f);
    fclose(f);
    f = fopen(RESTIR_TMP "/house-layer/planted.c", "w");
    CHECK(f != NULL);
    fputs("#include \"planted.h\"\n", f);
    fclose(f);
    bad = layer_violation(RESTIR_TMP "/house-layer", 3 /* restir */, edges, why, sizeof why);
    CHECKF(bad && strstr(why, "include/restir/metrics/stats.h"), "planted include not found (%s)", bad ? why : "-");
    memset(edges, 0, sizeof edges);
    why[0] = 0;
    edges[5] = 1u << 6; /* oracle -> metrics */
    edges[6] = 1u << 5; /* metrics -> oracle */
    for (bad = 0, m = 0; m < HOUSE_MODULES && !bad; ++m)
        if (!colour[m]) bad = module_circle(edges, m, colour, why, sizeof why);
    CHECKF(bad && strstr(why, "oracle") && strstr(why, "metrics"), "planted circle not found (%s)", why);
}

/* ---- house_headers: every source names its module ---- */

/* 1 if text starts (after its first comment opener) with "Private to src/<module>." */
static int marked_private(const char *text, const char *module)
{
    char want[64];
    snprintf(want, sizeof want, "/* Private to src/%s.", module);
    return !strncmp(text, want, strlen(want));
}

/* Every src/M/X.c (but the program's main.c) includes as its first header its interface:
 * include/restir/M/X.h, or a private src/M/X.h whose comment begins "Private to src/M.";
 * every header beside the sources is marked private the same way. */
static int header_violation(const char *module, char *why, size_t size)
{
    path_list files = {0};
    char dir[64];
    int i, bad = 0;
    snprintf(dir, sizeof dir, "src/%s", module);
    list_sources(&files, dir);
    for (i = 0; i < files.count && !bad; ++i) {
        const char *f = files.name[i];
        size_t n = strlen(f);
        char *text = test_read_text(f), inc[256], pub[256], priv[256];
        const char *base = strrchr(f, '/') + 1;
        if (!text) continue;
        if (f[n - 1] == 'h') {
            if (!marked_private(text, module)) bad = snprintf(why, size, "%s: a header beside the sources must begin \"/* Private to src/%s.\"", f, module) > 0;
        } else if (strcmp(f, "src/cli/main.c")) {
            snprintf(pub, sizeof pub, "include/restir/%s/%.*s.h", module, (int)(strlen(base) - 2), base);
            snprintf(priv, sizeof priv, "src/%s/%.*s.h", module, (int)(strlen(base) - 2), base);
            if (!nth_include(text, f, 0, inc, sizeof inc) || (strcmp(inc, pub) && strcmp(inc, priv)))
                bad = snprintf(why, size, "%s: its first #include is not its interface %s (or %s)", f, pub, priv) > 0;
        }
        free(text);
    }
    free(files.name);
    return bad;
}

TEST(house_headers_show_their_module)
{
    char why[512] = "";
    int m, bad = 0;
    for (m = 0; m < HOUSE_MODULES && !bad; ++m) bad = header_violation(house_modules[m].name, why, sizeof why);
    CHECKF(!bad, "house_headers: %s (docs/design.md, Layout)", why);
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
