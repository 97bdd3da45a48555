#!/bin/sh
# ReSTIR PT Enhanced measured on our scenes (docs/results.md, "ReSTIR PT Enhanced"): Table 1
# in spirit, the paired pass against the disk pass, the footprint criterion on a near and a
# far view, and equal-time error of the GRIS baseline against Enhanced. Every number is the
# mean over seeds with a 95% t interval (half-width). Not part of `make test`.
#   sh scripts/results_enhanced.sh [OUT_DIR] [BUILD_DIR]
# PART selects one part (default all; about an hour on a shared 2-core machine, most of it the
# path-traced references, which are cached in OUT_DIR/ref):
#   table1rt   Table 1 in CPU time: ms per stage of the real-time pipeline (gris-realtime) at
#              SIZE² as the features are switched on in turn; LIGHT_RIS / EXTRA_ROWS add rows
#   table1     (only when asked for) the same for one offline frame, wall-clock stage timers (THREADS; superseded by
#              table1rt: under load its intervals cover the differences between rows)
#   pairs      the paired pass against the disk pass: CPU milliseconds per spatial pass
#              (process user + system time of a K-pass render minus the same render with 0
#              passes, so the reuse-texture build and everything but the passes cancel;
#              --threads 1, so CPU time is the pass's cost whatever the machine's load), and
#              the shifts per pixel and pass from --stats
#   footprint  the footprint criterion against GRIS thresholds on scenes/hall (near) and
#              hall-far at equal CPU time: error and reconnection rates
#   equaltime  equal-time MAPE, relMSE and HDR-FLIP of GRIS against Enhanced on every scene
#   fpsummary, etsummary  only the paired-by-seed ratio tables, from the rows of earlier runs
#   control    (only when asked for) the paired ratios with a deliberately broken estimator
#              (--ablate) against the correct one: do they see it?
# Differences from the paper's Table 1: CPU, not GPU; no replay compaction, code micro-
# optimisation or Russian-roulette rows (not separate features here), no light-RIS row yet.
# LIGHT RIS (after merging the light-RIS branch): the row is ready, not yet run:
#   PART=table1rt TABLE1_SCENES="scenes/many-lights.scene scenes/cornell-glossy.scene" \
#       LIGHT_RIS="--light-ris 32 --light-tiles" sh scripts/results_enhanced.sh
# adds "+ light RIS (§6.1)" on top of the last row; ENH_EXTRA="--light-ris 32 --light-tiles"
# adds it to the Enhanced configuration of PART=equaltime (ET_SCENES to add the scene).
set -eu
. "$(dirname "$0")/results/lib.sh"
results_init out/results-enhanced "$@"
defaults SIZE=256 THREADS=2 "SEEDS=1 2 3" SCENES=scenes/cornell-glossy.scene PART=all

# mean_fixed [DECIMALS]: mean_ci (lib.sh) with DECIMALS (default 1) after the point
mean_fixed() { mean_ci "%.${1:-1}f ± %.${1:-1}f"; }
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

if [ "$PART" = table1 ]; then # not in "all"
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
        for c in 1 2 3 4; do cols="$cols | $(awk -v c=$c '{ print $c }' "$OUT/$name.rows" | mean_fixed)"; done
        total=$(awk '{ print $1 + $2 + $3 + $4 }' "$OUT/$name.rows" | mean_fixed)
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
                echo "| $nb | $1 | $(awk -v c="$2" '{ print $c }' "$OUT/pairs.rows" | mean_fixed) |" \
                    "$(awk -v c="$3" '{ s += $c } END { printf "%.2f", s / NR }' "$OUT/pairs.rows") |" \
                    "$(awk -v c="$4" '{ print $c }' "$OUT/pairs.rows" | mean_fixed 2) |"
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


