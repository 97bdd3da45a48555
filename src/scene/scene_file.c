/* The scene file: one directive per line (docs/scene-format.md).
 *
 *   mesh PATH                         (several allowed; relative to the scene file)
 *   camera eye X Y Z target X Y Z up X Y Z fov DEGREES
 *   keyframe FRAME eye ... target ... up ... fov ...
 *   size WIDTH HEIGHT
 *   material NAME [type T] [kd R G B] [ks R G B] [ke R G B] [roughness R] [ior N]
 *   animate OBJECT FRAME [translate X Y Z] [rotate AX AY AZ DEGREES] [pivot X Y Z]
 *   environment constant R G B | environment map FILE [rotate DEGREES] [scale S]
 *   sun DX DY DZ ANGLE_DEGREES R G B
 *   light sphere X Y Z RADIUS R G B | quad CX CY CZ UX UY UZ VX VY VZ R G B | disk CX CY CZ NX NY NZ RADIUS R G B
 *
 * Names and paths containing spaces are written in double quotes. The file is read
 * completely first; then the meshes are loaded in order, then the material lines are
 * applied in order, so a material line may come before the mesh that uses it. */
#include "restir/scene/scene_file.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/core/image.h"
#include "restir/scene/animation.h"
#include "restir/scene/camera_path.h"
#include "restir/scene/light_shapes.h"
#include "restir/scene/obj.h"
#include "restir/scene/scene_builder.h"
#include "restir/scene/sky.h"
#include "restir/scene/text.h"

typedef struct {
    char name[MATERIAL_NAME_MAX];
    long line;
    int has_type, has_kd, has_ks, has_ke, has_roughness, has_ior;
    enum material_type type;
    rgb kd, ks, ke;
    real roughness, ior;
} material_line;

/* One `animate` line, resolved against the object names once the meshes are loaded. */
typedef struct {
    char name[MATERIAL_NAME_MAX];
    long line;
    object_keyframe key;
    vec3 pivot;
    int has_pivot;
} animate_line;

typedef struct {
    scene_builder *b;
    text_reader text;
    const char *path;
    char dir[4096];
    char **meshes;
    long *mesh_lines;
    size_t mesh_count, mesh_capacity, mesh_line_capacity;
    material_line *materials;
    size_t material_count, material_capacity;
    size_t keyframe_capacity;
    animate_line *animates;
    size_t animate_count, animate_capacity;
    light_shape *lights; /* `light` lines, built after the meshes */
    long *light_lines;
    size_t light_count, light_capacity, light_line_capacity, light_triangles;
    long camera_line, size_line, keyframe_line, last_keyframe_line, environment_line, sun_line;
} scene_parser;

const char *const material_type_names[] = {"lambert", "conductor", "plastic", "dielectric", "rough-dielectric", NULL};

/* The next token; a token starting with '"' runs to the next '"' (no escapes). */
static int next_word(scene_parser *p, char **rest, char **word, rerror *e)
{
    char *s = text_skip_space(*rest), *end;
    if (*s != '"') {
        *word = text_next_token(rest);
        return 0;
    }
    end = strchr(s + 1, '"');
    if (!end) return rerror_at(e, p->path, p->text.line, "unterminated quoted string");
    *end = '\0';
    *word = s + 1;
    *rest = end + 1;
    if (**rest && !text_is_space((unsigned char)**rest))
        return rerror_at(e, p->path, p->text.line, "expected a space after the closing quote");
    return 0;
}

static int read_reals(scene_parser *p, char **rest, const char *what, int count, double *out, rerror *e)
{
    int i;
    for (i = 0; i < count; ++i) {
        char *tok = text_next_token(rest);
        enum number_status st;
        if (!tok) return rerror_at(e, p->path, p->text.line, "%s: expected %d number%s", what, count, count > 1 ? "s" : "");
        st = text_parse_double(tok, &out[i]);
        if (st != NUMBER_OK)
            return rerror_at(e, p->path, p->text.line, "%s: %s '%s'", what, text_number_problem(st), tok);
    }
    return 0;
}

