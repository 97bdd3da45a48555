#!/bin/sh
# Regenerates the worked example of docs/tour.md (the block between the inspect-example
# markers) from `restir inspect`; test tour_example_matches_inspect keeps them equal.
# usage: scripts/tour_example.sh [RESTIR]   (default build/restir; run from the repository root)
set -e
BIN=${1:-build/restir}
"$BIN" inspect scenes/cornell.scene --size 64x64 --pixel 20,40 --neighbor 23,40 > docs/tour.md.example.tmp
awk -v ex=docs/tour.md.example.tmp '
    /^<!-- inspect-example begin -->$/ { print; print "```"; while ((getline l < ex) > 0) print l; skip = 1; next }
    /^<!-- inspect-example end -->$/ { print "```"; skip = 0 }
    !skip { print }' docs/tour.md > docs/tour.md.tmp
rm -f docs/tour.md.example.tmp
mv docs/tour.md.tmp docs/tour.md
