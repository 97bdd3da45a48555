#!/bin/sh
# A/B CPU time of one restir command line run by two binaries, side by side in one run:
# ROUNDS rounds, alternating which binary goes first, each timed by its CPU time (user +
# system, from perf stat's task-clock: insensitive to waiting for a core on a loaded
# machine). Prints the median A/B time ratio (the speed-up of B) with its min..max, and
# whether the two wrote the same bytes (-o OUT is appended: every output file is compared).
#   tools/ab_cmd.sh A_BIN B_BIN ROUNDS ARGS...      e.g.
#   tools/ab_cmd.sh old/restir build/restir 5 render scenes/cornell.scene --method pt --spp 4 --threads 1
set -eu
a=$1 b=$2 rounds=$3
shift 3
tmp=$(mktemp -d)
mkdir "$tmp/a" "$tmp/b"
trap 'rm -rf "$tmp"' EXIT
cpu_ms() { # bin out -> task-clock in ms
    bin=$1 out=$2; shift 2; nice -n 5 perf stat -x, -e task-clock -o "$tmp/stat" "$bin" "$@" -o "$out" > /dev/null 2>&1 || true
    grep task-clock "$tmp/stat" | cut -d, -f1
}
i=0
while [ $i -lt "$rounds" ]; do
    if [ $((i % 2)) -eq 0 ]; then
        ta=$(cpu_ms "$a" "$tmp/a/out.pfm" "$@"); tb=$(cpu_ms "$b" "$tmp/b/out.pfm" "$@")
    else
        tb=$(cpu_ms "$b" "$tmp/b/out.pfm" "$@"); ta=$(cpu_ms "$a" "$tmp/a/out.pfm" "$@")
    fi
    echo "$ta $tb" >> "$tmp/rows"
    i=$((i + 1))
done
same=no
# Every file written (a --sequence writes out.0000.pfm, ...; PNG previews too).
[ -n "$(ls "$tmp/a")" ] && diff -r -q "$tmp/a" "$tmp/b" > /dev/null && same=yes
awk '{print $1 / $2, $1, $2}' "$tmp/rows" | sort -g | awk -v same=$same '
    {r[NR] = $1; a += $2; b += $3}
    END {m = (NR % 2) ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2;
         printf "speed-up A/B median %.3f  min %.3f  max %.3f  (rounds %d; mean CPU ms A %.0f B %.0f; outputs identical: %s)\n",
                m, r[1], r[NR], NR, a / NR, b / NR, same}'