# ---- shared by the PARTs below (table1rt, footprint, equaltime) --------------------------
# Timed renders run with --threads 1 and are charged their process CPU time (user + system,
# /usr/bin/time): the machine is shared, so wall clock would measure the other jobs.
ESIZE=${ESIZE:-128}       # image size of the error measurements (Table 1 asks 256²)
BUDGET=${BUDGET:-2}       # CPU seconds per error render
ESEEDS=${ESEEDS:-1 2 3 4 5}
REF_SPP=${REF_SPP:-4096}  # path-traced references: scripts/results_enhanced_ref.sh
REF_THREADS=${REF_THREADS:-2}
# Offline ReSTIR PT of the error PARTs: the mean of independent frames (GRIS Eq. 47), one path
# tree per frame, 3 spatial passes of 3 neighbours in radius 10, pairwise-defensive, hybrid.
EBASE="--method restir --candidates 1 --spatial-passes 3 --neighbors 3 --radius 10 --mis pairwise-defensive --shift hybrid"
# The Enhanced configuration (there is no Enhanced preset): paired spatial reuse with the pair
# step, the footprint criterion, vector shading, forced NEE reconnection; ENH_EXTRA is added
# to it (the coordinator: ENH_EXTRA="--light-ris 32 --light-tiles" once light RIS is merged).
ENH="--rc-criterion footprint --pairing paired --shading vector --force-nee-reconnection ${ENH_EXTRA:-}"

# cpu_run PFM JSON SCENE OPTS...: one render on 1 thread; prints its CPU seconds (the time
# file is per PART, so that PARTs can run at once into one OUT_DIR)
TF=$OUT/t.$PART.txt
cpu_run() {
    o=$1; j=$2; shift 2
    # shellcheck disable=SC2086
    /usr/bin/time -f "%U %S %e" -o "$TF" "$R" render "$@" --threads 1 --quiet --no-png -o "$o" --stats "$j" >/dev/null
    awk '{ printf "%.3f", $1 + $2 }' "$TF"
}
# frames_for SCENE OPTS...: "N MS": N frames cost BUDGET CPU seconds at MS CPU ms per frame, the
# marginal cost of a frame from 1 and 3 frames of seed 99. One-time costs (scene load, BVH, the
# reuse textures of --pairing paired, which a real-time renderer precomputes) are not charged.
frames_for() {
    t1=$(cpu_run "$OUT/c.pfm" "$OUT/c.json" "$@" --seed 99 --frames 1)
    t3=$(cpu_run "$OUT/c.pfm" "$OUT/c.json" "$@" --seed 99 --frames 3)
    awk -v a="$t1" -v b="$t3" -v B="$BUDGET" 'BEGIN { f = (b - a) / 2; if (f < 0.005) f = b / 3; if (f < 0.005) f = 0.005
        n = int(B / f + 0.5); printf "%d %.0f\n", (n < 1 ? 1 : n), 1000 * f }'
}
# metric TEST REF NAME: one line of `restir compare` (mape, relmse, flip_hdr, ...)
metric() { "$R" compare "$1" "$2" | awk -v k="$3" '$1 == k { print $2 }'; }
# rc_stats JSON: share of the selected initial samples reconnecting at k = 2, share with no
# reconnection vertex, mean k of the reconnecting ones, share of the spatial shifts refused by
# the offset path's criterion (rc_earlier + rc_prev + rc_roughness + rc_distance + rc_footprint)
rc_stats() {
    tr -d '\n' <"$1" | awk 'function num(s, key,   r) {
            if (!match(s, "\"" key "\": [-0-9.e+]+")) return 0
            r = substr(s, RSTART, RLENGTH); sub(/.*: /, "", r); return r + 0 }
        { ini = substr($0, index($0, "\"initial\": {\"pixels\""))
          sel = num(ini, "selected")
          match(ini, /"selected_by_reconnection_index": \[[0-9, ]*\]/)
          a = substr(ini, RSTART, RLENGTH); sub(/.*\[/, "", a); sub(/\].*/, "", a); n = split(a, idx, /, */)
          rec = 0; sk = 0; for (j = 3; j <= n; ++j) { rec += idx[j]; sk += (j - 1) * idx[j] } # idx[1]: none, idx[3]: k = 2
          sp = substr($0, index($0, "\"spatial\": {\"passes\""))
          so = substr(sp, index(sp, "\"shift_outcomes\"")); so = substr(so, 1, index(so, "}"))
          sh = num(sp, "shifts")
          rc = num(so, "rc_earlier") + num(so, "rc_prev") + num(so, "rc_roughness") + num(so, "rc_distance") + num(so, "rc_footprint")
          printf "%.4f %.4f %.3f %.4f\n", idx[3] / sel, idx[1] / sel, (rec > 0 ? sk / rec : 0), (sh > 0 ? rc / sh : 0) }'
}
col() { awk -v c="$1" '{ print $c }' "$2" | mean_fixed "${3:-4}"; }