static int read_int(scene_parser *p, char **rest, const char *what, long lo, long hi, long *out, rerror *e)
{
    char *tok = text_next_token(rest);
    const char *end;
    enum number_status st;
    if (!tok) return rerror_at(e, p->path, p->text.line, "%s: expected an integer", what);
    st = text_parse_long(tok, &end, out);
    if (st == NUMBER_OK && *end) st = NUMBER_MALFORMED;
    if (st != NUMBER_OK)
        return rerror_at(e, p->path, p->text.line, "%s: %s '%s' (expected an integer)", what,
                         text_number_problem(st), tok);
    if (*out < lo || *out > hi) return rerror_at(e, p->path, p->text.line, "%s: %ld outside [%ld, %ld]", what, *out, lo, hi);
    return 0;
}

/* read_reals for positions and directions: |value| <= SCENE_COORD_MAX (camera_path.h),
 * so the float geometry computed from them stays finite. */
static int read_coords(scene_parser *p, char **rest, const char *what, int count, double *out, rerror *e)
{
    int i;
    if (read_reals(p, rest, what, count, out, e)) return -1;
    for (i = 0; i < count; ++i)
        if (!(fabs(out[i]) <= SCENE_COORD_MAX))
            return rerror_at(e, p->path, p->text.line, "%s: %g is out of range (|coordinate| <= %g: float geometry)",
                             what, out[i], SCENE_COORD_MAX);
    return 0;
}

static int no_more(scene_parser *p, char *rest, const char *what, rerror *e)
{
    char *tok = text_next_token(&rest);
    if (tok) return rerror_at(e, p->path, p->text.line, "%s: unexpected '%.60s'", what, tok);
    return 0;
}

static vec3 vec3_of(const double v[3]) { return v3((real)v[0], (real)v[1], (real)v[2]); }

/* eye X Y Z target X Y Z up X Y Z fov F, in any order, each exactly once. */
static int read_pose(scene_parser *p, char *rest, const char *what, camera_pose *pose, rerror *e)
{
    int have_eye = 0, have_target = 0, have_up = 0, have_fov = 0;
    char *key;
    double v[3];
    enum camera_pose_problem problem;
    while ((key = text_next_token(&rest)) != NULL) {
        int *have = !strcmp(key, "eye") ? &have_eye
                    : !strcmp(key, "target") ? &have_target
                    : !strcmp(key, "up") ? &have_up
                    : !strcmp(key, "fov") ? &have_fov
                    : NULL;
        if (!have) return rerror_at(e, p->path, p->text.line, "%s: unknown key '%.60s' (eye, target, up, fov)", what, key);
        if (*have) return rerror_at(e, p->path, p->text.line, "%s: '%s' given twice", what, key);
        *have = 1;
        if (have == &have_fov) {
            if (read_reals(p, &rest, "fov", 1, v, e)) return -1;
            if (!(v[0] > 0 && v[0] < 180))
                return rerror_at(e, p->path, p->text.line, "%s: fov %g outside (0, 180) degrees", what, v[0]);
            pose->fov_y_degrees = (real)v[0];
            continue;
        }
        if (read_coords(p, &rest, key, 3, v, e)) return -1;
        if (have == &have_eye) pose->eye = vec3_of(v);
        else if (have == &have_target) pose->target = vec3_of(v);
        else pose->up = vec3_of(v);
    }
    if (!have_eye || !have_target || !have_up || !have_fov)
        return rerror_at(e, p->path, p->text.line, "%s: missing '%s' (needs eye, target, up and fov)", what,
                         !have_eye ? "eye" : !have_target ? "target" : !have_up ? "up" : "fov");
    /* The gluLookAt basis needs target != eye and up not parallel to the view. */
    problem = camera_pose_check(pose);
    if (problem != CAMERA_POSE_OK)
        return rerror_at(e, p->path, p->text.line, "%s: %s", what, camera_pose_problem_text(problem));
    return 0;
}

