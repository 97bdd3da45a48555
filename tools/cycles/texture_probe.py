"""The texture probes of docs/environment.md 8.6, as numbers (standard library only).

  python3 tools/cycles/texture_probe.py DIR

DIR holds the 1-sample renders (PFM, row 0 at the top after pfmstat.read_pfm):
  probe_ours.pfm, probe_cy.pfm, probe_cys.pfm   tools/cycles/texture-probe.scene: ours at the
      pixel centres, Cycles with the exact mapping, Cycles with --srgb-node 1
  srgb_ours.pfm, srgb_cy.pfm, srgb_cys.pfm      tools/cycles/texture-srgb.scene, the same three
and texels.pfm: `restir merge -o texels.pfm tools/cycles/texture-probe.png --counts 1`
(the probe map as restir decodes it).

1. Lookup: each render against the exact bilinear/repeat lookup of the decoded texels at the
   render's sample point: pixel (p, q) at texel coordinates (p/4, q/4) (texture-probe.scene's
   UVs), Cycles' single sample displaced by +d pixel right and up (d = 1/2048, its filter
   table; fitted: 0 and 1/1024 leave 40 times larger residuals). For --srgb-node, also
   against "interpolate the 8-bit codes, then decode" (Cycles' byte sRGB images).
2. The sRGB curve: texture-srgb.scene's pixel (4m, 4n) is the decoded code of block (m, n)
   whatever the interpolation; each render against the IEC 61966-2-1 curve in double
   precision, --srgb-node's also against ours code by code; and an emulation in float of
   Cycles 3.4's SSE decode (util/color.h: color_srgb_to_linear on ssef, fastpow24: a guess
   of x^(4/5) from the float's bits, 3 Newton steps, cubed) against the exact curve.
"""
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pfmstat import read_pfm  # noqa: E402

D_PX = 1.0 / 2048


def codes():
    return [[(k, 255 - k, (97 * k) % 256) for k in range(16 * j, 16 * j + 16)] for j in range(16)]


def srgb_exact(c):
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def bits(x):
    return struct.unpack("<I", struct.pack("<f", x))[0]


def from_bits(i):
    return struct.unpack("<f", struct.pack("<I", i & 0xffffffff))[0]


def fastpow45(a):
    """Cycles' fastpow<4/5>: the float's bits scaled as an integer (an initial guess)."""
    r = f32(a * from_bits(0x4F55A7FB))
    r = f32(float(bits(r)))               # ssef(cast(ret)): the bit pattern as an int, to float
    r = f32(r * from_bits(0x3F4CCCCD))
    return from_bits(int(r))              # cast(ssei(ret)): truncating conversion, as bits


def srgb_cycles(c, fma):
    """color_srgb_to_linear(ssef) of Cycles 3.4's util/color.h, in float32 arithmetic."""
    c = f32(c)
    if c < f32(0.04045):
        return max(f32(c * f32(1.0 / 12.92)), 0.0)
    base = f32(f32(c + f32(0.055)) * f32(1.0 / 1.055))
    x = fastpow45(base)
    a2 = f32(base * base)
    a4 = f32(a2 * a2)
    for _ in range(3):
        p2 = f32(x * x)
        p4 = f32(p2 * p2)
        t = f32(a4 / p4)
        s = f32(4.0 * x + t) if fma else f32(f32(4.0 * x) + t)
        x = f32(s * f32(1.0 / 5.0))
    return f32(x * f32(x * x))


def bilinear(tex, x, y, decode=None):
    h, w = len(tex), len(tex[0])
    x0, y0 = math.floor(x), math.floor(y)
    fx, fy = x - x0, y - y0
    out = []
    for c in range(3):
        def g(i, j):
            return tex[j % h][i % w][c]
        v = ((1 - fx) * (1 - fy) * g(x0, y0) + fx * (1 - fy) * g(x0 + 1, y0)
             + (1 - fx) * fy * g(x0, y0 + 1) + fx * fy * g(x0 + 1, y0 + 1))
        out.append(decode(v) if decode else v)
    return out


def worst(im, model, shift):
    """Largest |render - model| over the 64 x 64 pixels and channels, and where."""
    best = (0.0, None)
    for q in range(64):
        for p in range(64):
            e = model(p / 4 + shift / 4, q / 4 - shift / 4)  # texel units; raster y is up
            for c in range(3):
                d = abs(im[q][p][c] - e[c])
                if d > best[0]:
                    best = (d, (p, q, "RGB"[c], im[q][p][c], e[c]))
    return best


