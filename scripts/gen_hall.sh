#!/bin/sh
# Writes scenes/hall.obj and scenes/hall.mtl: a 6 m x 4 m x 60 m hall with a glossy conductor
# floor (roughness 0.45, GGX alpha ~0.2), glossy plastic pillars along both walls every 10 m
# and 11 small ceiling lights every 5 m. Made for the near/far footprint comparison
# (docs/results.md, "ReSTIR PT Enhanced" (c)): the scene diagonal is 60.4 m, so the GRIS
# d_min = 0.02 x diagonal = 1.2 m, while the cameras of hall.scene (near) and hall-far.scene
# see the same stretch of floor from 5 m and from 30 m. Metres.
#   sh scripts/gen_hall.sh [DIR]
set -eu
D=${1:-scenes}
awk 'function box(x0, y0, z0, x1, y1, z1, m) { # an axis-aligned box, outward faces
        printf("usemtl %s\n", m)
        v(x0,y0,z0); v(x1,y0,z0); v(x1,y1,z0); v(x0,y1,z0); v(x0,y0,z1); v(x1,y0,z1); v(x1,y1,z1); v(x0,y1,z1)
        b = nv - 8
        q(b+1,b+4,b+3,b+2); q(b+5,b+6,b+7,b+8); q(b+1,b+5,b+8,b+4); q(b+2,b+3,b+7,b+6); q(b+1,b+2,b+6,b+5); q(b+4,b+8,b+7,b+3)
     }
     function v(x, y, z) { printf("v %g %g %g\n", x, y, z); ++nv }
     function q(a, b, c, d) { printf("f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d) }
     function quad(x0, y0, z0, ux, uy, uz, wx, wy, wz, m) { # corner + two edges, normal u x w
        printf("usemtl %s\n", m)
        v(x0, y0, z0); v(x0+ux, y0+uy, z0+uz); v(x0+ux+wx, y0+uy+wy, z0+uz+wz); v(x0+wx, y0+wy, z0+wz)
        q(nv-3, nv-2, nv-1, nv)
     }
     BEGIN {
        print "# hall: written by scripts/gen_hall.sh"
        print "mtllib hall.mtl"
        quad(-3, 0, 0, 0, 0, 60, 6, 0, 0, "floor")      # normal +y
        quad(-3, 4, 0, 6, 0, 0, 0, 0, 60, "ceiling")    # normal -y
        quad(-3, 0, 0, 0, 4, 0, 0, 0, 60, "wall_left")  # normal +x
        quad(3, 0, 0, 0, 0, 60, 0, 4, 0, "wall_right")  # normal -x
        quad(-3, 0, 0, 6, 0, 0, 0, 4, 0, "end")         # normal +z
        quad(-3, 0, 60, 0, 4, 0, 6, 0, 0, "end")        # normal -z
        for (z = 5; z <= 55; z += 10) {
            box(-2.9, 0, z - 0.25, -2.4, 4, z + 0.25, "pillar")
            box(2.4, 0, z - 0.25, 2.9, 4, z + 0.25, "pillar")
        }
        for (z = 5; z <= 55; z += 5) quad(-0.4, 3.98, z - 0.4, 0.8, 0, 0, 0, 0, 0.8, "light") # normal -y
     }' >"$D/hall.obj"
cat >"$D/hall.mtl" <<'MTL'
# hall: written by scripts/gen_hall.sh
newmtl floor
Kd 0.85 0.8 0.7
Ke 0 0 0
Pm 1
Pr 0.45

newmtl ceiling
Kd 0.7 0.7 0.7
Ke 0 0 0
illum 1

newmtl wall_left
Kd 0.65 0.2 0.12
Ke 0 0 0
illum 1

newmtl wall_right
Kd 0.2 0.35 0.6
Ke 0 0 0
illum 1

newmtl end
Kd 0.6 0.6 0.55
Ke 0 0 0
illum 1

newmtl pillar
Kd 0.75 0.72 0.65
Ks 1 1 1
Ke 0 0 0
Pm 0
Pr 0.4
Ni 1.5

newmtl light
Kd 0 0 0
Ke 30 28 24
illum 1
MTL
