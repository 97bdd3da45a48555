#!/bin/sh
# Stochastic pairwise MIS against deterministic (defensive) pairwise MIS re-measured like for
# like (issue 28): the SAME domains for both (equal neighbour count M: a box window of
# (2 BOX + 1)^2 - 1 neighbours, GRIS Fig. 7's 7 x 7 at BOX = 3, and the Stochastic MIS §5.1
# reuse cells), at equal neighbour count and at equal CPU time, in the real-time pipeline the
# paper targets (gris-realtime: temporal Talbot, one spatial pass).
#   sh scripts/claims_stochastic.sh [OUT_DIR] [BUILD_DIR]
#
# Per scene in SCENES and window, SEEDS sequences 0..LAST with --threads 1 (CPU time =
# the run's cost, whatever the machine's load; run on an idle machine anyway):
#   det      --mis pairwise-defensive over the window (all M neighbours shifted);
#   sto-N    --mis stochastic-pairwise --stochastic-n N (N in NTILDE) over the same window,
#            confidences scaled (§4.3): equal neighbour count;
#   sto-N-t  the same with --candidates C, C the largest in CAL (1 2 4 ... 64) whose CPU time
#            per run (calibration: seed 99) does not exceed det's: equal CPU time (the time
#            saved by not shifting every neighbour buys initial candidates). The table shows
#            the CPU time ratio achieved: if C is the ladder's top, the budget was not reached.
#            The last column, relMSE x CPU time over det's per seed, is the efficiency ratio
#            (it assumes error ~ 1/time, exact for averages of independent frames only).
# Error: relMSE of frame LAST against a REF_SPP path-traced reference of that frame. Paired by
# seed (same initial candidates for det and sto at equal count): relMSE(sto) / relMSE(det) and
# CPU time(sto) / CPU time(det) per seed, mean ± 95% t half-width (restir stats mean-ci).
# Expected run time on 2 idle cores with the defaults: about 45 minutes, mostly on one core
# (measured at 64^2, 9 frames, one thread: defensive over the 7 x 7 box 0.88 CPU s on pillars,
# 1.21 s on cornell-glossy, over reuse cells 0.89 s, stochastic Ñ = 1 0.15 s; x16 at 256^2;
# 2 scenes x 2 windows x (det + 2 NTILDE x (equal count, calibration, equal time)) x 8 seeds,
# plus the two 4096-spp references). Smoke test (seconds):
#   SIZE=16 LAST=2 SEEDS="1 2" REF_SPP=16 NTILDE=1 SCENES=scenes/pillars.scene sh scripts/claims_stochastic.sh /tmp/st
set -eu
. "$(dirname "$0")/results/lib.sh"
. "$(dirname "$0")/results/claims_lib.sh"
results_init out/claims-stochastic "$@"
defaults SIZE=256 LAST=8 "SEEDS=1 2 3 4 5 6 7 8" REF_SPP=4096 "NTILDE=1 4" BOX=3 THREADS=2 "CAL=1 2 4 8 16 32 64" \
    "SCENES=scenes/pillars.scene scenes/cornell-glossy.scene"
CACHE="$OUT/ref"
mkdir -p "$TMP" "$CACHE"
PRESET="--preset gris-realtime"
WINDOWS="box:--pattern box --radius $BOX|cells:--reuse-cells"

