#!/bin/sh
# Offline ReSTIR PT against the path tracer at equal CPU time, with the CPU time of each stage,
# before and after a change that keeps the outputs bit-identical (issue 28).
#   sh scripts/claims_equal_time.sh [OUT_DIR] [BUILD_DIR]       (BEFORE=old/restir for the before rows)
#
# GRIS §9.3 measures offline ReSTIR PT (§8.3: 32 path trees, 3 spatial passes of 6 neighbours,
# defensive pairwise MIS, no temporal reuse) against a path tracer at equal time, MAPE of
# indirect light. Here, per scene of SCENES and light (all; indirect = paths of >= 3 segments,
# `--paths indirect` / `--min-depth 3`):
#  1. errors, seeds 1..SEEDS: one gris-offline frame and the path tracer at PT_SPP spp (32: the
#     same number of paths as the 32 path trees; its CPU time is near ReSTIR's, the speed-up
#     below divides the difference out), relMSE and MAPE against a reference (the path tracer,
#     REF_SPP spp of seed 9001, or for REF_RESTIR scenes gris-offline over REF_FRAMES frames,
#     whose path tracer has fireflies) whose own error is measured from its two halves;
#  2. CPU time, ROUNDS rounds on seed 1, BEFORE and the binary under test alternately, each
#     run --threads 1 and charged its process CPU time (user + system: load on the shared
#     machine inflates it little), the stages' milliseconds from --stats (one thread: the
#     stage's time on its core);
#  3. the speed-up of ReSTIR over the path tracer at equal CPU time, per seed
#        (relMSE_PT * t_PT) / (relMSE_ReSTIR * t_ReSTIR)
#     (both average independent samples, so relMSE ~ 1/time: the ratio of efficiencies), and
#     the same from MAPE with MAPE ~ 1/sqrt(time); geometric mean and 95% interval over seeds,
#     t the median CPU time of that binary. With BEFORE given, part 2 checks that both
#     binaries write the same bytes for every configuration (seed 1, each round), so the
#     errors of part 1 (rendered by the binary under test) are both binaries' errors.
# Knobs: SIZE (128), SEEDS (5), SCENES, PT_SPP (32), REF_SPP (2048), REF_FRAMES (64),
# REF_RESTIR (ajar), ROUNDS (3), REF_THREADS (2), BEFORE (empty: no before rows),
# PARTS ("refs errors times report").
# Expected run time on 2 idle cores with the defaults: references ~10 min, errors ~4 min,
# times ~4 min per binary.   Smoke test (seconds):
#   SIZE=16 SEEDS=2 SCENES=cornell REF_SPP=8 ROUNDS=1 sh scripts/claims_equal_time.sh /tmp/et
set -eu
HERE=$(dirname "$0")
. "$HERE/results/lib.sh"
. "$HERE/results/claims_lib.sh"
. "$HERE/results/equal_time.sh" # et_reference, geo_ci
results_init out/claims-equal-time "$@"
defaults SIZE=128 SEEDS=5 "SCENES=cornell ajar textured-room courtyard many-lights" PT_SPP=32 REF_SPP=2048 \
    REF_FRAMES=64 REF_RESTIR=ajar ROUNDS=3 REF_THREADS=2 "PARTS=refs errors times report"
BEFORE=${BEFORE:-}
SUMMARY="$HERE/results/summary.awk"
CACHE="$OUT/cache"
mkdir -p "$TMP" "$CACHE"
AFTER=$R
MODES="all indirect"

has_part() { case " $PARTS " in *" $1 "*) return 0 ;; esac; return 1; }
# options of one method for light MODE
restir_opts() { echo "--method restir --preset gris-offline --paths $1"; }
pt_opts() { if [ "$1" = indirect ]; then echo "--method pt --spp $PT_SPP --min-depth 3"; else echo "--method pt --spp $PT_SPP"; fi; }

ref_of() { # SCENE MODE -> reference path (rendered once, cached): results/equal_time.sh's choice
    THREADS=$REF_THREADS ET_SIZE=$SIZE ET_REF_PT_SPP=$REF_SPP ET_REF_FRAMES=$REF_FRAMES ET_REF_RESTIR=$REF_RESTIR
    et_reference "$1" "$2"
}

