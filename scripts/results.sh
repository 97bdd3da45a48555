#!/bin/sh
# Regenerates the measurements of docs/results.md (GRIS Figs. 7, 8, 11 and offline ReSTIR PT
# vs the path tracer at equal time) with our own CLI: render, compare, merge, plot.
#   make results                          (= sh scripts/results.sh out/results build)
#   SEEDS=2 SIZE=16 make results          (smoke run, ~1 minute; does not touch docs/)
# Knobs (environment): SEEDS (runs per point, default 5), SIZE (Figs. 7, 8, 11 image side,
# default 64), ET_SIZE (equal time, default 2 * SIZE), FIG_REF_SPP (4096; Figs. 7, 8),
# F11_REF_SPP (Fig. 11, default FIG_REF_SPP), TALBOT_MAX_R (7: Fig. 8 Talbot windows), ET_FRAMES (ReSTIR
# frames per equal-time run, 1), ET_SCENES ("cornell ajar"), ET_REF_PT_SPP (1024),
# ET_REF_FRAMES (32), THREADS (2), PARTS ("fig7 fig11 equal_time fig8";
# PARTS=docs WRITE_DOCS=1 only splices the sections of an earlier run into docs/results.md).
# WRITE_DOCS=0 never touches docs/.
# A run with every knob at its default (or WRITE_DOCS=1) also rewrites the generated tables
# of docs/results.md and copies the plots to docs/results/; any knob set makes it a smoke
# run that writes only out/results/.
# References are cached in OUT/cache (keyed by scene, size, method, budget, seed) and reused.
# Not part of `make test`.
set -eu
OUT=${1:-out/results}
BUILD=${2:-build}
R=$BUILD/restir
HERE=$(dirname "$0")
SUMMARY="$HERE/results/summary.awk"

smoke=0
for knob in SEEDS SIZE ET_SIZE FIG_REF_SPP F11_REF_SPP TALBOT_MAX_R ET_FRAMES ET_SCENES ET_REF_PT_SPP ET_REF_FRAMES PARTS; do
    eval "[ -n \"\${$knob+x}\" ]" && smoke=1
done
[ "${WRITE_DOCS:-}" = 1 ] && smoke=0
[ "${WRITE_DOCS:-}" = 0 ] && smoke=1
SEEDS=${SEEDS:-5}
SIZE=${SIZE:-64}
ET_SIZE=${ET_SIZE:-$((2 * SIZE))}
FIG_REF_SPP=${FIG_REF_SPP:-4096}
F11_REF_SPP=${F11_REF_SPP:-$FIG_REF_SPP}
TALBOT_MAX_R=${TALBOT_MAX_R:-7}
ET_FRAMES=${ET_FRAMES:-1}
ET_SCENES=${ET_SCENES:-cornell ajar}
ET_REF_PT_SPP=${ET_REF_PT_SPP:-1024}
ET_REF_FRAMES=${ET_REF_FRAMES:-32}
THREADS=${THREADS:-2}
PARTS=${PARTS:-fig7 fig11 equal_time fig8}
TMP="$OUT/tmp"
CACHE="$OUT/cache"
mkdir -p "$OUT" "$TMP" "$CACHE"

# ---- helpers ------------------------------------------------------------------------------
# metric NAME TEST.pfm REF.pfm: one value from `restir compare`
metric() { "$R" compare "$2" "$3" | awk -v m="$1" '$1 == m { print $2 }'; }
# wall seconds of the rendering of the last run (its --stats file)
render_seconds() { grep -o '"render": [0-9.e+-]*' "$1" | tail -n 1 | awk '{ print $2 }'; }
# render SIDE SCENE options...: one render at SIDE x SIDE
render() {
    side=$1; shift
    "$R" render "$@" --size "${side}x${side}" --threads "$THREADS" --quiet --no-png
}
seq_seeds() { i=1; while [ $i -le "$SEEDS" ]; do echo $i; i=$((i + 1)); done; }
calc() { awk "BEGIN { printf \"%.6g\", $1 }"; }

