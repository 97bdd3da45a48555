/* Wavefront MTL reader and the MTL -> material mapping (docs/scene-format.md). */
#include "restir/scene/mtl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "restir/scene/scene_builder.h"
#include "restir/scene/text.h"
#include "restir/scene/texture.h"

typedef struct {
    scene_builder *b;
    text_reader text;
    const char *path;
    int open;          /* a newmtl block is being read */
    char name[MATERIAL_NAME_MAX];
    long name_line;
    mtl_record r;
    char dir[4096];    /* the library's directory: map file names are relative to it */
} mtl_parser;

/* Statements we accept and skip: ambient colour (Ka; no ambient term in a path tracer),
 * transmission filter (Tf, Kt), sharpness, the PBR extension keys we do not model
 * (sheen, clearcoat, anisotropy), bump/normal/displacement/reflection maps and every
 * map_ other than the five read (map_Kd, map_Ke, map_Pr, map_Ns, map_d). */
static const char *const ignored_keys[] = {"Ka", "Tf", "Kt", "Km", "sharpness", "Ps", "Pc", "Pcr", "aniso", "anisor",
                                           "bump", "disp", "decal", "refl", "norm", NULL};

static int ci_equal(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b) {
        int ca = (unsigned char)*a, cb = (unsigned char)*b;
        if (ca >= 'A' && ca <= 'Z') ca += 'a' - 'A';
        if (cb >= 'A' && cb <= 'Z') cb += 'a' - 'A';
        if (ca != cb) return 0;
    }
    return *a == *b;
}

static int is_ignored_key(const char *key)
{
    const char *const *k;
    if (!strncmp(key, "map_", 4) || !strncmp(key, "MAP_", 4)) return 1;
    for (k = ignored_keys; *k; ++k)
        if (ci_equal(*k, key)) return 1;
    return 0;
}

real roughness_from_phong_exponent(double ns)
{
    /* Walter et al. 2007, Sec. 5.2: Phong exponent a_p = 2 / a_b^2 - 2, so a_b = sqrt(2 / (a_p + 2)).
     * Used as the GGX alpha; alpha = r^2 gives the linear roughness r. */
    double alpha = sqrt(2.0 / (ns + 2.0));
    return (real)sqrt(alpha);
}

static int is_transparent_illum(int illum) { return illum == 4 || illum == 6 || illum == 7 || illum == 9; }

/* The mapping without maps (rules 1-7 of docs/scene-format.md); *uses_glossy: the
 * roughness is `glossy` (set from Pr or Ns). */
static material lobed_material(const char *name, const mtl_record *r, int *uses_glossy, int *dissolve_ignored)
{
    material m = material_default(name);
    rgb kd = r->has_kd ? r->kd : m.diffuse, ks = r->has_ks ? r->ks : rgb_gray(0);
    double dissolve = r->has_d ? r->d : (r->has_tr ? 1.0 - r->tr : 1.0);
    int pbr = r->has_pr || r->has_pm;
    int transparent = (r->has_illum && is_transparent_illum(r->illum)) || (dissolve < 1 && r->has_ni && r->ni > 1);
    real glossy = r->has_pr ? (real)r->pr : (r->has_ns ? roughness_from_phong_exponent(r->ns) : (real)0.5);
    real coat_ior = r->has_ni && r->ni > 1 ? (real)r->ni : (real)1.5;

    *uses_glossy = 0;
    m.diffuse = kd;
    m.emission = r->has_ke ? r->ke : rgb_gray(0);
    if (r->has_pm && r->pm > 0.5) { /* 1. PBR metal: the base colour Kd is F0 */
        m.type = MAT_CONDUCTOR;
        m.specular = kd;
        m.roughness = glossy;
        m.map_kd_is_f0 = 1;
        *uses_glossy = 1;
    } else if (!r->has_pm && r->has_illum && (r->illum == 3 || r->illum == 5)) { /* 2. mirror */
        m.type = MAT_CONDUCTOR;
        m.specular = ks;
        m.roughness = r->has_pr ? (real)r->pr : 0;
    } else if (transparent) { /* 3. glass */
        m.type = r->has_pr && r->pr > 0 ? MAT_ROUGH_DIELECTRIC : MAT_DIELECTRIC;
        m.specular = rgb_gray(1);
        m.roughness = r->has_pr ? (real)r->pr : 0;
        m.ior = r->has_ni && r->ni > 0 ? (real)r->ni : (real)1.5;
    } else if (!pbr && r->has_illum && (r->illum == 0 || r->illum == 1)) { /* 4. no highlight */
        m.type = MAT_LAMBERT;
    } else if (pbr) { /* 5. PBR dielectric base: diffuse + coat */
        m.type = MAT_PLASTIC;
        m.specular = rgb_max(ks) > 0 ? ks : rgb_gray(1);
        m.roughness = glossy;
        m.ior = coat_ior;
        *uses_glossy = 1;
    } else if (rgb_max(ks) > 0) { /* 6. classic highlight */
        m.type = rgb_max(kd) > 0 ? MAT_PLASTIC : MAT_CONDUCTOR;
        m.specular = ks;
        m.roughness = glossy;
        m.ior = coat_ior;
        *uses_glossy = 1;
    } else { /* 7. */
        m.type = MAT_LAMBERT;
    }
    if (m.type != MAT_PLASTIC && m.type != MAT_DIELECTRIC && m.type != MAT_ROUGH_DIELECTRIC) m.ior = (real)1.5;
    *dissolve_ignored = dissolve < 1 && m.type != MAT_DIELECTRIC && m.type != MAT_ROUGH_DIELECTRIC;
    return m;
}