static int directive_camera(scene_parser *p, char *rest, rerror *e)
{
    scene *s = p->b->s;
    if (p->camera_line)
        return rerror_at(e, p->path, p->text.line, "camera given twice (first on line %ld)", p->camera_line);
    if (p->keyframe_line)
        return rerror_at(e, p->path, p->text.line, "camera and keyframe lines cannot be mixed (keyframe on line %ld)",
                         p->keyframe_line);
    if (read_pose(p, rest, "camera", &s->camera, e)) return -1;
    p->camera_line = p->text.line;
    s->has_camera = 1;
    return 0;
}

static int directive_keyframe(scene_parser *p, char *rest, rerror *e)
{
    scene *s = p->b->s;
    long frame;
    camera_keyframe k;
    if (p->camera_line)
        return rerror_at(e, p->path, p->text.line, "camera and keyframe lines cannot be mixed (camera on line %ld)",
                         p->camera_line);
    if (read_int(p, &rest, "keyframe", -1000000000L, 1000000000L, &frame, e)) return -1;
    if (s->keyframe_count && frame <= s->keyframes[s->keyframe_count - 1].frame)
        return rerror_at(e, p->path, p->text.line, "keyframe %ld: frames must increase (previous keyframe is %d)", frame,
                         s->keyframes[s->keyframe_count - 1].frame);
    memset(&k, 0, sizeof k);
    k.frame = (int)frame;
    if (read_pose(p, rest, "keyframe", &k.pose, e)) return -1;
    if (s->keyframe_count) { /* every frame between this keyframe and the previous one needs a basis too */
        int bad = 0;
        enum camera_pose_problem problem = camera_segment_check(&s->keyframes[s->keyframe_count - 1], &k, &bad);
        if (problem != CAMERA_POSE_OK)
            return rerror_at(e, p->path, p->text.line,
                             "keyframe %ld: the camera interpolated from keyframe %d (line %ld) is degenerate at frame "
                             "%d: %s",
                             frame, s->keyframes[s->keyframe_count - 1].frame, p->last_keyframe_line, bad,
                             camera_pose_problem_text(problem));
    }
    if (builder_reserve((void **)&s->keyframes, &p->keyframe_capacity, s->keyframe_count + 1, sizeof k, e))
        return -1;
    p->last_keyframe_line = p->text.line;
    s->keyframes[s->keyframe_count++] = k;
    s->camera = s->keyframes[0].pose;
    s->has_camera = 1;
    if (!p->keyframe_line) p->keyframe_line = p->text.line;
    return 0;
}

static int directive_size(scene_parser *p, char *rest, rerror *e)
{
    long w, h;
    if (p->size_line) return rerror_at(e, p->path, p->text.line, "size given twice (first on line %ld)", p->size_line);
    if (read_int(p, &rest, "size", 1, 65536, &w, e) || read_int(p, &rest, "size", 1, 65536, &h, e) ||
        no_more(p, rest, "size", e))
        return -1;
    if (w * h > IMAGE_MAX_PIXELS)
        return rerror_at(e, p->path, p->text.line, "size %ld x %ld: more than %ld pixels", w, h, IMAGE_MAX_PIXELS);
    p->b->s->width = (int)w;
    p->b->s->height = (int)h;
    p->size_line = p->text.line;
    return 0;
}

static int directive_mesh(scene_parser *p, char *rest, rerror *e)
{
    char *name, full[4096];
    size_t n;
    if (next_word(p, &rest, &name, e)) return -1;
    if (!name || !*name) return rerror_at(e, p->path, p->text.line, "mesh: missing file name");
    if (no_more(p, rest, "mesh", e)) return -1;
    if (text_join_path(full, sizeof full, p->dir, name)) return rerror_at(e, p->path, p->text.line, "mesh: path too long");
    if (builder_reserve((void **)&p->meshes, &p->mesh_capacity, p->mesh_count + 1, sizeof(char *), e) ||
        builder_reserve((void **)&p->mesh_lines, &p->mesh_line_capacity, p->mesh_count + 1, sizeof(long), e))
        return -1;
    n = strlen(full);
    p->meshes[p->mesh_count] = rmalloc(n + 1, 1, e);
    if (!p->meshes[p->mesh_count]) return -1;
    memcpy(p->meshes[p->mesh_count], full, n + 1);
    p->mesh_lines[p->mesh_count++] = p->text.line;
    return 0;
}

