# GRIS Figs. 7, 8 and 11 (sourced by scripts/results.sh, which defines the helpers).

# A grey Cornell box (every reflectance and the light made grey with its luminance): GRIS §9.1
# computes the convergence errors "in grayscale images"; with a grey integrand F(Y) / p̂(Y) is
# constant, so the single-sample error is that of the resampling alone.
grey_cornell() {
    d="$TMP/grey"
    mkdir -p "$d"
    cp scenes/cornell.obj "$d/cornell.obj"
    awk '$1 == "Kd" || $1 == "Ke" { y = 0.2126 * $2 + 0.7152 * $3 + 0.0722 * $4; print $1, y, y, y; next } { print }' \
        scenes/cornell.mtl > "$d/cornell.mtl"
    sed 's/kd 0.725 0.71 0.68/kd 0.711 0.711 0.711/' scenes/cornell.scene > "$d/cornell-grey.scene"
    echo "$d/cornell-grey.scene"
}

# The setup of GRIS §9.1 (Figs. 7, 8): three-bounce INDIRECT light (path lengths 3..4), the
# reconnection shift, one spatial pass over a box window, no normal/depth rejection.
GREY_OPTS="--max-depth 4 --paths indirect --shift reconnection --spatial-passes 1 --pattern box --no-reject"
grey_reference() {
    reference grey-indirect "$SIZE" "$(grey_cornell)" pt "$FIG_REF_SPP" --max-depth 4 --min-depth 3
}

# window_run SEED RUNS X SERIES options...: one spatial-only frame on the grey box; appends
# "X,SERIES,SEED,relMSE" to RUNS and "X,SERIES,SEED,domains per pixel" to RUNS.domains
window_run() {
    seed=$1 runs=$2 x=$3 series=$4; shift 4
    render "$SIZE" "$GREY" --method restir $GREY_OPTS "$@" --seed "$seed" -o "$TMP/window.pfm" --stats "$TMP/window.json"
    echo "$x,$series,$seed,$(metric relmse "$TMP/window.pfm" "$GREF.pfm")" >> "$runs"
    # mean number of domains (canonical + in-image neighbours) per pixel: the effective window
    tr -d '\n' < "$TMP/window.json" | grep -o '"steps": [0-9]*, "domains": [0-9]*' |
        awk -v p="$x,$series,$seed" '{ gsub(",", ""); print p "," $4 / $2 }' >> "$runs.domains"
}

ref_line() { # REF SMALLEST: the reference's measured error next to the smallest it judges
    e=$(ref_relmse "$1")
    echo "Reference: its own relMSE, measured from its two halves, is $(calc "$e") = $(calc "$e / $2") × the smallest mean relMSE it judges ($(calc "$2"))."
}
# the smallest mean of a wide CSV (x column dropped)
smallest_mean() { tail -n +2 "$1" | awk -F, '{ for (i = 2; i <= NF; ++i) if ($i != "") print $i }' | sort -g | head -n 1; }

# ---- (a) GRIS Fig. 7: fixed 7x7 window, N samples per pixel --------------------------------
fig7() {
    GREY=$(grey_cornell); GREF=$(grey_reference)
    runs="$OUT/fig7.runs.csv"; : > "$runs"; : > "$runs.domains"
    for seed in $(seq_seeds); do
        for n in 1 2 4 8 16; do
            for mis in constant talbot pairwise; do
                window_run "$seed" "$runs" "$n" "$mis" --candidates "$n" --radius 3 --mis "$mis"
            done
        done
    done
    summarise "$runs" fig7 samples_per_pixel "GRIS Fig. 7: 7x7 window, grey Cornell indirect, ${SIZE}^2, mean of $SEEDS seeds" \
        "input samples per pixel N" "relMSE (one frame)"
    dom=$(awk -F, '{ s += $4; n++ } END { printf "%.4g", s / n }' "$runs.domains")
    {
        echo "Setup: grey Cornell box, ${SIZE} × ${SIZE}, indirect light only (path lengths 3–4, \`--max-depth 4 --paths indirect\`), reconnection shift, one spatial pass over the 7 × 7 box window (\`--pattern box --radius 3 --no-reject\`; $dom domains per pixel on average inside the image, of 49), N path trees per pixel, one frame; relMSE over $SEEDS seeds (1–$SEEDS), mean ± 95% Student-t interval."
        echo "$(ref_line "$GREF" "$(smallest_mean "$OUT/fig7.csv")") Reference: path tracer \`--min-depth 3 --max-depth 4\`, $FIG_REF_SPP spp, seed 9001."
        echo
        cat "$OUT/fig7.table.md"
        echo
        echo "Error ratio relMSE(N = 1) / relMSE(N = 16), per seed (paired), mean ± 95% interval over seeds:"
        echo "constant $(drop "$runs" constant 1 16), Talbot $(drop "$runs" talbot 1 16), pairwise $(drop "$runs" pairwise 1 16) (perfect 1/N scaling: 16)."
        echo
        echo "Pairwise / Talbot relMSE per seed (paired), mean ± 95% interval:"
        echo
        echo "| N | pairwise / Talbot |"
        echo "|---|---|"
        paired_ratio "$runs" pairwise talbot
    } > "$OUT/fig7.section.md"
}

