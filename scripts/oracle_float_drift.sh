#!/bin/sh
# Float vs double drift per stage (docs/oracle.md §4): the binary32 build acts as the "other
# implementation". Dumps both builds on the same scene/seed and diffs them stage by stage.
# Usage: scripts/oracle_float_drift.sh OUTDIR [SIZE] [FRAMES] [SEEDS...]
# Needs build/restir and build/float/restir (make; make PRECISION=float).
set -e
out=${1:?OUTDIR}; size=${2:-64x48}; frames=${3:-0..3}; shift 3 2>/dev/null || shift $#
seeds=${*:-1 2 3}
mkdir -p "$out"
for scene in pillars cornell; do
    for seed in $seeds; do
        for build in build build/float; do
            tag=$(echo $build | tr / _)
            ./$build/restir render scenes/$scene.scene --method restir --preset gris-realtime --spatial-passes 2 \
                --size $size --sequence $frames --seed $seed --quiet --no-png --threads 2 \
                -o "$out/$scene-$seed-$tag.pfm" --dump-dir "$out/$scene-$seed-$tag" >/dev/null
        done
        ./build/restir diff-dump "$out/$scene-$seed-build" "$out/$scene-$seed-build_float" --json --first 0 \
            > "$out/$scene-$seed.json" || true
    done
done
