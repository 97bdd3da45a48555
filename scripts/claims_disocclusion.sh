#!/bin/sh
# Stochastic MIS Fig. 1 (recovery after a disocclusion) re-measured as a PAIRED ratio (issue
# 28): the runs of every configuration share their seeds, so the error of configuration X on
# seed k is divided by the preset's on seed k and the ratios are averaged, instead of
# comparing two unpaired intervals that overlap.   sh scripts/claims_disocclusion.sh [OUT_DIR] [BUILD_DIR]
#
# The pillars pan (a disocclusion every frame), the real-time pipeline (gris-realtime preset:
# temporal Talbot cap 20, one spatial pass of 3 r2 neighbours in radius 20, pairwise-defensive)
# against the same pipeline with one stochastic pairwise pass over a reuse cell (Ñ = 1; Ñ = 4,
# Ñ_c = 2; confidences scaled, Stochastic MIS §4.3, §5), and the deterministic defensive pass
# over the same reuse cell (equal neighbour count). Frame LAST of K sequences per
# configuration, seeds 1..K. Error per run: nmse = sum (run - ref)^2 / sum ref^2 of luminance
# over the pixels whose temporal history is a frames old (`--aov age`, the same for every
# seed: it depends on the geometry only), against a REF_SPP path-traced reference of frame
# LAST. Reported per age bucket: each configuration's nmse (mean ± 95% t half-width over the
# runs) and its paired ratio to the preset's, nmse(X, k) / nmse(preset, k), mean ± 95% t
# half-width over k (restir stats mean-ci); a ratio interval that excludes 1 is a difference.
# Expected run time on 2 idle cores with the defaults: about 10 minutes (measured at 96^2 on one
# thread: 0.47 CPU s per 17-frame run, 0.30 s per 64 spp; here 4 configurations x 128 runs at
# 128^2 and the 32768-spp reference, THREADS = 2). Smoke test:
#   SIZE=16 LAST=3 K=3 REF_SPP=16 sh scripts/claims_disocclusion.sh /tmp/dis
set -eu
. "$(dirname "$0")/results/lib.sh"
. "$(dirname "$0")/results/claims_lib.sh"
results_init out/claims-disocclusion "$@"
defaults SIZE=128 K=128 LAST=16 REF_SPP=32768 THREADS=2 "AGES=0 1 2 3 4-16"
SCENE=scenes/pillars.scene
CACHE="$OUT/ref"
mkdir -p "$TMP" "$CACHE"
F=$(printf %04d "$LAST")
PRESET="--method restir --preset gris-realtime --sequence 0..$LAST"
CONFIGS="base det-cells sto1 sto4"
opts() {
    case $1 in
    base) echo "" ;;
    det-cells) echo "--mis pairwise-defensive --reuse-cells" ;;
    sto1) echo "--mis stochastic-pairwise --reuse-cells --stochastic-n 1" ;;
    sto4) echo "--mis stochastic-pairwise --reuse-cells --stochastic-n 4 --stochastic-nc 2" ;;
    esac
}
label() {
    case $1 in
    base) echo "r2 neighbours, defensive (preset)" ;;
    det-cells) echo "reuse cells, defensive (all M)" ;;
    sto1) echo "reuse cells, stochastic Ñ = 1" ;;
    sto4) echo "reuse cells, stochastic Ñ = 4, Ñ_c = 2" ;;
    esac
}
ref=$(reference "pillars-f$LAST" "$SIZE" "$SCENE" pt "$REF_SPP" --frame "$LAST") # lib.sh's render()
# from here on render() is the one sequence_runs.sh expects (scene and size fixed)
render() { "$R" render "$SCENE" "$@" --size "${SIZE}x${SIZE}" --threads "$THREADS" --quiet --no-png; }
AGE="$TMP/age.$F.pfm"
[ -f "$AGE" ] || render $PRESET --aov age -o "$TMP/age.pfm"
. "$(dirname "$0")/results/sequence_runs.sh"
# shellcheck disable=SC2046
for c in $CONFIGS; do sequence_runs "$c" $(opts "$c"); done

echo "## Recovery after a disocclusion, paired by seed (pillars ${SIZE}², frame $LAST, K = $K runs, reference $REF_SPP spp)"
echo
printf "| history age a |"; for c in $CONFIGS; do printf " %s: nmse |" "$(label "$c")"; done
for c in $CONFIGS; do [ "$c" = base ] || printf " %s / preset (paired) |" "$c"; done; echo
printf "| --- |"; for c in $CONFIGS; do printf " --- |"; done; for c in $CONFIGS; do [ "$c" = base ] || printf " --- |"; done; echo
for a in $AGES; do
    lo=${a%-*} hi=${a#*-}
    range="$(awk -v l="$lo" 'BEGIN { print l - 0.5 }'),$(awk -v h="$hi" 'BEGIN { print h + 0.5 }')"
    row="| $a |"
    for c in $CONFIGS; do
        : > "$TMP/$c.nmse"
        k=1
        while [ "$k" -le "$K" ]; do masked_nmse "$TMP/$c.$k.pfm" "$ref.pfm" "$AGE" "$range" >> "$TMP/$c.nmse"; k=$((k + 1)); done
        row="$row $(col_ci "$TMP/$c.nmse") |"
    done
    for c in $CONFIGS; do [ "$c" = base ] || row="$row $(ratio_ci "$TMP/$c.nmse" "$TMP/base.nmse") |"; done
    echo "$row"
done
