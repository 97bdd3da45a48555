#!/bin/sh
# docs/tradeoffs.md: the speed/accuracy trade of every knob a user can turn, measured on
# every shipped scene (make tradeoffs; about 20 minutes on an idle 2-core machine).
#   sh scripts/tradeoffs.sh OUT BUILD FLOAT_BUILD
#   SEEDS=2 SCENES=cornell SIZE=16 sh scripts/tradeoffs.sh    (smoke run; docs/ left alone)
# Knobs (environment): SEEDS (runs per configuration, default 3), SIZE (image side, 32),
# SCENES (the shipped still scenes), REF_SPP (path-traced reference, 2048 spp), REF_FRAMES
# (gris-offline reference frames for REF_RESTIR scenes, 32), REF_RESTIR ("ajar": scenes
# whose path tracer has fireflies; as in scripts/results/equal_time.sh), THREADS (1).
#
# Every configuration renders SEEDS times (seeds 1..SEEDS); each image is compared with
# the scene's reference (`restir compare`: MAPE, relMSE, FLIP, rel_bias) and timed (the
# "render" seconds of --stats). Tables give the mean over seeds with a 95% t interval.
# rel_bias is the signed relative error of the image's mean luminance: its interval
# over seeds tests for bias (the reference's own error, in the table header, is not in
# the interval). One configuration per knob is the baseline; the summary divides every
# configuration's time and relMSE by the baseline's, seed by seed, and takes the
# geometric mean over scenes.
set -eu
OUT=${1:-out/tradeoffs}
BUILD=${2:-build}
FLOAT_BUILD=${3:-build/float}
R=$BUILD/restir
HERE=$(dirname "$0")
SUMMARY="$HERE/results/summary.awk"

smoke=0
for knob in SEEDS SIZE SCENES REF_SPP REF_FRAMES; do
    eval "[ -n \"\${$knob+x}\" ]" && smoke=1
done
SEEDS=${SEEDS:-3}
SIZE=${SIZE:-32}
SCENES=${SCENES:-cornell cornell-glossy ajar corridor glass pillars shadow}
REF_SPP=${REF_SPP:-2048}
REF_FRAMES=${REF_FRAMES:-32}
REF_RESTIR=${REF_RESTIR:-ajar}
THREADS=${THREADS:-1}
TMP="$OUT/tmp"
CACHE=${CACHE:-out/results/cache} # shared with scripts/results.sh (same keys)
mkdir -p "$OUT" "$TMP" "$CACHE"
. "$HERE/results/lib.sh"