def fit_offset(im, model):
    """Per pixel, the (dx, dy) in pixels (right, up) that best explains render - model to
    first order, from the model's one-sided gradient towards +x and raster-up; averaged."""
    h = 1e-3
    sx = sy = 0.0
    n = 0
    for q in range(64):
        for p in range(64):
            x, y = p / 4, q / 4
            e = model(x, y)
            gx = [(a - b) / h for a, b in zip(model(x + h, y), e)]
            gy = [(a - b) / h for a, b in zip(model(x, y - h), e)]  # raster up = rows up
            dv = [im[q][p][c] - e[c] for c in range(3)]
            axx = sum(g * g for g in gx)
            ayy = sum(g * g for g in gy)
            axy = sum(a * b for a, b in zip(gx, gy))
            bx = sum(a * b for a, b in zip(gx, dv))
            by = sum(a * b for a, b in zip(gy, dv))
            det = axx * ayy - axy * axy
            if det < 1e-6:
                continue
            sx += (ayy * bx - axy * by) / det
            sy += (axx * by - axy * bx) / det
            n += 1
    return 4 * sx / n, 4 * sy / n  # texel units to pixels (4 pixels per texel)


def main():
    d = sys.argv[1]
    texels = read_pfm(os.path.join(d, "texels.pfm"))
    enc = [[tuple(v / 255.0 for v in px) for px in row] for row in codes()]
    lin = lambda x, y: bilinear(texels, x, y)  # noqa: E731
    dec_after = lambda x, y: bilinear(enc, x, y, srgb_exact)  # noqa: E731
    print("1. lookup: max |render - model| over 64 x 64 x 3 (at p, q, channel, render, model)")
    for name, model, label, shift in (
            ("probe_ours", lin, "bilinear of decoded texels, pixel centre", 0.0),
            ("probe_cy", lin, "bilinear of decoded texels, pixel centre", 0.0),
            ("probe_cy", lin, "bilinear of decoded texels, centre + 1/2048 px", D_PX),
            ("probe_cys", lin, "bilinear of decoded texels, centre + 1/2048 px", D_PX),
            ("probe_cys", dec_after, "decode(bilinear of codes), centre + 1/2048 px", D_PX)):
        im = read_pfm(os.path.join(d, name + ".pfm"))
        w, where = worst(im, model, shift)
        print("  %-10s vs %-46s %.3g  %s" % (name, label, w, where))
    im = read_pfm(os.path.join(d, "probe_cy.pfm"))
    print("  Cycles' sample offset (pixels right and up; probe_cy): residual by offset %s"
          % ", ".join("%g: %.2g" % (s, worst(im, lin, s)[0])
                      for s in (0.0, 1 / 4096, 1 / 2048, 3 / 4096, 1 / 1024)))
    print("  least-squares offset from the map's gradient, mean over pixels: x %+.3g, y %+.3g px"
          % fit_offset(im, lin))
    print("2. sRGB curve at the 256 codes x 3 channels (values > 0.001: relative; else absolute)")
    blocks = codes()
    ims = {n: read_pfm(os.path.join(d, n + ".pfm")) for n in ("srgb_ours", "srgb_cy", "srgb_cys")}
    ours = lambda code, n, m, c: ims["srgb_ours"][4 * n][4 * m][c]  # noqa: E731
    exact = lambda code, n, m, c: srgb_exact(code / 255.0)  # noqa: E731
    for name, label, model in (("srgb_ours", "the IEC curve in double", exact),
                               ("srgb_cy", "the IEC curve in double", exact),
                               ("srgb_cys", "the IEC curve in double", exact),
                               ("srgb_cys", "ours, code by code", ours)):
        rel = ab = 0.0
        at = None
        for n in range(16):
            for m in range(16):
                for c in range(3):
                    code = blocks[n][m][c]
                    e = model(code, n, m, c)
                    v = ims[name][4 * n][4 * m][c]
                    if e > 1e-3:
                        if abs(v / e - 1) > rel:
                            rel, at = abs(v / e - 1), (code, v, e)
                    else:
                        ab = max(ab, abs(v - e))
        print("  %-9s vs %-24s max rel %.3g at (code, render, model) %s; max abs below 1e-3 %.3g"
              % (name, label, rel, at, ab))
    emu = [(abs(srgb_cycles(k / 255.0, fma) / srgb_exact(k / 255.0) - 1), k)
           for fma in (False, True) for k in range(11, 256)]
    print("  emulated Cycles SSE decode vs the IEC curve, codes 11..255 (with and without FMA): "
          "max rel %.3g (code %d), mean %.3g" % (max(emu)[0], max(emu)[1],
                                                 sum(r for r, _ in emu) / len(emu)))

main()
