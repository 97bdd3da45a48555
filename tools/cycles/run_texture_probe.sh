#!/bin/sh
# The texture probes of docs/environment.md 8.6: 1-sample renders of texture-probe.scene and
# texture-srgb.scene by restir (pixel centres) and by Cycles (exact mapping, and --srgb-node 1),
# then texture_probe.py. For our own checks only; see tools/cycles/README.md.
#   tools/cycles/run_texture_probe.sh [OUT_DIR]
set -eu
OUT=${1:-/tmp/restir-texture-probe}
RESTIR=${RESTIR_BIN:-build/restir}
HERE=$(dirname "$0")
mkdir -p "$OUT"
"$RESTIR" merge -o "$OUT/texels.pfm" "$HERE/texture-probe.png" --counts 1 --no-png --quiet
for probe in probe srgb; do
    scene="$HERE/texture-$probe.scene"
    nice "$RESTIR" render "$scene" --method pt --spp 1 --max-depth 2 --threads 1 \
        -o "$OUT/${probe}_ours.pfm" > "$OUT/${probe}_ours.log" 2>&1
    for mode in 0 1; do
        name=${probe}_cy$([ "$mode" = 1 ] && echo s || true)
        nice blender -b --factory-startup -noaudio --python-exit-code 1 \
            -P "$HERE/restir_to_cycles.py" -- "$scene" "$OUT/$name.exr" --restir "$RESTIR" \
            --samples 1 --max-depth 2 --threads 1 --srgb-node "$mode" > "$OUT/$name.log" 2>&1
        "$RESTIR" merge -o "$OUT/$name.pfm" "$OUT/$name.exr" --counts 1 --no-png --quiet
    done
done
python3 "$HERE/texture_probe.py" "$OUT"