# The configurations: knob|label|build (double|float)|options. The first row of a knob
# is its baseline. "offline" is --preset gris-offline (32 path trees, 3 spatial passes,
# 6 neighbours, pairwise-defensive MIS, hybrid shift; GRIS 8.3), one frame.
OFF="--method restir --preset gris-offline"
configs() {
    cat <<EOF
method|PT MIS 16 spp|double|--method pt --spp 16
method|PT NEE 16 spp|double|--method pt --spp 16 --pt-strategy nee
method|PT BSDF 16 spp|double|--method pt --spp 16 --pt-strategy bsdf
method|ReSTIR offline|double|$OFF
method|ReSTIR real-time (4th frame)|double|--method restir --preset gris-realtime --sequence 0..3
samples|PT 16 spp|double|--method pt --spp 16
samples|PT 4 spp|double|--method pt --spp 4
samples|PT 64 spp|double|--method pt --spp 64
samples|offline 1 frame|double|$OFF
samples|offline 4 frames|double|$OFF --frames 4
depth|PT depth 10|double|--method pt --spp 16
depth|PT depth 2|double|--method pt --spp 16 --max-depth 2
depth|PT depth 3|double|--method pt --spp 16 --max-depth 3
depth|PT depth 5|double|--method pt --spp 16 --max-depth 5
depth|offline depth 10|double|$OFF
depth|offline depth 3|double|$OFF --max-depth 3
depth|offline depth 5|double|$OFF --max-depth 5
roulette|PT 16 spp|double|--method pt --spp 16
roulette|PT 16 spp --rr|double|--method pt --spp 16 --rr
roulette|offline|double|$OFF
roulette|offline --russian-roulette|double|$OFF --russian-roulette
precision|PT 16 spp double|double|--method pt --spp 16
precision|PT 16 spp float|float|--method pt --spp 16
precision|offline double|double|$OFF
precision|offline float|float|$OFF
shift|offline hybrid|double|$OFF
shift|offline reconnection|double|$OFF --shift reconnection
shift|offline replay|double|$OFF --shift replay
mis|offline pairwise-defensive|double|$OFF
mis|offline constant (biased)|double|$OFF --mis constant
mis|offline talbot|double|$OFF --mis talbot
mis|offline pairwise|double|$OFF --mis pairwise
mis|offline stochastic-pairwise|double|$OFF --mis stochastic-pairwise
spatial|offline 3 passes x 6|double|$OFF
spatial|offline 0 passes|double|$OFF --spatial-passes 0
spatial|offline 1 pass x 6|double|$OFF --spatial-passes 1
spatial|offline 3 passes x 3|double|$OFF --neighbors 3
spatial|offline 3 passes x 12|double|$OFF --neighbors 12
EOF
}
KNOBS="method samples depth roulette precision shift mis spatial"

scene_reference() { # SCENE -> reference path (cached)
    case " $REF_RESTIR " in
    *" $1 "*) reference "$1-all-gris-offline" "$SIZE" "scenes/$1.scene" restir "$REF_FRAMES" --preset gris-offline \
        --paths all ;;
    *) reference "$1-all" "$SIZE" "scenes/$1.scene" pt "$REF_SPP" ;;
    esac
}

# The real-time configuration is judged on the 4th frame of its sequence: in a scene with
# a moving camera or objects (pillars, shadow) that needs a reference of frame 3.
is_animated() { grep -q '^[[:space:]]*\(keyframe\|animate\)' "scenes/$1.scene"; }
frame3_reference() { # SCENE -> reference path of frame 3 (cached)
    reference "$1-frame3" "$SIZE" "scenes/$1.scene" pt "$REF_SPP" --frame 3
}

# run_one SCENE SEED BUILD OPTIONS -> "seconds,mape,relmse,flip,rel_bias" (cached per
# binary, scene, size, seed, options and reference, so a configuration shared by two
# knobs renders once)
run_one() {
    sc=$1 seed=$2 bin=$3 opts=$4
    judge=$ref
    case "$opts" in *"--sequence 0..3"*) is_animated "$sc" && judge=$ref3 ;; esac
    key=$(printf '%s|%s|%s|%s|%s' "$bin" "$sc" "$SIZE" "$seed" "$opts" | cksum | awk '{ print $1 }')
    [ "$judge" = "$ref" ] || key="$key-frame3"
    row="$OUT/runs/$key"
    if [ ! -f "$row" ]; then
        frames=1
        case "$opts" in *"--sequence 0..3"*) frames=4 ;; esac
        # shellcheck disable=SC2086 # options are words
        "$bin/restir" render "scenes/$sc.scene" $opts --seed "$seed" --size "${SIZE}x${SIZE}" --threads "$THREADS" \
            --quiet --no-png -o "$TMP/run.pfm" --stats "$TMP/run.json"
        img="$TMP/run.pfm"
        [ $frames = 4 ] && img="$TMP/run.0003.pfm"
        t=$(render_seconds "$TMP/run.json")
        "$R" compare "$img" "$judge.pfm" > "$TMP/run.cmp"
        m() { awk -v m="$1" '$1 == m { print $2 }' "$TMP/run.cmp"; }
        echo "$(calc "$t / $frames"),$(m mape),$(m relmse),$(m flip_hdr),$(m rel_bias)" > "$row.tmp"
        mv "$row.tmp" "$row"
        echo "$t" >> "$TMP/rendered"
    fi
    cat "$row"
}