material mtl_to_material(const char *name, const mtl_record *given, int *dissolve_ignored)
{
    mtl_record q = *given;
    material m;
    int uses_glossy;
    /* A map multiplies its scalar (MTL specification); a map given without its scalar
     * multiplies 1 (Ns: 1000, the top of the exporters' 0..1000 range). */
    if (q.map_kd && !q.has_kd) q.kd = rgb_gray(1), q.has_kd = 1;
    if (q.map_ke && !q.has_ke) q.ke = rgb_gray(1), q.has_ke = 1;
    if (q.map_pr && !q.has_pr) q.pr = 1, q.has_pr = 1;
    if (q.map_ns && !q.has_ns) q.ns = 1000, q.has_ns = 1;
    m = lobed_material(name, &q, &uses_glossy, dissolve_ignored);
    m.map_kd = q.map_kd;
    m.map_ke = q.map_ke;
    m.map_alpha = q.map_d;
    if (q.map_pr && m.type != MAT_LAMBERT && m.type != MAT_DIELECTRIC) { /* wherever Pr sets r */
        m.map_roughness = q.map_pr;
        m.roughness_map_scale = (real)q.pr;
    } else if (q.map_ns && uses_glossy && !given->has_pr) { /* wherever Ns sets r */
        m.map_roughness = q.map_ns;
        m.roughness_from_ns = 1;
        m.roughness_map_scale = (real)q.ns;
    }
    return m;
}

static int number(mtl_parser *p, const char *key, const char *tok, double lo, double hi, double *out, rerror *e)
{
    enum number_status st;
    if (!tok) return rerror_at(e, p->path, p->text.line, "%s: missing value", key);
    st = text_parse_double(tok, out);
    if (st != NUMBER_OK) return rerror_at(e, p->path, p->text.line, "%s: %s '%s'", key, text_number_problem(st), tok);
    if (*out < lo || *out > hi)
        return rerror_at(e, p->path, p->text.line, "%s: %s outside [%g, %g]", key, tok, lo, hi);
    return 0;
}

/* "K r [g b]": one value means grey. */
static int colour(mtl_parser *p, const char *key, char *rest, double hi, rgb *out, int *has, rerror *e)
{
    double v[3];
    char *tok[4];
    int n = 0, i;
    while (n < 4 && (tok[n] = text_next_token(&rest)) != NULL) n++;
    if (n >= 1 && (!strcmp(tok[0], "spectral") || !strcmp(tok[0], "xyz")))
        return rerror_at(e, p->path, p->text.line, "%s %s: only RGB colours are supported", key, tok[0]);
    if (n != 1 && n != 3) return rerror_at(e, p->path, p->text.line, "%s: expected 1 or 3 numbers", key);
    for (i = 0; i < n; ++i)
        if (number(p, key, tok[i], 0, hi, &v[i], e)) return -1;
    if (n == 1) v[1] = v[2] = v[0];
    *out = rgb_make((real)v[0], (real)v[1], (real)v[2]);
    *has = 1;
    return 0;
}