# ---- Table 1 in CPU time: the real-time pipeline, per stage (Enhanced Table 1) -----------
# --preset gris-realtime (1 path tree, temporal reuse with cap 20, 1 spatial pass of 3
# neighbours in radius 20), a still camera, SIZE², --threads 1. Per seed two runs, frame 0 alone
# and frames 0..RT_FRAMES-1; their difference / (RT_FRAMES - 1) is the cost of one frame with
# temporal history, without one-time costs (scene load, BVH, the reuse textures). The stage
# timers of src/frame/pipeline.c are wall clock (CLOCK_MONOTONIC); each run's stage times are
# scaled by the run's CPU time / wall time (under load the other jobs stretch all stages alike
# on one thread), so the columns are CPU ms per frame; "frame" is the process CPU time per
# frame and "shade and other" the frame minus the other columns (shading, motion vectors, the
# copy of the reservoirs for the next frame, --stats counting). "duplication statistics" is
# the duplication map of every frame (docs/correlation.md; --stats "correlation"), which only
# --dedup uses: a diagnostic the paper's pipeline does not have. Rows: set -- below; LIGHT_RIS (e.g. "--light-ris 32
# --light-tiles", after merging lightris; with TABLE1_SCENES=the many-lights scene) adds the
# light-RIS row on top of the last one, and EXTRA_ROWS adds rows "label|options" (one a line).
if [ "$PART" = all ] || [ "$PART" = table1rt ]; then
    RT_FRAMES=${RT_FRAMES:-8}
    ALL_ENH="--rc-criterion footprint --pairing paired --shading vector --force-nee-reconnection"
    ROWS="GRIS baseline (gris-realtime: disk, gris criterion, scalar)|
+ footprint criterion (§4)|--rc-criterion footprint
+ paired neighbours (§3, pattern only)|--rc-criterion footprint --pairing paired --no-pair-step
+ pair step (§3, 2 shifts per pair)|--rc-criterion footprint --pairing paired
+ vector shading (§6.3)|--rc-criterion footprint --pairing paired --shading vector
+ forced NEE reconnection (§6.2.3)|$ALL_ENH"
    [ -z "${LIGHT_RIS:-}" ] || ROWS="$ROWS
+ light RIS (§6.1)|$ALL_ENH $LIGHT_RIS"
    [ -z "${EXTRA_ROWS:-}" ] || ROWS="$ROWS
