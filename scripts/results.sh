#!/bin/sh
# Regenerates the measurements of docs/results.md (the GRIS claims, Figs. 7, 8, 11 and
# equal-time ReSTIR PT vs the path tracer) with our own CLI: render, compare, plot.
#   make results            (or: sh scripts/results.sh [OUT_DIR] [BUILD_DIR])
# Small images and short runs so that it fits a 2-core machine in ~10 minutes; the sizes
# are variables below. Not part of `make test`.
set -eu
OUT=${1:-out/results}
R=${2:-build}/restir
SIZE=${SIZE:-32}
THREADS=${THREADS:-2}
REF_SPP=${REF_SPP:-16384}
mkdir -p "$OUT"
TMP="$OUT/tmp"
mkdir -p "$TMP"

# metric NAME TEST.pfm REF.pfm: one value from `restir compare`
metric() { "$R" compare "$2" "$3" | awk -v m="$1" '$1 == m { print $2 }'; }
# seconds of the last render (its --stats file)
render_seconds() { grep -o '"render": [0-9.e+-]*' "$1" | awk '{ print $2 }'; }
render() { "$R" render "$@" --size "${SIZE}x${SIZE}" --threads "$THREADS" --quiet --no-png; }

reference() { # scene -> $TMP/NAME.ref.pfm
    name=$(basename "$1" .scene)
    [ -f "$TMP/$name.ref.pfm" ] || render "$1" --method pt --spp "$REF_SPP" --seed 9001 -o "$TMP/$name.ref.pfm"
}

# A grey Cornell box (every reflectance and the light made grey with its luminance): with a
# grey integrand F(Y) / p̂(Y) is constant, so the single-sample error measures the
# resampling alone and not the colour noise of shading one path with a luminance target.
grey_cornell() {
    d="$TMP/grey"
    mkdir -p "$d"
    cp scenes/cornell.obj "$d/cornell.obj"
    awk '$1 == "Kd" || $1 == "Ke" { y = 0.2126 * $2 + 0.7152 * $3 + 0.0722 * $4; print $1, y, y, y; next } { print }' \
        scenes/cornell.mtl > "$d/cornell.mtl"
    sed 's/kd 0.725 0.71 0.68/kd 0.711 0.711 0.711/' scenes/cornell.scene > "$d/cornell-grey.scene"
    echo "$d/cornell-grey.scene"
}

# relMSE against the grey reference of one spatial-only frame (1 pass, box window, no
# rejection), averaged over seeds 1-3. Arguments: SCENE, then the remaining render options.
mean_relmse() {
    scene=$1; shift
    sum=0
    for seed in 1 2 3; do
        render "$scene" --method restir --spatial-passes 1 --pattern box --no-reject "$@" --seed $seed \
            -o "$TMP/window.pfm"
        e=$(metric relmse "$TMP/window.pfm" "$TMP/cornell-grey.ref.pfm")
        sum=$(awk -v a="$sum" -v b="$e" 'BEGIN { print a + b }')
    done
    awk -v a="$sum" 'BEGIN { printf "%.6g", a / 3 }'
}

# ---- (a) GRIS Fig. 7: single-frame error vs input samples per pixel, fixed 7x7 window --------
fig7() {
    S=$(grey_cornell)
    reference $S
    csv="$OUT/fig7.csv"
    echo "samples_per_pixel,constant,talbot,pairwise" > "$csv.tmp"
    for n in 1 2 4 8 16; do
        row="$n"
        for mis in constant talbot pairwise; do
            row="$row,$(mean_relmse "$S" --candidates $n --radius 3 --mis $mis)"
        done
        echo "$row" >> "$csv.tmp"
    done
    mv "$csv.tmp" "$csv"
    "$R" plot "$csv" -o "$OUT/fig7.svg" --title "GRIS Fig. 7: 7x7 window, grey cornell ${SIZE}^2, one frame" \
        --xlabel "input samples per pixel (path trees)" --ylabel "relMSE"
}

# ---- (b) GRIS Fig. 8: growing window, one canonical sample --------------------------------------
fig8() {
    S=$(grey_cornell)
    reference $S
    csv="$OUT/fig8.csv"
    echo "window_pixels,constant,pairwise,pairwise-defensive,talbot" > "$csv.tmp"
    for r in 1 2 3 5 7 10 15; do
        w=$(( (2 * r + 1) * (2 * r + 1) ))
        row="$w"
        for mis in constant pairwise pairwise-defensive talbot; do
            if [ $mis = talbot ] && [ $r -gt 7 ]; then row="$row,"; continue; fi # O(M^2) shifts
            row="$row,$(mean_relmse "$S" --candidates 1 --radius $r --mis $mis)"
        done
        echo "$row" >> "$csv.tmp"
    done
    mv "$csv.tmp" "$csv"
    "$R" plot "$csv" -o "$OUT/fig8.svg" --title "GRIS Fig. 8: growing window, 1 canonical sample, grey cornell ${SIZE}^2" \
        --xlabel "window pixels (2r+1)^2" --ylabel "relMSE"
}

