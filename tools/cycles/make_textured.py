"""Writes the textured scenes of docs/environment.md §8.6 (standard library only; run from
the repository root, the outputs are committed next to this file):

  python3 tools/cycles/make_textured.py

texture-probe.png   16 x 16 RGB, every 8-bit code once per channel: R = k, G = 255 - k,
                    B = 97 k mod 256 for texel k = 16 row + column (row 0 at the top)
texture-srgb.png    32 x 32: the same codes in 2 x 2 blocks
texture-probe.obj/.mtl/.scene, texture-srgb.obj/.mtl/.scene
                    a square under a near-point sun, seen from straight above; its UVs are
                    laid so that the probe's 64 x 64 pixel centres fall on texel coordinates
                    x = p/4, y = q/4 (texel centres, quarter and half points, the repeat seam)
courtyard-checker.png, courtyard-bricks.png
                    8 x 8 and 16 x 8 RGB colour maps of random codes (fixed seed)
courtyard-textured.obj/.mtl, courtyard-textured.scene
                    scenes/courtyard.obj with planar UVs on the ground (map_Kd checker) and the
                    back wall (map_Kd bricks times Kd); the two glossy boxes made Lambertian
"""
import math
import os
import random
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")


def write_png(path, w, h, rows):
    """8-bit RGB, no filtering (filter byte 0), one IDAT; rows[0] is the top row."""
    def chunk(kind, data):
        c = kind + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c) & 0xffffffff)
    raw = b"".join(b"\0" + bytes(v for px in row for v in px) for row in rows)
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(png)