$EXTRA_ROWS"
    for scene in ${TABLE1_SCENES:-scenes/cornell-glossy.scene scenes/hall.scene}; do
        name=$(basename "$scene" .scene)
        echo "#### $name, ${SIZE}², gris-realtime, frames 0..$((RT_FRAMES - 1)), threads 1, seeds $SEEDS (CPU ms per frame)"
        echo
        echo "| configuration | G-buffer | initial | temporal | spatial | duplication statistics | shade and other | frame | ratio to baseline |"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
        base_total=""
        echo "$ROWS" | while IFS='|' read -r label opts; do
            : >"$OUT/rt.rows"
            for s in $SEEDS; do
                # per seed: frame 0 alone and frames 0..F-1; their difference is frames 1..F-1 (all
                # with temporal history), without the one-time costs (load, BVH, reuse textures)
                for last in 0 $((RT_FRAMES - 1)); do
                    # shellcheck disable=SC2086
                    cpu_run "$OUT/rt.pfm" "$OUT/rt.json" "$scene" --method restir --preset gris-realtime $opts --seed "$s" \
                        --size "${SIZE}x${SIZE}" --sequence "0..$last" >/dev/null
                    # the sequence's stage times (the first "milliseconds" object) scaled by CPU / wall, and the CPU ms
                    tr -d '\n' <"$OUT/rt.json" | awk -v tf="$TF" 'function num(s, key,   r) {
                            if (!match(s, "\"" key "\": \\[?[-0-9.e+]+")) return 0
                            r = substr(s, RSTART, RLENGTH); sub(/.*: \[?/, "", r); return r + 0 }
                        { getline tl <tf; split(tl, t, " "); c = 1000 * (t[1] + t[2]); k = (t[3] > 0 ? c / (1000 * t[3]) : 1)
                          ms = substr($0, index($0, "\"milliseconds\": {")); ms = substr(ms, 1, index(ms, "}"))
                          co = substr($0, index($0, "\"correlation\": {")); co = substr(co, 1, index(co, "}"))
                          printf "%.3f %.3f %.3f %.3f %.3f %.3f ", k * num(ms, "gbuffer"), k * num(ms, "initial"),
                              k * num(ms, "temporal"), k * num(ms, "spatial"), k * num(co, "milliseconds"), c }'
                done | awk -v F="$RT_FRAMES" '{ n = F - 1
                    g = ($7 - $1) / n; i = ($8 - $2) / n; tp = ($9 - $3) / n; sp = ($10 - $4) / n; co = ($11 - $5) / n
                    f = ($12 - $6) / n
                    printf "%.3f %.3f %.3f %.3f %.3f %.3f %.3f\n", g, i, tp, sp, co, f - g - i - tp - sp - co, f }' >>"$OUT/rt.rows"
            done
            mean_total=$(awk '{ s += $7 } END { print s / NR }' "$OUT/rt.rows")
            [ -n "$base_total" ] || base_total=$mean_total
            ratio=$(awk -v a="$mean_total" -v b="$base_total" 'BEGIN { printf "%.2f", a / b }')
            echo "| $label | $(col 1 "$OUT/rt.rows" 1) | $(col 2 "$OUT/rt.rows" 1) | $(col 3 "$OUT/rt.rows" 1) |" \
                "$(col 4 "$OUT/rt.rows" 1) | $(col 5 "$OUT/rt.rows" 1) | $(col 6 "$OUT/rt.rows" 1) | $(col 7 "$OUT/rt.rows" 1) | $ratio |"
        done
        echo
    done
    rm -f "$OUT/rt.rows" "$OUT/rt.pfm" "$OUT/rt.json"
fi