# ---- (c) GRIS Fig. 11: reconnection vs hybrid shift, rough vs glossy Cornell box ---------------
fig11() {
    csv="$OUT/fig11.csv"
    echo "frames,cornell-reconnection,cornell-hybrid,glossy-reconnection,glossy-hybrid" > "$csv.tmp"
    reference scenes/cornell.scene
    reference scenes/cornell-glossy.scene
    for f in 1 2 4 8 16; do
        row="$f"
        for S in scenes/cornell.scene scenes/cornell-glossy.scene; do
            name=$(basename $S .scene)
            for shift in reconnection hybrid; do
                render $S --method restir --candidates 4 --spatial-passes 3 --neighbors 6 --radius 3 --shift $shift \
                    --frames $f -o "$TMP/f11.pfm"
                row="$row,$(metric relmse "$TMP/f11.pfm" "$TMP/$name.ref.pfm")"
            done
        done
        echo "$row" >> "$csv.tmp"
    done
    mv "$csv.tmp" "$csv"
    "$R" plot "$csv" -o "$OUT/fig11.svg" --title "GRIS Fig. 11: shifts on rough vs glossy Cornell box (${SIZE}^2)" \
        --xlabel "frames (4 path trees, 3 passes, 6 neighbours)" --ylabel "relMSE"
}

# ---- (d) equal time: offline ReSTIR PT vs the path tracer ---------------------------------------
equal_time() {
    table="$OUT/equal_time.csv"
    echo "scene,pt_seconds,pt_mape,restir_seconds,restir_mape,restir_seconds_to_pt_mape,speedup" > "$table.tmp"
    for S in scenes/cornell.scene scenes/cornell-glossy.scene scenes/glass.scene scenes/ajar.scene; do
        name=$(basename $S .scene)
        reference $S
        csv="$OUT/equal_time_$name.csv"
        echo "seconds,pt,restir" > "$csv.tmp"
        : > "$TMP/pt.$name"
        : > "$TMP/rs.$name"
        for spp in 16 32 64 128 256 512 1024; do
            render $S --method pt --spp $spp --seed 77 -o "$TMP/et.pfm" --stats "$TMP/et.json"
            t=$(render_seconds "$TMP/et.json"); e=$(metric mape "$TMP/et.pfm" "$TMP/$name.ref.pfm")
            echo "$t $e" >> "$TMP/pt.$name"; echo "$t,$e," >> "$csv.tmp"
        done
        for f in 1 2 4 8 16 32; do
            render $S --method restir --preset gris-offline --radius 3 --frames $f --seed 77 -o "$TMP/et.pfm" \
                --stats "$TMP/et.json"
            t=$(render_seconds "$TMP/et.json"); e=$(metric mape "$TMP/et.pfm" "$TMP/$name.ref.pfm")
            echo "$t $e" >> "$TMP/rs.$name"; echo "$t,,$e" >> "$csv.tmp"
        done
        mv "$csv.tmp" "$csv"
        "$R" plot "$csv" -o "$OUT/equal_time_$name.svg" --title "$name ${SIZE}^2: MAPE vs seconds" \
            --xlabel seconds --ylabel MAPE
        # time for ReSTIR to reach the PT's final MAPE: log-log interpolation between records
        # (extrapolated with the last two records' slope if it is not reached)
        awk -v name="$name" '
            FNR == NR { pt_t = $1; pt_e = $2; next }
            { n++; t[n] = $1; e[n] = $2 }
            END {
                reach = -1
                for (k = 1; k <= n; ++k) if (e[k] <= pt_e) { reach = k; break }
                if (reach == 1) tt = t[1];
                else {
                    a = reach > 1 ? reach - 1 : n - 1; b = reach > 1 ? reach : n
                    s = (log(t[b]) - log(t[a])) / (log(e[b]) - log(e[a]))
                    tt = exp(log(t[a]) + s * (log(pt_e) - log(e[a])))
                }
                printf "%s,%.4g,%.5g,%.4g,%.5g,%.4g%s,%.3g\n", name, pt_t, pt_e, t[n], e[n], tt, reach < 0 ? "(extrapolated)" : "", pt_t / tt
            }' "$TMP/pt.$name" "$TMP/rs.$name" >> "$table.tmp"
    done
    mv "$table.tmp" "$table"
}

for part in ${PARTS:-fig7 fig8 fig11 equal_time}; do $part; done
echo "results in $OUT: fig7, fig8, fig11, equal_time_*.svg/csv, equal_time.csv"
