#!/bin/sh
# Renders SCENE K times with restir's path tracer and K times with Blender Cycles (independent
# seeds 1..K, SPP samples per pixel each, one thread per renderer, both under nice), then
# compares them (compare.py). For our own checks only; see tools/cycles/README.md.
#   tools/cycles/run_compare.sh [SCENE] [K] [SPP] [OUT_DIR]
# Environment: RESTIR_BIN, DEPTH (default 10), CYCLES_ARGS (more options for
# restir_to_cycles.py, e.g. "--srgb-node 1").
set -eu
SCENE=${1:-tools/cycles/courtyard-diffuse.scene}
K=${2:-8}
SPP=${3:-1024}
OUT=${4:-/tmp/restir-cycles}
RESTIR=${RESTIR_BIN:-build/restir}
DEPTH=${DEPTH:-10}
CYCLES_ARGS=${CYCLES_ARGS:-}
HERE=$(dirname "$0")
mkdir -p "$OUT/ours" "$OUT/cycles"
ours() {
    for k in $(seq 1 "$K"); do
        nice "$RESTIR" render "$SCENE" --method pt --spp "$SPP" --jitter --max-depth "$DEPTH" \
            --seed "$k" --threads 1 -o "$OUT/ours/run$k.pfm" > "$OUT/ours/run$k.log" 2>&1
    done
}
cycles() {
    for k in $(seq 1 "$K"); do
        nice blender -b --factory-startup -noaudio --python-exit-code 1 \
            -P "$HERE/restir_to_cycles.py" -- "$SCENE" "$OUT/cycles/run$k.exr" --restir "$RESTIR" \
            --samples "$SPP" --seed "$k" --max-depth "$DEPTH" --threads 1 $CYCLES_ARGS \
            > "$OUT/cycles/run$k.log" 2>&1
        "$RESTIR" merge -o "$OUT/cycles/run$k.pfm" "$OUT/cycles/run$k.exr" --counts 1 > /dev/null
    done
}
ours & P1=$!
cycles & P2=$!
wait $P1
wait $P2
python3 "$HERE/compare.py" "$OUT" "$K"
