"""Pure-Python PFM helpers for tools/cycles (no numpy in Debian's Blender or system Python).
Images are lists of rows, row 0 at the top, each row a list of (r, g, b)."""
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    toks, pos = [], 0
    while len(toks) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        toks.append(data[pos:end].decode())
        pos = end
    pos += 1
    w, h, s = int(toks[1]), int(toks[2]), float(toks[3])
    n = 3 if toks[0] == "PF" else 1
    px = struct.unpack_from(("<" if s < 0 else ">") + "%df" % (w * h * n), data, pos)
    rows = []
    for y in range(h):  # the file's first row is the bottom one
        base = (h - 1 - y) * w * n
        rows.append([tuple(px[base + n * x + c] if n == 3 else px[base + x] for c in range(3))
                     for x in range(w)])
    return rows


if __name__ == "__main__":
    a, b = read_pfm(sys.argv[1]), read_pfm(sys.argv[2])
    tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-4
    bad = [(x, y) for y in range(len(a)) for x in range(len(a[0]))
           if max(abs(a[y][x][c] - b[y][x][c]) / max(abs(b[y][x][c]), 1e-6) for c in range(3)) > tol]
    print("pixels differing by more than %g relative: %d of %d" % (tol, len(bad), len(a) * len(a[0])))
    for x, y in bad[:20]:
        print(x, y, a[y][x], b[y][x])
