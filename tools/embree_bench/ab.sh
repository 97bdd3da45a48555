#!/bin/sh
# Embree yardstick, before/after: two embree_bench binaries (e.g. one built from main, one
# from this tree) run alternately, ROUNDS runs each, on the issue's bunny view, on the
# 1M-triangle displaced sphere and on the generated Sponza-like atrium (docs/scenes.md §11;
# 1024x1024, written by this tree's restir binary: $RESTIR, default build/restir). Prints one
# row per scene and ray kind: the ratio restir/Embree of every run of A and of B (each run's
# ratio is the median of its interleaved repetitions), then restir's and Embree's Mrays per
# CPU second of B's runs.
#   tools/embree_bench/ab.sh A_HARNESS B_HARNESS [ROUNDS=2] [REPEATS=5]
set -eu
a=$1 b=$2 rounds=${3:-2} repeats=${4:-5}
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
field() { # file kind name -> value
    grep "\"rays\": \"$2\"" "$1" | sed "s/.*\"$3\": \([0-9.]*\).*/\1/"
}
restir=${RESTIR:-$here/../../build/restir}
"$restir" generate atrium -o "$tmp/atrium.obj" > /dev/null
for scene in bunny sphere atrium; do
    i=0
    while [ "$i" -lt "$rounds" ]; do
        for which in a b; do
            bin=$a
            [ "$which" = b ] && bin=$b
            if [ "$scene" = bunny ]; then
                (cd "$here" && nice -n 5 "$bin" bunny.scene --repeats "$repeats") > "$tmp/$scene.$which.$i"
            elif [ "$scene" = atrium ]; then
                nice -n 5 "$bin" "$tmp/atrium.scene" --size 1024x1024 --repeats "$repeats" > "$tmp/$scene.$which.$i"
            else
                nice -n 5 "$bin" --generated 289 --size 512x512 --repeats "$repeats" > "$tmp/$scene.$which.$i"
            fi
        done
        i=$((i + 1))
    done
    for kind in primary diffuse_bounce shadow; do
        ra="" rb="" mr="" me=""
        i=0
        while [ "$i" -lt "$rounds" ]; do
            ra="$ra $(field "$tmp/$scene.a.$i" $kind ratio)"
            rb="$rb $(field "$tmp/$scene.b.$i" $kind ratio)"
            mr="$mr $(field "$tmp/$scene.b.$i" $kind restir_mrays)"
            me="$me $(field "$tmp/$scene.b.$i" $kind embree_mrays)"
            i=$((i + 1))
        done
        echo "$scene $kind | A:$ra | B:$rb | B restir Mrays:$mr | Embree Mrays:$me"
    done
done
cat /proc/loadavg