static int read_colour(scene_parser *p, char **rest, const char *key, double hi, rgb *out, int *has, rerror *e)
{
    double v[3];
    int i;
    if (read_reals(p, rest, key, 3, v, e)) return -1;
    for (i = 0; i < 3; ++i)
        if (v[i] < 0 || v[i] > hi)
            return rerror_at(e, p->path, p->text.line, "material %s: %g outside [0, %g]", key, v[i], hi);
    *out = rgb_make((real)v[0], (real)v[1], (real)v[2]);
    *has = 1;
    return 0;
}

static int read_material_key(scene_parser *p, material_line *m, const char *key, char **rest, rerror *e)
{
    double v;
    if (!strcmp(key, "type")) {
        char *t = text_next_token(rest);
        int i;
        if (!t) return rerror_at(e, p->path, p->text.line, "material type: missing value");
        for (i = 0; i < MATERIAL_TYPE_COUNT; ++i)
            if (!strcmp(t, material_type_names[i])) break;
        if (i == MATERIAL_TYPE_COUNT)
            return rerror_at(e, p->path, p->text.line,
                             "material type: unknown '%.60s' (lambert, conductor, plastic, dielectric, rough-dielectric)",
                             t);
        m->type = (enum material_type)i;
        m->has_type = 1;
        return 0;
    }
    if (!strcmp(key, "kd")) return read_colour(p, rest, "kd", 1, &m->kd, &m->has_kd, e);
    if (!strcmp(key, "ks")) return read_colour(p, rest, "ks", 1, &m->ks, &m->has_ks, e);
    if (!strcmp(key, "ke")) return read_colour(p, rest, "ke", 1e30, &m->ke, &m->has_ke, e);
    if (!strcmp(key, "roughness") || !strcmp(key, "ior")) {
        int is_ior = key[0] == 'i';
        if (read_reals(p, rest, key, 1, &v, e)) return -1;
        if (is_ior ? !(v > 0) : (v < 0 || v > 1))
            return rerror_at(e, p->path, p->text.line, "material %s: %g outside %s", key, v, is_ior ? "(0, inf)" : "[0, 1]");
        if (is_ior) m->ior = (real)v, m->has_ior = 1;
        else m->roughness = (real)v, m->has_roughness = 1;
        return 0;
    }
    return rerror_at(e, p->path, p->text.line, "material: unknown key '%.60s' (type, kd, ks, ke, roughness, ior)", key);
}

static int directive_material(scene_parser *p, char *rest, rerror *e)
{
    material_line m;
    char *name, *key;
    memset(&m, 0, sizeof m);
    if (next_word(p, &rest, &name, e)) return -1;
    if (!name) return rerror_at(e, p->path, p->text.line, "material: missing name");
    if (strlen(name) >= MATERIAL_NAME_MAX)
        return rerror_at(e, p->path, p->text.line, "material: name longer than %d bytes", MATERIAL_NAME_MAX - 1);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.line = p->text.line;
    while ((key = text_next_token(&rest)) != NULL)
        if (read_material_key(p, &m, key, &rest, e)) return -1;
    if (builder_reserve((void **)&p->materials, &p->material_capacity, p->material_count + 1, sizeof m, e)) return -1;
    p->materials[p->material_count++] = m;
    return 0;
}

/* animate NAME FRAME [translate X Y Z] [rotate AX AY AZ DEG] [pivot X Y Z]; a name's lines
 * must have increasing frames and one pivot (given on any of them; default the origin). */