# runs NAME SCENE REF OPTIONS...: SEEDS runs -> TMP/NAME.{rel,cpu,eff}, one line per seed
# (eff = relMSE x CPU seconds)
runs() {
    name=$1 scene=$2 ref=$3; shift 3
    : > "$TMP/$name.rel"; : > "$TMP/$name.cpu"
    for s in $SEEDS; do
        # shellcheck disable=SC2086
        cpu_sequence "$TMP/run" "$LAST" "$scene" $PRESET "$@" --size "${SIZE}x${SIZE}" --seed "$s" >> "$TMP/$name.cpu"
        metric_of "$TMP/run.pfm" "$ref.pfm" relmse >> "$TMP/$name.rel"
    done
    paste "$TMP/$name.rel" "$TMP/$name.cpu" | awk '{ print $1 * $2 }' > "$TMP/$name.eff"
}
# calibrate_candidates BUDGET_S SCENE OPTIONS...: the largest C in CAL whose run (seed 99)
# costs at most BUDGET_S CPU seconds (1 if none does)
calibrate_candidates() {
    budget=$1 scene=$2; shift 2
    best=1
    for c in $CAL; do
        # shellcheck disable=SC2086
        t=$(cpu_sequence "$TMP/cal" "$LAST" "$scene" $PRESET "$@" --candidates "$c" --size "${SIZE}x${SIZE}" --seed 99)
        if awk -v t="$t" -v b="$budget" 'BEGIN { exit !(t <= b) }'; then best=$c; else break; fi
    done
    echo "$best"
}

echo "## Stochastic vs defensive pairwise MIS, equal neighbour count and equal CPU time; ${SIZE}², frame $LAST, seeds $SEEDS"
echo
for scene in $SCENES; do
    sname=$(basename "$scene" .scene)
    ref=$(reference "$sname-f$LAST" "$SIZE" "$scene" pt "$REF_SPP" --frame "$LAST")
    echo "### $sname; reference $REF_SPP spp, its own relMSE $(ref_relmse "$ref")"
    echo
    echo "| window | configuration | candidates | relMSE | CPU s per run | relMSE / det's (paired) | CPU time / det's (paired) | relMSE × CPU time / det's (paired) |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
    old_ifs=$IFS; IFS='|'; set -- $WINDOWS; IFS=$old_ifs
    for w in "$@"; do
        wname=${w%%:*} wopts=${w#*:}
        det="$sname.$wname.det"
        # shellcheck disable=SC2086
        runs "$det" "$scene" "$ref" --mis pairwise-defensive $wopts
        budget=$(col_ci "$TMP/$det.cpu" | awk '{ print $1 }')
        echo "| $wname | defensive pairwise (all M) | 1 | $(col_ci "$TMP/$det.rel") | $(col_ci "$TMP/$det.cpu") | 1 | 1 | 1 |"
        for n in $NTILDE; do
            sto="$sname.$wname.sto$n"
            # shellcheck disable=SC2086
            runs "$sto" "$scene" "$ref" --mis stochastic-pairwise --stochastic-n "$n" $wopts
            echo "| $wname | stochastic Ñ = $n (equal count) | 1 | $(col_ci "$TMP/$sto.rel") | $(col_ci "$TMP/$sto.cpu") |" \
                "$(ratio_ci "$TMP/$sto.rel" "$TMP/$det.rel") | $(ratio_ci "$TMP/$sto.cpu" "$TMP/$det.cpu") | $(ratio_ci "$TMP/$sto.eff" "$TMP/$det.eff") |"
            # shellcheck disable=SC2086
            c=$(calibrate_candidates "$budget" "$scene" --mis stochastic-pairwise --stochastic-n "$n" $wopts)
            # shellcheck disable=SC2086
            runs "$sto.t" "$scene" "$ref" --mis stochastic-pairwise --stochastic-n "$n" --candidates "$c" $wopts
            echo "| $wname | stochastic Ñ = $n (equal CPU time) | $c | $(col_ci "$TMP/$sto.t.rel") | $(col_ci "$TMP/$sto.t.cpu") |" \
                "$(ratio_ci "$TMP/$sto.t.rel" "$TMP/$det.rel") | $(ratio_ci "$TMP/$sto.t.cpu" "$TMP/$det.cpu") | $(ratio_ci "$TMP/$sto.t.eff" "$TMP/$det.eff") |"
        done
    done
    echo
done
rm -f "$TMP"/run.* "$TMP"/cal.*
