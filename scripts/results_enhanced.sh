#!/bin/sh
# Enhanced Table 1 in spirit (docs/results.md, "ReSTIR PT Enhanced: cost per stage"):
# milliseconds per stage of one offline ReSTIR PT frame at SIZE x SIZE as the Enhanced
# features of this branch are switched on in turn, from the GRIS baseline. Every number is
# the mean over SEEDS seeds with a 95% t interval (half-width), from the renders' own
# --stats. Not part of `make test`.
#   sh scripts/results_enhanced.sh [OUT_DIR] [BUILD_DIR]
# Differences from the paper's Table 1: CPU, not GPU; one frame, 1 path tree, 1 spatial
# pass with 3 neighbours (R = 10) and pairwise MIS, no temporal reuse; no equal-time error
# (MAPE, FLIP) columns yet.
# PART=pairs (or all, the default) adds "the paired pass against the disk pass": CPU
# milliseconds per spatial pass (process user + system time of a K-pass render minus the
# same render with 0 passes, so the reuse-texture build and everything but the passes
# cancel; --threads 1, so CPU time is the pass's cost whatever the machine's load), and
# the shifts per pixel and pass from --stats.
set -eu
OUT=${1:-out/results-enhanced}
R=${2:-build}/restir
SIZE=${SIZE:-256}
THREADS=${THREADS:-2}
SEEDS=${SEEDS:-1 2 3}
SCENES=${SCENES:-scenes/cornell-glossy.scene}
PART=${PART:-all}
mkdir -p "$OUT"

mean_ci() { # [decimals]
    awk -v d="${1:-1}" '{ x[NR] = $1; s += $1 } END {
        n = NR; m = s / n; v = 0
        for (i = 1; i <= n; ++i) v += (x[i] - m) ^ 2
        v = n > 1 ? v / (n - 1) : 0
        split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262", t, " ")
        q = n - 1 <= 9 ? t[n - 1] : 1.96
        h = n > 1 ? q * sqrt(v / n) : 0
        printf("%." d "f ± %." d "f", m, h) }'
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
    "+ paired neighbours (§3, pattern only)|--rc-criterion footprint --pairing paired --no-pair-step" \
    "+ pair step (§3, 2 shifts per pair)|--rc-criterion footprint --pairing paired" \
    "+ vector shading (§6.3)|--rc-criterion footprint --pairing paired --shading vector" \
    "+ forced NEE reconnection (§6.2.3)|--rc-criterion footprint --pairing paired --shading vector --force-nee-reconnection"

if [ "$PART" = all ] || [ "$PART" = table1 ]; then
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
fi

# ---- the paired pass against the disk pass at equal neighbour count ---------------------
# cpu_ms OPTS...: user + system milliseconds of one render
cpu_ms() {
    # shellcheck disable=SC2086
    /usr/bin/time -f "%U %S" -o "$OUT/time.txt" "$R" render "$@" --threads 1 --quiet --no-png -o "$OUT/p.pfm" \
        --stats "$OUT/p.json" >/dev/null
    awk '{ printf "%.1f", 1000 * ($1 + $2) }' "$OUT/time.txt"
}
shifts_pp() { sed -n 's/.*"shifts_per_pixel_per_frame": \([0-9.]*\).*/\1/p' "$OUT/p.json" | head -1; }

if [ "$PART" = all ] || [ "$PART" = pairs ]; then
    K=${PASSES:-3}
    for scene in $SCENES; do
        name=$(basename "$scene" .scene)
        echo "### $name, ${SIZE}², $K spatial passes, pairwise-defensive, hybrid, threads 1, seeds $SEEDS"
        echo
        echo "| neighbours | pass | CPU ms per pass | shifts per pixel and pass | disk / this (per seed) |"
        echo "| --- | --- | --- | --- | --- |"
        for nb in ${NEIGHBORS:-3 6}; do
            P="$scene --method restir --candidates 1 --neighbors $nb --radius 10 --mis pairwise-defensive --shift hybrid --size ${SIZE}x${SIZE}"
            : >"$OUT/pairs.rows"
            # per seed: disk, no-step, pair-step ms per pass; their shifts; ratios (kept in pairs.$nb.rows)
            for s in $SEEDS; do
                # shellcheck disable=SC2086
                d0=$(cpu_ms $P --seed "$s" --spatial-passes 0)
                # shellcheck disable=SC2086
                dk=$(cpu_ms $P --seed "$s" --spatial-passes "$K"); ds=$(shifts_pp)
                # shellcheck disable=SC2086
                p0=$(cpu_ms $P --seed "$s" --spatial-passes 0 --pairing paired)
                # shellcheck disable=SC2086
                nk=$(cpu_ms $P --seed "$s" --spatial-passes "$K" --pairing paired --no-pair-step); ns=$(shifts_pp)
                # shellcheck disable=SC2086
                pk=$(cpu_ms $P --seed "$s" --spatial-passes "$K" --pairing paired); ps=$(shifts_pp)
                echo "$d0 $dk $ds $p0 $nk $ns $pk $ps" | awk -v K="$K" '{
                    d = ($2 - $1) / K; n = ($5 - $4) / K; p = ($7 - $4) / K
                    print d, n, p, $3 / K, $6 / K, $8 / K, 1, d / n, d / p }' >>"$OUT/pairs.rows"
            done
            row() { # label, ms column, shifts column, ratio column
                echo "| $nb | $1 | $(awk -v c="$2" '{ print $c }' "$OUT/pairs.rows" | mean_ci) |" \
                    "$(awk -v c="$3" '{ s += $c } END { printf "%.2f", s / NR }' "$OUT/pairs.rows") |" \
                    "$(awk -v c="$4" '{ print $c }' "$OUT/pairs.rows" | mean_ci 2) |"
            }
            row "disk (r2)" 1 4 7
            row "paired, per-pixel step (--no-pair-step)" 2 5 8
            row "paired, pair step" 3 6 9
            cp "$OUT/pairs.rows" "$OUT/pairs.$nb.rows"
        done
        echo
    done
    rm -f "$OUT/time.txt"
