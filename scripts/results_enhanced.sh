#!/bin/sh
# Enhanced Table 1 in spirit (docs/results.md, "ReSTIR PT Enhanced: cost per stage"):
# milliseconds per stage of one offline ReSTIR PT frame at SIZE x SIZE as the Enhanced
# features of this branch are switched on in turn, from the GRIS baseline. Every number is
# the mean over SEEDS seeds with a 95% t interval (half-width), from the renders' own
# --stats. Not part of `make test`.
#   sh scripts/results_enhanced.sh [OUT_DIR] [BUILD_DIR]
# Differences from the paper's Table 1: CPU, not GPU; one frame, 1 path tree, 1 spatial
# pass with 3 neighbours (R = 10) and pairwise MIS, no temporal reuse; the paired pass is
# only the paired neighbour pattern (the two-shift pair step is not implemented), so no
# speed-up is expected from it; no equal-time error (MAPE, FLIP) columns yet.
set -eu
OUT=${1:-out/results-enhanced}
R=${2:-build}/restir
SIZE=${SIZE:-256}
THREADS=${THREADS:-2}
SEEDS=${SEEDS:-1 2 3}
SCENES=${SCENES:-scenes/cornell-glossy.scene}
mkdir -p "$OUT"

mean_ci() {
    awk '{ x[NR] = $1; s += $1 } END {
        n = NR; m = s / n; v = 0
        for (i = 1; i <= n; ++i) v += (x[i] - m) ^ 2
        v = n > 1 ? v / (n - 1) : 0
        split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262", t, " ")
        q = n - 1 <= 9 ? t[n - 1] : 1.96
        h = n > 1 ? q * sqrt(v / n) : 0
        printf "%.1f ± %.1f", m, h }'
}
# stage NAME of a --stats file: gbuffer, initial, spatial (pass 0), shade
stage() {
    sed -n 's/.*"milliseconds": {\(.*\)}.*/\1/p' "$2" | head -1 | tr ',' '\n' | tr -d ' "[]' |
        awk -F: -v k="$1" '$1 == k { print $2; exit }'
}

BASE="--method restir --candidates 1 --spatial-passes 1 --neighbors 3 --radius 10 --mis pairwise --shift hybrid"
set -- \
    "GRIS baseline (disk, gris criterion, scalar)|" \
    "+ footprint criterion (§4)|--rc-criterion footprint" \
    "+ paired neighbours (§3, pattern only)|--rc-criterion footprint --pairing paired" \
    "+ vector shading (§6.3)|--rc-criterion footprint --pairing paired --shading vector" \
    "+ forced NEE reconnection (§6.2.3)|--rc-criterion footprint --pairing paired --shading vector --force-nee-reconnection"

for scene in $SCENES; do
    name=$(basename "$scene" .scene)
    echo "### $name, ${SIZE}², threads $THREADS, seeds $SEEDS"
    echo
    echo "| configuration | G-buffer ms | initial ms | spatial ms | shade ms | frame ms | ratio to baseline |"
    echo "| --- | --- | --- | --- | --- | --- | --- |"
    base_total=""
    for row in "$@"; do
        label=${row%%|*}
        opts=${row#*|}
        for s in $SEEDS; do
            # shellcheck disable=SC2086
            "$R" render "$scene" $BASE $opts --seed "$s" --size "${SIZE}x${SIZE}" --threads "$THREADS" --quiet \
                --no-png -o "$OUT/$name.$s.pfm" --stats "$OUT/$name.$s.json" >/dev/null
            g=$(stage gbuffer "$OUT/$name.$s.json"); i=$(stage initial "$OUT/$name.$s.json")
            p=$(stage spatial "$OUT/$name.$s.json"); h=$(stage shade "$OUT/$name.$s.json")
            echo "$g $i $p $h" >>"$OUT/$name.rows"
        done
        cols=""
        for c in 1 2 3 4; do cols="$cols | $(awk -v c=$c '{ print $c }' "$OUT/$name.rows" | mean_ci)"; done
        total=$(awk '{ print $1 + $2 + $3 + $4 }' "$OUT/$name.rows" | mean_ci)
        mean_total=$(awk '{ s += $1 + $2 + $3 + $4 } END { print s / NR }' "$OUT/$name.rows")
        [ -n "$base_total" ] || base_total=$mean_total
        ratio=$(awk -v a="$mean_total" -v b="$base_total" 'BEGIN { printf "%.2f", a / b }')
        echo "| $label$cols | $total | $ratio |"
        rm -f "$OUT/$name.rows"
    done
    echo
done
