#!/bin/sh
# ReSTIR milliseconds per stage of one `restir render` run, summed over its frames (the
# stage timers of --stats; wall clock, so rough on a loaded machine). Prints one line:
# "gbuffer initial spatial temporal shade" (spatial: the first pass).
#   tools/stage_ms.sh BIN SCENE OUT_DIR ARGS...   e.g.
#   tools/stage_ms.sh build/restir scenes/cornell.scene /tmp/s --method restir --preset gris-realtime --sequence 0..3
set -eu
bin=$1 scene=$2 out=$3
shift 3
mkdir -p "$out"
nice -n 5 "$bin" render "$scene" "$@" -o "$out/stage.pfm" --stats "$out/stage.json" > /dev/null 2>&1
tr -d '\n' < "$out/stage.json" | sed 's/.*"milliseconds": {\([^}]*\)}.*/\1/' |
    sed 's/"gbuffer": \([0-9.]*\), "initial": \([0-9.]*\), "spatial": \[\([0-9.]*\)[^]]*\], "temporal": \([0-9.]*\), "shade": \([0-9.]*\).*/\1 \2 \3 \4 \5/'
echo
