#!/bin/sh
# A/B ray throughput of two restir binaries on one scene, side by side in one run:
# N rounds, each runs `bench rays --threads 1 --repeats 3` of A and of B (alternating
# which goes first), and takes the per-core Mrays/s (CPU time, less sensitive to other
# load). Prints per kind the median B/A ratio over the rounds with its min..max.
#   tools/ab_rays.sh A_BIN B_BIN SCENE|--generated=N [ROUNDS=7] [SIZE=512x512]
set -eu
a=$1 b=$2 scene=$3 rounds=${4:-7} size=${5:-512x512}
case $scene in --generated=*) src="--generated ${scene#--generated=}" ;; *) src=$scene ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
per_core() { # file kind -> number (the 1-thread result's per_core entry)
    tr -d '\n' < "$1" | sed 's/.*"per_core": {\([^}]*\)}.*/\1/' | sed "s/.*\"$2_mrays\": \([0-9.]*\).*/\1/"
}
i=0
while [ $i -lt "$rounds" ]; do
    if [ $((i % 2)) -eq 0 ]; then first=$a second=$b; else first=$b second=$a; fi
    nice -n 5 "$first" bench rays $src --threads 1 --repeats 3 --size "$size" > "$tmp/1.json"
    nice -n 5 "$second" bench rays $src --threads 1 --repeats 3 --size "$size" > "$tmp/2.json"
    if [ "$first" = "$a" ]; then fa=$tmp/1.json fb=$tmp/2.json; else fa=$tmp/2.json fb=$tmp/1.json; fi
    for k in primary secondary shadow; do
        echo "$k $(per_core "$fa" $k) $(per_core "$fb" $k)" >> "$tmp/rows"
    done
    i=$((i + 1))
done
for k in primary secondary shadow; do
    grep "^$k " "$tmp/rows" | awk '{print $3 / $2, $2, $3}' | sort -g | awk -v k=$k '
        {r[NR] = $1; a[NR] = $2; b[NR] = $3}
        END {m = (NR % 2) ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2;
             printf "%-9s B/A median %.3f  min %.3f  max %.3f  (rounds %d)\n", k, m, r[1], r[NR], NR}'
done
