#!/bin/sh
# The Embree yardstick by two independently written harnesses (issue 28): embree_bench
# (the rays of `restir bench rays`, CPU time, A/B interleaved) and sceptic_embree_bench (its
# own pixel-centre camera rays and Embree-spawned secondaries, wall and CPU time, each
# tracer's repetitions in a row), run alternately ROUNDS times on the issue's 1024² bunny view.
# One line per run and ray kind: harness, clock, ratio restir/Embree, and the load average at
# the start of the run (the machine is shared: read the CPU-time ratios when it was busy).
#   tools/embree_bench/two_harnesses.sh [ROUNDS=3] [REPEATS=7]
set -eu
rounds=${1:-3} repeats=${2:-7}
here=$(cd "$(dirname "$0")" && pwd)
cd "$here"
printf 'run\tharness\tclock\tprimary\tdiffuse_bounce\tshadow\tload1\n'
ratio() { # file kind [clock]
    if [ $# -eq 3 ]; then
        grep "\"rays\": \"$2\"" "$1" | sed "s/.*\"$3\": {[^}]*\"ratio\": \([0-9.]*\)}.*/\1/"
    else
        grep "\"rays\": \"$2\"" "$1" | sed 's/.*"ratio": \([0-9.]*\),.*/\1/'
    fi
}
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
i=1
while [ "$i" -le "$rounds" ]; do
    load=$(cut -d' ' -f1 /proc/loadavg)
    ./embree_bench bunny.scene --repeats "$repeats" > "$tmp"
    printf '%d\tembree_bench\tcpu\t%s\t%s\t%s\t%s\n' "$i" "$(ratio "$tmp" primary)" "$(ratio "$tmp" diffuse_bounce)" \
        "$(ratio "$tmp" shadow)" "$load"
    load=$(cut -d' ' -f1 /proc/loadavg)
    ./sceptic_embree_bench bunny.scene 1024x1024 "$repeats" > "$tmp"
    for clock in cpu wall; do
        printf '%d\tsceptic_bench\t%s\t%s\t%s\t%s\t%s\n' "$i" "$clock" "$(ratio "$tmp" primary $clock)" \
            "$(ratio "$tmp" diffuse_bounce $clock)" "$(ratio "$tmp" shadow $clock)" "$load"
    done
    i=$((i + 1))
done