# ---- the footprint criterion on a near and a far view (Enhanced Figs. 10-12 in spirit) ----
# scenes/hall.scene (near: the floor 5 m ahead, fov 60) and scenes/hall-far.scene (far: the same
# stretch of floor 30 m ahead, fov 12): a 60 m hall with a glossy conductor floor (GGX α ≈ 0.2),
# so the GRIS d_min = 0.02 × diagonal is 1.2 m in both views while the primary footprint (and
# the spread of the neighbours' primary hits) differs by (30/5)². Equal CPU time: per view and
# setting, the frame count whose CPU time is BUDGET (frames_for, seed 99), then ESEEDS renders
# of that many frames; ESIZE², EBASE. MAPE / relMSE against REF_SPP path-traced references whose
# own error is printed below the table. Reconnection rates are from each render's --stats
# (initial samples: k = 2 share, no reconnection, mean k; spatial shifts refused by the offset's
# criterion). GRIS settings: d_min in FP_DMIN (fractions of the diagonal; 0.02 is our default;
# 0.0013 x 60.4 m = 8 cm is the paper's rule, 2 % of the shortest scene dimension, 4 m),
# footprint: c in FP_C (0.02 is the paper's).
FP_VIEWS=${FP_VIEWS:-hall hall-far} # near view first; hall-glossy hall-glossy-far: the floor at roughness 0.15
if [ "$PART" = all ] || [ "$PART" = footprint ]; then
    # shellcheck disable=SC2046
    sh scripts/results_enhanced_ref.sh "$OUT" "$R" "$ESIZE" "$REF_SPP" "$REF_THREADS" $(printf 'scenes/%s.scene ' $FP_VIEWS)
    echo "#### $FP_VIEWS, ${ESIZE}², $BUDGET CPU s per render (--threads 1), seeds $ESEEDS"
    echo
    echo "| view | criterion | frames | CPU ms per frame | CPU s | MAPE | relMSE | k = 2 | no rc vertex | mean k | shifts refused by the criterion |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    : >"$OUT/fp.best"
    for view in $FP_VIEWS; do
        scene=scenes/$view.scene
        settings=""
        for d in ${FP_DMIN:-0.0013 0.005 0.02 0.08}; do settings="$settings gris:$d"; done
        for c in ${FP_C:-0.005 0.02 0.08}; do settings="$settings footprint:$c"; done
        for st in $settings; do
            crit=${st%%:*}; v=${st#*:}
            if [ "$crit" = gris ]; then opts="--rc-criterion gris --distance-threshold $v"; label="gris, d_min $v"
            else opts="--rc-criterion footprint --footprint-c $v"; label="footprint, c = $v"; fi
            # shellcheck disable=SC2086
            set -- $(frames_for "$scene" $EBASE $opts --size "${ESIZE}x${ESIZE}"); T=$1; F=$2
            : >"$OUT/fp.rows"
            for s in $ESEEDS; do
                # shellcheck disable=SC2086
                t=$(cpu_run "$OUT/fp.pfm" "$OUT/fp.json" "$scene" $EBASE $opts --size "${ESIZE}x${ESIZE}" --seed "$s" --frames "$T")
                "$R" compare "$OUT/fp.pfm" "$OUT/ref/$view.pfm" >"$OUT/fp.cmp"
                echo "$t $(awk '$1 == "mape" { m = $2 } $1 == "relmse" { r = $2 } END { print m, r }' "$OUT/fp.cmp")" \
                    "$(rc_stats "$OUT/fp.json") $T $F" >>"$OUT/fp.rows" # cpu, mape, relmse, k2, none, mean k, refused, frames, ms

            done
            echo "| $view | $label | $T | $F | $(col 1 "$OUT/fp.rows" 2) | $(col 2 "$OUT/fp.rows") | $(col 3 "$OUT/fp.rows") |" \
                "$(col 4 "$OUT/fp.rows" 3) | $(col 5 "$OUT/fp.rows" 3) | $(col 6 "$OUT/fp.rows" 2) | $(col 7 "$OUT/fp.rows" 3) |"
            awk -v v="$view" -v l="$label" '{ m += $2; r += $3 } END { print v "|" l "|" m / NR "|" r / NR }' "$OUT/fp.rows" >>"$OUT/fp.best"
            cp "$OUT/fp.rows" "$OUT/fp.$view.$crit-$v.rows"
        done
    done
    echo
    for view in $FP_VIEWS; do
        awk -v v="$view" '{ printf "%s: reference %d spp, its own relMSE %.2g, MAPE %.3g (from its two halves)\n", v, $3, $1, $2 }' \
            "$OUT/ref/$view.self"
    done
    echo
    # the best setting of each family per view (by mean relMSE, then by mean MAPE)
    for m in 4 3; do
        [ "$m" = 4 ] && mn=relMSE || mn=MAPE
        for view in $FP_VIEWS; do
            for fam in gris footprint; do
                awk -F'|' -v v="$view" -v f="$fam" -v c="$m" '$1 == v && index($2, f) == 1 && (b == "" || $c < bv) { b = $2; bv = $c }
                    END { printf "best %s by mean %s in %s: %s (%.4g)\n", f, "'"$mn"'", v, b, bv }' "$OUT/fp.best"
            done
        done
    done
    echo
    rm -f "$OUT/fp.rows" "$OUT/fp.cmp" "$OUT/fp.pfm" "$OUT/fp.json" "$OUT/c.pfm" "$OUT/c.json"
fi
# PART=footprint (or fpsummary, from the rows a footprint run left in OUT_DIR): each setting's
# error divided by the GRIS default's (d_min 0.02) on the same seed, mean ± 95 % t half-width.
# The seeds address the same initial candidates under every setting, so the ratio cancels
# most of the noise the unpaired columns above carry.
if [ "$PART" = all ] || [ "$PART" = footprint ] || [ "$PART" = fpsummary ]; then
    echo "| view | criterion | MAPE / default's (per seed) | relMSE / default's | MAPE × √time / default's | relMSE × time / default's |"
    echo "| --- | --- | --- | --- | --- | --- |"
    for view in $FP_VIEWS; do
        for f in "$OUT"/fp."$view".*.rows; do
            [ -f "$f" ] || continue
            st=${f#"$OUT/fp.$view."}; st=${st%.rows}; crit=${st%%-*}; v=${st#*-}
            [ "$crit" = gris ] && label="gris, d_min $v" || label="footprint, c = $v"
            # time = the render's measured CPU seconds (column 1): the whole frames make the budgets
            # differ by up to one frame; relMSE × time and MAPE × √time correct for it
            paste "$f" "$OUT/fp.$view.gris-0.02.rows" | awk '{ a = $1; b = $10
                print $2 / $11, $3 / $12, $2 * sqrt(a) / ($11 * sqrt(b)), $3 * a / ($12 * b) }' >"$OUT/fp.ratio"
            echo "| $view | $label | $(col 1 "$OUT/fp.ratio" 3) | $(col 2 "$OUT/fp.ratio" 3) | $(col 3 "$OUT/fp.ratio" 3) |" \
                "$(col 4 "$OUT/fp.ratio" 3) |"
        done
    done
    echo
    rm -f "$OUT/fp.ratio"
fi

# ---- equal-time error, GRIS baseline vs Enhanced, every shipped scene ----------------------
# Offline pipeline (EBASE): the frames are independent, so a CPU-time budget buys a whole
# number of frames and the error of their mean falls as 1 / frames (relMSE); the real-time
# pipeline's frames are correlated through temporal reuse and its per-frame error cannot be
# bought at equal time. Per scene and configuration, frames_for picks the frame count whose CPU
# time is BUDGET; ESEEDS renders; MAPE, relMSE and HDR-FLIP (src/metrics/flip.c) against the
# REF_SPP reference, whose own relMSE (from its two halves) is printed in the last column.
if [ "$PART" = all ] || [ "$PART" = equaltime ]; then
    ET_SCENES=${ET_SCENES:-scenes/cornell.scene scenes/cornell-glossy.scene scenes/glass.scene scenes/ajar.scene scenes/corridor.scene scenes/pillars.scene scenes/shadow.scene scenes/hall.scene}
    # shellcheck disable=SC2086
    sh scripts/results_enhanced_ref.sh "$OUT" "$R" "$ESIZE" "$REF_SPP" "$REF_THREADS" $ET_SCENES
    echo "#### ${ESIZE}², $BUDGET CPU s per render (--threads 1), seeds $ESEEDS"
    echo
    echo "| scene | configuration | frames | CPU ms per frame | CPU s | MAPE | relMSE | HDR-FLIP | reference: spp, own relMSE |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    for scene in $ET_SCENES; do
        name=$(basename "$scene" .scene)
        for cfg in "GRIS baseline|" "Enhanced|$ENH"; do
            label=${cfg%%|*}; opts=${cfg#*|}
            # shellcheck disable=SC2086
            set -- $(frames_for "$scene" $EBASE $opts --size "${ESIZE}x${ESIZE}"); T=$1; F=$2
            : >"$OUT/et.rows"
            for s in $ESEEDS; do
                # shellcheck disable=SC2086
                t=$(cpu_run "$OUT/et.pfm" "$OUT/et.json" "$scene" $EBASE $opts --size "${ESIZE}x${ESIZE}" --seed "$s" --frames "$T")
                "$R" compare "$OUT/et.pfm" "$OUT/ref/$name.pfm" >"$OUT/et.cmp"
                echo "$t $(awk '$1 == "mape" { m = $2 } $1 == "relmse" { r = $2 } $1 == "flip_hdr" { f = $2 } END { print m, r, f }' \
                    "$OUT/et.cmp") $T $F" >>"$OUT/et.rows" # cpu, mape, relmse, flip, frames, ms
            done
            echo "| $name | $label | $T | $F | $(col 1 "$OUT/et.rows" 2) | $(col 2 "$OUT/et.rows") | $(col 3 "$OUT/et.rows") |" \
                "$(col 4 "$OUT/et.rows") | $(awk '{ printf "%d, %.2g", $3, $1 }' "$OUT/ref/$name.self") |"
            cp "$OUT/et.rows" "$OUT/et.$name.$(echo "$label" | cut -c1-3).rows"
        done
    done
    echo
    rm -f "$OUT/et.rows" "$OUT/et.cmp" "$OUT/et.pfm" "$OUT/et.json" "$OUT/c.pfm" "$OUT/c.json"
fi
# PART=equaltime (or etsummary, from the rows an equaltime run left in OUT_DIR): GRIS's error
# divided by Enhanced's on the same seed (> 1: Enhanced is better), mean ± 95 % t half-width.
if [ "$PART" = all ] || [ "$PART" = equaltime ] || [ "$PART" = etsummary ]; then
    # time-normalised: relMSE × time and MAPE × √time, time = the render's measured CPU seconds
    # (the whole frames make the two budgets differ by up to one frame; Enhanced's time includes
    # building the reuse textures, ≈ 0.05 s at 128²)
    echo "| scene | MAPE GRIS / Enhanced (per seed) | relMSE GRIS / Enhanced | HDR-FLIP GRIS / Enhanced | MAPE × √time | relMSE × time |"
    echo "| --- | --- | --- | --- | --- | --- |"
    for f in "$OUT"/et.*.GRI.rows; do
        name=${f#"$OUT/et."}; name=${name%.GRI.rows}
        paste "$f" "$OUT/et.$name.Enh.rows" | awk '{ a = $1; b = $7
            print $2 / $8, $3 / $9, $4 / $10, $2 * sqrt(a) / ($8 * sqrt(b)), $3 * a / ($9 * b) }' >"$OUT/et.ratio"
        echo "| $name | $(col 1 "$OUT/et.ratio" 2) | $(col 2 "$OUT/et.ratio" 2) | $(col 3 "$OUT/et.ratio" 2) |" \
            "$(col 4 "$OUT/et.ratio" 2) | $(col 5 "$OUT/et.ratio" 2) |"
    done
    echo
    rm -f "$OUT/et.ratio"
fi

# ---- control: do the paired error ratios see a broken estimator? -------------------------
# The same frames and seeds with and without a deliberately broken estimator (--ablate; the
# ablations are biased): the ratio broken / correct per seed, as in the summaries above.
# Rows "scene|frames|correct options|ablation".
if [ "$PART" = control ]; then
    CONTROL_ROWS=${CONTROL_ROWS:-"hall|10|--rc-criterion footprint|footprint-base-only
hall|10|--rc-criterion footprint|jacobian
cornell|8|$ENH|pair-mis"}
    echo "| scene | configuration | ablation | frames | MAPE broken / correct (per seed) | relMSE broken / correct |"
    echo "| --- | --- | --- | --- | --- | --- |"
    echo "$CONTROL_ROWS" | while IFS='|' read -r name T opts abl; do
        : >"$OUT/ctl.rows"
        for s in $ESEEDS; do
            for a in none "$abl"; do
                # shellcheck disable=SC2086
                cpu_run "$OUT/ctl.pfm" "$OUT/ctl.json" "scenes/$name.scene" $EBASE $opts --ablate "$a" --size "${ESIZE}x${ESIZE}" \
                    --seed "$s" --frames "$T" >/dev/null
                "$R" compare "$OUT/ctl.pfm" "$OUT/ref/$name.pfm" | awk '$1 == "mape" { m = $2 } $1 == "relmse" { r = $2 }
                    END { printf "%s %s ", m, r }'
            done
            echo
        done | awk '{ print $3 / $1, $4 / $2 }' >"$OUT/ctl.rows"
        echo "| $name | ${opts:-GRIS} | $abl | $T | $(col 1 "$OUT/ctl.rows" 3) | $(col 2 "$OUT/ctl.rows" 3) |"
    done
    echo
    rm -f "$OUT/ctl.rows" "$OUT/ctl.pfm" "$OUT/ctl.json"
fi
rm -f "$TF"
