#!/bin/sh
# Regenerates docs/results.md's "MCMC mutations" section (issue 13) with our own CLI; not
# part of `make test`.   sh scripts/results_mutations.sh [OUT_DIR] [BUILD_DIR]   (make results-mutations)
# The real-time pipeline (gris-realtime preset, hybrid shift, SIZE x SIZE, frames 0..LAST,
# frame LAST measured) with N mutations after temporal reuse (Mutations §3), RUNS = NGROUPS x
# PER_GROUP seeds per configuration; mean ± 95% t half-width:
#   table 1, per scene x strategy x N in {0, 1, 5}: acceptance rate, rejected for T = 0, the
#     fraction of duplicated samples among the shaded reservoirs (Fig. 8), covariance (Eq. 21,
#     radius 8, `restir compare --covariance`, over NGROUPS groups of PER_GROUP images; Table 1,
#     Figs. 9, 13), relMSE against a path-traced reference (over seeds), and the frame time over
#     the frame time without the mutation stage, within each run (robust to machine load);
#   table 2, the M-cap (Fig. 11): --mcap 20 and 100 with 0 and 5 rv mutations, frames 0..LAST2.
set -eu
. "$(dirname "$0")/results/lib.sh"
results_init out/results-mutations "$@"
defaults SIZE=48 THREADS=2 LAST=3 LAST2=5 NGROUPS=4 PER_GROUP=4 REF_SPP=4096 SCENES=cornell-glossy
mkdir -p "$TMP"

render() { "$R" render "$@" --size "${SIZE}x${SIZE}" --threads "$THREADS" --quiet --no-png; }
# acceptance, T = 0 rejections / proposals, duplicates / valid, frame ms (the last frame's stats)
stats() {
    python3 - "$1" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
st = d["restir"]["stats"]
m = st["mutations"]
ms = st["milliseconds"]
frame = sum(v for v in ms.values() if isinstance(v, (int, float))) + sum(ms.get("spatial", []) or [])
props = max(m["proposals"], 1)
mut = m["milliseconds"]
print(m["acceptance_rate"], sum(m["rejected"].values()) / props, m["duplicates"] / max(m["final_valid"], 1), frame,
      (frame + mut) / max(frame, 1e-9))  # "milliseconds" holds every stage but the mutations
PY
}

# one configuration: NAME SCENE LASTFRAME ARGS... ; writes $TMP/NAME.{acc,t0,dup,ms,rel,cov}
config() {
    name=$1 scene=$2 last=$3
    shift 3
    ref="$TMP/$scene.$last.ref.pfm"
    [ -f "$ref" ] || render "scenes/$scene.scene" --method pt --spp "$REF_SPP" --seed 9001 --frame "$last" --max-depth 10 -o "$ref"
    for x in acc t0 dup ms share rel cov; do : > "$TMP/$name.$x"; done
    g=0
    while [ "$g" -lt "$NGROUPS" ]; do
        files=""
        i=0
        while [ "$i" -lt "$PER_GROUP" ]; do
            seed=$((1 + g * PER_GROUP + i))
            f="$TMP/$name.$seed"
            img="$f.$(printf %04d "$last").pfm"
            [ -f "$img" ] && [ -f "$f.json" ] ||
                render "scenes/$scene.scene" --method restir --preset gris-realtime --shift hybrid \
                    --sequence "0..$last" --seed "$seed" -o "$f.pfm" --stats "$f.json" "$@"
            files="$files $img"
            "$R" compare "$img" "$ref" | awk '$1 == "relmse" { print $2 }' >> "$TMP/$name.rel"
            stats "$f.json" > "$f.stats"
            awk '{ print $1 }' "$f.stats" >> "$TMP/$name.acc"
            awk '{ print $2 }' "$f.stats" >> "$TMP/$name.t0"
            awk '{ print $3 }' "$f.stats" >> "$TMP/$name.dup"
            awk '{ print $4 }' "$f.stats" >> "$TMP/$name.ms"
            awk '{ print $5 }' "$f.stats" >> "$TMP/$name.share"
            i=$((i + 1))
        done
        # shellcheck disable=SC2086
        "$R" compare --covariance $files --radius 8 | awk '/covariance/ { print $NF }' >> "$TMP/$name.cov"
        g=$((g + 1))
    done
}

echo "| scene | strategy | mutations | acceptance | rejected (T = 0) | duplicated samples | covariance (Eq. 21, r = 8) | relMSE | frame time with / without the mutation stage (same run) |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for scene in $SCENES; do
    config "$scene.off" "$scene" "$LAST" --mutations 0
    echo "| $scene | — | 0 | — | — | $(mean_ci < "$TMP/$scene.off.dup") | $(mean_ci < "$TMP/$scene.off.cov") | $(mean_ci < "$TMP/$scene.off.rel") | 1 |"
    for strategy in rv pp fp; do
        for n in 1 5; do
            name="$scene.$strategy.$n"
            config "$name" "$scene" "$LAST" --mutations "$n" --mutation "$strategy"
            echo "| $scene | $strategy | $n | $(mean_ci < "$TMP/$name.acc") | $(mean_ci < "$TMP/$name.t0") | $(mean_ci < "$TMP/$name.dup") | $(mean_ci < "$TMP/$name.cov") | $(mean_ci < "$TMP/$name.rel") | $(mean_ci < "$TMP/$name.share") |"
        done
    done
done
echo
echo "| scene | M-cap | rv mutations | duplicated samples | covariance (Eq. 21, r = 8) | relMSE |"
echo "| --- | --- | --- | --- | --- | --- |"
scene=cornell-glossy
for cap in 20 100; do
    for n in 0 5; do
        name="$scene.cap$cap.$n"
        config "$name" "$scene" "$LAST2" --mcap "$cap" --mutations "$n"
        echo "| $scene | $cap | $n | $(mean_ci < "$TMP/$name.dup") | $(mean_ci < "$TMP/$name.cov") | $(mean_ci < "$TMP/$name.rel") |"
    done
done
