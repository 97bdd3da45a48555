#!/bin/sh
# Prints the tables of docs/results.md's "Light RIS for NEE" section (issue 11, Enhanced §6.1)
# with our own CLI; not part of `make test`.
#   sh scripts/results_lightris.sh [OUT_DIR] [BUILD_DIR]
# The path tracer on the many-lights hall (SIZE x SIZE, paths up to DEPTH segments, SPP
# samples per pixel), plain light sampler vs light RIS with N = 8 and 32 candidates, without
# and with light tiles, SEEDS seeds each: relMSE against a reference (light RIS N = 32,
# 2 x REF_SPP/2 spp, seeds 9001/9002, independent of the measured runs), the render time and
# the efficiency 1 / (relMSE x time) relative to the plain sampler's (equal-time gain, exact
# when the error falls as 1/time); mean ± 95% t half-width over the seeds. The reference's
# own relMSE is estimated from its two halves: relMSE(half 1, half 2) / 4.
# Then the light-selection cost from `restir bench restir --light-ris 32 [--light-tiles]`.
set -eu
. "$(dirname "$0")/results/lib.sh"
results_init out/results-lightris "$@"
defaults SIZE=48 DEPTH=3 SPP=16 SEEDS=5 REF_SPP=2048 THREADS=2
SCENE=scenes/many-lights.scene
mkdir -p "$TMP"

render() { "$R" render "$SCENE" --size "${SIZE}x${SIZE}" --max-depth "$DEPTH" --threads "$THREADS" --quiet --no-png "$@"; }
relmse() { "$R" compare "$1" "$2" | awk '$1 == "relmse" { print $2 }'; }
seconds() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["pt"]["seconds"])' "$1"; }

half=$((REF_SPP / 2))
ref="$TMP/ref.pfm"
if [ ! -f "$ref" ]; then
    render --light-ris 32 --spp "$half" --seed 9001 -o "$TMP/ref1.pfm"
    render --light-ris 32 --spp "$half" --seed 9002 -o "$TMP/ref2.pfm"
    "$R" merge -o "$ref" "$TMP/ref1.pfm" "$TMP/ref2.pfm" --counts "$half,$half" >/dev/null
fi
ref_own=$(relmse "$TMP/ref1.pfm" "$TMP/ref2.pfm" | awk '{ printf "%.3g", $1 / 4 }')

for cfg in plain "ris8:--light-ris 8" "ris8t:--light-ris 8 --light-tiles" "ris32:--light-ris 32" "ris32t:--light-ris 32 --light-tiles"; do
    name=${cfg%%:*}
    args=""
    [ "$name" = plain ] || args=${cfg#*:}
    : > "$TMP/$name.rel"
    : > "$TMP/$name.sec"
    s=1
    while [ "$s" -le "$SEEDS" ]; do
        # shellcheck disable=SC2086
        render $args --spp "$SPP" --seed "$s" -o "$TMP/$name.$s.pfm" --stats "$TMP/$name.$s.json"
        relmse "$TMP/$name.$s.pfm" "$ref" >> "$TMP/$name.rel"
        seconds "$TMP/$name.$s.json" >> "$TMP/$name.sec"
        s=$((s + 1))
    done
done
plain_rel=$(awk '{ s += $1 } END { print s / NR }' "$TMP/plain.rel")
plain_sec=$(awk '{ s += $1 } END { print s / NR }' "$TMP/plain.sec")

echo "many-lights hall, ${SIZE}², paths up to $DEPTH segments, $SPP spp per run, $SEEDS seeds; reference: light RIS N = 32, $REF_SPP spp (own relMSE ≈ $ref_own); $THREADS threads on a shared machine"
echo
echo "| NEE light selection | relMSE | seconds per run | efficiency vs plain (1/(relMSE·time)) |"
echo "| --- | --- | --- | --- |"
for cfg in "plain:plain p_0 (power, uniform point)" "ris8:light RIS, N = 8" "ris8t:light RIS, N = 8, tiles" "ris32:light RIS, N = 32" "ris32t:light RIS, N = 32, tiles"; do
    name=${cfg%%:*}
    label=${cfg#*:}
    paste "$TMP/$name.rel" "$TMP/$name.sec" | awk -v r="$plain_rel" -v t="$plain_sec" '{ print (r * t) / ($1 * $2) }' > "$TMP/$name.eff"
    echo "| $label | $(mean_ci < "$TMP/$name.rel") | $(mean_ci < "$TMP/$name.sec") | $(mean_ci < "$TMP/$name.eff") |"
done
echo
echo "Light-selection cost (\`restir bench restir scenes/many-lights.scene --light-ris 32 [--light-tiles]\`, one thread, primary hits of a 64² view):"
echo
echo '```'
for tiles in "" --light-tiles; do
    # shellcheck disable=SC2086
    "$R" bench restir "$SCENE" --light-ris 32 $tiles --threads "$THREADS" 2>/dev/null | grep -A1 '"light_selection"' || true
done
echo '```'
