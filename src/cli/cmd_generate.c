/* restir generate ajar|glass|corridor|sphere|pillars|shadow|ajar-swing|ajar-swing-still|many-lights|many-lights-sky|atrium -o OUT.obj: writes a generated scene as OUT.obj,
 * OUT.mtl and OUT.scene (docs/scenes.md). */
#include "cmd_generate.h"

#include <stdio.h>
#include <string.h>
#include "restir/cli/cli.h"
#include "restir/core/progress.h"
#include "restir/scene/generate.h"
#include "restir/scene/generate_atrium.h"
#include "restir/scene/generate_rooms.h"
#include "args.h"
#include "outputs_ready.h"

typedef struct {
    const char *output;
    double door_angle;
    int subdivisions;
    int no_scene;
    int angle_seen, subdivisions_seen;
    int progress;          /* --progress (enum progress_mode) */
    double progress_every; /* --progress-every */
} generate_args;

/* The library's progress steps (generate.h) shown as render's progress (progress.h), one
 * per phase: `generate: writing OBJ: 40% (...), 4.0 s elapsed, ETA 6.0 s` every
 * --progress-every seconds in a log, a bar on a terminal. Only `sphere` with a large
 * --subdivisions runs long enough to show any (2000: about a minute); the other kinds take
 * well under a second. */
typedef struct {
    progress bar;
    char phase[48]; /* the phase shown ("": none begun) */
    char label[64];
} generate_shown;

static int show_step(void *ctx, const char *phase, long done, long total)
{
    generate_shown *g = ctx;
    if (strcmp(g->phase, phase)) {
        if (g->phase[0]) progress_end(&g->bar);
        snprintf(g->phase, sizeof g->phase, "%s", phase);
        snprintf(g->label, sizeof g->label, "generate: %s", phase);
        progress_begin(&g->bar, g->label, 0);
        progress_expect(&g->bar, total);
    }
    progress_update(&g->bar, done, total);
    return 0; /* generate stops on a signal by removing its outputs (signal_cleanup.h) */
}

static void show_end(generate_shown *g)
{
    if (g->phase[0]) progress_end(&g->bar);
    g->phase[0] = '\0';
}

#define GENERATE_KINDS_TEXT "ajar, glass, corridor, sphere, pillars, shadow, ajar-swing, ajar-swing-still, many-lights, many-lights-sky, atrium"

static int known_kind(const char *kind)
{
    static const char *const kinds[] = {"ajar", "glass", "corridor", "sphere", "pillars", "shadow", "ajar-swing", "ajar-swing-still", "many-lights", "many-lights-sky", "atrium"};
    size_t i;
    for (i = 0; i < sizeof kinds / sizeof *kinds; ++i)
        if (!strcmp(kind, kinds[i])) return 1;
    return 0;
}

/* OUT.obj -> OUT.scene (any other name: NAME.scene). */
static void scene_path_for(const char *obj_path, char *out, size_t size)
{
    size_t len = strlen(obj_path);
    if (len >= 4 && !strcmp(obj_path + len - 4, ".obj"))
        snprintf(out, size, "%.*s.scene", (int)(len - 4), obj_path);
    else
        snprintf(out, size, "%s.scene", obj_path);
}