static int scalar(mtl_parser *p, const char *key, char *rest, double lo, double hi, double *out, int *has, rerror *e)
{
    char *tok = text_next_token(&rest);
    if (number(p, key, tok, lo, hi, out, e)) return -1;
    if (text_next_token(&rest)) return rerror_at(e, p->path, p->text.line, "%s: expected one number", key);
    *has = 1;
    return 0;
}

static int define_current(mtl_parser *p, rerror *e)
{
    scene_builder *b = p->b;
    uint32_t index;
    int dissolve_ignored;
    if (!p->open) return 0;
    p->open = 0;
    if (builder_material(b, p->name, &index, e)) return -1; /* only out of memory: names were checked */
    if (b->material_origin[index] != MATERIAL_UNDEFINED)
        return builder_warn(b, p->path, p->name_line, "material '%s' defined again; the first definition is kept",
                            p->name)
                   ? rerror_set(e, "out of memory")
                   : 0;
    if (p->r.map_d && p->r.has_ke && rgb_max(p->r.ke) > 0)
        return rerror_at(e, p->path, p->name_line,
                         "material '%s': map_d (cut-out) on an emitting material is not supported", p->name);
    b->s->materials[index] = mtl_to_material(p->name, &p->r, &dissolve_ignored);
    if (p->r.map_d) b->s->has_cutouts = 1;
    b->material_origin[index] = MATERIAL_FROM_MTL;
    if (dissolve_ignored &&
        builder_warn(b, p->path, p->name_line,
                     "material '%s': partial dissolve (d < 1 or Tr > 0) without a refractive illum model or Ni > 1 "
                     "is ignored; the material is opaque",
                     p->name))
        return rerror_set(e, "out of memory");
    return 0;
}

static int start_material(mtl_parser *p, char *rest, rerror *e)
{
    const char *name = text_rest(rest);
    if (define_current(p, e)) return -1;
    if (strlen(name) >= MATERIAL_NAME_MAX)
        return rerror_at(e, p->path, p->text.line, "newmtl: material name longer than %d bytes", MATERIAL_NAME_MAX - 1);
    snprintf(p->name, sizeof p->name, "%s", name);
    p->name_line = p->text.line;
    memset(&p->r, 0, sizeof p->r);
    p->open = 1;
    return 0;
}

/* "map_X file": the file name is the rest of the line (it may contain spaces), relative
 * to the library's directory. Options (-o, -s, -clamp, -bm, ...) are refused: the lookup
 * is the one documented reference (unscaled UVs, repeat wrap). */
static int map_statement(mtl_parser *p, const char *key, char *rest, enum texture_kind kind, uint32_t *map,
                         rerror *e)
{
    const char *name = text_rest(rest);
    char path[4096];
    if (!p->open) return rerror_at(e, p->path, p->text.line, "'%s' before the first newmtl", key);
    if (!*name) return rerror_at(e, p->path, p->text.line, "%s: missing file name", key);
    if (name[0] == '-')
        return rerror_at(e, p->path, p->text.line, "%s: option '%.20s' is not supported (docs/materials.md, Textures)",
                         key, name);
    if (text_join_path(path, sizeof path, p->dir, name))
        return rerror_at(e, p->path, p->text.line, "%s: path too long", key);
    if (builder_texture(p->b, path, kind, map, e)) {
        char what[sizeof e->msg];
        memcpy(what, e->msg, sizeof what);
        /* As a missing mtllib: an error unless the caller allows missing material files. */
        if (p->b->options.allow_missing_mtl)
            return builder_warn(p->b, p->path, p->text.line, "%s: %s (the map is ignored)", key, what)
                       ? rerror_set(e, "out of memory")
                       : 0;
        return rerror_at(e, p->path, p->text.line, "%s: %s", key, what);
    }
    return 0;
}