static int directive_animate(scene_parser *p, char *rest, rerror *e)
{
    animate_line a;
    char *name, *key;
    long frame;
    int have_t = 0, have_r = 0;
    size_t i;
    double v[4];
    memset(&a, 0, sizeof a);
    if (next_word(p, &rest, &name, e)) return -1;
    if (!name || !*name) return rerror_at(e, p->path, p->text.line, "animate: missing object name");
    if (strlen(name) >= sizeof a.name)
        return rerror_at(e, p->path, p->text.line, "animate: name longer than %d bytes", (int)sizeof a.name - 1);
    snprintf(a.name, sizeof a.name, "%s", name);
    a.line = p->text.line;
    if (read_int(p, &rest, "animate", -1000000000L, 1000000000L, &frame, e)) return -1;
    a.key.frame = (int)frame;
    a.key.axis = v3(0, 1, 0);
    while ((key = text_next_token(&rest)) != NULL) {
        int *have = !strcmp(key, "translate") ? &have_t : !strcmp(key, "rotate") ? &have_r
                    : !strcmp(key, "pivot") ? &a.has_pivot : NULL;
        if (!have)
            return rerror_at(e, p->path, p->text.line, "animate: unknown key '%.60s' (translate, rotate, pivot)", key);
        if (*have) return rerror_at(e, p->path, p->text.line, "animate: '%s' given twice", key);
        *have = 1;
        if (read_coords(p, &rest, key, have == &have_r ? 4 : 3, v, e)) return -1;
        if (have == &have_t) a.key.translate = vec3_of(v);
        else if (have == &a.has_pivot) a.pivot = vec3_of(v);
        else {
            a.key.axis = vec3_of(v);
            a.key.angle_degrees = (real)v[3];
            if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0))
                return rerror_at(e, p->path, p->text.line, "animate: rotate: the axis is zero");
        }
    }
    for (i = p->animate_count; i-- > 0;) {
        const animate_line *o = &p->animates[i];
        if (strcmp(o->name, a.name)) continue;
        if (a.key.frame <= o->key.frame)
            return rerror_at(e, p->path, p->text.line,
                             "animate '%s': frame %d after frame %d (line %ld): frames must increase", a.name,
                             a.key.frame, o->key.frame, o->line);
        break;
    }
    for (i = 0; i < p->animate_count; ++i) {
        const animate_line *o = &p->animates[i];
        if (strcmp(o->name, a.name) || !o->has_pivot || !a.has_pivot) continue;
        if (o->pivot.x != a.pivot.x || o->pivot.y != a.pivot.y || o->pivot.z != a.pivot.z)
            return rerror_at(e, p->path, p->text.line, "animate '%s': pivot differs from line %ld (one pivot per object)",
                             a.name, o->line);
    }
    if (builder_reserve((void **)&p->animates, &p->animate_capacity, p->animate_count + 1, sizeof a, e)) return -1;
    p->animates[p->animate_count++] = a;
    return 0;
}

/* After the meshes and materials: one animation per named object, in order of first line. */
static int apply_animations(scene_parser *p, rerror *e)
{
    scene *s = p->b->s;
    size_t i, j, n;
    for (i = 0; i < p->animate_count; ++i) {
        const animate_line *a = &p->animates[i];
        object_keyframe *keys;
        vec3 pivot = v3(0, 0, 0);
        uint32_t object;
        int done = 0, status;
        for (j = 0; j < i; ++j) done |= !strcmp(p->animates[j].name, a->name);
        if (done) continue;
        for (object = 0; object < s->object_count; ++object)
            if (!strcmp(s->object_names[object], a->name)) break;
        if (object == s->object_count)
            return rerror_at(e, p->path, a->line, "animate: no object named '%s' in the meshes (OBJ o/g names)",
                             a->name);
        keys = rmalloc(p->animate_count, sizeof *keys, e);
        if (!keys) return -1;
        for (j = i, n = 0; j < p->animate_count; ++j) {
            if (strcmp(p->animates[j].name, a->name)) continue;
            keys[n++] = p->animates[j].key;
            if (p->animates[j].has_pivot) pivot = p->animates[j].pivot;
        }
        status = scene_add_object_animation(s, object, pivot, keys, n, e);
        free(keys);
        if (status) {
            char msg[sizeof e->msg];
            snprintf(msg, sizeof msg, "%s", e->msg);
            return rerror_at(e, p->path, a->line, "animate: %s", msg);
        }
    }
    return 0;
}

