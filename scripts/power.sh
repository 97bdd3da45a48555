#!/bin/sh
# Power of `restir check` on real renders (docs/statistics.md, "Power table"): the
# smallest relative bias b of ReSTIR PT (1 candidate, PASSES spatial passes) that check
# calls different against the path tracer (PT_SPP spp) in >= 80% of independent seed
# pairs, for the image-mean part and the block part, vs image size and K runs.
#   sh scripts/power.sh [OUT_DIR] [BUILD_DIR]
# Environment: SEEDS (10), SIZES ("16 32 64"), KS ("4 8 16"), BIASES (percent, "0.5 1 2 4 8
# 16 32"), PASSES (3), PT_SPP (64), SCENE (scenes/cornell.scene), ALPHA (0.01), THREADS (1).
# The bias is planted with `check --scale-a 1+b` (every ReSTIR run multiplied by 1 + b,
# like W x (1 + b) at every pixel). Alongside, the image-mean part's b80 derived from the
# measured standard errors: b80 = (t_{1-alpha/4,nu} + t_{0.8,nu}) se / mean (mean over
# seeds; t by the Cornish-Fisher expansion). Run it with `nice -n 10`; not in `make test`.
set -eu
. "$(dirname "$0")/results/lib.sh"
results_init out/power "$@"
defaults SEEDS=10 "SIZES=16 32 64" "KS=4 8 16" "BIASES=0.5 1 2 4 8 16 32" PASSES=3 PT_SPP=64 SCENE=scenes/cornell.scene
defaults ALPHA=0.01 THREADS=1
LOG="$OUT/power.txt"
: > "$LOG"

# se of side X ("a" or "b") of the image mean
side_se() { grep "\"$2\": {\"source\"" "$1" | sed 's/.*"se": \([^,]*\),.*/\1/'; }

for size in $SIZES; do
    for k in $KS; do
        i=1
        while [ "$i" -le "$SEEDS" ]; do
            seed=$((100000 * k + 1000 * i))
            "$R" render "$SCENE" --method restir --spatial-passes "$PASSES" --size "${size}x${size}" --runs "$k" \
                --seed "$seed" --threads "$THREADS" --quiet --no-png -o "$OUT/restir.pfm"
            "$R" render "$SCENE" --method pt --spp "$PT_SPP" --size "${size}x${size}" --runs "$k" \
                --seed $((seed + 500)) --threads "$THREADS" --quiet --no-png -o "$OUT/pt.pfm"
            for b in 0 $BIASES; do
                scale=$(awk -v b="$b" 'BEGIN { printf "%.6f", 1 + b / 100 }')
                status=0
                "$R" check --a-moments "$OUT/restir" --b-moments "$OUT/pt" --alpha "$ALPHA" --scale-a "$scale" \
                    --quiet --json "$OUT/check.json" > /dev/null 2>&1 || status=$?
                # 3: inconclusive (heavy-tailed runs); the parts counted here are the tests' own
                [ "$status" -le 1 ] || [ "$status" = 3 ] || { echo "check failed (status $status)" >&2; exit 2; }
                [ "$status" = 3 ] && echo "$size $k $i inconclusive $b" >> "$LOG"
                g=$(json_value "$OUT/check.json" image_mean reject)
                nb=$(json_value "$OUT/check.json" blocks rejected)
                if [ "$b" = 0 ]; then
                    sa=$(side_se "$OUT/check.json" a)
                    sb=$(side_se "$OUT/check.json" b)
                    mb=$(grep '"b": {"source"' "$OUT/check.json" | sed 's/.*"mean": \([^,]*\),.*/\1/')
                    dof=$(json_value "$OUT/check.json" image_mean dof)
                    echo "$size $k $i se $sa $sb $mb $dof" >> "$LOG"
                fi
                echo "$size $k $i $b $g $nb" >> "$LOG"
            done
            i=$((i + 1))
        done
    done
done

echo "# check power: ReSTIR ($PASSES spatial passes) x (1 + b) vs PT ($PT_SPP spp), $(basename "$SCENE" .scene), alpha $ALPHA, $SEEDS seed pairs per row"
echo "| size | K | image mean: b80 derived | image mean: rejected at b = $(echo "$BIASES" | sed 's/ /, /g') % | image mean: smallest b with >= 80% | blocks: rejected at b = ... | blocks: smallest b with >= 80% | false alarms at b = 0 (mean, blocks) |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
awk -v alpha="$ALPHA" -v biases="$BIASES" '
    # Student t quantile from the normal one (Cornish-Fisher, Abramowitz & Stegun 26.7.5).
    function tq(z, nu) { return z + (z^3 + z) / (4 * nu) + (5 * z^5 + 16 * z^3 + 3 * z) / (96 * nu^2) \
                             + (3 * z^7 + 19 * z^5 + 17 * z^3 - 15 * z) / (384 * nu^3) }
    BEGIN { nb = split(biases, bs, " ") }
    $4 == "inconclusive" { next }
    $4 == "se" { key = $1 " " $2; rel[key] += sqrt($5 * $5 + $6 * $6) / $7; dofs[key] += $8; nse[key]++; next }
    { key = $1 " " $2; if (!(key in seen)) { seen[key] = 1; order[++nk] = key }
      n[key, $4]++; g[key, $4] += ($5 == "true"); bl[key, $4] += ($6 > 0) }
    END {
        zc = (alpha == 0.01 ? 2.807034 : alpha == 0.05 ? 2.241403 : alpha == 0.1 ? 1.959964 : 2.807034); zp = 0.841621
        for (j = 1; j <= nk; j++) {
            key = order[j]; split(key, sk, " ")
            nu = dofs[key] / nse[key]
            b80 = (tq(zc, nu) + tq(zp, nu)) * rel[key] / nse[key]
            gl = ""; bll = ""; gmin = "> " bs[nb] " %"; bmin = "> " bs[nb] " %"
            for (q = nb; q >= 1; q--) {
                b = bs[q]
                if (g[key, b] >= 0.8 * n[key, b]) gmin = b " %"
                if (bl[key, b] >= 0.8 * n[key, b]) bmin = b " %"
            }
            for (q = 1; q <= nb; q++) { b = bs[q]; gl = gl (q > 1 ? ", " : "") g[key, b]; bll = bll (q > 1 ? ", " : "") bl[key, b] }
            printf "| %d² | %d | %.2f %% | %s | %s | %s | %s | %d, %d of %d |\n", sk[1], sk[2], 100 * b80, gl, gmin, bll, bmin,
                g[key, 0], bl[key, 0], n[key, 0]
        }
    }' "$LOG"
