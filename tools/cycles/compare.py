"""Compares K restir path-tracer runs (OUT/ours/run{1..K}.pfm) with K Cycles runs
(OUT/cycles/run{1..K}.pfm), per channel R, G, B (tools/cycles/README.md).

  python3 tools/cycles/compare.py OUT K

1. Image means: the relative difference (mean_cycles - mean_ours) / mean_ours of the K-run
   averages, with a Welch t interval (95 % and 99 %) from the spread of the per-run means of
   both sides, and each side's own relative standard error.
2. Per pixel, the K-run averages A (Cycles) and B (ours, the reference): relMSE and MAPE per
   channel with eps = 0.01 mean luminance of B (docs/metrics.md's eps), against what noise
   alone would give: from the per-pixel run-to-run variances s2_A, s2_B, the expected relMSE
   is mean_p (s2_A/K + s2_B/K) / (eps + |B_p|)^2 and the expected MAPE (normal noise)
   mean_p sqrt(2/pi) sqrt(s2_A/K + s2_B/K) / (eps + |B_p|). Each side's own noise level is
   the same with only its variance.
3. Pixels whose difference is large against its own noise: |z| > 4 per channel, with
   z = (A_p - B_p) / sqrt(s2_A/K + s2_B/K).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pfmstat import read_pfm  # noqa: E402

# two-sided Student t quantiles, by degrees of freedom (95 %, 99 %)
T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306,
       9: 2.262, 10: 2.228, 12: 2.179, 14: 2.145, 16: 2.120, 20: 2.086, 30: 2.042, 60: 2.000}
T99 = {1: 63.657, 2: 9.925, 3: 5.841, 4: 4.604, 5: 4.032, 6: 3.707, 7: 3.499, 8: 3.355,
       9: 3.250, 10: 3.169, 12: 3.055, 14: 2.977, 16: 2.921, 20: 2.845, 30: 2.750, 60: 2.660}


def tq(table, df):
    keys = sorted(table)
    for k in keys:  # the next smaller tabulated df: conservative
        if k > df:
            break
        best = k
    return table[best]


def c4(k):
    return math.sqrt(2.0 / (k - 1)) * math.exp(math.lgamma(k / 2.0) - math.lgamma((k - 1) / 2.0))


def t_tail2(z, df, steps=20000):
    """P(|T| > z) for Student t with df degrees of freedom (midpoint rule on [0, z])."""
    c = math.exp(math.lgamma((df + 1) / 2.0) - math.lgamma(df / 2.0)) / math.sqrt(df * math.pi)
    hstep = z / steps
    area = sum(c * (1 + ((i + 0.5) * hstep) ** 2 / df) ** (-(df + 1) / 2.0) for i in range(steps))
    return 1 - 2 * area * hstep


def mean_var(xs):
    m = sum(xs) / len(xs)
    return m, sum((x - m) ** 2 for x in xs) / (len(xs) - 1)


def main():
    out, k = sys.argv[1], int(sys.argv[2])
    sides = {}
    for side in ("cycles", "ours"):
        sides[side] = [read_pfm(os.path.join(out, side, "run%d.pfm" % i)) for i in range(1, k + 1)]
    h, w = len(sides["ours"][0]), len(sides["ours"][0][0])
    n = w * h
    names = "RGB"
    print("K = %d runs per side, %d x %d pixels" % (k, w, h))
    print("\n1. image means (relative difference cycles/ours - 1, Welch t intervals)")
    print("ch   mean_ours   rse_ours  mean_cycles rse_cycles   rel.diff    95% half  99% half   z")
    for c in range(3):
        per = {s: [sum(p[c] for row in im for p in row) / n for im in sides[s]] for s in sides}
        ma, va = mean_var(per["cycles"])
        mb, vb = mean_var(per["ours"])
        se = math.sqrt(va / k + vb / k)
        df = (va / k + vb / k) ** 2 / ((va / k) ** 2 / (k - 1) + (vb / k) ** 2 / (k - 1))
        rel = ma / mb - 1
        print("%s  %10.6f  %8.2e  %10.6f  %8.2e  %+9.2e  %8.2e  %8.2e  %+5.2f" % (
            names[c], mb, math.sqrt(vb / k) / mb, ma, math.sqrt(va / k) / ma, rel,
            tq(T95, int(df)) * se / mb, tq(T99, int(df)) * se / mb, (ma - mb) / se))
    # per-pixel statistics
    avg, var = {}, {}
    for s, ims in sides.items():
        avg[s] = [[[0.0] * 3 for _ in range(w)] for _ in range(h)]
        var[s] = [[[0.0] * 3 for _ in range(w)] for _ in range(h)]
        for y in range(h):
            for x in range(w):
                for c in range(3):
                    m, v = mean_var([im[y][x][c] for im in ims])
                    avg[s][y][x][c], var[s][y][x][c] = m, v
    lum = sum(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] for row in avg["ours"] for p in row) / n
    eps = 0.01 * abs(lum)
    print("\n2. per pixel, K-run averages, cycles against ours (eps = %.6g)" % eps)
    print("ch   relMSE   expected  own(ours) own(cyc)     MAPE   expected  own(ours) own(cyc)   "
          "|z|>4 (expected %.0f)  noiseless: n, max rel. diff" % (t_tail2(4.0, k - 1) * n))
    # relMSE excess z: the mean over pixels of ((A-B)^2 - s2_A/K - s2_B/K)/(eps+|B|)^2 over its
    # standard error (pixels independent): about N(0, 1) if the two renderers agree
    for c in range(3):
        acc = [0.0] * 8
        excess = []  # per pixel: observed minus expected relMSE term
        big = 0
        still, still_max = 0, 0.0
        for y in range(h):
            for x in range(w):
                a, b = avg["cycles"][y][x][c], avg["ours"][y][x][c]
                sa, sb = var["cycles"][y][x][c] / k, var["ours"][y][x][c] / k
                d = eps + abs(b)
                acc[0] += (a - b) ** 2 / d ** 2
                acc[1] += (sa + sb) / d ** 2
                excess.append(((a - b) ** 2 - (sa + sb)) / d ** 2)
                acc[2] += sb / d ** 2
                acc[3] += sa / d ** 2
                acc[4] += abs(a - b) / d
                acc[5] += math.sqrt(2 / math.pi) * math.sqrt(sa + sb) / d / c4(k)
                acc[6] += math.sqrt(2 / math.pi) * math.sqrt(sb) / d / c4(k)
                acc[7] += math.sqrt(2 / math.pi) * math.sqrt(sa) / d / c4(k)
                if sa == 0 and sb == 0:
                    still += 1
                    still_max = max(still_max, abs(a - b) / max(abs(b), 1e-30))
                elif abs(a - b) / math.sqrt(sa + sb) > 4:
                    big += 1
        em, ev = mean_var(excess)
        print("%s  %s  %5d                %5d  %.1e   relMSE excess z %+.2f" % (
            names[c], "  ".join("%8.2e" % (v / n) for v in acc), big, still, still_max,
            em / math.sqrt(ev / n)))


main()