# ---- (b) GRIS Fig. 8: growing window, one canonical sample ---------------------------------
fig8() {
    GREY=$(grey_cornell); GREF=$(grey_reference)
    runs="$OUT/fig8.runs.csv"; : > "$runs"; : > "$runs.domains"
    for seed in $(seq_seeds); do
        for r in 1 2 3 5 7 10 15; do
            w=$(((2 * r + 1) * (2 * r + 1)))
            for mis in constant pairwise pairwise-defensive talbot; do
                if [ $mis = talbot ] && [ $r -gt "$TALBOT_MAX_R" ]; then continue; fi # O(M^2) shifts
                window_run "$seed" "$runs" "$w" "$mis" --candidates 1 --radius "$r" --mis "$mis"
            done
        done
    done
    summarise "$runs" fig8 window_pixels "GRIS Fig. 8: growing window, N = 1, grey Cornell indirect, ${SIZE}^2, $SEEDS seeds" \
        "window pixels (2r+1)^2" "relMSE (one frame)"
    {
        echo "Setup: as Fig. 7 with N = 1 path tree per pixel and box windows of (2r + 1)² pixels, r = 1, 2, 3, 5, 7, 10, 15 (Talbot only up to r = $TALBOT_MAX_R: (M − 1)² shifts per pixel); ${SIZE} × ${SIZE}, $SEEDS seeds, mean ± 95% interval."
        echo "$(ref_line "$GREF" "$(smallest_mean "$OUT/fig8.csv")") (The same reference as Fig. 7.)"
        echo
        echo "Effective window: the mean number of domains per pixel (the pixel itself and its neighbours inside the image; no other rejection):"
        echo
        echo "| window pixels | domains per pixel inside the image |"
        echo "|---|---|"
        awk -F, '{ if (!($1 in s)) o[++n] = $1; s[$1] += $4; c[$1]++ } END { for (i = 1; i <= n; ++i) printf "| %s | %.4g |\n", o[i], s[o[i]] / c[o[i]] }' "$runs.domains"
        echo
        cat "$OUT/fig8.table.md"
        echo
        echo "Ratio relMSE(961-pixel window) / relMSE(49-pixel window) per seed (paired), mean ± 95% interval:"
        echo "constant $(drop "$runs" constant 961 49), pairwise $(drop "$runs" pairwise 961 49), pairwise defensive $(drop "$runs" pairwise-defensive 961 49); Talbot relMSE($(((2 * TALBOT_MAX_R + 1) * (2 * TALBOT_MAX_R + 1)))) / relMSE(49): $(drop "$runs" talbot $(((2 * TALBOT_MAX_R + 1) * (2 * TALBOT_MAX_R + 1))) 49)."
    } > "$OUT/fig8.section.md"
}

# ---- (c) GRIS Fig. 11: reconnection vs hybrid shift, rough vs glossy Cornell box ------------
# T frames = frames [0, T): the frame ranges [0,1), [1,2), [2,4), [4,8), [8,16) are rendered once
# and merged cumulatively (frames are independent, GRIS Eq. 47), so T = 1..16 cost 16 frames.
F11_OPTS="--method restir --candidates 4 --spatial-passes 3 --neighbors 6 --radius 3"
fig11() {
    runs="$OUT/fig11.runs.csv"; : > "$runs"
    for S in cornell cornell-glossy; do
        ref=$(reference "$S" "$SIZE" "scenes/$S.scene" pt "$F11_REF_SPP")
        eval "ref_$(echo $S | tr - _)=\$ref"
        for seed in $(seq_seeds); do
            for shift in reconnection hybrid; do
                acc="$TMP/f11.acc.pfm"
                render "$SIZE" "scenes/$S.scene" $F11_OPTS --shift $shift --frames 1 --seed "$seed" -o "$acc"
                echo "1,$S $shift,$seed,$(metric relmse "$acc" "$ref.pfm")" >> "$runs"
                for t in 1 2 4 8; do
                    render "$SIZE" "scenes/$S.scene" $F11_OPTS --shift $shift --frames $t --first-frame $t --seed "$seed" \
                        -o "$TMP/f11.part.pfm"
                    "$R" merge -o "$TMP/f11.next.pfm" "$acc" "$TMP/f11.part.pfm" --counts $t,$t --no-png --quiet
                    mv "$TMP/f11.next.pfm" "$acc"
                    echo "$((2 * t)),$S $shift,$seed,$(metric relmse "$acc" "$ref.pfm")" >> "$runs"
                done
            done
        done
    done
    summarise "$runs" fig11 frames "GRIS Fig. 11: shifts on rough vs glossy Cornell box, ${SIZE}^2, $SEEDS seeds" \
        "frames T (4 path trees, 3 passes, 6 neighbours)" "relMSE"
    {
        echo "Setup: \`cornell\` (GGX roughness 0.5) and \`cornell-glossy\` (roughness 0.15), ${SIZE} × ${SIZE}, all light, max depth 10, 4 path trees, 3 spatial passes, 6 neighbours (r2) in radius 3, Talbot MIS, the mean of T independent frames; $SEEDS seeds, mean ± 95% interval."
        echo "cornell: $(ref_line "$ref_cornell" "$(awk -F, 'NR > 1 { if (m == "" || $2 < m) m = $2; if ($3 < m) m = $3 } END { print m }' "$OUT/fig11.csv")")"
        echo "cornell-glossy: $(ref_line "$ref_cornell_glossy" "$(awk -F, 'NR > 1 { if (m == "" || $4 < m) m = $4; if ($5 < m) m = $5 } END { print m }' "$OUT/fig11.csv")")"
        echo "References: path tracer, $F11_REF_SPP spp, seed 9001."
        echo
        cat "$OUT/fig11.table.md"
        echo
        echo "Hybrid / reconnection relMSE per seed (paired: same seed), mean ± 95% interval over seeds:"
        echo
        echo "| T | cornell: hybrid / reconnection |"
        echo "|---|---|"
        paired_ratio "$runs" "cornell hybrid" "cornell reconnection"
        echo
        echo "| T | cornell-glossy: hybrid / reconnection |"
        echo "|---|---|"
        paired_ratio "$runs" "cornell-glossy hybrid" "cornell-glossy reconnection"
    } > "$OUT/fig11.section.md"
}
