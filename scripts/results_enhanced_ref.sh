#!/bin/sh
# Path-traced references for scripts/results_enhanced.sh (PARTs equaltime and footprint),
# cached in OUT/ref: NAME.pfm is the sample-count-weighted mean of two independent halves
# (seeds 1001 and 1002, REF_SPP/2 samples each, `restir merge --counts`), and NAME.self holds
# the reference's own error, estimated from the halves: relMSE(A, B) / 4 and MAPE(A, B) / 2
# (each half has twice the variance of the merged image, and A − B has twice a half's;
# MAPE scales as the standard deviation). A reference that exists is not rendered again.
#   sh scripts/results_enhanced_ref.sh OUT RESTIR SIZE REF_SPP REF_THREADS SCENE...
set -eu
OUT=$1; R=$2; SIZE=$3; REF_SPP=$4; REF_THREADS=$5; shift 5
mkdir -p "$OUT/ref"
half=$((REF_SPP / 2))
for scene in "$@"; do
    name=$(basename "$scene" .scene)
    [ -f "$OUT/ref/$name.pfm" ] && [ -f "$OUT/ref/$name.self" ] && continue
    for s in 1001 1002; do
        "$R" render "$scene" --method pt --spp "$half" --seed "$s" --size "${SIZE}x${SIZE}" --threads "$REF_THREADS" \
            --quiet --no-png -o "$OUT/ref/$name.$s.pfm" >/dev/null
    done
    "$R" merge -o "$OUT/ref/$name.pfm" "$OUT/ref/$name.1001.pfm" "$OUT/ref/$name.1002.pfm" --counts "$half,$half" \
        --quiet --no-png
    "$R" compare "$OUT/ref/$name.1001.pfm" "$OUT/ref/$name.1002.pfm" |
        awk -v spp="$REF_SPP" '$1 == "relmse" { r = $2 } $1 == "mape" { m = $2 }
            END { printf "%g %g %d\n", r / 4, m / 2, spp }' >"$OUT/ref/$name.self"
    rm -f "$OUT/ref/$name.1001.pfm" "$OUT/ref/$name.1002.pfm"
done
