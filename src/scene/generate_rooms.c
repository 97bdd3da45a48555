/* The generated rooms of generate_rooms.h (docs/scenes.md).
 *
 * Building blocks: the closed solids of mesh_writer.h (watertight, outward faces).
 * Solids that meet interpenetrate instead of
 * touching: a wall reaches into the floor slab and into the walls it joins, so a
 * junction has no crack for light to pass, and the extents are chosen so that no two
 * faces of different solids lie in one plane where they overlap (no coplanar faces). */
#include "restir/scene/generate_rooms.h"
#include "restir/scene/mesh_writer.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "restir/core/atomic_file.h"
#include "restir/core/rng.h"
#include "restir/scene/animation.h"
#include "restir/scene/scene_builder.h"
#include "restir/scene/sky.h"
#include "restir/scene/triangulate.h"

/* ------------------------------------------------------------------------------- */
/* The door ajar                                                                      */

/* Building (metres): x across, y up, z away from the camera. Dark room x in [0, W],
 * z in [0, D1]; dividing wall z in [D1, D1 + T]; lit room z in [D1 + T, Z_END]. */
#define AJ_W 4.0
#define AJ_H 2.5
#define AJ_D1 4.0
#define AJ_T 0.15
#define AJ_Z_END (AJ_D1 + AJ_T + 2.5)
/* Doorway through the dividing wall, from the floor up to AJ_OPEN_TOP. */
#define AJ_OPEN_X0 2.2
#define AJ_OPEN_X1 3.1
#define AJ_OPEN_TOP 2.1
/* Door leaf: laps over the frame by AJ_LAP on the sides and the top, is AJ_DOOR_T thick
 * and, closed, reaches AJ_EMBED into the dividing wall (and 0.02 into the floor), so
 * the closed door seals the doorway with overlapping solids, not touching faces. */
#define AJ_LAP 0.05
#define AJ_DOOR_T 0.05
#define AJ_EMBED 0.01

static const material_spec ajar_materials[] = {
    {"wall", MAT_LAMBERT, {0.75, 0.73, 0.70}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"floor", MAT_PLASTIC, {0.45, 0.33, 0.22}, {1, 1, 1}, {0, 0, 0}, 0.35, 1.5},
    {"door", MAT_PLASTIC, {0.60, 0.55, 0.45}, {1, 1, 1}, {0, 0, 0}, 0.5, 1.5},
    {"table", MAT_PLASTIC, {0.30, 0.17, 0.08}, {1, 1, 1}, {0, 0, 0}, 0.2, 1.5},
    {"dark", MAT_LAMBERT, {0.15, 0.15, 0.15}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"blue", MAT_LAMBERT, {0.20, 0.30, 0.55}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"copper", MAT_CONDUCTOR, {0, 0, 0}, {0.95, 0.64, 0.54}, {0, 0, 0}, 0.25, 1.5},
    {"light", MAT_LAMBERT, {0, 0, 0}, {0, 0, 0}, {180, 162, 135}, 1, 1.5},
};

/* Extents per family keep every face plane distinct where faces overlap: slabs reach 2T
 * beyond the interior, side walls 1.5T along z and 0.5T into the slabs, the walls across
 * (front, dividing, back) 0.5T into the side walls and 0.7T into the slabs. */
static void ajar_shell(mesh_writer *m)
{
    const double t = AJ_T, side_y0 = -0.5 * t, side_y1 = AJ_H + 0.5 * t;
    const double across_y0 = -0.7 * t, across_y1 = AJ_H + 0.7 * t, across_x0 = -0.5 * t, across_x1 = AJ_W + 0.5 * t;
    /* The dividing wall: a U-shaped prism along z (polygon in (u, v) = (x, y)), the
     * doorway being the notch. */
    const double divider[8][2] = {{across_x0, across_y0}, {AJ_OPEN_X0, across_y0}, {AJ_OPEN_X0, AJ_OPEN_TOP},
                                  {AJ_OPEN_X1, AJ_OPEN_TOP}, {AJ_OPEN_X1, across_y0}, {across_x1, across_y0},
                                  {across_x1, across_y1}, {across_x0, across_y1}};
    mesh_use(m, "floor", "floor");
    mesh_box(m, -2 * t, -t, -2 * t, AJ_W + 2 * t, 0, AJ_Z_END + 2 * t);
    mesh_use(m, "wall", "ceiling");
    mesh_box(m, -2 * t, AJ_H, -2 * t, AJ_W + 2 * t, AJ_H + t, AJ_Z_END + 2 * t);
    mesh_use(m, "wall", "wall_left");
    mesh_box(m, -t, side_y0, -1.5 * t, 0, side_y1, AJ_Z_END + 1.5 * t);
    mesh_use(m, "wall", "wall_right");
    mesh_box(m, AJ_W, side_y0, -1.5 * t, AJ_W + t, side_y1, AJ_Z_END + 1.5 * t);
    mesh_use(m, "wall", "wall_front");
    mesh_box(m, across_x0, across_y0, -t, across_x1, across_y1, 0);
    mesh_use(m, "wall", "wall_back");
    mesh_box(m, across_x0, across_y0, AJ_Z_END, across_x1, across_y1, AJ_Z_END + t);
    mesh_use(m, "wall", "wall_dividing");
    mesh_prism(m, divider[0], 8, 2, AJ_D1, AJ_D1 + t);
}

