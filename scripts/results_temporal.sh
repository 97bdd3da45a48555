#!/bin/sh
# Regenerates the temporal-reuse measurements of docs/results.md ("Temporal reuse: GRIS
# Fig. 9") with our own CLI: render --sequence --accumulate, compare, plot.
#   make results-temporal     (or: sh scripts/results_temporal.sh [OUT_DIR] [BUILD_DIR])
# Still camera on the Cornell box, SIZE x SIZE pixels, the gris-realtime preset; every point
# is the mean over SEEDS seeds with a 95% t interval (half-width). Not part of `make test`.
#   (a) GRIS Fig. 9a: relMSE of the running average of T real-time frames vs T, for the
#       confidence caps 1, 5, 20, 100, inf;
#   (b) GRIS Fig. 9b: the running average of real-time frames (cap 20) vs the average of
#       independent frames of the same pipeline without temporal reuse (GRIS §6.5), at
#       equal time (seconds from the renders' own --stats).
set -eu
. "$(dirname "$0")/results/lib.sh"
results_init out/results-temporal "$@"
defaults SIZE=32 THREADS=2 REF_SPP=16384 FRAMES=256 "SEEDS=1 2 3 4 5" SCENE=scenes/cornell.scene
mkdir -p "$TMP"

render() { "$R" render "$@" --size "${SIZE}x${SIZE}" --threads "$THREADS" --quiet --no-png; }
FRAME_POINTS=""
t=1
while [ "$t" -le "$FRAMES" ]; do FRAME_POINTS="$FRAME_POINTS $t"; t=$((t * 2)); done

REF="$TMP/ref.pfm"
[ -f "$REF" ] || render "$SCENE" --method pt --spp "$REF_SPP" --seed 9001 -o "$REF"

# sequence NAME OPTIONS...: FRAMES accumulated frames per seed -> $TMP/NAME.SEED.NNNN.pfm,
# and $TMP/NAME.SEED.json (--stats)
sequence() {
    name=$1; shift
    for seed in $SEEDS; do
        render "$SCENE" --method restir --preset gris-realtime --sequence 0..$((FRAMES - 1)) --accumulate \
            --seed "$seed" "$@" -o "$TMP/$name.$seed.pfm" --stats "$TMP/$name.$seed.json"
    done
}
# relmse_at NAME T METRIC: "mean halfwidth" over seeds of METRIC of the T-frame average
metric_at() {
    for seed in $SEEDS; do metric "$3" "$TMP/$1.$seed.$(printf %04d $(($2 - 1))).pfm" "$REF"; done | mean_ci "%.6g %.3g"
}
seconds_per_frame() {
    for seed in $SEEDS; do grep -o '"render": [0-9.e+-]*' "$TMP/$1.$seed.json" | awk -v f="$FRAMES" '{ print $2 / f }'; done |
        mean_ci "%.6g %.3g" | awk '{ print $1 }'
}

# ---- (a) GRIS Fig. 9a -------------------------------------------------------------------------
CAPS="1 5 20 100 inf"
for c in $CAPS; do sequence "cap$c" --mcap "$c"; done
csv="$OUT/fig9a.csv"
md="$OUT/fig9a.md"
{ printf "frames"; for c in $CAPS; do printf ",cap %s" "$c"; done; echo; } > "$csv.tmp"
{ printf "| frames |"; for c in $CAPS; do printf " cap %s |" "$c"; done; echo
  printf "| --- |"; for c in $CAPS; do printf " --- |"; done; echo; } > "$md.tmp"
for t in $FRAME_POINTS; do
    row="$t"; mrow="| $t |"
    for c in $CAPS; do
        set -- $(metric_at "cap$c" "$t" relmse)
        row="$row,$1"; mrow="$mrow $1 ± $2 |"
    done
    echo "$row" >> "$csv.tmp"; echo "$mrow" >> "$md.tmp"
done
mv "$csv.tmp" "$csv"; mv "$md.tmp" "$md"
"$R" plot "$csv" -o "$OUT/fig9a.svg" --title "GRIS Fig. 9a: still camera, running average, cornell ${SIZE}^2" \
    --xlabel "frames averaged" --ylabel "relMSE"

# the bias of the long average (rel_bias: mean(test - ref) / mean(ref), docs/metrics.md)
{ echo "| cap | relMSE after $FRAMES frames | rel_bias after $FRAMES frames |"; echo "| --- | --- | --- |"
  for c in $CAPS; do
      set -- $(metric_at "cap$c" "$FRAMES" relmse); e="$1 ± $2"
      set -- $(metric_at "cap$c" "$FRAMES" rel_bias); echo "| $c | $e | $1 ± $2 |"
  done; } > "$OUT/fig9a-bias.md"

# ---- (b) GRIS Fig. 9b -------------------------------------------------------------------------
sequence independent --no-temporal
sequence temporal --mcap 20
csv="$OUT/fig9b.csv"
md="$OUT/fig9b.md"
st=$(seconds_per_frame temporal)
si=$(seconds_per_frame independent)
echo "seconds,real-time (temporal cap 20),independent frames" > "$csv.tmp"
{ echo "| frames | seconds (temporal) | relMSE temporal | seconds (independent) | relMSE independent |"
  echo "| --- | --- | --- | --- | --- |"; } > "$md.tmp"
for t in $FRAME_POINTS; do
    set -- $(metric_at temporal "$t" relmse); et=$1; ht=$2
    set -- $(metric_at independent "$t" relmse); ei=$1; hi=$2
    xt=$(awk -v a="$st" -v t="$t" 'BEGIN { printf "%.4g", a * t }')
    xi=$(awk -v a="$si" -v t="$t" 'BEGIN { printf "%.4g", a * t }')
    echo "$xt,$et," >> "$csv.tmp"
    echo "$xi,,$ei" >> "$csv.tmp"
    echo "| $t | $xt | $et ± $ht | $xi | $ei ± $hi |" >> "$md.tmp"
done
mv "$csv.tmp" "$csv"; mv "$md.tmp" "$md"
"$R" plot "$csv" -o "$OUT/fig9b.svg" --title "GRIS Fig. 9b: equal time, cornell ${SIZE}^2" \
    --xlabel "seconds" --ylabel "relMSE"
echo "wrote $OUT/fig9a.{csv,md,svg} fig9a-bias.md fig9b.{csv,md,svg}"
