/* Writes the textured interior of docs/scenes.md: scenes/textured-room.{obj,mtl,scene} and
 * its five small PNG maps scenes/textured-room-*.png (docs/materials.md, "Textures").
 *   make -j2 build/librestir.a && cc -O2 -std=c99 -Iinclude -o /tmp/textured_room \
 *       tools/textured_room.c build/librestir.a -lm && /tmp/textured_room scenes
 * A room open at the front (a dim constant sky outside) with a ceiling light, a checker
 * floor (map_Kd, map_Pr), a painting (map_Kd), an emissive sign (map_Ke) and a plant of
 * three crossed cut-out leaf cards (map_d). Deterministic: no random numbers. Metres. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "restir/core/png.h"

static int write_png(const char *dir, const char *name, int w, int h, void (*texel)(int, int, unsigned char *))
{
    unsigned char px[64 * 64 * 3];
    char path[1024];
    rerror e;
    int x, y;
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) texel(x, y, px + 3 * (y * w + x));
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (png_write_rgb8(path, w, h, px, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    return 0;
}

static void set(unsigned char *p, int r, int g, int b)
{
    p[0] = (unsigned char)r;
    p[1] = (unsigned char)g;
    p[2] = (unsigned char)b;
}

/* 16 x 16: 4 x 4 squares of two wood tones with a thin grain (sRGB codes). */
static void floor_texel(int x, int y, unsigned char *p)
{
    int dark = ((x / 4) + (y / 4)) & 1, grain = (x % 4 == 0) ? 18 : 0;
    if (dark) set(p, 120 - grain, 72 - grain, 40);
    else set(p, 214 - grain, 170 - grain, 112);
}

/* Roughness (data, linear): 0.35 on the light squares, 1 on the dark ones (times Pr). */
static void floor_rough_texel(int x, int y, unsigned char *p)
{
    int v = (((x / 4) + (y / 4)) & 1) ? 255 : 89;
    set(p, v, v, v);
}

/* 24 x 16: a sunset over a sea, in bands, with a round sun. */
static void painting_texel(int x, int y, unsigned char *p)
{
    double dx = x - 15.5, dy = y - 6.5;
    if (dx * dx + dy * dy < 9) set(p, 255, 220, 60);
    else if (y < 9) set(p, 230 - 12 * y, 90 + 10 * y, 60 + 8 * y);
    else set(p, 20, 60 + 6 * (y - 9), 140 + 10 * (y - 9));
}

/* 16 x 16 leaf mask (data): an ellipse with two holes; white = leaf. */
static void leaf_texel(int x, int y, unsigned char *p)
{
    double u = (x + 0.5) / 16 - 0.5, v = (y + 0.5) / 16 - 0.5;
    int leaf = u * u / 0.16 + v * v / 0.25 < 1, hole = (x == 5 && y == 5) || (x >= 9 && x <= 10 && y >= 10 && y <= 11);
    int a = leaf && !hole ? 255 : 0;
    set(p, a, a, a);
}

/* 8 x 4 emission pattern of the sign: a warm bar on a cool ground. */
static void sign_texel(int x, int y, unsigned char *p)
{
    if (y >= 1 && y <= 2 && x >= 1 && x <= 6) set(p, 255, 180, 80);
    else set(p, 60, 90, 200);
}

static FILE *open_out(const char *dir, const char *name)
{
    char path[1024];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "w");
    if (!f) perror(path);
    return f;
}

static int vcount, tcount;

/* A quad p, p+e1, p+e1+e2, p+e2 with UVs (0,0) (us,0) (us,vs) (0,vs); front along e1 x e2. */
static void quad(FILE *f, const double p[3], const double e1[3], const double e2[3], double us, double vs)
{
    int k;
    for (k = 0; k < 4; ++k) {
        double a = (k == 1 || k == 2), b = (k >= 2);
        fprintf(f, "v %.6g %.6g %.6g\n", p[0] + a * e1[0] + b * e2[0], p[1] + a * e1[1] + b * e2[1],
                p[2] + a * e1[2] + b * e2[2]);
        fprintf(f, "vt %.6g %.6g\n", a * us, b * vs);
    }
    fprintf(f, "f %d/%d %d/%d %d/%d %d/%d\n", vcount + 1, tcount + 1, vcount + 2, tcount + 2, vcount + 3, tcount + 3,
            vcount + 4, tcount + 4);
    vcount += 4;
    tcount += 4;
}

static void q(FILE *f, const char *object, const char *mtl, double px, double py, double pz, double ax, double ay,
              double az, double bx, double by, double bz, double us, double vs)
{
    double p[3], e1[3], e2[3];
    p[0] = px, p[1] = py, p[2] = pz;
    e1[0] = ax, e1[1] = ay, e1[2] = az;
    e2[0] = bx, e2[1] = by, e2[2] = bz;
    fprintf(f, "o %s\nusemtl %s\n", object, mtl);
    quad(f, p, e1, e2, us, vs);
}