# run BIN OUT_PREFIX SCENE SEED OPTIONS...: one single-threaded render; prints its CPU seconds
run() {
    bin=$1 prefix=$2 scene=$3 seed=$4; shift 4
    cpu_run "$prefix" "$bin" render "scenes/$scene.scene" "$@" --size "${SIZE}x${SIZE}" \
        --threads 1 --seed "$seed" --quiet --no-png -o "$prefix.pfm" --stats "$prefix.json" > /dev/null
    cpu_seconds "$prefix"
}
# stage_ms JSON: "initial spatial rest" milliseconds of a ReSTIR run (rest = the render's
# seconds minus both: G-buffer, shading, frame set-up)
stage_ms() {
    tr -d '\n' < "$1" | awk '{
        s = $0; i = index(s, "\"milliseconds\": {\"gbuffer\""); s = substr(s, i)
        match(s, /"initial": [0-9.e+-]+/); ini = substr(s, RSTART + 11, RLENGTH - 11)
        match(s, /"spatial": \[[^]]*\]/); sp = substr(s, RSTART + 12, RLENGTH - 13)
        n = split(sp, a, ","); spa = 0; for (k = 1; k <= n; ++k) spa += a[k]
        t = $0; match(t, /"render": [0-9.e+-]+/); r = substr(t, RSTART + 10, RLENGTH - 10) * 1000
        printf "%.1f %.1f %.1f\n", ini, spa, r - ini - spa }'
}

refs() {
    : > "$TMP/refs"
    for sc in $SCENES; do for mode in $MODES; do echo "$sc $mode|$(ref_of "$sc" "$mode")" >> "$TMP/refs"; done; done
}

errors() {
    runs="$OUT/errors.csv"; : > "$runs"
    for sc in $SCENES; do for mode in $MODES; do
        ref=$(ref_of "$sc" "$mode") x="$sc $mode"
        for seed in $(seq_seeds); do
            run "$AFTER" "$TMP/rs" "$sc" "$seed" $(restir_opts "$mode") > /dev/null
            run "$AFTER" "$TMP/pt" "$sc" "$seed" $(pt_opts "$mode") > /dev/null
            for m in rs pt; do
                e=$(need "$x $m relMSE" "$(metric relmse "$TMP/$m.pfm" "$ref.pfm")")
                a=$(need "$x $m MAPE" "$(metric mape "$TMP/$m.pfm" "$ref.pfm")")
                printf '%s,%s relMSE,%s,%s\n%s,%s MAPE,%s,%s\n' "$x" "$m" "$seed" "$e" "$x" "$m" "$seed" "$a" >> "$runs"
            done
        done
    done; done
}

time_runs() {
    rows="$OUT/times.csv"; : > "$rows" # scene mode,binary,round,restir cpu,initial,spatial,rest,pt cpu
    for sc in $SCENES; do for mode in $MODES; do
        k=1
        while [ "$k" -le "$ROUNDS" ]; do
            bins="after"; [ -n "$BEFORE" ] && { if [ $((k % 2)) = 1 ]; then bins="before after"; else bins="after before"; fi; }
            for b in $bins; do
                bin=$AFTER; [ "$b" = before ] && bin=$BEFORE
                t_rs=$(run "$bin" "$TMP/t-rs" "$sc" 1 $(restir_opts "$mode"))
                st=$(need "$sc $mode stage times" "$(stage_ms "$TMP/t-rs.json")")
                t_pt=$(run "$bin" "$TMP/t-pt" "$sc" 1 $(pt_opts "$mode"))
                echo "$sc $mode,$b,$k,$t_rs,$(echo "$st" | tr ' ' ,),$t_pt" >> "$rows"
                cp "$TMP/t-rs.pfm" "$TMP/t-rs.$b.pfm"; cp "$TMP/t-pt.pfm" "$TMP/t-pt.$b.pfm"
            done
            if [ -n "$BEFORE" ]; then # the change must keep the bytes: then the errors are the same
                cmp -s "$TMP/t-rs.before.pfm" "$TMP/t-rs.after.pfm" && cmp -s "$TMP/t-pt.before.pfm" "$TMP/t-pt.after.pfm" ||
                    { echo "claims_equal_time: $sc $mode: $BEFORE and $AFTER write different images" >&2; exit 1; }
            fi
            k=$((k + 1))
        done
    done; done
}

