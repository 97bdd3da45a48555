# Offline ReSTIR PT (--preset gris-offline) vs the path tracer at equal time (sourced by
# scripts/results.sh). Per seed: ReSTIR renders ET_FRAMES frames, then the path tracer renders
# whole 1-spp passes for the same wall time (--time-limit = ReSTIR's seconds), one after the
# other so both see the same load on the shared machine. Both estimators are unbiased averages
# of independent samples (PT: paths; ReSTIR: frames, GRIS Eq. 47), so relMSE ~ c / time and the
# time ReSTIR needs to reach the path tracer's relMSE is a fraction
#     speed-up = (relMSE_PT * t_PT) / (relMSE_ReSTIR * t_ReSTIR)
# of the path tracer's: the ratio of efficiencies. Its interval is over seeds, on log(speed-up)
# (a ratio of heavy-tailed errors: the log makes the t interval meaningful), reported as the
# geometric mean [low, high].
#
# References: the path tracer, except for ET_REF_RESTIR scenes (default: ajar), whose path
# tracer has fireflies that would need ~100x the time: there the reference is gris-offline
# ReSTIR itself with ET_REF_FRAMES frames of seed 9001 (independent of the judged runs, seeds
# 1..SEEDS; ReSTIR's unbiasedness against the path tracer is what `make test` checks). The
# path tracer's global rel_bias against it is reported as a cross-check.
ET_REF_RESTIR=${ET_REF_RESTIR:-ajar}

et_reference() { # SCENE MODE -> reference path
    sc=$1 mode=$2
    case " $ET_REF_RESTIR " in
    *" $sc "*) reference "$sc-$mode-gris-offline" "$ET_SIZE" "scenes/$sc.scene" restir "$ET_REF_FRAMES" \
        --preset gris-offline --paths "$mode" ;;
    *) if [ "$mode" = indirect ]; then
           reference "$sc-$mode" "$ET_SIZE" "scenes/$sc.scene" pt "$ET_REF_PT_SPP" --min-depth 3
       else
           reference "$sc-$mode" "$ET_SIZE" "scenes/$sc.scene" pt "$ET_REF_PT_SPP"
       fi ;;
    esac
}

# geometric mean [low, high] (95% t interval of the mean log) of column 2 of "x,value" rows for x
geo_ci() {
    awk -F, -v x="$2" -v ttable="$(t_table)" '
        BEGIN { NT = split(ttable, T, " ") }
        $1 == x && $2 > 0 { l = log($2); s += l; q += l * l; n++ }
        END {
            if (n == 0) { print "–"; exit }
            m = s / n
            if (n < 2) { printf "%.3g (1 seed)", exp(m); exit }
            v = (q - n * m * m) / (n - 1); if (v < 0) v = 0
            t = n - 1 <= NT ? T[n - 1] : T[NT]
            h = t * sqrt(v / n)
            printf "%.3g [%.3g, %.3g]", exp(m), exp(m - h), exp(m + h)
        }' "$1"
}

# reference_rows RUNS REFS RS PT: the table rows "| x | reference | its relMSE (ratio) | its
# MAPE (ratio) |" of the references in REFS ("x|path" lines). RUNS has "x,NAME,seed,value"
# rows with NAME "RS relMSE", "PT MAPE", ...; ratio = the reference's own error / the smaller
# of the two methods' mean errors it judges. The reference's kind from ET_REF_RESTIR,
# ET_REF_FRAMES and ET_REF_PT_SPP (as et_reference chose it).
reference_rows() {
    while IFS='|' read -r x ref; do
        case " $ET_REF_RESTIR " in *" ${x% *} "*) what="ReSTIR gris-offline, $ET_REF_FRAMES frames, seed 9001" ;;
            *) what="path tracer, $ET_REF_PT_SPP spp, seed 9001" ;; esac
        minr=$(smaller_mean "$1" "$x" "$3 relMSE" "$4 relMSE") minm=$(smaller_mean "$1" "$x" "$3 MAPE" "$4 MAPE")
        er=$(ref_relmse "$ref") em=$(ref_mape "$ref")
        echo "| $x | $what | $(calc "$er") ($(calc "$er / $minr")) | $(calc "$em") ($(calc "$em / $minm")) |"
    done < "$2"
}
# smaller_mean RUNS X NAME_A NAME_B: the smaller of the mean values of rows X,NAME_A and X,NAME_B
smaller_mean() {
    awk -F, -v x="$2" -v a="$3" -v b="$4" '$1 == x && ($2 == a || $2 == b) { s[$2] += $4; n[$2]++ }
        END { p = s[a] / n[a]; q = s[b] / n[b]; print (p < q ? p : q) }' "$1"
}