/* The scene's sky description, created by its first environment or sun line. */
static scene_sky *sky_of(scene_parser *p, rerror *e)
{
    scene *s = p->b->s;
    if (!s->sky) {
        s->sky = rmalloc(1, sizeof *s->sky, e);
        if (s->sky) sky_init(s->sky);
    }
    return s->sky;
}

static int read_radiance(scene_parser *p, char **rest, const char *what, rgb *out, rerror *e)
{
    double v[3];
    if (read_reals(p, rest, what, 3, v, e)) return -1;
    if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[0] > 1e30 || v[1] > 1e30 || v[2] > 1e30)
        return rerror_at(e, p->path, p->text.line, "%s: radiance %g %g %g outside [0, 1e30]", what, v[0], v[1], v[2]);
    *out = rgb_make((real)v[0], (real)v[1], (real)v[2]);
    return 0;
}

/* environment constant R G B | environment map FILE [rotate DEG] [scale S] (docs/environment.md) */
static int directive_environment(scene_parser *p, char *rest, rerror *e)
{
    char *kind, *name, full[4096], *key;
    double rotate = 0, scale = 1;
    int have_rotate = 0, have_scale = 0;
    scene_sky *k;
    if (p->environment_line)
        return rerror_at(e, p->path, p->text.line, "environment given twice (first on line %ld)", p->environment_line);
    p->environment_line = p->text.line;
    kind = text_next_token(&rest);
    if (!kind || (strcmp(kind, "constant") && strcmp(kind, "map")))
        return rerror_at(e, p->path, p->text.line, "environment: expected 'constant R G B' or 'map FILE [rotate DEG] [scale S]'");
    if (!(k = sky_of(p, e))) return -1;
    if (!strcmp(kind, "constant")) {
        if (read_radiance(p, &rest, "environment constant", &k->env_constant, e) || no_more(p, rest, "environment", e))
            return -1;
        k->has_env = 1;
        k->env_is_map = 0;
        return 0;
    }
    if (next_word(p, &rest, &name, e)) return -1;
    if (!name || !*name) return rerror_at(e, p->path, p->text.line, "environment map: missing file name");
    while ((key = text_next_token(&rest)) != NULL) {
        int *have = !strcmp(key, "rotate") ? &have_rotate : !strcmp(key, "scale") ? &have_scale : NULL;
        if (!have) return rerror_at(e, p->path, p->text.line, "environment map: unknown key '%.60s' (rotate, scale)", key);
        if (*have) return rerror_at(e, p->path, p->text.line, "environment map: %s given twice", key);
        *have = 1;
        if (read_reals(p, &rest, key, 1, have == &have_rotate ? &rotate : &scale, e)) return -1;
    }
    if (scale < 0) return rerror_at(e, p->path, p->text.line, "environment map: scale %g is negative", scale);
    if (text_join_path(full, sizeof full, p->dir, name))
        return rerror_at(e, p->path, p->text.line, "environment map: path too long");
    k->rotate_degrees = (real)rotate;
    if (sky_load_map(k, full, (real)scale, e)) {
        char what[sizeof e->msg];
        memcpy(what, e->msg, sizeof what);
        return rerror_at(e, p->path, p->text.line, "environment map: %s", what);
    }
    return 0;
}

