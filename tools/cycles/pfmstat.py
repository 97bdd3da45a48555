"""Pure-Python PFM helpers for tools/cycles (no numpy in Debian's Blender or system Python).
Images are lists of rows, row 0 at the top, each row a list of (r, g, b)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "scripts", "results"))
from relmse_channels import read_pfm as read_pfm_flat  # noqa: E402  (one PFM reader)


def read_pfm(path):
    w, h, px = read_pfm_flat(path)
    # the file's first row is the bottom one
    return [[tuple(px[3 * ((h - 1 - y) * w + x) + c] for c in range(3)) for x in range(w)]
            for y in range(h)]


if __name__ == "__main__":
    a, b = read_pfm(sys.argv[1]), read_pfm(sys.argv[2])
    tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-4
    bad = [(x, y) for y in range(len(a)) for x in range(len(a[0]))
           if max(abs(a[y][x][c] - b[y][x][c]) / max(abs(b[y][x][c]), 1e-6) for c in range(3)) > tol]
    print("pixels differing by more than %g relative: %d of %d" % (tol, len(bad), len(a) * len(a[0])))
    for x, y in bad[:20]:
        print(x, y, a[y][x], b[y][x])