fi

# ---- the footprint criterion on a near and a far view (Enhanced Figs. 10-12 in spirit) ----
# The same glossy scene from the default camera ("near") and from 4.75x the distance with the
# field of view narrowed to keep the framing ("far"): the primary footprint grows with the
# distance, d_min (a fraction of the scene diagonal) does not. Equal wall time per render
# (BUDGET seconds, --time-limit; the machine is shared, so "equal time" is approximate),
# MAPE against a path-traced reference (REF_SPP), and the fraction of initial samples that
# reconnect at k = 2 and the mean reconnection index k (from --stats).
if [ "$PART" = all ] || [ "$PART" = footprint ]; then
    FS=${FSIZE:-64}
    BUDGET=${BUDGET:-5}
    REF_SPP=${REF_SPP:-2048}
    scene=scenes/cornell-glossy.scene
    echo "### cornell-glossy near and far, ${FS}², ${BUDGET} s per render, reference $REF_SPP spp, seeds $SEEDS"
    echo
    echo "| view | criterion | MAPE | initial samples reconnecting at k = 2 | mean k (reconnecting samples) | frames in the budget |"
    echo "| --- | --- | --- | --- | --- | --- |"
    for view in near far; do
        if [ "$view" = near ]; then V="--eye 278,273,-800 --target 278,273,0 --fov 39.3076481"
        else V="--eye 278,273,-3800 --target 278,273,0 --fov 9.2"; fi
        # shellcheck disable=SC2086
        "$R" render "$scene" $V --method pt --spp "$REF_SPP" --size "${FS}x${FS}" --threads "$THREADS" --quiet --no-png \
            -o "$OUT/ref-$view.pfm" >/dev/null
        for crit in "gris, d_min 0.02 (default)|--rc-criterion gris" "gris, d_min 0.005|--rc-criterion gris --distance-threshold 0.005" \
            "gris, d_min 0.08|--rc-criterion gris --distance-threshold 0.08" "footprint, c = 0.02|--rc-criterion footprint"; do
            label=${crit%%|*}
            opts=${crit#*|}
            : >"$OUT/fp.rows"
            for s in $SEEDS; do
                # shellcheck disable=SC2086
                "$R" render "$scene" $V --method restir --candidates 1 --spatial-passes 1 --neighbors 3 --radius 10 \
                    --mis pairwise-defensive --shift hybrid $opts --time-limit "$BUDGET" --seed "$s" --size "${FS}x${FS}" \
                    --threads "$THREADS" --quiet --no-png -o "$OUT/fp.pfm" --stats "$OUT/fp.json" >/dev/null
                mape=$("$R" compare "$OUT/fp.pfm" "$OUT/ref-$view.pfm" | awk '$1 == "mape" { print $2 }')
                # the stats JSON spans lines: flatten it first
                rc=$(tr -d '\n' <"$OUT/fp.json" |
                    sed -n 's/.*"initial": {[^}]*"selected": \([0-9]*\),.*"selected_by_reconnection_index": \[\([0-9, ]*\)\].*/\1,\2/p' |
                    awk -F, '{ n = 0; s = 0; for (k = 4; k <= NF; ++k) { n += $k; s += (k - 2) * $k }
                               printf "%.4f %.3f", $4 / $1, (n > 0 ? s / n : 0) }')
                frames=$(tr -d '\n' <"$OUT/fp.json" | sed -n 's/.*"stats": *{ *"frames": \([0-9]*\),.*/\1/p')
                echo "$mape $rc $frames" >>"$OUT/fp.rows" # mape, k=2 share, mean k, frames
            done
            echo "| $view | $label | $(awk '{ print $1 }' "$OUT/fp.rows" | mean_ci 4) |" \
                "$(awk '{ print $2 }' "$OUT/fp.rows" | mean_ci 3) | $(awk '{ print $3 }' "$OUT/fp.rows" | mean_ci 3) |" \
                "$(awk '{ print $4 }' "$OUT/fp.rows" | mean_ci 0) |"
        done
    done
    echo
    rm -f "$OUT/fp.rows"
fi
