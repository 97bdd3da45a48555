/* restir inspect SCENE --pixel x,y [--neighbor x,y] [restir options]: one pixel's
 * selected path (vertices, lobes, k, technique, F, W) and its shift to a neighbour with
 * the Jacobian's factors (docs/restir-pt.md "restir inspect"). */
#include "cmd_inspect.h"

#include <stdio.h>
#include <string.h>
#include "restir/frame/options.h"
#include "restir/oracle/inspect.h"
#include "restir/scene/animation.h"
#include "args.h"
#include "cmd_replay.h"
#include "render_restir.h"
#include "scene_args.h"

static int parse_pixel(const char *text, int xy[2])
{
    char extra;
    return text && sscanf(text, "%d,%d%c", &xy[0], &xy[1], &extra) == 2;
}

int cmd_inspect(int argc, char **argv)
{
    restir_options o;
    render_restir_flags flags;
    scene_overrides overrides;
    cli_option options[64];
    int given[64];
    const char *positional[1], *pixel = NULL, *neighbor = NULL;
    int n, count, status, xy[2], nxy[2], preset = 0, json = 0, temporal = 0;
    double load, prepare;
    scene s;
    rerror e;
    for (n = 1; n < argc; ++n) /* a stage of a dump (cmd_replay.h) */
        if (!strcmp(argv[n], "--from-dump")) return cmd_inspect_from_dump(argc, argv);
    restir_options_default(&o);
    memset(&overrides, 0, sizeof overrides);
    {
        const cli_option rows[] = {
            {"--pixel", OPT_STRING, &pixel, "pixel to inspect, x,y (row 0 at the top)", NULL, 0, 0, NULL},
            {"--neighbor", OPT_STRING, &neighbor, "pixel to shift the selected path to (default x+1,y)", NULL, 0, 0,
             NULL},
            {"--seed", OPT_UINT32, &o.seed, "run seed of the addressed RNG (default 1)", NULL, 0, 0, NULL},
            {"--jitter", OPT_FLAG, &o.jitter, "jittered primary rays", NULL, 0, 0, NULL},
            {"--json", OPT_FLAG, &json, "one JSON object with every number at 17 digits (docs/tour.md)", NULL, 0, 0,
             NULL},
            {"--temporal", OPT_FLAG, &temporal,
             "also the temporal step against the pixel's initial reservoir of frame --first-frame - 1 (static scenes)",
             NULL, 0, 0, NULL},
            {"--mcap", OPT_REAL, &o.temporal.mcap, "with --temporal: the previous confidence is capped at C x the current one (default 20)",
             NULL, 1e-300, 1e300, NULL},
        };
        for (n = 0; n < (int)(sizeof rows / sizeof rows[0]); ++n) options[n] = rows[n];
    }
    options[n++] = render_restir_preset_row(&preset);
    n += render_restir_options(options + n, &o, &flags);
    n += scene_override_options(options + n, &overrides);
    memset(&options[n], 0, sizeof options[n]);
    cli_track_given(options, given);
    status = cli_parse("inspect", argc, argv, options, positional, 1, &count);
    if (status == 1) {
        cli_print_help(stdout, "inspect", "SCENE --pixel x,y [options]", options);
        return 0;
    }
    if (status) return status;
    render_restir_apply(options, given, preset, &flags, &o);
    if ((status = render_restir_validate("inspect", &o)) != 0) return status;
    if (count != 1 || !parse_pixel(pixel, xy)) {
        fprintf(stderr, "restir inspect: expected SCENE and --pixel x,y (see restir inspect --help)\n");
        return 2;
    }
    nxy[0] = xy[0] + 1;
    nxy[1] = xy[1];
    if (neighbor && !parse_pixel(neighbor, nxy)) {
        fprintf(stderr, "restir inspect: --neighbor expects x,y, not '%s'\n", neighbor);
        return 2;
    }
    status = load_scene_for_command("inspect", positional[0], &overrides, &s, &load, &prepare);
    if (status) return status;
    /* an animated scene as frame --first-frame of a sequence sees it (diff-dump's reproduce lines) */
    if (scene_is_animated(&s) && scene_pose_at(&s, o.first_frame, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        scene_free(&s);
        return 2;
    }
    if (restir_inspect(stdout, &s, &o, xy[0], xy[1], nxy[0], nxy[1], json, temporal, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        status = 2;
    }
    scene_free(&s);
    return status;
}
