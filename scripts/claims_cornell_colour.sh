#!/bin/sh
# Why the path tracer beats offline ReSTIR PT in relMSE on the Cornell box while their MAPEs
# are equal (docs/results.md (d); issue 28: "explain the Cornell relMSE result with evidence:
# where the error sits, and which configuration changes it").
#   sh scripts/claims_cornell_colour.sh [OUT_DIR] [BUILD_DIR]      (needs python3, stdlib only)
# Per seed 1..SEEDS at SIZE^2: ReSTIR --preset gris-offline (scalar shading), the same without
# spatial reuse (--spatial-passes 0: 32-candidate RIS, one sample kept), the same with Enhanced
# §6.3 vector shading (--shading vector), and the path tracer for the scalar run's wall time
# (--spp 0 --time-limit, as scripts/results/equal_time.sh). Each image's relMSE against a
# REF_SPP path-traced reference (two halves, its own error measured) is split by
# scripts/results/relmse_channels.py into R, G, B, luminance and the share of the worst 0.1 % /
# 1 % of the pixels. Reported: mean ± 95% t half-width over seeds, and per seed the paired ratio
# ReSTIR/PT of each part. About 4 minutes on two cores at the defaults. Smoke test:
#   SIZE=16 SEEDS=2 REF_SPP=64 sh scripts/claims_cornell_colour.sh /tmp/cc
# SCENE (default cornell) names another scene of scenes/ for the same split (its reference is
# the path tracer too: choose a scene whose path tracer converges, not ajar).
set -eu
here=$(dirname "$0")
. "$here/results/lib.sh"
results_init out/claims-cornell-colour "$@"
defaults SIZE=128 SEEDS=5 REF_SPP=1024 THREADS=2 SCENE=cornell
CACHE="$OUT/ref"
mkdir -p "$TMP" "$CACHE"
scene=scenes/$SCENE.scene
ref=$(reference "$SCENE-all" "$SIZE" "$scene" pt "$REF_SPP")
split() { python3 "$here/results/relmse_channels.py" "$ref.pfm" "$@"; }
runs="$OUT/runs.csv"
echo "config,seed,relmse,relmse_r,relmse_g,relmse_b,relmse_y,top01_share,top1_share" > "$runs"
for seed in $(seq_seeds); do
    render "$SIZE" "$scene" --method restir --preset gris-offline --seed "$seed" -o "$TMP/scalar.pfm" --stats "$TMP/scalar.json"
    render "$SIZE" "$scene" --method restir --preset gris-offline --spatial-passes 0 --seed "$seed" -o "$TMP/no_reuse.pfm"
    render "$SIZE" "$scene" --method restir --preset gris-offline --shading vector --seed "$seed" -o "$TMP/vector.pfm"
    render "$SIZE" "$scene" --method pt --spp 0 --time-limit "$(render_seconds "$TMP/scalar.json")" --seed "$seed" \
        -o "$TMP/pt.pfm"
    for c in scalar no_reuse vector pt; do
        split "$TMP/$c.pfm" | sed "s|^[^,]*,|$c,$seed,|"
    done >> "$runs"
done
col() { awk -F, -v c="$1" -v k="$2" '$1 == c { print $k }' "$runs"; }
ratio() { # CONFIG COLUMN: per-seed CONFIG / pt of that column
    awk -F, -v c="$1" -v k="$2" '$1 == c { a[$2] = $k } $1 == "pt" { b[$2] = $k }
        END { for (s in a) if (b[s] > 0) print a[s] / b[s] }' "$runs"
}
{
    echo "Reference: path tracer, $REF_SPP spp, seed 9001; its own relMSE $(ref_relmse "$ref") (two halves)."
    echo "$SIZE x $SIZE, seeds 1..$SEEDS, mean ± 95% t half-width over seeds."
    echo
    echo "| configuration | relMSE | R | G | B | luminance | worst 0.1 % share | worst 1 % share |"
    echo "|---|---|---|---|---|---|---|---|"
    for c in pt scalar no_reuse vector; do
        printf '| %s |' "$c"
        for k in 3 4 5 6 7 8 9; do printf ' %s |' "$(col "$c" "$k" | mean_ci)"; done
        echo
    done
    echo
    echo "Paired ratio to the path tracer at equal time (per seed, then mean ± 95% t):"
    echo
    echo "| configuration | relMSE | R | G | B | luminance |"
    echo "|---|---|---|---|---|---|"
    for c in scalar no_reuse vector; do
        printf '| %s / pt |' "$c"
        for k in 3 4 5 6 7; do printf ' %s |' "$(ratio "$c" "$k" | mean_ci)"; done
        echo
    done
} | tee "$OUT/table.md"
