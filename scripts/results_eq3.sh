#!/bin/sh
# Enhanced Eq. 3 settled by measurement (docs/enhanced.md §2, "Eq. 3, measured"; issue 28):
# for every reading of the garbled equation (include/restir/restir/pairing.h) and target
# sigma in [0.8, 32], the pass count n and the standard deviation the offsets of TEXTURES
# independent 254 x 254 reuse textures reach per axis (mean, 99% t-interval), as
# OUT/eq3.json and the Markdown table OUT/eq3.md.   usage: results_eq3.sh OUT BUILD [TEXTURES]
set -eu
out=$1 build=$2 textures=${3:-16}
mkdir -p "$out"
"$build/restir" bench pairing-sigma --textures "$textures" > "$out/eq3.json.tmp"
mv "$out/eq3.json.tmp" "$out/eq3.json"
# one element per line: sigma, reading, passes, std_x {mean rel_err rel_lo rel_hi}, std_y {...}
awk -v K="$textures" '
function num(key, s,   i) { i = index(s, "\"" key "\": "); s = substr(s, i + length(key) + 4); return s + 0 }
function after(key, s) { return substr(s, index(s, "\"" key "\"")) }
/"pairing-sigma"/ {
    s = $0
    sig = num("sigma", s); r = s; sub(/.*"reading": "/, "", r); sub(/".*/, "", r); n = num("passes", s)
    x = after("std_x", s); y = after("std_y", s)
    if (!(sig in seen)) { seen[sig] = 1; order[++ns] = sig }
    if (!(r in rseen)) { rseen[r] = 1; rorder[++nr] = r }
    cell[sig, r] = sprintf("%d: %.3f %+.1f%% [%+.1f, %+.1f] / %+.1f%%", n, num("mean", x), 100 * num("rel_err", x),
                           100 * num("rel_lo", x), 100 * num("rel_hi", x), 100 * num("rel_err", y))
    e = num("rel_err", x); if (e < 0) e = -e; f = num("rel_err", y); if (f < 0) f = -f
    if (sig >= 2) { if (e > worst[r]) worst[r] = e; if (f > worst[r]) worst[r] = f; sum[r] += e + f; cnt[r] += 2 }
}
END {
    printf "Per cell: n (passes): achieved sigma along x, its relative error with the 99%% interval over %d textures, then the error along y.\n\n", K
    printf "| sigma |"; for (j = 1; j <= nr; ++j) printf " %s |", rorder[j]; printf "\n|---|"
    for (j = 1; j <= nr; ++j) printf "---|"; printf "\n"
    for (i = 1; i <= ns; ++i) {
        printf "| %g |", order[i]
        for (j = 1; j <= nr; ++j) printf " %s |", cell[order[i], rorder[j]]
        printf "\n"
    }
    printf "| **sigma >= 2: worst / mean abs error** |"
    for (j = 1; j <= nr; ++j) printf " %.1f%% / %.2f%% |", 100 * worst[rorder[j]], 100 * sum[rorder[j]] / cnt[rorder[j]]
    printf "\n"
}' "$out/eq3.json" > "$out/eq3.md"
cat "$out/eq3.md"