/* sun DX DY DZ ANGLE_DEG R G B: direction towards the sun, angular radius, radiance. */
static int directive_sun(scene_parser *p, char *rest, rerror *e)
{
    double d[3], angle;
    scene_sky *k;
    if (p->sun_line) return rerror_at(e, p->path, p->text.line, "sun given twice (first on line %ld)", p->sun_line);
    p->sun_line = p->text.line;
    if (!(k = sky_of(p, e))) return -1;
    if (read_reals(p, &rest, "sun direction", 3, d, e) || read_reals(p, &rest, "sun angle", 1, &angle, e) ||
        read_radiance(p, &rest, "sun radiance", &k->sun_radiance, e) || no_more(p, rest, "sun", e))
        return -1;
    if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 1e-24))
        return rerror_at(e, p->path, p->text.line, "sun: the direction is zero");
    if (!(angle > 0 && angle < 90))
        return rerror_at(e, p->path, p->text.line, "sun: angular radius %g degrees outside (0, 90)", angle);
    k->has_sun = 1;
    k->sun_direction = vec3_of(d);
    k->sun_angle_degrees = (real)angle;
    return 0;
}

/* light sphere X Y Z RADIUS R G B | light quad CX CY CZ UX UY UZ VX VY VZ R G B |
 * light disk CX CY CZ NX NY NZ RADIUS R G B (docs/scene-format.md, "Lights"). */
static int directive_light(scene_parser *p, char *rest, rerror *e)
{
    light_shape l;
    char *kind = text_next_token(&rest), what[16];
    double v[13];
    int n, k;
    memset(&l, 0, sizeof l);
    if (!kind) return rerror_at(e, p->path, p->text.line, "light: missing shape (sphere, quad, disk)");
    if (!strcmp(kind, "sphere")) l.kind = LIGHT_SPHERE, n = 7;
    else if (!strcmp(kind, "quad")) l.kind = LIGHT_QUAD, n = 12;
    else if (!strcmp(kind, "disk")) l.kind = LIGHT_DISK, n = 10;
    else return rerror_at(e, p->path, p->text.line, "light: unknown shape '%.60s' (sphere, quad, disk)", kind);
    snprintf(what, sizeof what, "light %s", kind);
    if (read_reals(p, &rest, what, n, v, e) || no_more(p, rest, what, e)) return -1;
    for (k = 0; k < 3; ++k) {
        l.centre[k] = v[k];
        l.u[k] = l.kind == LIGHT_QUAD ? v[3 + k] : 0;
        l.v[k] = l.kind == LIGHT_QUAD ? v[6 + k] : 0;
        l.normal[k] = l.kind == LIGHT_DISK ? v[3 + k] : 0;
    }
    l.radius = l.kind == LIGHT_SPHERE ? v[3] : l.kind == LIGHT_DISK ? v[6] : 0;
    l.radiance = rgb_make((real)v[n - 3], (real)v[n - 2], (real)v[n - 1]);
    if (light_shape_check(&l, e)) {
        char msg[sizeof e->msg];
        snprintf(msg, sizeof msg, "%s", e->msg);
        return rerror_at(e, p->path, p->text.line, "%s: %s", what, msg);
    }
    /* A bound on what a short file can ask for (a sphere line is 8000 triangles). */
    p->light_triangles += l.kind == LIGHT_SPHERE ? 20 * LIGHT_SPHERE_DIVISIONS * LIGHT_SPHERE_DIVISIONS
                          : l.kind == LIGHT_DISK ? LIGHT_DISK_SEGMENTS : 2;
    if (p->light_triangles > LIGHT_MAX_TRIANGLES)
        return rerror_at(e, p->path, p->text.line, "light: the lights would have more than %d triangles in all",
                         LIGHT_MAX_TRIANGLES);
    if (builder_reserve((void **)&p->lights, &p->light_capacity, p->light_count + 1, sizeof l, e) ||
        builder_reserve((void **)&p->light_lines, &p->light_line_capacity, p->light_count + 1, sizeof(long), e))
        return -1;
    p->lights[p->light_count] = l;
    p->light_lines[p->light_count++] = p->text.line;
    return 0;
}

/* After the meshes (their triangles keep their indices): each light is a new pure emitter
 * material and object named "light (line N)". */
static int apply_lights(scene_parser *p, rerror *e)
{
    size_t i;
    for (i = 0; i < p->light_count; ++i) {
        char name[64];
        snprintf(name, sizeof name, "light (line %ld)", p->light_lines[i]);
        if (light_shape_add(p->b, &p->lights[i], name, e)) {
            char msg[sizeof e->msg];
            snprintf(msg, sizeof msg, "%s", e->msg);
            return rerror_at(e, p->path, p->light_lines[i], "light: %s", msg);
        }
    }
    return 0;
}