def probe():
    rows = [[(k, 255 - k, (97 * k) % 256) for k in range(16 * j, 16 * j + 16)] for j in range(16)]
    write_png(os.path.join(HERE, "texture-probe.png"), 16, 16, rows)
    # Camera at height 2 looking down (-y), image right = +x, image up = -z, fov 8 degrees:
    # the plane y = 0 is seen over |x|, |z| <= hv = 2 tan 4 deg. Pixel p of 64 (left to right)
    # has its centre at x = hv (2 (p + 0.5)/64 - 1). u = u0 + (x + hv)/(2 hv) makes the texel
    # coordinate u W - 1/2 = 16 u0 + (p + 0.5)/4 - 1/2, = p/4 for u0 = 0.375/16. Row q (top to
    # bottom) is at -z = hv (1 - 2 (q + 0.5)/64); v = -u0 + (-z + hv)/(2 hv) makes the texel row
    # (1 - v) H - 1/2 = q/4. The square reaches twice as far as the view, so its UVs run
    # about half a period beyond [0, 1] on every side (the repeat wrap, negative UVs).
    hv = 2.0 * math.tan(math.radians(4.0))
    u0 = 0.375 / 16
    a = 2.0 * hv
    corners = [(-a, a), (a, a), (a, -a), (-a, -a)]  # (x, z), counter-clockwise seen from +y
    # texture-srgb.*: the same square with a 32 x 32 map of 2 x 2 blocks, one code each (block
    # (m, n) holds the probe's texel (m, n)): pixel (4m, 4n) falls on the point shared by the
    # block's four texels, so any lookup returns the decoded code whatever the interpolation
    # or a small error of the hit point (docs/environment.md 8.6: the sRGB curve itself).
    rows32 = [[rows[j // 2][i // 2] for i in range(32)] for j in range(32)]
    write_png(os.path.join(HERE, "texture-srgb.png"), 32, 32, rows32)
    for name in ("texture-probe", "texture-srgb"):
        with open(os.path.join(HERE, name + ".obj"), "w") as f:
            f.write("# Texture probe (tools/cycles/make_textured.py, docs/environment.md 8.6): a\n"
                    "# square whose UVs put the probe camera's pixel centres on quarter texels.\n"
                    "mtllib %s.mtl\nusemtl probe\n" % name)
            for x, z in corners:
                f.write("v %.9g 0 %.9g\n" % (x, z))
            for x, z in corners:
                f.write("vt %.17g %.17g\n" % (u0 + (x + hv) / (2 * hv), -u0 + (-z + hv) / (2 * hv)))
            f.write("f 1/1 2/2 3/3 4/4\n")
        with open(os.path.join(HERE, name + ".mtl"), "w") as f:
            f.write("newmtl probe\nmap_Kd %s.png\n" % name)
    # the sun's radiance makes a facing Lambertian pixel equal its Kd: Kd/pi * pi L sin^2 a
    a_deg = 0.02
    rad = 1.0 / math.sin(math.radians(a_deg)) ** 2
    for name in ("texture-probe", "texture-srgb"):
        with open(os.path.join(HERE, name + ".scene"), "w") as f:
            f.write("# The texture lookup seen directly (docs/environment.md 8.6): a map_Kd square under\n"
                    "# a 0.02 degree sun overhead whose radiance 1/sin^2(a) makes each pixel its Kd\n"
                    "# (to 1 - cos a = 6e-8); 64 x 64 pixel centres on quarter texels.\n"
                    "mesh %s.obj\n"
                    "camera eye 0 2 0 target 0 0 0 up 0 0 -1 fov 8\n"
                    "size 64 64\n"
                    "sun 0 1 0 %g %.9g %.9g %.9g\n" % (name, a_deg, rad, rad, rad))


def courtyard_maps():
    rnd = random.Random(30)
    checker = [[tuple(rnd.randrange(256) for _ in range(3)) for _ in range(8)] for _ in range(8)]
    write_png(os.path.join(HERE, "courtyard-checker.png"), 8, 8, checker)
    bricks = [[tuple(rnd.randrange(60, 256) for _ in range(3)) for _ in range(16)] for _ in range(8)]
    write_png(os.path.join(HERE, "courtyard-bricks.png"), 16, 8, bricks)


def courtyard_obj():
    """courtyard.obj with the ground's and the back wall's faces given planar UVs."""
    src = open(os.path.join(ROOT, "scenes", "courtyard.obj")).read().splitlines()
    verts = [[float(x) for x in l.split()[1:4]] for l in src if l.startswith("v ")]
    out, vts, obj = [], [], None
    for line in src:
        t = line.split()
        if t and t[0] == "o":
            obj = t[1]
        if t and t[0] == "usemtl" and obj in ("ground", "wall-back"):
            line = "usemtl %s-tex" % obj
        if t and t[0] == "f" and obj in ("ground", "wall-back"):
            idx = [int(w) for w in t[1:]]
            corners = []
            for i in idx:
                x, y, z = verts[i - 1]
                if obj == "ground":  # 4 m per period, origin off the texel grid
                    uv = (x / 4.0 + 0.1, -z / 4.0 + 0.3)
                else:  # the back wall: along x and y (its end faces get a degenerate strip)
                    uv = (x / 2.0 + 0.05, y / 1.2 + 0.2)
                vts.append(uv)
                corners.append("%d/%d" % (i, len(vts)))
            line = "f " + " ".join(corners)
        out.append(line)
    out = [l.replace("mtllib courtyard.mtl", "mtllib courtyard-textured.mtl") for l in out]
    first_f = next(i for i, l in enumerate(out) if l.startswith("o "))
    out[first_f:first_f] = ["vt %.9g %.9g" % uv for uv in vts]
    out.insert(0, "# Written by tools/cycles/make_textured.py from scenes/courtyard.obj: planar UVs\n"
                  "# on the ground and the back wall (docs/environment.md 8.6).")
    with open(os.path.join(HERE, "courtyard-textured.obj"), "w") as f:
        f.write("\n".join(out) + "\n")
    mtl = open(os.path.join(ROOT, "scenes", "courtyard.mtl")).read()
    mtl = mtl.replace("# courtyard (docs/scenes.md)", "# courtyard-textured (tools/cycles/make_textured.py)")
    mtl += ("newmtl ground-tex\nmap_Kd courtyard-checker.png\n"
            "newmtl wall-back-tex\nKd 0.9 0.85 0.8\nmap_Kd courtyard-bricks.png\n")
    with open(os.path.join(HERE, "courtyard-textured.mtl"), "w") as f:
        f.write(mtl)
    scene = open(os.path.join(HERE, "courtyard-diffuse.scene")).read().splitlines()
    scene = [l for l in scene if not l.startswith("#")]
    scene = [l.replace("../../scenes/courtyard.obj", "courtyard-textured.obj") for l in scene]
    with open(os.path.join(HERE, "courtyard-textured.scene"), "w") as f:
        f.write("# courtyard-diffuse.scene with a map_Kd checker on the ground and bricks on the back\n"
                "# wall (tools/cycles/make_textured.py; docs/environment.md 8.6).\n")
        f.write("\n".join(scene) + "\n")


probe()
courtyard_maps()
courtyard_obj()
