#!/bin/sh
# The measurements of docs/performance.md (issue 17), side by side in one run: every
# figure is a ratio of two things run alternately (A, B, B, A, ...) on the same loaded
# machine, reported as the median over rounds with min..max. Minutes; never in make test.
#   sh scripts/performance.sh BASE_BIN NEW_BIN OUT_DIR [ROUNDS]
# BASE_BIN: build/restir of the code before the speed work (main at ea610ee);
# NEW_BIN: this tree's build/restir. The Embree yardstick (tools/embree_bench) is run
# separately (docs/performance.md says how).
set -eu
base=$1 new=$2 out=$3 rounds=${4:-3}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
echo "load: $(cat /proc/loadavg 2>/dev/null || uptime)" > "$out/load.txt"

# The generated Sponza-like atrium (docs/scenes.md §11) is not shipped: NEW writes it, both
# binaries render it (BASE predates the generator but loads the OBJ).
mkdir -p "$out/atrium"
"$new" generate atrium -o "$out/atrium/atrium.obj" > /dev/null
scene_file() { # name -> path
    if [ "$1" = atrium ]; then echo "$out/atrium/atrium.scene"; else echo "$here/scenes/$1.scene"; fi
}

# 1. Path tracer, 1 thread, CPU time, every shipped scene and the atrium (256x256, 2 spp; the
#    atrium 8 spp, so that loading its 266k triangles is not most of the run).
: > "$out/pt.txt"
for sc in cornell cornell-glossy glass ajar corridor pillars shadow atrium; do
    spp=2
    [ "$sc" = atrium ] && spp=8
    printf '%-15s ' "$sc" >> "$out/pt.txt"
    sh "$here/tools/ab_cmd.sh" "$base" "$new" "$rounds" render "$(scene_file "$sc")" --method pt --spp $spp \
        --size 256x256 --threads 1 >> "$out/pt.txt"
done

# 2. ReSTIR PT, 1 thread, CPU time of a whole run: the offline frame (GRIS offline preset)
#    and the real-time pipeline (4 frames of the real-time preset).
: > "$out/restir.txt"
for sc in cornell cornell-glossy glass ajar corridor pillars shadow atrium; do
    printf '%-15s offline  ' "$sc" >> "$out/restir.txt"
    sh "$here/tools/ab_cmd.sh" "$base" "$new" "$rounds" render "$(scene_file "$sc")" --method restir \
        --preset gris-offline --size 128x128 --threads 1 >> "$out/restir.txt"
done
for sc in cornell ajar shadow; do
    printf '%-15s realtime ' "$sc" >> "$out/restir.txt"
    sh "$here/tools/ab_cmd.sh" "$base" "$new" "$rounds" render "$here/scenes/$sc.scene" --method restir \
        --preset gris-realtime --sequence 0..3 --size 128x128 --threads 1 >> "$out/restir.txt"
done

# 3. ReSTIR ms per stage (wall clock, from --stats), base vs new, interleaved.
stage_ms() { # bin name -> "gbuffer initial spatial temporal shade" (ms summed over frames)
    sh "$here/tools/stage_ms.sh" "$1" "$here/scenes/cornell.scene" "$out/$2" --method restir --preset gris-realtime \
        --sequence 0..3 --size 128x128 --threads 1
}
: > "$out/stages.rows"
i=0
while [ $i -lt "$rounds" ]; do
    if [ $((i % 2)) -eq 0 ]; then
        a=$(stage_ms "$base" a); b=$(stage_ms "$new" b)
    else
        b=$(stage_ms "$new" b); a=$(stage_ms "$base" a)
    fi
    echo "$a $b" >> "$out/stages.rows"
    i=$((i + 1))
done
awk '{for (k = 1; k <= 5; ++k) {sa[k] += $k; sb[k] += $(k + 5)}}
     END {split("gbuffer initial spatial temporal shade", n, " ");
          for (k = 1; k <= 5; ++k) printf "%-9s ms (4 frames, 128x128, 1 thread, mean of %d) base %.1f new %.1f ratio %.2f\n",
                                          n[k], NR, sa[k] / NR, sb[k] / NR, (sb[k] > 0 ? sa[k] / sb[k] : 0)}' \
    "$out/stages.rows" > "$out/stages.txt"

# 4. Thread scaling, new binary: 1 vs 2 threads, wall clock and CPU time, PT on the
#    Cornell box at 512x512, 4 spp (a frame of 64 tiles of 16x16... 1024 tiles).
wall_cpu() { # threads -> "wall_s cpu_s"
    nice -n 5 perf stat -x, -e task-clock -o "$out/ts.stat" "$new" render "$here/scenes/cornell.scene" --method pt \
        --spp 4 --threads "$1" -o "$out/ts.pfm" --stats "$out/ts.json" > /dev/null 2>&1
    echo "$(tr -d '\n' < "$out/ts.json" | sed 's/.*"render": \([0-9.]*\).*/\1/') $(grep task-clock "$out/ts.stat" | cut -d, -f1)"
}
: > "$out/threads.rows"
i=0
while [ $i -lt "$rounds" ]; do
    if [ $((i % 2)) -eq 0 ]; then one=$(wall_cpu 1); two=$(wall_cpu 2); else two=$(wall_cpu 2); one=$(wall_cpu 1); fi
    echo "$one $two" >> "$out/threads.rows"
    i=$((i + 1))
done
awk '{print $1 / $3, ($4 / 1000) / ($2 / 1000)}' "$out/threads.rows" | sort -g | awk '
    {s[NR] = $1; c[NR] = $2}
    END {printf "2 threads vs 1: wall speed-up median %.2f (min %.2f, max %.2f; rounds %d); CPU time ratio 2T/1T %.3f..%.3f\n",
                s[int((NR + 1) / 2)], s[1], s[NR], NR, c[1], c[NR]}' > "$out/threads.txt"
echo "load at the end: $(cat /proc/loadavg 2>/dev/null || uptime)" >> "$out/load.txt"
cat "$out"/load.txt "$out"/pt.txt "$out"/restir.txt "$out"/stages.txt "$out"/threads.txt