static void write_obj(FILE *f)
{
    int i;
    fprintf(f, "# textured-room (docs/scenes.md), written by tools/textured_room.c. Metres.\nmtllib textured-room.mtl\n");
    q(f, "floor", "floor", -2, 0, 2, 4, 0, 0, 0, 0, -4, 4, 4);
    q(f, "ceiling", "white", -2, 2.5, -2, 4, 0, 0, 0, 0, 4, 1, 1);
    q(f, "back", "white", -2, 0, -2, 4, 0, 0, 0, 2.5, 0, 1, 1);
    q(f, "left", "white", -2, 0, 2, 0, 0, -4, 0, 2.5, 0, 1, 1);
    q(f, "right", "white", 2, 0, -2, 0, 0, 4, 0, 2.5, 0, 1, 1);
    q(f, "light", "light", -0.5, 2.49, -0.5, 1, 0, 0, 0, 0, 1, 1, 1);
    q(f, "painting", "painting", -1.4, 0.9, -1.99, 1.5, 0, 0, 0, 1, 0, 1, 1);
    q(f, "sign", "sign", -1.99, 1.2, 0.2, 0, 0, -0.8, 0, 0.4, 0, 1, 1);
    /* the pot: an open-topped box is enough from the camera's side */
    q(f, "pot", "pot", 0.75, 0, 0.05, 0.5, 0, 0, 0, 0.35, 0, 1, 1);
    q(f, "pot", "pot", 1.25, 0, 0.05, 0, 0, -0.5, 0, 0.35, 0, 1, 1);
    q(f, "pot", "pot", 0.75, 0, -0.45, 0, 0, 0.5, 0, 0.35, 0, 1, 1);
    q(f, "pot", "pot", 1.25, 0, -0.45, -0.5, 0, 0, 0, 0.35, 0, 1, 1);
    for (i = 0; i < 3; ++i) { /* three leaf cards crossed at the pot's axis */
        double a = 3.14159265358979 * i / 3, cx = 1.0, cz = -0.2, hw = 0.45;
        double dx = cos(a) * hw, dz = sin(a) * hw;
        q(f, "plant", "leaf", cx - dx, 0.3, cz - dz, 2 * dx, 0, 2 * dz, 0, 1.2, 0, 1, 1);
    }
}

static const char mtl_text[] =
    "# textured-room (docs/scenes.md): maps relative to this file (docs/materials.md, Textures)\n"
    "newmtl floor\nKd 1 1 1\nPr 0.6\nmap_Kd textured-room-floor.png\nmap_Pr textured-room-floor-rough.png\n"
    "newmtl white\nKd 0.7 0.7 0.68\n"
    "newmtl light\nKd 0 0 0\nKe 12 11 9\n"
    "newmtl painting\nKd 0.9 0.9 0.9\nmap_Kd textured-room-painting.png\n"
    "newmtl sign\nKd 0.1 0.1 0.1\nKe 2 2 2\nmap_Ke textured-room-sign.png\n"
    "newmtl pot\nKd 0.55 0.25 0.15\nKs 0.04 0.04 0.04\nNs 200\n"
    "newmtl leaf\nKd 0.25 0.55 0.15\nmap_d textured-room-leaf.png\n";

static const char scene_text[] =
    "# Textured interior (docs/scenes.md): a room open at the front under a dim constant sky,\n"
    "# a ceiling light, a checker floor (map_Kd, map_Pr), a painting (map_Kd), an emissive sign\n"
    "# (map_Ke) and a plant of cut-out leaf cards (map_d). Written by tools/textured_room.c.\n"
    "mesh textured-room.obj\n"
    "camera eye 0.2 1.4 3.9 target 0 0.9 -0.5 up 0 1 0 fov 52\n"
    "size 128 128\n"
    "environment constant 0.25 0.3 0.4\n";

int main(int argc, char **argv)
{
    FILE *f;
    if (argc != 2) {
        fprintf(stderr, "usage: textured_room DIR\n");
        return 2;
    }
    if (write_png(argv[1], "textured-room-floor.png", 16, 16, floor_texel) ||
        write_png(argv[1], "textured-room-floor-rough.png", 16, 16, floor_rough_texel) ||
        write_png(argv[1], "textured-room-painting.png", 24, 16, painting_texel) ||
        write_png(argv[1], "textured-room-leaf.png", 16, 16, leaf_texel) ||
        write_png(argv[1], "textured-room-sign.png", 8, 4, sign_texel))
        return 1;
    if (!(f = open_out(argv[1], "textured-room.obj"))) return 1;
    write_obj(f);
    fclose(f);
    if (!(f = open_out(argv[1], "textured-room.mtl"))) return 1;
    fputs(mtl_text, f);
    fclose(f);
    if (!(f = open_out(argv[1], "textured-room.scene"))) return 1;
    fputs(scene_text, f);
    fclose(f);
    return 0;
}