equal_time() {
    runs="$OUT/equal_time.runs.csv"; : > "$runs"
    speed="$OUT/equal_time.speedup.csv"; : > "$speed"
    refs="$TMP/equal_time.refs"; : > "$refs"
    for sc in $ET_SCENES; do
        for mode in all indirect; do
            ref=$(et_reference "$sc" "$mode")
            echo "$sc $mode|$ref" >> "$refs"
            pt_opts=""; [ "$mode" = indirect ] && pt_opts="--min-depth 3"
            for seed in $(seq_seeds); do
                render "$ET_SIZE" "scenes/$sc.scene" --method restir --preset gris-offline --paths "$mode" \
                    --frames "$ET_FRAMES" --seed "$seed" -o "$TMP/et_rs.pfm" --stats "$TMP/et_rs.json"
                t_rs=$(render_seconds "$TMP/et_rs.json")
                render "$ET_SIZE" "scenes/$sc.scene" --method pt $pt_opts --spp 0 --time-limit "$t_rs" --seed "$seed" \
                    -o "$TMP/et_pt.pfm" --stats "$TMP/et_pt.json"
                t_pt=$(render_seconds "$TMP/et_pt.json")
                spp=$(grep -o '"spp": [0-9]*' "$TMP/et_pt.json" | head -n 1 | awk '{ print $2 }')
                e_rs=$(metric relmse "$TMP/et_rs.pfm" "$ref.pfm"); e_pt=$(metric relmse "$TMP/et_pt.pfm" "$ref.pfm")
                x="$sc $mode"
                {
                    echo "$x,ReSTIR seconds,$seed,$t_rs"
                    echo "$x,ReSTIR relMSE,$seed,$e_rs"
                    echo "$x,ReSTIR MAPE,$seed,$(metric mape "$TMP/et_rs.pfm" "$ref.pfm")"
                    echo "$x,PT seconds,$seed,$t_pt"
                    echo "$x,PT spp,$seed,$spp"
                    echo "$x,PT relMSE,$seed,$e_pt"
                    echo "$x,PT MAPE,$seed,$(metric mape "$TMP/et_pt.pfm" "$ref.pfm")"
                    echo "$x,PT rel_bias,$seed,$(metric rel_bias "$TMP/et_pt.pfm" "$ref.pfm")"
                    echo "$x,ReSTIR rel_bias,$seed,$(metric rel_bias "$TMP/et_rs.pfm" "$ref.pfm")"
                } >> "$runs"
                echo "$x,$(calc "$e_pt * $t_pt / ($e_rs * $t_rs)")" >> "$speed"
            done
        done
    done
    equal_time_section
}

# The tables of the equal-time part from OUT/equal_time.runs.csv and .speedup.csv (also on
# its own: PARTS="equal_time_section docs" WRITE_DOCS=1 with the knobs of the run).
equal_time_section() {
    runs="$OUT/equal_time.runs.csv"; speed="$OUT/equal_time.speedup.csv"; refs="$TMP/equal_time.refs"
    # the same speed-up from MAPE, assuming MAPE ~ 1 / sqrt(time): (MAPE_PT / MAPE_ReSTIR)^2 t_PT / t_ReSTIR
    awk -F, '{ v[$1, $2, $3] = $4; if (!(($1, $3) in seen)) { seen[$1, $3] = 1; key[++n] = $1 SUBSEP $3 } }
        END { for (i = 1; i <= n; ++i) { split(key[i], k, SUBSEP); x = k[1]; s = k[2]
            a = v[x, "PT MAPE", s] / v[x, "ReSTIR MAPE", s]
            printf "%s,%.6g\n", x, a * a * v[x, "PT seconds", s] / v[x, "ReSTIR seconds", s] } }' "$runs" > "$OUT/equal_time.speedup_mape.csv"
    # per-seed relMSE of both methods (the spread behind the intervals), for the plot
    awk -F, '$2 == "ReSTIR relMSE" || $2 == "PT relMSE" { print $3 "," $1 " " $2 "," $3 "," $4 }' "$runs" |
        summary -v mode=wide -v xname=seed > "$OUT/equal_time.csv"
    "$R" plot "$OUT/equal_time.csv" -o "$OUT/equal_time.svg" --logy \
        --title "equal time at ${ET_SIZE}^2: relMSE per seed (ReSTIR $ET_FRAMES frame(s) vs PT)" --xlabel seed --ylabel relMSE
    {
        echo "Setup: ${ET_SIZE} × ${ET_SIZE}, max depth 10, pixel centres, $THREADS threads on the shared 2-core machine, $SEEDS seeds (1–$SEEDS). ReSTIR: \`--preset gris-offline\` (32 path trees, 3 spatial passes, 6 neighbours in radius 10, defensive pairwise MIS, hybrid shift), $ET_FRAMES frame(s). PT: \`--spp 0 --time-limit\` = the ReSTIR run's seconds (whole 1-spp passes, so it stops at most one pass later). Rows \`indirect\`: \`--paths indirect\` / \`--min-depth 3\` (path length ≥ 3), as GRIS §9.3 measures; rows \`all\`: all light. Mean ± 95% Student-t interval over seeds."
        echo
        summary -v mode=header -v xname="scene, light" "$runs"
        summary -v mode=md "$runs"
        echo
        echo "Speed-up (time the path tracer needs for ReSTIR's relMSE / ReSTIR's time = ratio of efficiencies, per seed), geometric mean [95% interval over seeds]:"
        echo
        echo "| scene, light | speed-up of ReSTIR over PT (relMSE) | the same from MAPE, assuming MAPE ∝ 1/√time |"
        echo "|---|---|---|"
        while IFS='|' read -r x ref; do
            echo "| $x | $(geo_ci "$speed" "$x") | $(geo_ci "$OUT/equal_time.speedup_mape.csv" "$x") |"
        done < "$refs"
        echo
        echo "References and their own error (measured from their two halves; ratio = reference error / the smaller of the two methods' mean errors it judges):"
        echo
        echo "| scene, light | reference | its relMSE (ratio) | its MAPE (ratio) |"
        echo "|---|---|---|---|"
        reference_rows "$runs" "$refs" ReSTIR PT
    } > "$OUT/equal_time.section.md"
}