mkdir -p "$OUT/runs"
runs="$OUT/runs.csv"
: > "$runs"
refs="$OUT/refs.md"
: > "$refs"
: > "$TMP/rendered"
start=$(date +%s)
for sc in $SCENES; do
    ref=$(scene_reference "$sc")
    echo "| $sc | $(basename "$ref") | $(ref_relmse "$ref") | $(ref_mape "$ref") |" >> "$refs"
    ref3=$ref
    if is_animated "$sc"; then
        ref3=$(frame3_reference "$sc")
        echo "| $sc, frame 3 (real-time) | $(basename "$ref3") | $(ref_relmse "$ref3") | $(ref_mape "$ref3") |" >> "$refs"
    fi
    echo "tradeoffs: $sc ($(date -u +%H:%M:%S))" >&2
    configs | while IFS='|' read -r knob label prec opts; do
        bin=$BUILD
        [ "$prec" = float ] && bin=$FLOAT_BUILD
        for seed in $(seq_seeds); do
            echo "$knob,$label,$sc,$seed,$(run_one "$sc" "$seed" "$bin" "$opts")" >> "$runs"
        done
    done
done
elapsed=$(($(date +%s) - start))

# ---- tables -----------------------------------------------------------------------------
# long rows for summary.awk: x = label, series = metric, seed = scene:seed
metric_rows() { # KNOB SCENE
    awk -F, -v k="$1" -v sc="$2" '$1 == k && $3 == sc {
        print $2 ",seconds," $4 "," $5; print $2 ",MAPE," $4 "," $6; print $2 ",relMSE," $4 "," $7
        print $2 ",FLIP," $4 "," $8; print $2 ",rel_bias," $4 "," $9 }' "$runs"
}
# per-seed ratios to the knob's baseline, geometric mean over scenes and seeds with a 95% t
# interval on the log: "| label | time ratio | relMSE ratio | efficiency ratio |"
ratio_table() { # KNOB
    awk -F, -v k="$1" -v ttable="$(t_table)" '
        BEGIN { NT = split(ttable, T, " ") }
        function tq(df) { return df <= NT ? T[df] : T[NT] }
        function gm(s, q, n,    m, v, h) {
            if (n < 1) return "–"
            m = s / n; if (n < 2) return sprintf("%.3g", exp(m))
            v = (q - n * m * m) / (n - 1); if (v < 0) v = 0; h = tq(n - 1) * sqrt(v / n)
            return sprintf("%.3g [%.3g, %.3g]", exp(m), exp(m - h), exp(m + h))
        }
        $1 == k {
            if (base == "") base = $2
            if (!($2 in seen)) { seen[$2] = 1; order[++n] = $2 }
            t[$2, $3, $4] = $5; e[$2, $3, $4] = $7; key[$3, $4] = 1
        }
        END {
            for (i = 1; i <= n; ++i) {
                l = order[i]; st = qt = se = qe = sf = qf = c = 0
                for (sk in key) {
                    split(sk, p, SUBSEP)
                    if (t[l, p[1], p[2]] <= 0 || t[base, p[1], p[2]] <= 0 || e[l, p[1], p[2]] <= 0 || e[base, p[1], p[2]] <= 0) continue
                    a = log(t[l, p[1], p[2]] / t[base, p[1], p[2]]); b = log(e[l, p[1], p[2]] / e[base, p[1], p[2]])
                    st += a; qt += a * a; se += b; qe += b * b; sf -= a + b; qf += (a + b) * (a + b); c++
                }
                printf "| %s | %s | %s | %s |\n", l, gm(st, qt, c), gm(se, qe, c), gm(sf, qf, c)
            }
        }' "$runs"
}
# plot CSV: x = seconds (mean over seeds), one column per scene = relMSE (mean), the
# configurations of the knob as points in order of time
plot_knob() { # KNOB
    awk -F, -v k="$1" -v scenes="$SCENES" '
        BEGIN { ns = split(scenes, S, " "); printf "seconds"; for (i = 1; i <= ns; ++i) printf ",%s", S[i]; print "" }
        $1 == k { n[$2, $3]++; t[$2, $3] += $5; e[$2, $3] += $7; if (!($2 in seen)) { seen[$2] = 1; L[++nl] = $2 } }
        END {
            for (i = 1; i <= ns; ++i) for (j = 1; j <= nl; ++j) {
                if (!n[L[j], S[i]]) continue
                printf "%.6g", t[L[j], S[i]] / n[L[j], S[i]]
                for (c = 1; c <= ns; ++c) printf ",%s", c == i ? sprintf("%.6g", e[L[j], S[i]] / n[L[j], S[i]]) : ""
                print ""
            }
        }' "$runs" | { IFS= read -r h; echo "$h"; sort -t, -g -k1,1; } > "$OUT/tradeoffs-$1.csv"
    "$R" plot "$OUT/tradeoffs-$1.csv" -o "$OUT/tradeoffs-$1.svg" --title "$1: relMSE against time (${SIZE}x${SIZE})" \
        --xlabel "render seconds (1 thread)" --ylabel "relMSE"
}