/* The door leaf, hinged on the vertical axis through its back edge on the hinge side
 * (x = opening - lap, inside the dividing wall), opened into the dark room: the latch
 * side moves towards -z. */
static void ajar_door(mesh_writer *m, double angle_degrees)
{
    const double hinge_x = AJ_OPEN_X0 - AJ_LAP, hinge_z = AJ_D1 + AJ_EMBED;
    const double width = (AJ_OPEN_X1 + AJ_LAP) - hinge_x;
    mesh_use(m, "door", "door");
    mesh_turned_box(m, hinge_x, hinge_z, width, AJ_DOOR_T, angle_degrees, -0.02, AJ_OPEN_TOP + AJ_LAP);
}

/* Furniture of the dark room: a glossy table with a copper box on it and a blue box on
 * the floor near the lit side of the door. Everything reaches 1 cm into what it
 * stands on. */
static void ajar_furniture(mesh_writer *m)
{
    const double x0 = 0.6, x1 = 1.8, z0 = 1.8, z1 = 2.6, top0 = 0.72, top1 = 0.76, leg = 0.06, inset = 0.04;
    int i;
    mesh_use(m, "table", "table_top");
    mesh_box(m, x0, top0, z0, x1, top1, z1);
    mesh_use(m, "dark", "table_legs");
    for (i = 0; i < 4; ++i) {
        double lx = (i & 1) ? x1 - inset - leg : x0 + inset, lz = (i & 2) ? z1 - inset - leg : z0 + inset;
        mesh_box(m, lx, -0.01, lz, lx + leg, top0 + 0.02, lz + leg);
    }
    mesh_use(m, "copper", "copper_box");
    mesh_box(m, 1.0, top1 - 0.01, 2.0, 1.25, 1.0, 2.25);
    mesh_use(m, "blue", "blue_box");
    mesh_turned_box(m, 3.05, 2.35, 0.5, 0.5, 25, -0.01, 0.45);
}

/* The emitter: a panel 1 cm in front of the lit room's back wall, facing the doorway
 * (front face (v1 - v0) x (v2 - v0) = (y x x) = -z). */
static void ajar_light(mesh_writer *m)
{
    const double z = AJ_Z_END - 0.01, x0 = 0.8, x1 = 3.4, y0 = 0.5, y1 = 2.0;
    uint32_t a, b, c, d;
    mesh_use(m, "light", "light");
    a = mesh_vertex(m, x0, y0, z);
    b = mesh_vertex(m, x0, y1, z);
    c = mesh_vertex(m, x1, y1, z);
    d = mesh_vertex(m, x1, y0, z);
    mesh_quad(m, a, b, c, d);
}

int generate_ajar(scene *s, double door_angle_degrees, rerror *e)
{
    mesh_writer m;
    char name[64];
    if (!(door_angle_degrees >= 0 && door_angle_degrees <= AJAR_MAX_DOOR_ANGLE)) {
        memset(s, 0, sizeof *s);
        return rerror_set(e, "generate ajar: door angle %g is not in [0, %g] degrees", door_angle_degrees,
                          AJAR_MAX_DOOR_ANGLE);
    }
    snprintf(name, sizeof name, "generated:ajar(%g)", door_angle_degrees);
    if (mesh_writer_begin(&m, s, name, e)) return -1;
    mesh_define_materials(&m, ajar_materials, (int)(sizeof ajar_materials / sizeof *ajar_materials));
    ajar_shell(&m);
    ajar_door(&m, door_angle_degrees);
    ajar_furniture(&m);
    ajar_light(&m);
    mesh_set_camera(s, 0.45, 1.55, 0.35, 2.9, 0.85, 3.6, 62);
    return mesh_writer_end(&m);
}

/* ------------------------------------------------------------------------------- */
/* The glass room                                                                     */

/* Cornell Box interior (mm): x in [0, 556] (x = 0 green, on the image's right), y in
 * [0, 548.8], z in [0, 559.2], open at z = 0 towards the camera. */
#define GR_W 556.0
#define GR_H 548.8
#define GR_D 559.2

static const material_spec glass_room_materials[] = {
    {"white", MAT_LAMBERT, {0.725, 0.71, 0.68}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"red", MAT_LAMBERT, {0.63, 0.065, 0.05}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"green", MAT_LAMBERT, {0.14, 0.45, 0.091}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"glass", MAT_DIELECTRIC, {0, 0, 0}, {1, 1, 1}, {0, 0, 0}, 0, 1.5},
    /* The Cornell light's radiance (17, 12, 4) times its area 130 x 105 over ours 40 x 40:
     * the same power from 1/8.5 of the area. */
    {"light", MAT_LAMBERT, {0, 0, 0}, {0, 0, 0}, {17 * 13650.0 / 1600, 12 * 13650.0 / 1600, 4 * 13650.0 / 1600}, 1, 1.5},
};

