#!/bin/sh
# False-alarm rate (and power) of `restir check` for a renderer that correlates pixels:
# ReSTIR PT with 1-3 spatial passes against the reference path tracer, one independent
# pair of `render --runs K` file sets per seed (docs/statistics.md, "Correlated renderers").
#   sh scripts/false-alarm.sh [OUT_DIR] [BUILD_DIR]
# Environment: SEEDS (default 40), SIZE (24), RUNS (K, 8), SCENE (scenes/cornell.scene),
# PT_SPP (64), RESTIR_ARGS (extra ReSTIR options, e.g. "--ablate jacobian" for power),
# THREADS (1), CHECK_ARGS (extra check options). Seed i renders ReSTIR with seeds 1000 i .. 1000 i + K - 1 and 1 + (i mod 3)
# spatial passes, and the path tracer with seeds 1000 i + 500 .. (independent of ReSTIR).
# Every pair is checked six ways: alpha 0.01 and 0.1, each with the per-run block means
# (what `render --runs` writes now) and check's default skew correction, with them and
# --no-skew-correction (plain Welch), and moments-only (the same file set without them, as
# before: the block tests then assume independent pixels). Prints one table row per
# configuration: rejections of the image-mean part, of the block part, and of the verdict,
# each with its Wilson 95% interval. Run it with `nice -n 10`; not part of `make test`.
set -eu
. "$(dirname "$0")/results/lib.sh"
results_init out/false-alarm "$@"
defaults SEEDS=40 SIZE=24 RUNS=8 SCENE=scenes/cornell.scene PT_SPP=64 THREADS=1
RESTIR_ARGS=${RESTIR_ARGS:-}
CHECK_ARGS=${CHECK_ARGS:-}
LOG="$OUT/checks.txt"
: > "$LOG"

# moments_only PREFIX OUT_PREFIX: the same file set without the per-run block means.
moments_only() {
    cp "$1.mean.pfm" "$2.mean.pfm"
    cp "$1.var.pfm" "$2.var.pfm"
    base=$(basename "$2")
    grep -v '"block_sizes"\|"block_means"' "$1.moments.json" |
        sed "s|\"mean\": \"[^\"]*\"|\"mean\": \"$base.mean.pfm\"|; s|\"var\": \"[^\"]*\"|\"var\": \"$base.var.pfm\"|" > "$2.moments.json"
}

i=1
while [ "$i" -le "$SEEDS" ]; do
    passes=$((1 + i % 3))
    seed=$((1000 * i))
    d="$OUT/seed$i"
    mkdir -p "$d"
    # The file sets are kept: a second run (e.g. with another check) renders nothing.
    # shellcheck disable=SC2086
    [ -f "$d/restir.moments.json" ] ||
        "$R" render "$SCENE" --method restir --spatial-passes "$passes" $RESTIR_ARGS --size "${SIZE}x${SIZE}" \
            --runs "$RUNS" --seed "$seed" --threads "$THREADS" --quiet --no-png -o "$d/restir.pfm"
    [ -f "$d/pt.moments.json" ] ||
        "$R" render "$SCENE" --method pt --spp "$PT_SPP" --size "${SIZE}x${SIZE}" --runs "$RUNS" \
            --seed $((seed + 500)) --threads "$THREADS" --quiet --no-png -o "$d/pt.pfm"
    moments_only "$d/restir" "$d/restir-old"
    moments_only "$d/pt" "$d/pt-old"
    for alpha in 0.01 0.1; do
        for kind in blocks plain old; do
            a="$d/restir" b="$d/pt" extra=""
            [ "$kind" = plain ] && extra="--no-skew-correction"
            [ "$kind" = old ] && a="$d/restir-old" b="$d/pt-old"
            status=0
            # shellcheck disable=SC2086
            "$R" check --a-moments "$a" --b-moments "$b" --alpha "$alpha" $extra $CHECK_ARGS --quiet --json "$OUT/check.json" \
                > /dev/null 2>&1 || status=$?
            [ "$status" -le 1 ] || [ "$status" = 3 ] || { echo "check failed (status $status) at seed $i" >&2; exit 2; }
            g=$(json_value "$OUT/check.json" image_mean reject)
            nb=$(json_value "$OUT/check.json" blocks rejected)
            z=$(json_value "$OUT/check.json" most_extreme z)
            echo "$i $passes $alpha $kind $g $nb $status $z" >> "$LOG"
        done
    done
    i=$((i + 1))
done

echo "# restir check on ReSTIR (spatial passes 1-3, $RESTIR_ARGS) vs PT ($PT_SPP spp), $(basename "$SCENE" .scene) ${SIZE}x${SIZE}, K = $RUNS, $SEEDS seeds"
echo "| alpha | block variances | image mean rejected | blocks rejected | verdict different | inconclusive (heavy tails, exit 3) | max |z| of a block (median) |"
echo "| --- | --- | --- | --- | --- | --- | --- |"
for alpha in 0.01 0.1; do
    for kind in blocks plain old; do
        awk -v alpha="$alpha" -v kind="$kind" '
            function wilson(k, n,   p, z, c, h) { z = 1.959964; p = k / n; c = (p + z * z / (2 * n)) / (1 + z * z / n)
                h = z * sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
                return sprintf("%d/%d = %.1f%% [%.1f, %.1f]", k, n, 100 * p, 100 * (c - h < 0 ? 0 : c - h), 100 * (c + h)) }
            $3 == alpha && $4 == kind { n++; g += ($5 == "true"); b += ($6 > 0); d += ($7 == 1); inc += ($7 == 3); zs[n] = ($8 < 0 ? -$8 : $8) }
            END { for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (zs[j] < zs[i]) { t = zs[i]; zs[i] = zs[j]; zs[j] = t }
                  med = n % 2 ? zs[(n + 1) / 2] : (zs[n / 2] + zs[n / 2 + 1]) / 2
                  printf "| %s | %s | %s | %s | %s | %s | %.2f |\n", alpha,
                      kind == "blocks" ? "per-run block means, skew-corrected (default)" : \
                      kind == "plain" ? "per-run block means, plain Welch" : "moments only (independent-pixel formula)",
                      wilson(g, n), wilson(b, n), wilson(d, n), wilson(inc, n), med }' "$LOG"
    done
done