section="$OUT/tradeoffs.section.md"
{
    echo "Run of $(date -u +%Y-%m-%d): ${SIZE}x${SIZE} pixels, $SEEDS seeds per configuration, $THREADS thread,"
    echo "$(nproc 2>/dev/null || echo ?) cores, load average $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo ?) at the end;"
    echo "$elapsed s in all, of which this invocation rendered $(wc -l < "$TMP/rendered") of the $(wc -l < "$runs") runs"
    echo "(the others were cached in $OUT/runs by an earlier invocation). Scenes: $SCENES."
    echo
    echo "References (the reference's own error in relMSE and MAPE, estimated from its two halves):"
    echo
    echo "| scene | reference | relMSE | MAPE |"
    echo "|---|---|---|---|"
    cat "$refs"
    for knob in $KNOBS; do
        echo
        echo "### Knob: $knob"
        echo
        echo "Against the baseline (first row), per seed and scene; geometric mean over scenes and"
        echo "seeds [95% interval]. Efficiency = 1 / (time x relMSE): > 1 is better than the baseline."
        echo
        echo "| configuration | time ratio | relMSE ratio | efficiency ratio |"
        echo "|---|---|---|---|"
        ratio_table "$knob"
        plot_knob "$knob"
        echo
        echo "![$knob](tradeoffs/tradeoffs-$knob.svg)"
        for sc in $SCENES; do
            metric_rows "$knob" "$sc" > "$TMP/knob.csv"
            echo
            echo "**$sc**"
            echo
            summary -v mode=header -v xname=configuration "$TMP/knob.csv"
            summary -v mode=md "$TMP/knob.csv"
        done
    done
} > "$section"

if [ $smoke = 0 ]; then
    mkdir -p docs/tradeoffs
    awk -v file="$section" '
        $0 == "<!-- generated:tradeoffs -->" { print; while ((getline l < file) > 0) print l; skip = 1; next }
        $0 == "<!-- /generated:tradeoffs -->" { skip = 0 }
        !skip { print }' docs/tradeoffs.md > docs/tradeoffs.md.tmp
    mv docs/tradeoffs.md.tmp docs/tradeoffs.md
    cp "$OUT"/tradeoffs-*.svg docs/tradeoffs/
    echo "tradeoffs: docs/tradeoffs.md and docs/tradeoffs/*.svg updated" >&2
else
    echo "tradeoffs: smoke run (a knob was set): docs/ left alone; see $section" >&2
fi
