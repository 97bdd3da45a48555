#!/bin/sh
# docs/performance.md, section "Offline ReSTIR per candidate path on a CPU (issue 28)":
# BEFORE against AFTER, side by side in one run (tools/ab_cmd.sh: CPU time from task-clock,
# alternated, median with min..max, every output compared byte for byte), on five scenes at
# 128², one thread: the gris-offline frame, its initial sampling alone (--spatial-passes 0:
# 32 path trees per pixel) and the path tracer with as many paths (--spp 32); then the
# wall-clock stage timers of --stats (initial, spatial[3]), mean of ROUNDS runs per binary.
# Minutes; never in make test.
#   sh scripts/performance_candidates.sh BEFORE AFTER OUT_DIR [ROUNDS]
set -eu
before=$1 after=$2 out=$3 rounds=${4:-5}
here=$(cd "$(dirname "$0")/.." && pwd)
scenes="cornell ajar textured-room courtyard many-lights"
common="--size 128x128 --threads 1 --quiet --no-png"
mkdir -p "$out"
echo "load: $(cat /proc/loadavg 2>/dev/null || uptime)" > "$out/load.txt"

: > "$out/ab.txt"
for sc in $scenes; do
    s="$here/scenes/$sc.scene"
    for run in "frame:--method restir --preset gris-offline" \
               "initial:--method restir --preset gris-offline --spatial-passes 0" \
               "pt32:--method pt --spp 32"; do
        printf '%-14s %-8s ' "$sc" "${run%%:*}" >> "$out/ab.txt"
        # shellcheck disable=SC2086 # the option lists are meant to split
        sh "$here/tools/ab_cmd.sh" "$before" "$after" "$rounds" render "$s" ${run#*:} $common >> "$out/ab.txt"
    done
done

# Stage timers (wall clock inside the process; one thread): initial and the three spatial passes.
: > "$out/stages.raw"
for sc in $scenes; do
    for bin in "$before" "$after"; do
        i=0
        while [ $i -lt "$rounds" ]; do
            # shellcheck disable=SC2086
            "$bin" render "$here/scenes/$sc.scene" --method restir --preset gris-offline $common \
                -o "$out/stage.pfm" --stats "$out/stage.json" > /dev/null
            python3 -c 'import json, sys; m = json.load(open(sys.argv[1]))["restir"]["stats"]["milliseconds"]
print(sys.argv[2], sys.argv[3], m["initial"], *m["spatial"])' "$out/stage.json" "$sc" "$bin" >> "$out/stages.raw"
            i=$((i + 1))
        done
    done
done
rm -f "$out/stage.pfm" "$out/stage.json"
awk '{k = $1 " " $2; n[k]++; ini[k] += $3; sp[k] += ($4 + $5 + $6) / 3}
     END {for (k in n) printf "%s initial %.1f ms, spatial %.1f ms per pass\n", k, ini[k] / n[k], sp[k] / n[k]}' \
    "$out/stages.raw" | sort > "$out/stages.txt"
echo "load after: $(cat /proc/loadavg 2>/dev/null || uptime)" >> "$out/load.txt"
