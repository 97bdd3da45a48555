#!/bin/sh
# docs/performance.md, section "Path-tracer and initial-sampling throughput (ptspeed)": the
# speed-ups of the path tracer and of ReSTIR PT against two earlier builds, and of the
# LTO=1 build against the default one, side by side in one run (tools/ab_cmd.sh: CPU time,
# alternated, median with min..max, outputs compared byte for byte). Minutes; never in make test.
#   sh scripts/performance_ptspeed.sh BASE START NEW NEW_LTO OUT_DIR [ROUNDS]
# BASE: build/restir of main at ea610ee (before any speed work); START: of this branch's
# start (288619d); NEW: this tree's build/restir; NEW_LTO: this tree's `make LTO=1` binary.
set -eu
base=$1 start=$2 new=$3 lto=$4 out=$5 rounds=${6:-3}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
echo "load: $(cat /proc/loadavg 2>/dev/null || uptime)" > "$out/load.txt"

# One command line, three comparisons: base -> new, start -> new, new -> new with LTO.
three() { # label args...
    label=$1
    shift
    for pair in "$base $new base->new" "$start $new start->new" "$new $lto new->lto"; do
        a=${pair%% *} rest=${pair#* }
        b=${rest%% *} name=${rest#* }
        printf '%-24s %-11s ' "$label" "$name"
        sh "$here/tools/ab_cmd.sh" "$a" "$b" "$rounds" "$@"
    done
}

: > "$out/pt.txt"
for sc in cornell cornell-glossy glass ajar corridor pillars shadow; do
    three "pt $sc" render "$here/scenes/$sc.scene" --method pt --spp 2 --size 256x256 --threads 1 >> "$out/pt.txt"
done
: > "$out/restir.txt"
for sc in cornell cornell-glossy glass ajar corridor pillars shadow; do
    three "offline $sc" render "$here/scenes/$sc.scene" --method restir --preset gris-offline --size 128x128 \
        --threads 1 >> "$out/restir.txt"
done
for sc in cornell ajar shadow; do
    three "realtime $sc" render "$here/scenes/$sc.scene" --method restir --preset gris-realtime --sequence 0..3 \
        --size 128x128 --threads 1 >> "$out/restir.txt"
done

# ReSTIR ms per stage (wall clock), the four binaries in turn, ROUNDS times, mean.
: > "$out/stages.rows"
i=0
while [ $i -lt "$rounds" ]; do
    for bin in "$base" "$start" "$new" "$lto"; do
        sh "$here/tools/stage_ms.sh" "$bin" "$here/scenes/cornell.scene" "$out/stage" --method restir \
            --preset gris-realtime --sequence 0..3 --size 128x128 --threads 1 | tr '\n' ' '
    done >> "$out/stages.rows"
    echo >> "$out/stages.rows"
    i=$((i + 1))
done
awk '{for (k = 1; k <= 20; ++k) s[k] += $k}
     END {split("gbuffer initial spatial temporal shade", n, " ");
          printf "stage ms (cornell, gris-realtime, 4 frames, 128x128, 1 thread, mean of %d): base start new lto\n", NR;
          for (k = 1; k <= 5; ++k) printf "%-9s %8.1f %8.1f %8.1f %8.1f\n", n[k], s[k] / NR, s[k + 5] / NR, s[k + 10] / NR, s[k + 15] / NR}' \
    "$out/stages.rows" > "$out/stages.txt"
echo "load at the end: $(cat /proc/loadavg 2>/dev/null || uptime)" >> "$out/load.txt"
cat "$out"/load.txt "$out"/pt.txt "$out"/restir.txt "$out"/stages.txt
