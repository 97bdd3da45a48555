#!/bin/sh
# Regenerates the temporal-reuse measurements of docs/results.md ("Temporal reuse: GRIS
# Fig. 9") with our own CLI: render --sequence --accumulate, compare, plot.
#   make results-temporal     (or: sh scripts/results_temporal.sh [OUT_DIR] [BUILD_DIR])
# Still camera on the Cornell box, SIZE x SIZE pixels; every point is the mean over SEEDS
# seeds with a 95% t interval (half-width, `restir stats mean-ci`). Not part of `make test`.
# As the paper labels them (GRIS §8.2, Fig. 9 caption):
#   (a) GRIS Fig. 9a: the error of frame T itself (per frame, NOT averaged) of the real-time
#       pipeline (gris-realtime preset) with temporal reuse vs T, for the confidence caps
#       1, 5, 20, 100, inf  -> fig9a.{csv,md,svg};
#       also the running average of those frames (not a panel of the paper; the cap's bias
#       shows there)  -> running-average.{csv,md,svg}, running-average-bias.md;
#   (b) GRIS Fig. 9b: averaging consecutive frames of the real-time pipeline (cap 20, purple
#       in the paper) vs the paper's offline method (blue): temporal reuse off and the offline
#       parameters of GRIS §8.3 (--preset gris-offline: 32 path trees, 3 passes of 6
#       neighbours in radius 10, pairwise-defensive MIS), at equal time (seconds from the
#       renders' own --stats)  -> fig9b.{csv,md,svg}. The offline curve runs the sequence
#       pipeline with --no-temporal --accumulate: frame f's file is bit-identical to
#       `render --preset gris-offline --frames f+1` (checked at 16^2, 4 frames).
# Expected run time on 2 idle cores with the defaults: about 25 minutes (5 seeds x (5 caps x
# 256 frames twice + 2 x 256 frames) at 32^2 plus the 16384-spp reference). Smoke test:
#   SIZE=8 FRAMES=4 SEEDS="1 2" REF_SPP=64 sh scripts/results_temporal.sh /tmp/t9
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

