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

# ---- helpers (metric, render, reference, summarise ...: scripts/results/lib.sh) -----------------
. "$HERE/results/lib.sh"

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