# median of column COL of times.csv rows for X and binary B
median_of() {
    awk -F, -v x="$1" -v b="$2" -v c="$3" '$1 == x && $2 == b { print $c }' "$OUT/times.csv" | sort -g |
        awk '{ v[NR] = $1 } END { if (NR == 0) exit; print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
range_of() {
    awk -F, -v x="$1" -v b="$2" -v c="$3" '$1 == x && $2 == b { print $c }' "$OUT/times.csv" | sort -g |
        awk 'NR == 1 { lo = $1 } { hi = $1 } END { printf "%s–%s", lo, hi }'
}

# speedups X BINARY METRIC POWER -> per-seed "X,speed-up" rows: (e_PT^POWER t_PT) / (e_RS^POWER t_RS)
speedups() {
    t_rs=$(median_of "$1" "$2" 4) t_pt=$(median_of "$1" "$2" 8)
    awk -F, -v x="$1" -v m="$3" -v p="$4" -v trs="$t_rs" -v tpt="$t_pt" '
        $1 == x && $2 == "rs " m { rs[$3] = $4 } $1 == x && $2 == "pt " m { pt[$3] = $4 }
        END { for (s in rs) if (rs[s] > 0) printf "%s,%.6g\n", x, (pt[s] ^ p) * tpt / ((rs[s] ^ p) * trs) }' "$OUT/errors.csv"
}

report() {
    bins="after"; [ -n "$BEFORE" ] && bins="before after"
    echo "## Offline ReSTIR PT vs the path tracer at equal CPU time (${SIZE}², $SEEDS seeds, 1 thread)"
    echo
    echo "Errors (mean ± 95% t half-width over seeds 1–$SEEDS; the same images for every binary):"
    echo
    echo "| scene, light | ReSTIR relMSE | PT ($PT_SPP spp) relMSE | ReSTIR MAPE | PT MAPE |"
    echo "|---|---|---|---|---|"
    for sc in $SCENES; do for mode in $MODES; do
        x="$sc $mode"
        printf "| %s |" "$x"
        for col in "rs relMSE" "pt relMSE" "rs MAPE" "pt MAPE"; do
            printf " %s |" "$(awk -F, -v x="$x" -v c="$col" '$1 == x && $2 == c { print $4 }' "$OUT/errors.csv" | mean_ci)"
        done
        echo
    done; done
    echo
    echo "CPU time per stage, seed 1, median [min–max] over $ROUNDS rounds (ms; initial = 32 path trees per pixel, spatial = the 3 passes, rest = G-buffer, shading, set-up; the process's CPU seconds also include loading):"
    echo
    echo "| scene, light | binary | ReSTIR CPU s | initial ms | spatial ms | rest ms | PT CPU s | initial / PT |"
    echo "|---|---|---|---|---|---|---|---|"
    for sc in $SCENES; do for mode in $MODES; do for b in $bins; do
        x="$sc $mode"
        ini=$(median_of "$x" "$b" 5) tpt=$(median_of "$x" "$b" 8)
        echo "| $x | $b | $(median_of "$x" "$b" 4) [$(range_of "$x" "$b" 4)] | $ini | $(median_of "$x" "$b" 6) | $(median_of "$x" "$b" 7) | $tpt [$(range_of "$x" "$b" 8)] | $(calc "$ini / 1000 / $tpt") |"
    done; done; done
    echo
    echo "Speed-up of ReSTIR over the path tracer at equal CPU time (ratio of efficiencies per seed; geometric mean [95% interval over seeds]):"
    echo
    printf "| scene, light |"; for b in $bins; do printf " relMSE (%s) | MAPE (%s) |" "$b" "$b"; done; echo
    printf "|---|"; for b in $bins; do printf -- "---|---|"; done; echo
    for sc in $SCENES; do for mode in $MODES; do
        x="$sc $mode"
        printf "| %s |" "$x"
        for b in $bins; do
            speedups "$x" "$b" relMSE 1 > "$TMP/sp.relmse"; speedups "$x" "$b" MAPE 2 > "$TMP/sp.mape"
            printf " %s | %s |" "$(geo_ci "$TMP/sp.relmse" "$x")" "$(geo_ci "$TMP/sp.mape" "$x")"
        done
        echo
    done; done
    echo
    echo "References and their own error (from their two halves; ratio = its error / the smaller mean error it judges):"
    echo
    echo "| scene, light | reference | its relMSE (ratio) | its MAPE (ratio) |"
    echo "|---|---|---|---|"
    ET_REF_RESTIR=$REF_RESTIR ET_REF_FRAMES=$REF_FRAMES ET_REF_PT_SPP=$REF_SPP
    reference_rows "$OUT/errors.csv" "$TMP/refs" rs pt
}

has_part refs && refs
[ -f "$TMP/refs" ] || refs
has_part errors && errors
has_part times && time_runs
if has_part report; then report > "$OUT/equal_time.md"; cat "$OUT/equal_time.md"; fi