/* The five walls as quads over the eight shared corners of the room, facing inward:
 * corner(i) has x = W if bit 0, y = H if bit 1, z = D if bit 2. */
static void glass_room_walls(mesh_writer *m)
{
    uint32_t c[8];
    int i;
    mesh_use(m, "white", "floor");
    for (i = 0; i < 8; ++i) c[i] = mesh_vertex(m, (i & 1) ? GR_W : 0, (i & 2) ? GR_H : 0, (i & 4) ? GR_D : 0);
    mesh_quad(m, c[0], c[4], c[5], c[1]); /* floor y = 0: (z) x (x) = +y */
    mesh_use(m, "white", "ceiling");
    mesh_quad(m, c[2], c[3], c[7], c[6]); /* y = H: (x) x (z) = -y */
    mesh_use(m, "white", "back_wall");
    mesh_quad(m, c[4], c[6], c[7], c[5]); /* z = D: (y) x (x) = -z */
    mesh_use(m, "green", "right_wall");
    mesh_quad(m, c[0], c[2], c[6], c[4]); /* x = 0: (y) x (z) = +x */
    mesh_use(m, "red", "left_wall");
    mesh_quad(m, c[1], c[5], c[7], c[3]); /* x = W: (z) x (y) = -x */
}

int generate_glass_room(scene *s, rerror *e)
{
    mesh_writer m;
    /* The tall block of the Cornell Box Data: footprint corners in (x, z); the prism
     * reaches 1 mm below the floor so its base does not lie in the floor's plane. */
    const double block[4][2] = {{247, 423}, {296, 265}, {456, 314}, {406, 472}}; /* (u, v) = (z, x) */
    uint32_t a, b, c, d;
    if (mesh_writer_begin(&m, s, "generated:glass_room", e)) return -1;
    mesh_define_materials(&m, glass_room_materials, (int)(sizeof glass_room_materials / sizeof *glass_room_materials));
    glass_room_walls(&m);
    /* The small light 0.1 mm below the ceiling, centred like the Cornell light, facing
     * down: (x) x (z) = -y. */
    mesh_use(&m, "light", "light");
    a = mesh_vertex(&m, 258, GR_H - 0.1, 259.6);
    b = mesh_vertex(&m, 298, GR_H - 0.1, 259.6);
    c = mesh_vertex(&m, 298, GR_H - 0.1, 299.6);
    d = mesh_vertex(&m, 258, GR_H - 0.1, 299.6);
    mesh_quad(&m, a, b, c, d);
    mesh_use(&m, "white", "tall_block");
    mesh_prism(&m, block[0], 4, 1, -1, 330);
    /* The glass sphere where the Cornell short block stands, 1 mm above the floor. */
    mesh_use(&m, "glass", "glass_sphere");
    mesh_uv_sphere(&m, 185, 101, 169, 100, 64, 32);
    mesh_set_camera(s, 278, 273, -800, 278, 273, 0, 39.3076481);
    return mesh_writer_end(&m);
}

/* ------------------------------------------------------------------------------- */
/* Animated scenes (issue 10)                                                         */

static camera_pose pose_of(double ex, double ey, double ez, double tx, double ty, double tz, double fov)
{
    camera_pose p;
    p.eye = v3((real)ex, (real)ey, (real)ez);
    p.target = v3((real)tx, (real)ty, (real)tz);
    p.up = v3(0, 1, 0);
    p.fov_y_degrees = (real)fov;
    return p;
}

/* Camera keyframes (s->camera becomes the first pose). */
static int set_keyframes(scene *s, const camera_keyframe *k, size_t n, rerror *e)
{
    s->keyframes = rmalloc(n, sizeof *k, e);
    if (!s->keyframes) return -1;
    memcpy(s->keyframes, k, n * sizeof *k);
    s->keyframe_count = n;
    s->camera = k[0].pose;
    s->has_camera = 1;
    return 0;
}

static object_keyframe object_key(int frame, double tx, double ty, double tz, double axis_y, double degrees)
{
    object_keyframe k;
    k.frame = frame;
    k.translate = v3((real)tx, (real)ty, (real)tz);
    k.axis = v3(0, (real)(axis_y != 0 ? axis_y : 1), 0);
    k.angle_degrees = (real)degrees;
    return k;
}

static int animate_named(scene *s, const char *name, vec3 pivot, const object_keyframe *k, size_t n, rerror *e)
{
    uint32_t o;
    for (o = 0; o < s->object_count; ++o)
        if (!strcmp(s->object_names[o], name)) return scene_add_object_animation(s, o, pivot, k, n, e);
    return rerror_set(e, "generate: no object '%s'", name);
}

static const material_spec pillar_materials[] = {
    {"backdrop", MAT_LAMBERT, {0.80, 0.74, 0.55}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"floor", MAT_LAMBERT, {0.45, 0.45, 0.45}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"bars", MAT_PLASTIC, {0.08, 0.08, 0.10}, {1, 1, 1}, {0, 0, 0}, 0.3, 1.5},
    {"light", MAT_LAMBERT, {0, 0, 0}, {0, 0, 0}, {12, 12, 12}, 1, 1.5},
};

