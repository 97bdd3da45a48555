/* Generated rooms for ReSTIR PT (docs/scenes.md): a Cornell-style room with a glass
 * sphere and a small light (caustics, replay through delta lobes), and a room lit only
 * through a door ajar (difficult indirect light, after Veach's "door ajar" scene).
 * Everything is a pure function of the parameters: the same call writes the same
 * triangles on every machine. */
#ifndef RESTIR_GENERATE_ROOMS_H
#define RESTIR_GENERATE_ROOMS_H

#include "restir/core/error.h"
#include "restir/scene/scene.h"

/* The door angle of the shipped scenes/ajar.scene, in degrees. */
#define AJAR_DEFAULT_DOOR_ANGLE 10.0
#define AJAR_MAX_DOOR_ANGLE 90.0

/* Fills a zeroed scene (it is overwritten) with the door-ajar building: a dark room
 * (camera inside) and a lit room behind a dividing wall, joined by a doorway whose door
 * leaf is opened into the dark room by `door_angle_degrees` in [0, 90]. The only emitter
 * is a panel in the lit room facing the doorway. All walls, slabs, the door and the
 * furniture are closed solids (outward faces, shared vertices) that interpenetrate at
 * every junction, so light can pass only through the gap the open door leaves; at angle
 * 0 the dark room is sealed. Units: metres. Does not build the BVH (scene_prepare). */
int generate_ajar(scene *s, double door_angle_degrees, rerror *e);

/* Fills a zeroed scene with a Cornell-style room (Cornell Box dimensions in mm, open
 * front, the published camera), a smooth glass sphere (ior 1.5, radius 100, 64 x 32
 * UV tessellation, faceted: no shading normals), a Lambertian block and a small 40 x 40
 * light carrying the Cornell light's power. */
int generate_glass_room(scene *s, rerror *e);

/* Animated scenes (issue 10; docs/scenes.md "Animated scenes"). All are small, lit by
 * static lights, and fill a zeroed scene with geometry, keyframes and object animation. */
#define PILLARS_BARS 5
#define PILLARS_LAST_FRAME 16
#define SHADOW_LAST_FRAME 16
#define AJAR_SWING_LAST_FRAME 16
#define AJAR_SWING_DEGREES 30.0
/* Disocclusion: five dark bars 3 m in front of a lit backdrop; the camera pans 2 m
 * sideways over frames 0..16, so the backdrop behind each bar is uncovered. */
int generate_pillars(scene *s, rerror *e);
/* A moving shadow: a 0.6 m box crosses under a 0.8 m light over frames 0..16 (x from -1 to 1,
 * a quarter turn about y); the camera is still. */
int generate_shadow(scene *s, rerror *e);
/* The door-ajar building (door at 10 degrees) whose door swings open by a further 30
 * degrees over frames 0..16; the camera slides 0.6 m sideways, or is still. */
int generate_ajar_swing(scene *s, int still_camera, rerror *e);

/* Fills a zeroed scene with the mirror corridor (docs/scenes.md §8): a 0.6 x 0.6 x 5 m
 * corridor of glossy conductors (roughness 0.05 and 0.1, below the reconnection
 * threshold) that opens into a lit room holding a rough glass block; the camera looks
 * down the corridor, so most camera paths bounce 3 or more times off its walls before
 * their first rough vertex (hybrid shift: long replayed prefixes, late reconnection).
 * Metres. */
int generate_corridor(scene *s, rerror *e);

/* Fills a zeroed scene with the many-lights hall (docs/scenes.md): 1000 small square
 * emitters of 15 radiances over three decades on the ceiling and the long walls of an
 * 8 x 4 x 20 m hall with pillars, a glossy floor and a copper block (light RIS, Enhanced
 * §6.1). Metres. */
int generate_many_lights(scene *s, rerror *e);
/* The same hall open to the sky (docs/scenes.md): no ceiling slab (the ceiling lights hang
 * in place), a constant dusk sky and a low sun (scene.sky set): many lights plus the
 * environment as one more light of light RIS and tiles. Metres. */
int generate_many_lights_sky(scene *s, rerror *e);

/* Writes a scene file for s (atomically): `comment` (may be NULL, may hold several lines)
 * as # lines, `mesh MESH_NAME`, the camera (or its keyframes), the object animation, the size and one `material` line per
 * material with every field, so the scene file alone states the materials; a constant
 * environment and a sun when s has them (a map is not written). */
int generate_write_scene_file(const scene *s, const char *scene_path, const char *mesh_name, const char *comment,
                              rerror *e);

#endif
