#!/usr/bin/env python3
"""relMSE of TEST against REF split the ways the Cornell equal-time question needs (issue 28):
per colour channel R, G, B (their mean is `restir compare`'s relmse), of luminance alone, and
the share of the per-pixel relMSE sum held by the worst 0.1 % and 1 % of the pixels.
Same epsilon as docs/metrics.md: eps = 0.01 * mean |Y(REF)| (Rec. 709 luminance).
Standard library only.   relmse_channels.py REF.pfm TEST.pfm...  -> one CSV line per TEST:
test,relmse,relmse_r,relmse_g,relmse_b,relmse_y,top01_share,top1_share"""
import struct
import sys


def read_pfm(path):
    data = open(path, 'rb').read()
    tokens, i = [], 0
    while len(tokens) < 4:  # PF, width, height, scale; then exactly one whitespace byte
        while data[i:i + 1].isspace():
            i += 1
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        tokens.append(data[i:j].decode())
        i = j
    if tokens[0] != 'PF':
        sys.exit('%s: not a colour PFM' % path)
    w, h, scale = int(tokens[1]), int(tokens[2]), float(tokens[3])
    order = '<' if scale < 0 else '>'
    return w, h, struct.unpack(order + '%df' % (3 * w * h), data[i + 1:i + 1 + 12 * w * h])


def luminance(p, k):
    return 0.2126 * p[k] + 0.7152 * p[k + 1] + 0.0722 * p[k + 2]


def split(test, ref):
    w, h, x = read_pfm(test)
    w2, h2, r = read_pfm(ref)
    if (w, h) != (w2, h2):
        sys.exit('%s: size differs from the reference' % test)
    n = w * h
    eps = 0.01 * sum(abs(luminance(r, 3 * p)) for p in range(n)) / n
    channel, lum, per_pixel = [0.0, 0.0, 0.0], 0.0, []
    for p in range(n):
        k, term = 3 * p, 0.0
        for c in range(3):
            e = (x[k + c] - r[k + c]) ** 2 / (eps + abs(r[k + c])) ** 2
            channel[c] += e
            term += e / 3
        per_pixel.append(term)
        yr = luminance(r, k)
        lum += (luminance(x, k) - yr) ** 2 / (eps + abs(yr)) ** 2
    per_pixel.sort(reverse=True)
    total = sum(per_pixel)
    share = lambda f: sum(per_pixel[:max(1, int(n * f))]) / total if total > 0 else 0.0
    return [total / n] + [c / n for c in channel] + [lum / n, share(0.001), share(0.01)]


if __name__ == '__main__':
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    for test in sys.argv[2:]:
        print(','.join([test] + ['%.6g' % v for v in split(test, sys.argv[1])]))