int generate_pillars(scene *s, rerror *e)
{
    mesh_writer m;
    camera_keyframe k[2];
    int i;
    if (mesh_writer_begin(&m, s, "generated:pillars", e)) return -1;
    mesh_define_materials(&m, pillar_materials, (int)(sizeof pillar_materials / sizeof *pillar_materials));
    mesh_use(&m, "floor", "floor");
    mesh_box(&m, -3, -0.1, -5.2, 3, 0, 2);
    mesh_use(&m, "backdrop", "backdrop");
    mesh_box(&m, -3, -0.05, -5.1, 3, 3, -5);
    mesh_use(&m, "bars", "bars");
    for (i = 0; i < PILLARS_BARS; ++i) {
        double x = -1 + 0.5 * i;
        mesh_box(&m, x - 0.06, -0.01, -2.05, x + 0.06, 2.5, -1.95);
    }
    /* A 3 x 1 m panel above the space between bars and backdrop, facing down:
     * (b - a) x (c - a) = (3, 0, 0) x (3, 0, 1) = -3 y. */
    mesh_use(&m, "light", "light");
    {
        uint32_t a = mesh_vertex(&m, -1.5, 2.9, -4.5), b = mesh_vertex(&m, 1.5, 2.9, -4.5), c = mesh_vertex(&m, 1.5, 2.9, -3.5),
                 d = mesh_vertex(&m, -1.5, 2.9, -3.5);
        mesh_quad(&m, a, b, c, d);
    }
    mesh_set_camera(s, -1, 1.2, 2.5, -1, 1.0, -5, 45);
    s->width = s->height = 128;
    if (mesh_writer_end(&m)) return -1;
    k[0].frame = 0;
    k[0].pose = pose_of(-1, 1.2, 2.5, -1, 1.0, -5, 45);
    k[1].frame = PILLARS_LAST_FRAME;
    k[1].pose = pose_of(1, 1.2, 2.5, 1, 1.0, -5, 45);
    if (set_keyframes(s, k, 2, e)) {
        scene_free(s);
        return -1;
    }
    return 0;
}

static const material_spec shadow_materials[] = {
    {"floor", MAT_LAMBERT, {0.70, 0.70, 0.68}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"wall", MAT_LAMBERT, {0.55, 0.62, 0.75}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"mover", MAT_PLASTIC, {0.70, 0.12, 0.08}, {1, 1, 1}, {0, 0, 0}, 0.4, 1.5},
    {"light", MAT_LAMBERT, {0, 0, 0}, {0, 0, 0}, {25, 24, 21}, 1, 1.5},
};

int generate_shadow(scene *s, rerror *e)
{
    mesh_writer m;
    object_keyframe k[2];
    if (mesh_writer_begin(&m, s, "generated:shadow", e)) return -1;
    mesh_define_materials(&m, shadow_materials, (int)(sizeof shadow_materials / sizeof *shadow_materials));
    mesh_use(&m, "floor", "floor");
    mesh_box(&m, -2, -0.1, -2.2, 2, 0, 2);
    mesh_use(&m, "wall", "wall");
    mesh_box(&m, -2, -0.05, -2.1, 2, 2.5, -2);
    mesh_use(&m, "mover", "mover");
    mesh_box(&m, -0.3, 0.5, -0.3, 0.3, 1.1, 0.3);
    mesh_use(&m, "light", "light");
    {
        uint32_t a = mesh_vertex(&m, -0.4, 2.4, -0.4), b = mesh_vertex(&m, 0.4, 2.4, -0.4), c = mesh_vertex(&m, 0.4, 2.4, 0.4),
                 d = mesh_vertex(&m, -0.4, 2.4, 0.4);
        mesh_quad(&m, a, b, c, d);
    }
    mesh_set_camera(s, 0, 2.2, 3.5, 0, 0.4, -0.3, 50);
    s->width = s->height = 128;
    if (mesh_writer_end(&m)) return -1;
    /* The box crosses under the light from x = -1 to x = 1, turning a quarter turn. */
    k[0] = object_key(0, -1, 0, 0, 1, 0);
    k[1] = object_key(SHADOW_LAST_FRAME, 1, 0, 0, 1, 90);
    if (animate_named(s, "mover", v3(0, (real)0.8, 0), k, 2, e)) {
        scene_free(s);
        return -1;
    }
    return 0;
}