static int read_directive(scene_parser *p, char *line, rerror *e)
{
    char *rest = line, *word = text_next_token(&rest);
    if (!word) return 0;
    if (!strcmp(word, "mesh")) return directive_mesh(p, rest, e);
    if (!strcmp(word, "camera")) return directive_camera(p, rest, e);
    if (!strcmp(word, "keyframe")) return directive_keyframe(p, rest, e);
    if (!strcmp(word, "size")) return directive_size(p, rest, e);
    if (!strcmp(word, "material")) return directive_material(p, rest, e);
    if (!strcmp(word, "animate")) return directive_animate(p, rest, e);
    if (!strcmp(word, "environment")) return directive_environment(p, rest, e);
    if (!strcmp(word, "sun")) return directive_sun(p, rest, e);
    if (!strcmp(word, "light")) return directive_light(p, rest, e);
    return rerror_at(e, p->path, p->text.line,
                     "unknown directive '%.60s' (mesh, camera, keyframe, size, material, animate, environment, sun, light)",
                     word);
}

/* A material line changes the fields it names; a name no mesh defined becomes a new
 * material that starts from the default (Lambertian, Kd 0.8). */
static int apply_material_line(scene_parser *p, const material_line *m, rerror *e)
{
    scene_builder *b = p->b;
    material *dst;
    uint32_t index;
    if (builder_material(b, m->name, &index, e)) return rerror_at(e, p->path, m->line, "material: out of memory");
    dst = &b->s->materials[index];
    if (b->material_origin[index] == MATERIAL_UNDEFINED) b->material_origin[index] = MATERIAL_FROM_SCENE;
    if (m->has_type) dst->type = m->type;
    if (m->has_kd) dst->diffuse = m->kd;
    if (m->has_ks) dst->specular = m->ks;
    if (m->has_ke) dst->emission = m->ke;
    if (m->has_roughness) dst->roughness = m->roughness;
    if (m->has_ior) dst->ior = m->ior;
    return 0;
}

/* A mesh that cannot be opened is reported at its mesh line; errors inside it at the OBJ's own lines. */
static int load_mesh(scene_parser *p, size_t i, rerror *e)
{
    FILE *f = fopen(p->meshes[i], "rb");
    if (!f) return rerror_at(e, p->path, p->mesh_lines[i], "cannot open mesh '%s': %s", p->meshes[i], strerror(errno));
    fclose(f);
    return obj_load(p->b, p->meshes[i], e);
}

static void parser_free(scene_parser *p)
{
    size_t i;
    for (i = 0; i < p->mesh_count; ++i) free(p->meshes[i]);
    free(p->meshes);
    free(p->mesh_lines);
    free(p->materials);
    free(p->animates);
    free(p->lights);
    free(p->light_lines);
    text_close(&p->text);
}

int scene_file_load(scene_builder *b, const char *path, rerror *e)
{
    scene_parser p;
    char *line;
    size_t i;
    int status = 0;
    memset(&p, 0, sizeof p);
    p.b = b;
    p.path = path;
    text_directory_of(path, p.dir, sizeof p.dir);
    if (text_open(&p.text, path, e)) return -1;
    while (!status && (line = text_next_line(&p.text)) != NULL) status = read_directive(&p, line, e);
    if (!status && !p.mesh_count) status = rerror_at(e, path, 0, "no mesh directive (the scene has no geometry)");
    for (i = 0; !status && i < p.mesh_count; ++i) status = load_mesh(&p, i, e);
    for (i = 0; !status && i < p.material_count; ++i) status = apply_material_line(&p, &p.materials[i], e);
    if (!status) status = apply_lights(&p, e);
    if (!status) status = apply_animations(&p, e);
    if (!status && b->s->sky) status = sky_prepare(b->s->sky, e);
    parser_free(&p);
    return status;
}