# reference KEY SIDE SCENE METHOD BUDGET [options...] -> prints the path of the reference.
# Two independent halves A and B (PT: sample ranges [0, n/2) and [n/2, n) of seed 9001;
# ReSTIR: frame ranges [0, F/2) and [F/2, F)) merged into REF. Since REF = (A + B) / 2,
# A - REF = (A - B) / 2 has the variance of REF itself, so compare(A, REF) estimates the
# reference's own error in every metric (relMSE exactly in expectation; MAPE for Gaussian
# noise); written to KEY.err as "relmse mape".
reference() {
    key=$1 side=$2 scene=$3 method=$4 budget=$5; shift 5
    ref="$CACHE/$key-${side}-$method$budget-s9001"
    if [ ! -f "$ref.pfm" ] || [ ! -f "$ref.err" ]; then
        half=$((budget / 2))
        if [ "$method" = pt ]; then
            render "$side" "$scene" --method pt --spp $half --seed 9001 "$@" -o "$ref.a.pfm"
            render "$side" "$scene" --method pt --spp $half --sample-offset $half --seed 9001 "$@" -o "$ref.b.pfm"
        else
            render "$side" "$scene" --method restir --frames $half --seed 9001 "$@" -o "$ref.a.pfm"
            render "$side" "$scene" --method restir --frames $half --first-frame $half --seed 9001 "$@" -o "$ref.b.pfm"
        fi
        "$R" merge -o "$ref.tmp.pfm" "$ref.a.pfm" "$ref.b.pfm" --counts $half,$half --no-png --quiet
        echo "$(metric relmse "$ref.a.pfm" "$ref.tmp.pfm") $(metric mape "$ref.a.pfm" "$ref.tmp.pfm")" > "$ref.err"
        mv "$ref.tmp.pfm" "$ref.pfm"
    fi
    echo "$ref"
}
ref_relmse() { awk '{ print $1 }' "$1.err"; }
ref_mape() { awk '{ print $2 }' "$1.err"; }

# summarise RUNS.csv NAME XNAME TITLE XLABEL YLABEL: NAME.csv (means, plotted to NAME.svg) and
# the markdown table NAME.table.md (mean ± 95% interval over seeds).
summarise() {
    runs=$1 name=$2 xname=$3
    awk -F, -v mode=wide -v xname="$xname" -f "$SUMMARY" "$runs" > "$OUT/$name.csv"
    { awk -F, -v mode=header -v xname="$xname" -f "$SUMMARY" "$runs"
      awk -F, -v mode=md -f "$SUMMARY" "$runs"; } > "$OUT/$name.table.md"
    "$R" plot "$OUT/$name.csv" -o "$OUT/$name.svg" --title "$4" --xlabel "$5" --ylabel "$6"
}
# paired_ratio RUNS.csv NUM DEN: markdown rows "| x | mean ± hw |" of NUM/DEN per seed
paired_ratio() { awk -F, -v mode=ratio -v num="$2" -v den="$3" -f "$SUMMARY" "$1"; }
# drop RUNS.csv SERIES X1 X2: "mean ± hw" of value(X1)/value(X2) per seed
drop() { awk -F, -v mode=drop -v num="$2" -v lo="$3" -v hi="$4" -f "$SUMMARY" "$1"; }

. "$HERE/results/figs.sh"
. "$HERE/results/equal_time.sh"
docs() { :; } # PARTS=docs WRITE_DOCS=1: only splice the sections of an earlier run into docs/

for part in $PARTS; do
    echo "results: $part ($(date -u +%H:%M:%S))" >&2
    $part
done

# ---- docs: splice each generated section between its markers ------------------------------
if [ $smoke = 0 ]; then
    mkdir -p docs/results
    for md in "$OUT"/*.section.md; do
        [ -f "$md" ] || continue
        name=$(basename "$md" .section.md)
        awk -v name="$name" -v file="$md" '
            $0 == "<!-- generated:" name " -->" { print; while ((getline l < file) > 0) print l; skip = 1; next }
            $0 == "<!-- /generated:" name " -->" { skip = 0 }
            !skip { print }' docs/results.md > docs/results.md.tmp
        mv docs/results.md.tmp docs/results.md
    done
    for svg in "$OUT"/*.svg; do [ -f "$svg" ] && cp "$svg" docs/results/; done
    echo "results: docs/results.md and docs/results/*.svg updated" >&2
else
    echo "results: smoke run (a knob was set): docs/ left alone" >&2
fi
echo "results in $OUT"