int generate_ajar_swing(scene *s, int still_camera, rerror *e)
{
    object_keyframe k[2];
    camera_keyframe c[2];
    /* The door of generate_ajar at 10 degrees swings open to 40 about its hinge axis
     * (x = 2.15, z = 4.01; +y turns the latch side towards -z, the camera). */
    if (generate_ajar(s, AJAR_DEFAULT_DOOR_ANGLE, e)) return -1;
    k[0] = object_key(0, 0, 0, 0, 1, 0);
    k[1] = object_key(AJAR_SWING_LAST_FRAME, 0, 0, 0, 1, AJAR_SWING_DEGREES);
    if (animate_named(s, "door", v3((real)(AJ_OPEN_X0 - AJ_LAP), 0, (real)(AJ_D1 + AJ_EMBED)), k, 2, e)) {
        scene_free(s);
        return -1;
    }
    if (still_camera) return 0;
    /* The camera slides 0.6 m to the right while keeping its target. */
    c[0].frame = 0;
    c[0].pose = s->camera;
    c[1].frame = AJAR_SWING_LAST_FRAME;
    c[1].pose = s->camera;
    c[1].pose.eye.x += (real)0.6;
    if (set_keyframes(s, c, 2, e)) {
        scene_free(s);
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------------------------- */
/* The mirror corridor                                                                */

/* Metres; x across, y up, z away from the camera. Corridor interior x in [-CO_W/2, CO_W/2],
 * y in [0, CO_H], z in [0, CO_L]; it opens into a lit room, interior x in [-RO_W/2,
 * RO_W/2], y in [RO_Y0, RO_H], z in [CO_L, CO_L + RO_D]. The room floor is 1 cm below the
 * corridor's so that the two floors are never coplanar. */
#define CO_W 0.6
#define CO_H 0.6
#define CO_L 5.0
#define CO_T 0.1
#define RO_W 4.0
#define RO_H 2.5
#define RO_D 4.0
#define RO_Y0 (-0.01)

static const material_spec corridor_materials[] = {
    /* Glossy conductors below the reconnection threshold 0.2: the hybrid shift must
     * replay every bounce in the corridor. */
    {"mirror", MAT_CONDUCTOR, {0, 0, 0}, {0.95, 0.95, 0.95}, {0, 0, 0}, 0.05, 1.5},
    {"glossy", MAT_CONDUCTOR, {0, 0, 0}, {0.9, 0.85, 0.8}, {0, 0, 0}, 0.1, 1.5},
    {"dark", MAT_LAMBERT, {0.1, 0.1, 0.1}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"white", MAT_LAMBERT, {0.75, 0.73, 0.7}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"red", MAT_LAMBERT, {0.63, 0.065, 0.05}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"floor", MAT_PLASTIC, {0.45, 0.4, 0.35}, {1, 1, 1}, {0, 0, 0}, 0.5, 1.5},
    {"rough_glass", MAT_ROUGH_DIELECTRIC, {0, 0, 0}, {1, 1, 1}, {0, 0, 0}, 0.3, 1.5},
    {"light", MAT_LAMBERT, {0, 0, 0}, {0, 0, 0}, {12, 11, 10}, 1, 1.5},
};

/* The corridor: glossy floor and ceiling slabs, mirror side walls reaching into the
 * slabs, a dark cap behind the camera. Its walls run 1 cm into the room through the
 * room's front wall. */
static void corridor_tube(mesh_writer *m)
{
    const double t = CO_T, x = CO_W / 2, z1 = CO_L + 0.01;
    mesh_use(m, "glossy", "corridor_floor");
    mesh_box(m, -x - 2 * t, -t, -2 * t, x + 2 * t, 0, z1);
    mesh_use(m, "glossy", "corridor_ceiling");
    mesh_box(m, -x - 2 * t, CO_H, -2 * t, x + 2 * t, CO_H + t, z1);
    mesh_use(m, "mirror", "corridor_left");
    mesh_box(m, -x - t, -0.5 * t, -1.5 * t, -x, CO_H + 0.5 * t, z1);
    mesh_use(m, "mirror", "corridor_right");
    mesh_box(m, x, -0.5 * t, -1.5 * t, x + t, CO_H + 0.5 * t, z1);
    mesh_use(m, "dark", "corridor_cap");
    mesh_box(m, -x - 0.5 * t, -0.7 * t, -t, x + 0.5 * t, CO_H + 0.7 * t, 0);
}

/* The room: slabs, walls (the front wall a U-shaped prism whose notch holds the
 * corridor), a rough glass block facing the corridor and a ceiling light. */
static void corridor_room(mesh_writer *m)
{
    const double t = CO_T, x = RO_W / 2, z0 = CO_L, z1 = CO_L + RO_D;
    const double ay0 = RO_Y0 - 0.7 * t, ay1 = RO_H + 0.7 * t, ax = x + 0.5 * t, nx = CO_W / 2 + 0.5 * t;
    const double front[8][2] = {{-ax, ay0}, {-nx, ay0}, {-nx, CO_H + 0.5 * t}, {nx, CO_H + 0.5 * t},
                                {nx, ay0},  {ax, ay0},  {ax, ay1},           {-ax, ay1}};
    uint32_t a, b, c, d;
    mesh_use(m, "floor", "room_floor");
    mesh_box(m, -x - 2 * t, RO_Y0 - t, z0 - 2 * t, x + 2 * t, RO_Y0, z1 + 2 * t);
    mesh_use(m, "white", "room_ceiling");
    mesh_box(m, -x - 2 * t, RO_H, z0 - 2 * t, x + 2 * t, RO_H + t, z1 + 2 * t);
    mesh_use(m, "red", "room_left");
    mesh_box(m, -x - t, RO_Y0 - 0.5 * t, z0 - 1.5 * t, -x, RO_H + 0.5 * t, z1 + 1.5 * t);
    mesh_use(m, "white", "room_right");
    mesh_box(m, x, RO_Y0 - 0.5 * t, z0 - 1.5 * t, x + t, RO_H + 0.5 * t, z1 + 1.5 * t);
    mesh_use(m, "white", "room_back");
    mesh_box(m, -ax, ay0, z1, ax, ay1, z1 + t);
    mesh_use(m, "white", "room_front");
    mesh_prism(m, front[0], 8, 2, z0 - t, z0);
    /* The glass block stands 1 mm above the floor: no other surface may lie inside a
     * dielectric (a floor face inside the glass would be lit from within the medium). */
    mesh_use(m, "rough_glass", "rough_glass_block");
    mesh_box(m, -0.35, RO_Y0 + 0.001, z0 + 1.2, 0.45, 0.7, z0 + 1.6);
    /* The light: 1 x 1 m, 5 mm below the ceiling, facing down ((x) x (z) = -y). */
    mesh_use(m, "light", "light");
    a = mesh_vertex(m, -0.5, RO_H - 0.005, z0 + RO_D / 2 - 0.5);
    b = mesh_vertex(m, 0.5, RO_H - 0.005, z0 + RO_D / 2 - 0.5);
    c = mesh_vertex(m, 0.5, RO_H - 0.005, z0 + RO_D / 2 + 0.5);
    d = mesh_vertex(m, -0.5, RO_H - 0.005, z0 + RO_D / 2 + 0.5);
    mesh_quad(m, a, b, c, d);
}

/* The camera: in the corridor 0.2 m from its cap, looking past the corridor's far
 * end towards its upper right edge, so that most primary rays meet a wall first. */
#define CORRIDOR_CAMERA 0.0, 0.3, 0.2, 0.45, 0.55, 3.0, 40

int generate_corridor(scene *s, rerror *e)
{
    mesh_writer m;
    if (mesh_writer_begin(&m, s, "generated:corridor", e)) return -1;
    mesh_define_materials(&m, corridor_materials, (int)(sizeof corridor_materials / sizeof *corridor_materials));
    corridor_tube(&m);
    corridor_room(&m);
    mesh_set_camera(s, CORRIDOR_CAMERA);
    return mesh_writer_end(&m);
}

/* ------------------------------------------------------------------------------- */
/* Scene file output                                                                  */

static void write_pose(FILE *f, const char *head, const camera_pose *p)
{
    fprintf(f, "%s eye %.10g %.10g %.10g target %.10g %.10g %.10g up %.10g %.10g %.10g fov %.10g\n", head,
            (double)p->eye.x, (double)p->eye.y, (double)p->eye.z, (double)p->target.x, (double)p->target.y,
            (double)p->target.z, (double)p->up.x, (double)p->up.y, (double)p->up.z, (double)p->fov_y_degrees);
}

/* One `animate` line per object keyframe; the pivot on each object's first line. */
static void write_animation(FILE *f, const scene *s)
{
    size_t i, j, n;
    for (i = 0; i < scene_animated_object_count(s); ++i) {
        uint32_t object;
        vec3 c;
        const object_keyframe *k = scene_animated_object(s, i, &object, &c, &n);
        for (j = 0; j < n; ++j) {
            const char *q = strpbrk(s->object_names[object], " \t") ? "\"" : "";
            fprintf(f, "animate %s%s%s %d translate %.10g %.10g %.10g rotate %.10g %.10g %.10g %.10g", q, s->object_names[object], q,
                    k[j].frame, (double)k[j].translate.x, (double)k[j].translate.y, (double)k[j].translate.z,
                    (double)k[j].axis.x, (double)k[j].axis.y, (double)k[j].axis.z, (double)k[j].angle_degrees);
            if (!j) fprintf(f, " pivot %.10g %.10g %.10g", (double)c.x, (double)c.y, (double)c.z);
            fprintf(f, "\n");
        }
    }
}

static void write_scene_text(FILE *f, const scene *s, const char *mesh_name, const char *comment)
{
    const camera_pose *p = &s->camera;
    size_t i;
    if (comment) {
        const char *line = comment;
        while (*line) {
            size_t len = strcspn(line, "\n");
            fprintf(f, "# %.*s\n", (int)len, line);
            line += len + (line[len] == '\n');
        }
    }
    if (strpbrk(mesh_name, " \t")) fprintf(f, "mesh \"%s\"\n", mesh_name);
    else fprintf(f, "mesh %s\n", mesh_name);
    if (!s->keyframe_count) write_pose(f, "camera", p);
    for (i = 0; i < s->keyframe_count; ++i) {
        char head[32];
        snprintf(head, sizeof head, "keyframe %d", s->keyframes[i].frame);
        write_pose(f, head, &s->keyframes[i].pose);
    }
    write_animation(f, s);
    fprintf(f, "size %d %d\n", s->width, s->height);
    if (s->sky && s->sky->has_env && !s->sky->env_is_map)
        fprintf(f, "environment constant %.9g %.9g %.9g\n", (double)s->sky->env_constant.r,
                (double)s->sky->env_constant.g, (double)s->sky->env_constant.b);
    if (s->sky && s->sky->has_sun)
        fprintf(f, "sun %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", (double)s->sky->sun_direction.x,
                (double)s->sky->sun_direction.y, (double)s->sky->sun_direction.z, (double)s->sky->sun_angle_degrees,
                (double)s->sky->sun_radiance.r, (double)s->sky->sun_radiance.g, (double)s->sky->sun_radiance.b);
    fprintf(f, "\n");
    for (i = 0; i < s->material_count; ++i) {
        const material *m = &s->materials[i];
        fprintf(f,
                "material %s type %s kd %.9g %.9g %.9g ks %.9g %.9g %.9g ke %.9g %.9g %.9g roughness %.9g ior %.9g\n",
                m->name, material_type_names[m->type], (double)m->diffuse.r, (double)m->diffuse.g, (double)m->diffuse.b,
                (double)m->specular.r, (double)m->specular.g, (double)m->specular.b, (double)m->emission.r,
                (double)m->emission.g, (double)m->emission.b, (double)m->roughness, (double)m->ior);
    }
}

int generate_write_scene_file(const scene *s, const char *scene_path, const char *mesh_name, const char *comment,
                              rerror *e)
{
    atomic_file f;
    size_t i;
    for (i = 0; i < s->material_count; ++i)
        if (strpbrk(s->materials[i].name, " \t\"#"))
            return rerror_set(e, "%s: material name '%s' cannot be written unquoted", scene_path,
                              s->materials[i].name);
    if (strpbrk(mesh_name, "\"#\n")) return rerror_set(e, "%s: mesh name '%s' cannot be written", scene_path, mesh_name);
    if (atomic_file_open(&f, scene_path, e)) return -1;
    write_scene_text(f.fp, s, mesh_name, comment);
    return atomic_file_commit(&f, e);
}

/* ------------------------------------------------------------------------------- */
/* The many-lights hall (light RIS, Enhanced §6.1; docs/scenes.md)                     */

/* Hall (metres): x in [0, 8], y in [0, 4], z in [0, 20]; the camera at z = 0.6 looks
 * down it. Lights: MANY_LIGHTS_COUNT squares of 0.12 m on the ceiling (facing down) and
 * on the two long walls (facing in), each of one of MANY_LIGHTS_LEVELS radiances spread
 * log-uniformly over three decades, in three tints: their powers differ by 1000×, so
 * light selection by power (p_0) still sends most samples to lights that a given point
 * hardly sees, which is where RIS with an unshadowed target helps. Occluders: eight
 * pillars and a glossy copper block; the floor is glossy plastic. */
#define MANY_LIGHTS_COUNT 1000
#define MANY_LIGHTS_LEVELS 15
#define ML_W 8.0
#define ML_H 4.0
#define ML_D 20.0
#define ML_SIZE 0.12

static const material_spec many_lights_surfaces[] = {
    {"wall", MAT_LAMBERT, {0.70, 0.68, 0.65}, {0, 0, 0}, {0, 0, 0}, 1, 1.5},
    {"floor", MAT_PLASTIC, {0.25, 0.22, 0.20}, {1, 1, 1}, {0, 0, 0}, 0.15, 1.5},
    {"pillar", MAT_PLASTIC, {0.50, 0.45, 0.40}, {1, 1, 1}, {0, 0, 0}, 0.4, 1.5},
    {"copper", MAT_CONDUCTOR, {0, 0, 0}, {0.95, 0.64, 0.54}, {0, 0, 0}, 0.2, 1.5},
};

static const char *const many_lights_names[MANY_LIGHTS_LEVELS] = {
    "light00", "light01", "light02", "light03", "light04", "light05", "light06", "light07",
    "light08", "light09", "light10", "light11", "light12", "light13", "light14"};

/* Light level k: radiance 0.1 · 10^(3k/(LEVELS-1)) (0.1 .. 100), tint k mod 3. */
static void many_lights_materials(mesh_writer *m)
{
    static const double tint[3][3] = {{1.0, 0.85, 0.6}, {0.75, 0.85, 1.0}, {1.0, 1.0, 1.0}};
    material_spec specs[MANY_LIGHTS_LEVELS];
    int k;
    mesh_define_materials(m, many_lights_surfaces, (int)(sizeof many_lights_surfaces / sizeof *many_lights_surfaces));
    for (k = 0; k < MANY_LIGHTS_LEVELS; ++k) {
        double radiance = 0.1 * pow(10.0, 3.0 * k / (MANY_LIGHTS_LEVELS - 1));
        int c;
        memset(&specs[k], 0, sizeof specs[k]);
        specs[k].name = many_lights_names[k];
        specs[k].type = MAT_LAMBERT;
        for (c = 0; c < 3; ++c) specs[k].ke[c] = radiance * tint[k % 3][c];
        specs[k].roughness = 1;
        specs[k].ior = 1.5;
    }
    mesh_define_materials(m, specs, MANY_LIGHTS_LEVELS);
}

/* One light square 1 cm off a wall: centre c, facing along +-axis `axis` (sign), the
 * square spanning the two other axes. */
static void many_lights_square(mesh_writer *m, int axis, int sign, double w, double u, double v)
{
    const double h = ML_SIZE / 2;
    uint32_t a = mesh_axis_vertex(m, axis, w, u - h, v - h), b = mesh_axis_vertex(m, axis, w, u + h, v - h);
    uint32_t c = mesh_axis_vertex(m, axis, w, u + h, v + h), d = mesh_axis_vertex(m, axis, w, u - h, v + h);
    /* (u) x (v) = +axis: keep the order to face +axis, reverse it to face -axis. */
    if (sign > 0) mesh_quad(m, a, b, c, d);
    else mesh_quad(m, a, d, c, b);
}

static void many_lights_emitters(mesh_writer *m)
{
    int i;
    for (i = 0; i < MANY_LIGHTS_COUNT && !m->failed; ++i) {
        /* Placement and level from addressed numbers (stream RNG_TEST: a tool, not an estimator). */
        rng_key key = rng_key_make(2026, (uint32_t)i, 0);
        double where = rng_u(key, RNG_TEST, 0, 0), a = rng_u(key, RNG_TEST, 0, 1), b = rng_u(key, RNG_TEST, 0, 2);
        int level = (int)(rng_u(key, RNG_TEST, 0, 3) * MANY_LIGHTS_LEVELS);
        mesh_use(m, many_lights_names[level < MANY_LIGHTS_LEVELS ? level : MANY_LIGHTS_LEVELS - 1], "lights");
        if (where < 0.5) /* ceiling, facing down (-y); axis y: u = z, v = x */
            many_lights_square(m, 1, -1, ML_H - 0.01, 0.3 + a * (ML_D - 0.6), 0.3 + b * (ML_W - 0.6));
        else if (where < 0.75) /* left wall x = 0, facing +x; axis x: u = y, v = z */
            many_lights_square(m, 0, 1, 0.01, 0.3 + a * (ML_H - 0.6), 0.3 + b * (ML_D - 0.6));
        else /* right wall x = W, facing -x */
            many_lights_square(m, 0, -1, ML_W - 0.01, 0.3 + a * (ML_H - 0.6), 0.3 + b * (ML_D - 0.6));
    }
}

/* The hall, with its ceiling slab or open to the sky. */
static int many_lights_hall(scene *s, int open, rerror *e)
{
    const double t = 0.2;
    mesh_writer m;
    int i;
    if (mesh_writer_begin(&m, s, open ? "generated:many-lights-sky" : "generated:many-lights", e)) return -1;
    many_lights_materials(&m);
    /* The shell: slabs reach 2t beyond the interior, walls t beyond along z and into the
     * slabs, the end walls into the side walls (no coplanar overlapping faces). */
    mesh_use(&m, "floor", "floor");
    mesh_box(&m, -2 * t, -t, -2 * t, ML_W + 2 * t, 0, ML_D + 2 * t);
    if (!open) {
        mesh_use(&m, "wall", "ceiling");
        mesh_box(&m, -2 * t, ML_H, -2 * t, ML_W + 2 * t, ML_H + t, ML_D + 2 * t);
    }
    mesh_use(&m, "wall", "walls");
    mesh_box(&m, -t, -0.5 * t, -1.5 * t, 0, ML_H + 0.5 * t, ML_D + 1.5 * t);
    mesh_box(&m, ML_W, -0.5 * t, -1.5 * t, ML_W + t, ML_H + 0.5 * t, ML_D + 1.5 * t);
    mesh_box(&m, -0.5 * t, -0.7 * t, ML_D, ML_W + 0.5 * t, ML_H + 0.7 * t, ML_D + t);
    mesh_box(&m, -0.5 * t, -0.7 * t, -t, ML_W + 0.5 * t, ML_H + 0.7 * t, 0);
    mesh_use(&m, "pillar", "pillars");
    for (i = 0; i < 8; ++i) {
        double x = (i & 1) ? 5.6 : 2.0, z = 4.0 + 4.0 * (i / 2);
        mesh_box(&m, x, -0.01, z, x + 0.4, ML_H + 0.01, z + 0.4);
    }
    mesh_use(&m, "copper", "block");
    mesh_turned_box(&m, 3.6, 9.0, 0.8, 0.8, 30, -0.01, 0.9);
    many_lights_emitters(&m);
    mesh_set_camera(s, 4.0, 1.7, 0.6, 4.0, 1.3, 20.0, 60);
    return mesh_writer_end(&m);
}

int generate_many_lights(scene *s, rerror *e) { return many_lights_hall(s, 0, e); }

int generate_many_lights_sky(scene *s, rerror *e)
{
    if (many_lights_hall(s, 1, e)) return -1;
    s->sky = rmalloc(1, sizeof *s->sky, e);
    if (!s->sky) return -1;
    sky_init(s->sky);
    /* Dusk: a dim blue sky and a low warm sun along the hall, so the thousand lights still
     * matter (sky irradiance pi * 0.06 = 0.19 on the floor, sun ~0.13 at normal incidence). */
    s->sky->has_env = 1;
    s->sky->env_constant = rgb_make((real)0.04, (real)0.055, (real)0.09);
    s->sky->has_sun = 1;
    s->sky->sun_direction = v3_normalize(v3((real)0.2, (real)0.35, (real)0.9));
    s->sky->sun_angle_degrees = 1.5;
    s->sky->sun_radiance = rgb_make(60, 45, 30);
    return sky_prepare(s->sky, e);
}