# sequence NAME PRESET OPTIONS...: FRAMES frames per seed -> $TMP/NAME.SEED.NNNN.pfm (each
# the average of frames 0..N with --accumulate in OPTIONS, else frame N alone), and
# $TMP/NAME.SEED.json (--stats); a seed whose --stats file is there is kept (the stats are
# written after the last frame), so an interrupted measurement resumes
sequence() {
    name=$1 preset=$2; shift 2
    for seed in $SEEDS; do
        [ -f "$TMP/$name.$seed.json" ] && continue
        render "$SCENE" --method restir --preset "$preset" --sequence 0..$((FRAMES - 1)) \
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

# table NAME PREFIX TITLE YLABEL: for every cap, METRIC relmse of $TMP/PREFIX<cap> at the frame
# points -> $OUT/NAME.{csv,md,svg}
table() {
    name=$1 prefix=$2 title=$3 ylabel=$4
    csv="$OUT/$name.csv" md="$OUT/$name.md"
    { printf "frames"; for c in $CAPS; do printf ",cap %s" "$c"; done; echo; } > "$csv.tmp"
    { printf "| frame T |"; for c in $CAPS; do printf " cap %s |" "$c"; done; echo
      printf "| --- |"; for c in $CAPS; do printf " --- |"; done; echo; } > "$md.tmp"
    for t in $FRAME_POINTS; do
        row="$t"; mrow="| $t |"
        for c in $CAPS; do
            set -- $(metric_at "$prefix$c" "$t" relmse)
            row="$row,$1"; mrow="$mrow $1 ± $2 |"
        done
        echo "$row" >> "$csv.tmp"; echo "$mrow" >> "$md.tmp"
    done
    mv "$csv.tmp" "$csv"; mv "$md.tmp" "$md"
    "$R" plot "$csv" -o "$OUT/$name.svg" --title "$title" --xlabel "frame" --ylabel "$ylabel"
}

# ---- (a) GRIS Fig. 9a: the error of each frame ---------------------------------------------
CAPS="1 5 20 100 inf"
for c in $CAPS; do sequence "frame-cap$c" gris-realtime --mcap "$c"; done
table fig9a frame-cap "GRIS Fig. 9a: error of frame T, temporal reuse, still camera, cornell ${SIZE}^2" \
    "relMSE of frame T"
# steady state, paired by seed (the caps share their seeds): per seed the mean per-frame relMSE
# over frames STEADY..FRAMES-1 (every STRIDE-th), and its ratio to cap 20's on the same seed
defaults STEADY=$((FRAMES / 4)) STRIDE=8
steady_mean() {
    for seed in $SEEDS; do
        f=$STEADY
        while [ "$f" -lt "$FRAMES" ]; do metric relmse "$TMP/$1.$seed.$(printf %04d "$f").pfm" "$REF"; f=$((f + STRIDE)); done |
            awk '{ s += $1 } END { print s / NR }'
    done
}
for c in $CAPS; do steady_mean "frame-cap$c" > "$TMP/steady.cap$c"; done
{ echo "| cap | mean per-frame relMSE, frames $STEADY..$((FRAMES - 1)) (every $STRIDE-th) | / cap 20's (paired by seed) |"
  echo "| --- | --- | --- |"
  for c in $CAPS; do
      echo "| $c | $(mean_ci < "$TMP/steady.cap$c") | $(paste "$TMP/steady.cap$c" "$TMP/steady.cap20" | awk '{ print $1 / $2 }' | mean_ci) |"
  done; } > "$OUT/fig9a-steady.md"

# ---- the running average of the same pipeline (not a panel of the paper) --------------------
for c in $CAPS; do sequence "avg-cap$c" gris-realtime --mcap "$c" --accumulate; done
table running-average avg-cap "running average of T real-time frames (not a GRIS panel), cornell ${SIZE}^2" \
    "relMSE of the average"
# the bias of the long average (rel_bias: mean(test - ref) / mean(ref), docs/metrics.md)
{ echo "| cap | relMSE after $FRAMES frames | rel_bias after $FRAMES frames |"; echo "| --- | --- | --- |"
  for c in $CAPS; do
      set -- $(metric_at "avg-cap$c" "$FRAMES" relmse); e="$1 ± $2"
      set -- $(metric_at "avg-cap$c" "$FRAMES" rel_bias); echo "| $c | $e | $1 ± $2 |"
  done; } > "$OUT/running-average-bias.md"

# ---- (b) GRIS Fig. 9b: averaging real-time frames vs the offline method, equal time ---------
sequence offline gris-offline --no-temporal --accumulate
temporal=avg-cap20
csv="$OUT/fig9b.csv"
md="$OUT/fig9b.md"
st=$(seconds_per_frame $temporal)
so=$(seconds_per_frame offline)
echo "seconds,real-time with temporal reuse (cap 20) averaged,offline (GRIS 8.3: no temporal reuse)" > "$csv.tmp"
{ echo "| frames | seconds (real-time) | relMSE real-time averaged | seconds (offline) | relMSE offline |"
  echo "| --- | --- | --- | --- | --- |"; } > "$md.tmp"
for t in $FRAME_POINTS; do
    set -- $(metric_at $temporal "$t" relmse); et=$1; ht=$2
    set -- $(metric_at offline "$t" relmse); eo=$1; ho=$2
    xt=$(awk -v a="$st" -v t="$t" 'BEGIN { printf "%.4g", a * t }')
    xo=$(awk -v a="$so" -v t="$t" 'BEGIN { printf "%.4g", a * t }')
    echo "$xt,$et," >> "$csv.tmp"
    echo "$xo,,$eo" >> "$csv.tmp"
    echo "| $t | $xt | $et ± $ht | $xo | $eo ± $ho |" >> "$md.tmp"
done
mv "$csv.tmp" "$csv"; mv "$md.tmp" "$md"
# equal time, paired by seed: relMSE x seconds of the real-time average of FRAMES frames over
# the offline average's of FRAMES/16 frames (about the same time) and of FRAMES frames (the
# offline run's seconds scaled by the frame share; each run's own --stats seconds)
: > "$TMP/eff.rt"; : > "$TMP/eff.off16"; : > "$TMP/eff.off"
n16=$((FRAMES / 16 > 0 ? FRAMES / 16 : 1))
for seed in $SEEDS; do
    trt=$(render_seconds "$TMP/$temporal.$seed.json"); tof=$(render_seconds "$TMP/offline.$seed.json")
    last=$(printf %04d $((FRAMES - 1))); l16=$(printf %04d $((n16 - 1)))
    awk -v e="$(metric relmse "$TMP/$temporal.$seed.$last.pfm" "$REF")" -v t="$trt" 'BEGIN { print e * t }' >> "$TMP/eff.rt"
    awk -v e="$(metric relmse "$TMP/offline.$seed.$l16.pfm" "$REF")" -v t="$tof" -v s="$n16" -v f="$FRAMES" 'BEGIN { print e * t * s / f }' >> "$TMP/eff.off16"
    awk -v e="$(metric relmse "$TMP/offline.$seed.$last.pfm" "$REF")" -v t="$tof" 'BEGIN { print e * t }' >> "$TMP/eff.off"
done
{ echo "| quantity (relMSE × seconds: lower is better at equal time) | mean ± 95% half-width over seeds |"
  echo "| --- | --- |"
  echo "| real-time cap 20, average of $FRAMES frames | $(mean_ci < "$TMP/eff.rt") |"
  echo "| offline, average of $n16 frames | $(mean_ci < "$TMP/eff.off16") |"
  echo "| offline, average of $FRAMES frames | $(mean_ci < "$TMP/eff.off") |"
  echo "| real-time ($FRAMES) / offline ($n16), paired by seed | $(paste "$TMP/eff.rt" "$TMP/eff.off16" | awk '{ print $1 / $2 }' | mean_ci) |"
  echo "| real-time ($FRAMES) / offline ($FRAMES), paired by seed | $(paste "$TMP/eff.rt" "$TMP/eff.off" | awk '{ print $1 / $2 }' | mean_ci) |"
} > "$OUT/fig9b-equal-time.md"
"$R" plot "$csv" -o "$OUT/fig9b.svg" --title "GRIS Fig. 9b: averaging frames at equal time, cornell ${SIZE}^2" \
    --xlabel "seconds" --ylabel "relMSE"
echo "wrote $OUT/fig9a.{csv,md,svg} fig9a-steady.md fig9b-equal-time.md running-average.{csv,md,svg} running-average-bias.md fig9b.{csv,md,svg}"