/* OUT.obj -> OUT.mtl, as generate_write_obj names it. */
static void mtl_path_for(const char *obj_path, char *out, size_t size)
{
    snprintf(out, size, "%.*s.mtl", (int)(strlen(obj_path) - 4), obj_path);
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* The scene file's header: what it is and the command that wrote it. */
static void describe(const char *kind, const generate_args *a, char *out, size_t size)
{
    if (!strcmp(kind, "ajar"))
        snprintf(out, size,
                 "Door ajar (in the spirit of Veach & Guibas 1997, MLT): a dark room lit only through a door opened by\n"
                 "%g degrees; the emitter is in the adjacent room (docs/scenes.md). Metres.\n"
                 "Written by: restir generate ajar --door-angle %g -o %s",
                 a->door_angle, a->door_angle, base_name(a->output));
    else if (!strcmp(kind, "glass"))
        snprintf(out, size,
                 "Glass room: Cornell Box dimensions and camera, a smooth glass sphere (ior 1.5), a\n"
                 "Lambertian block and a small 40 x 40 mm light (docs/scenes.md). Millimetres.\n"
                 "Written by: restir generate glass -o %s",
                 base_name(a->output));
    else if (!strcmp(kind, "pillars"))
        snprintf(out, size,
                 "Disocclusion: five dark bars in front of a lit backdrop; the camera pans 2 m sideways over\n"
                 "frames 0..16 (docs/scenes.md). Metres.\nWritten by: restir generate pillars -o %s",
                 base_name(a->output));
    else if (!strcmp(kind, "shadow"))
        snprintf(out, size,
                 "Moving shadow: a box crosses under a small light over frames 0..16; still camera\n"
                 "(docs/scenes.md). Metres.\nWritten by: restir generate shadow -o %s",
                 base_name(a->output));
    else if (!strncmp(kind, "ajar-swing", 10))
        snprintf(out, size,
                 "Door ajar with the door swinging from 10 to 40 degrees over frames 0..16; %s\n"
                 "(docs/scenes.md). Metres.\nWritten by: restir generate %s -o %s",
                 strcmp(kind, "ajar-swing") ? "still camera" : "the camera slides 0.6 m sideways", kind,
                 base_name(a->output));
    else if (!strcmp(kind, "corridor"))
        snprintf(out, size,
                 "Mirror corridor: a 5 m corridor of glossy conductors (roughness 0.05 / 0.1) opening into a lit room\n"
                 "with a rough glass block; long replayed prefixes and late reconnections (docs/scenes.md). Metres.\n"
                 "Written by: restir generate corridor -o %s",
                 base_name(a->output));
    else if (!strcmp(kind, "many-lights"))
        snprintf(out, size,
                 "Many lights: 1000 small emitters of 15 radiances over three decades in an 8 x 4 x 20 m hall with\n"
                 "pillars, a glossy floor and a copper block; light RIS for NEE (Enhanced 6.1, docs/scenes.md). Metres.\n"
                 "Written by: restir generate many-lights -o %s",
                 base_name(a->output));
    else if (!strcmp(kind, "many-lights-sky"))
        snprintf(out, size,
                 "Many lights under the sky: the many-lights hall without its ceiling slab (the ceiling lights hang in\n"
                 "place) under a constant dusk sky and a low sun; the environment as one more light (docs/scenes.md). Metres.\n"
                 "Written by: restir generate many-lights-sky -o %s",
                 base_name(a->output));
    else if (!strcmp(kind, "atrium"))
        snprintf(out, size,
                 "Atrium: a generated Sponza-like interior (no Sponza in ../shared/data): a courtyard between two-storey\n"
                 "arcades of fluted columns, curtains, balusters and planters under a sky panel and a small sun;\n"
                 "the traversal yardstick's interior (docs/scenes.md 11). Metres.\n"
                 "Written by: restir generate atrium -o %s",
                 base_name(a->output));
    else
        snprintf(out, size, "Displaced sphere benchmark scene (generate.h).\nWritten by: restir generate sphere --subdivisions %d -o %s",
                 a->subdivisions, base_name(a->output));
}

static int generate_kind(const char *kind, const generate_args *a, const generate_progress *p, scene *s, rerror *e)
{
    if (!strcmp(kind, "ajar")) return generate_ajar(s, a->door_angle, e);
    if (!strcmp(kind, "glass")) return generate_glass_room(s, e);
    if (!strcmp(kind, "pillars")) return generate_pillars(s, e);
    if (!strcmp(kind, "shadow")) return generate_shadow(s, e);
    if (!strcmp(kind, "ajar-swing")) return generate_ajar_swing(s, 0, e);
    if (!strcmp(kind, "ajar-swing-still")) return generate_ajar_swing(s, 1, e);
    if (!strcmp(kind, "corridor")) return generate_corridor(s, e);
    if (!strcmp(kind, "many-lights")) return generate_many_lights(s, e);
    if (!strcmp(kind, "many-lights-sky")) return generate_many_lights_sky(s, e);
    if (!strcmp(kind, "atrium")) return generate_atrium(s, e);
    return generate_displaced_sphere_progress(s, a->subdivisions, p, e);
}

int cmd_generate(int argc, char **argv)
{
    generate_args a;
    const char *positional[2];
    char scene_path[4200], mtl_path[4200], comment[1024];
    file_before before[3];
    int count, status;
    scene s;
    rerror e;
    generate_shown shown;
    generate_progress steps;
    memset(&a, 0, sizeof a);
    a.door_angle = AJAR_DEFAULT_DOOR_ANGLE;
    a.subdivisions = 92;
    {
        const cli_option options[] = {
            {"-o", OPT_STRING, &a.output, "output OBJ; the MTL and the scene file go next to it (.mtl, .scene)", NULL, 0, 0, NULL},
            {"--door-angle", OPT_REAL, &a.door_angle, "ajar: door opening angle in degrees, 0..90 (default 10; 0 = closed)", NULL, 0, AJAR_MAX_DOOR_ANGLE, &a.angle_seen},
            /* at most 2000 (48M triangles, about 3 GB of memory and a 2 GB OBJ), as bench
             * --generated: 8192 (805M triangles) would need about 50 GB and write 34 GB (extrapolated
             * from 300: 67 MB resident, a 45 MB OBJ) */
            {"--subdivisions", OPT_INT, &a.subdivisions, "sphere: grid size per cube face, 1..2000 (default 92: 100k triangles)", NULL, 1, 2000, &a.subdivisions_seen},
            {"--no-scene", OPT_FLAG, &a.no_scene, "write only the OBJ and MTL", NULL, 0, 0, NULL},
            CLI_PROGRESS_ROWS(&a.progress, &a.progress_every),
            {NULL, OPT_FLAG, NULL, NULL, NULL, 0, 0, NULL},
        };
        status = cli_parse("generate", argc, argv, options, positional, 2, &count);
        if (status == 1) {
            cli_print_help(stdout, "generate", "KIND -o OUT.obj [options]  (KIND: " GENERATE_KINDS_TEXT ")", options);
            return 0;
        }
    }
    if (status) return status;
    if (count != 1 || !known_kind(positional[0])) {
        fprintf(stderr, "restir generate: expected one of " GENERATE_KINDS_TEXT " (restir generate --help)\n");
        return 2;
    }
    if (!a.output) {
        fprintf(stderr, "restir generate: -o OUT.obj is required\n");
        return 2;
    }
    if ((a.angle_seen && strcmp(positional[0], "ajar")) || (a.subdivisions_seen && strcmp(positional[0], "sphere"))) {
        fprintf(stderr, "restir generate: --door-angle is for ajar, --subdivisions for sphere\n");
        return 2;
    }
    if (strlen(a.output) < 5 || strcmp(a.output + strlen(a.output) - 4, ".obj")) {
        /* a scene file is read by its extension: OUT.scene holding OBJ text would not load */
        fprintf(stderr, "restir generate: -o %s: the output is an OBJ file and its name must end in .obj (the .mtl "
                        "and .scene go next to it)\n", a.output);
        return 2;
    }
    scene_path_for(a.output, scene_path, sizeof scene_path);
    mtl_path_for(a.output, mtl_path, sizeof mtl_path);
    {
        const named_file outs[] = {{a.output, "-o"}, {mtl_path, "the MTL"}, {a.no_scene ? NULL : scene_path, "the scene file"}};
        if (outputs_ready("generate", outs, 3, NULL, 0)) return 2;
    }
    memset(&shown, 0, sizeof shown);
    steps.step = show_step;
    steps.ctx = &shown;
    progress_set_mode((enum progress_mode)a.progress, a.progress_every);
    status = generate_kind(positional[0], &a, &steps, &s, &e);
    show_end(&shown);
    if (status) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    describe(positional[0], &a, comment, sizeof comment);
    file_before_note(&before[0], a.output);
    file_before_note(&before[1], mtl_path);
    file_before_note(&before[2], scene_path);
    status = generate_write_obj_progress(&s, a.output, &steps, &e);
    show_end(&shown);
    if (!status && !a.no_scene) status = generate_write_scene_file(&s, scene_path, base_name(a.output), comment, &e);
    if (status) {
        /* exit 2 leaves nothing: the OBJ or MTL committed before the failure goes too */
        int removed = file_remove_if_written(&before[0], a.output) + file_remove_if_written(&before[1], mtl_path) +
                      file_remove_if_written(&before[2], scene_path);
        fprintf(stderr, "%s\n", e.msg);
        if (removed) fprintf(stderr, "restir generate: removed the %d file(s) this call wrote before the error\n", removed);
    }
    scene_free(&s);
    return status ? 2 : 0;
}