/* The five maps read; 1 if key is one of them (the statement is then handled). */
static int read_map(mtl_parser *p, const char *key, char *rest, int *status, rerror *e)
{
    mtl_record *r = &p->r;
    if (ci_equal(key, "map_Kd")) *status = map_statement(p, "map_Kd", rest, TEXTURE_COLOUR, &r->map_kd, e);
    else if (ci_equal(key, "map_Ke")) *status = map_statement(p, "map_Ke", rest, TEXTURE_COLOUR, &r->map_ke, e);
    else if (ci_equal(key, "map_Pr")) *status = map_statement(p, "map_Pr", rest, TEXTURE_SCALAR, &r->map_pr, e);
    else if (ci_equal(key, "map_Ns")) *status = map_statement(p, "map_Ns", rest, TEXTURE_SCALAR, &r->map_ns, e);
    else if (ci_equal(key, "map_d")) *status = map_statement(p, "map_d", rest, TEXTURE_ALPHA, &r->map_d, e);
    else return 0;
    return 1;
}

static int read_statement(mtl_parser *p, char *line, rerror *e)
{
    char *rest = line, *key = text_next_token(&rest);
    mtl_record *r = &p->r;
    double v;
    if (!key) return 0;
    int status;
    if (ci_equal(key, "newmtl")) return start_material(p, rest, e);
    if (read_map(p, key, rest, &status, e)) return status;
    if (is_ignored_key(key)) return 0;
    if (!p->open) {
        if (ci_equal(key, "Kd") || ci_equal(key, "Ks") || ci_equal(key, "Ke") || ci_equal(key, "Ns") ||
            ci_equal(key, "Ni") || ci_equal(key, "d") || ci_equal(key, "Tr") || ci_equal(key, "illum") ||
            ci_equal(key, "Pr") || ci_equal(key, "Pm"))
            return rerror_at(e, p->path, p->text.line, "'%s' before the first newmtl", key);
    }
    /* Reflectances above 1 would create energy; emission is unbounded. */
    if (ci_equal(key, "Kd")) return colour(p, "Kd", rest, 1, &r->kd, &r->has_kd, e);
    if (ci_equal(key, "Ks")) return colour(p, "Ks", rest, 1, &r->ks, &r->has_ks, e);
    if (ci_equal(key, "Ke")) return colour(p, "Ke", rest, 1e30, &r->ke, &r->has_ke, e);
    if (ci_equal(key, "Ns")) return scalar(p, "Ns", rest, 0, 1e30, &r->ns, &r->has_ns, e);
    if (ci_equal(key, "Ni")) return scalar(p, "Ni", rest, 0, 1e30, &r->ni, &r->has_ni, e);
    if (ci_equal(key, "d")) {
        /* "d -halo f" is a variant of the dissolve statement. */
        char *save = rest, *tok = text_next_token(&save);
        if (tok && !strcmp(tok, "-halo")) rest = save;
        return scalar(p, "d", rest, 0, 1, &r->d, &r->has_d, e);
    }
    if (ci_equal(key, "Tr")) return scalar(p, "Tr", rest, 0, 1, &r->tr, &r->has_tr, e);
    if (ci_equal(key, "Pr")) return scalar(p, "Pr", rest, 0, 1, &r->pr, &r->has_pr, e);
    if (ci_equal(key, "Pm")) return scalar(p, "Pm", rest, 0, 1, &r->pm, &r->has_pm, e);
    if (ci_equal(key, "illum")) {
        int has;
        if (scalar(p, "illum", rest, 0, 10, &v, &has, e)) return -1;
        if (v != floor(v)) return rerror_at(e, p->path, p->text.line, "illum: expected an integer 0..10");
        r->illum = (int)v;
        r->has_illum = 1;
        return 0;
    }
    return rerror_at(e, p->path, p->text.line, "unknown MTL statement '%.60s'", key);
}

int mtl_load(scene_builder *b, const char *path, rerror *e)
{
    mtl_parser p;
    char *line;
    int status = 0;
    if (name_table_find(&b->libraries, path) >= 0) return 0;
    if (name_table_insert(&b->libraries, path, 0, e)) return -1;
    memset(&p, 0, sizeof p);
    p.b = b;
    p.path = path;
    text_directory_of(path, p.dir, sizeof p.dir);
    if (text_open(&p.text, path, e)) return -1;
    while (!status && (line = text_next_line(&p.text)) != NULL) status = read_statement(&p, line, e);
    if (!status) status = define_current(&p, e);
    text_close(&p.text);
    return status;
}
