#!/bin/sh
# `make run`: what an oracle does, in about two minutes on 2 cores (docs/tour.md §0).
#
#   1. the Cornell box with the reference path tracer and with offline ReSTIR PT
#      (gris-offline preset) at equal time, each as PFM + PNG;
#   2. MAPE and FLIP of each against a reference, with FLIP error maps;
#   3. `restir check`: do ReSTIR and the path tracer estimate the same image? (K independent
#      runs of each; docs/statistics.md);
#   4. a summary, and the list of files written.
#
# usage: scripts/demo.sh [OUT [RESTIR]]   (defaults out, build/restir; run from the repository root)
# environment (the README test uses small values): DEMO_SIZE (128x128), DEMO_SECONDS (15, per
# method), DEMO_RUNS (16, per side of check), DEMO_CHECK_SPP (32, path tracer spp per check run),
# DEMO_REF_SPP (1024: only when the shipped 128x128 reference does not apply and one is built).
set -e
OUT=${1:-out}
BIN=${2:-build/restir}
SIZE=${DEMO_SIZE:-128x128}
SECS=${DEMO_SECONDS:-15}
RUNS=${DEMO_RUNS:-16}
CHECK_SPP=${DEMO_CHECK_SPP:-32}
SCENE=scenes/cornell.scene
SHIPPED=scenes/reference/cornell-128x128.pfm
mkdir -p "$OUT/check"

# "render": seconds of the render itself, from a --stats file
render_seconds() { sed -n 's/.*"render": \([0-9.]*\).*/\1/p' "$1"; }
# one metric of a `compare --json` file
metric() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1" | head -n 1; }

if [ "$SIZE" = 128x128 ] && [ -f "$SHIPPED" ]; then
    REF=$SHIPPED
    REF_NOTE="shipped $SHIPPED (path tracer, 4096 spp; its own MAPE ~1.1%: docs/reference-renders.md)"
else
    REF=$OUT/cornell-reference.pfm
    REF_NOTE="built on the way: path tracer ${DEMO_REF_SPP:-1024} spp at $SIZE ($REF)"
    echo "== reference: path tracer, ${DEMO_REF_SPP:-1024} spp at $SIZE"
    "$BIN" render $SCENE --size "$SIZE" --method pt --spp "${DEMO_REF_SPP:-1024}" --seed 1000 -o "$REF" --quiet
fi

echo "== equal time at $SIZE: offline ReSTIR PT (gris-offline) for whole frames until $SECS s, then the path tracer as long"
"$BIN" render $SCENE --size "$SIZE" --method restir --preset gris-offline --time-limit "$SECS" \
    -o "$OUT/cornell-restir.pfm" --stats "$OUT/cornell-restir.stats.json" --quiet
# ReSTIR stops after the whole frame that crosses the limit: the path tracer gets the time
# ReSTIR actually took, so the comparison is at equal time
PT_SECS=$(render_seconds "$OUT/cornell-restir.stats.json")
"$BIN" render $SCENE --size "$SIZE" --method pt --spp 0 --time-limit "$PT_SECS" \
    -o "$OUT/cornell-pt.pfm" --stats "$OUT/cornell-pt.stats.json" --quiet
for m in restir pt; do
    "$BIN" compare "$OUT/cornell-$m.pfm" "$REF" --json "$OUT/cornell-$m.compare.json" \
        --error-map "$OUT/cornell-$m.flip.png" > /dev/null
done

echo "== check: $RUNS independent runs of each (ReSTIR 1 frame, path tracer $CHECK_SPP spp)"
"$BIN" render $SCENE --size "$SIZE" --method restir --preset gris-offline --runs "$RUNS" --seed 100 \
    -o "$OUT/check/restir.pfm" --quiet
"$BIN" render $SCENE --size "$SIZE" --method pt --spp "$CHECK_SPP" --runs "$RUNS" --seed 100 \
    -o "$OUT/check/pt.pfm" --quiet
set +e
"$BIN" check --a-moments "$OUT/check/restir" --b-moments "$OUT/check/pt" --json "$OUT/check/verdict.json" \
    > "$OUT/check/verdict.txt" 2>&1
status=$?
set -e
[ $status -le 1 ] || [ $status = 3 ] || { cat "$OUT/check/verdict.txt"; exit 2; }
verdict=$(sed -n 's/^verdict: //p' "$OUT/check/verdict.txt")
bias=$(sed -n 's/^relative bias A\/B - 1: //p' "$OUT/check/verdict.txt")

echo
echo "summary (cornell $SIZE; reference: $REF_NOTE)"
printf '  %-22s %8s %10s %10s %10s\n' method seconds samples MAPE FLIP
printf '  %-22s %8.2f %10s %10.4f %10.4f\n' "ReSTIR PT (offline)" "$(render_seconds "$OUT/cornell-restir.stats.json")" \
    "$(sed -n 's/.*"frames": \([0-9]*\),$/\1/p' "$OUT/cornell-restir.stats.json" | head -n 1) fr" \
    "$(metric "$OUT/cornell-restir.compare.json" mape)" "$(metric "$OUT/cornell-restir.compare.json" flip_hdr)"
printf '  %-22s %8.2f %10s %10.4f %10.4f\n' "path tracer" "$(render_seconds "$OUT/cornell-pt.stats.json")" \
    "$(sed -n 's/.*"spp": \([0-9]*\),.*/\1/p' "$OUT/cornell-pt.stats.json") spp" \
    "$(metric "$OUT/cornell-pt.compare.json" mape)" "$(metric "$OUT/cornell-pt.compare.json" flip_hdr)"
echo "  check ReSTIR vs path tracer ($RUNS runs each): $verdict; relative bias $bias"
echo
echo "files:"
for f in "$OUT"/cornell-restir.pfm "$OUT"/cornell-restir.png "$OUT"/cornell-restir.flip.png \
    "$OUT"/cornell-pt.pfm "$OUT"/cornell-pt.png "$OUT"/cornell-pt.flip.png \
    "$OUT"/cornell-restir.compare.json "$OUT"/cornell-pt.compare.json \
    "$OUT"/check/verdict.txt "$OUT"/check/verdict.json; do
    [ -f "$f" ] && echo "  $f"
done
[ "$REF" = "$SHIPPED" ] || echo "  $REF"
[ $status -eq 0 ] || { echo "demo: check says the two estimators DIFFER (exit 1)" >&2; exit 1; }
