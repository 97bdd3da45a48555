#!/bin/sh
# Mutations Table 1 / Figs. 9, 13 re-measured on the paper's setup (issue 28): the reduction of
# the average radial covariance (Mutations Eq. 21, boxes of radius 8) by N mutations after
# temporal reuse, with >= 100 PAIRED images per group at STEADY STATE, the paper's cap and
# candidates.   sh scripts/claims_covariance.sh [OUT_DIR] [BUILD_DIR]
#
# Setup (Mutations §5: M = 32 candidates, M_cap = 50, PT spatial radius 20 at 1920 x 1080):
# the real-time pipeline (gris-realtime preset) with --candidates CANDIDATES (32), --mcap MCAP
# (50) --mcap-mode MCAP_MODE (absolute: Algorithm 2 line 3), spatial radius RADIUS = 20 px x
# SIZE / 1080 (the same angular radius; at least 1), the paper's Gaussian perturbation
# (--mutation-kernel KERNEL, default gaussian) and strategy STRATEGY (rv). Frame LAST of a
# sequence 0..LAST is measured: with an absolute cap of 50 and 32 new samples per frame the
# history saturates by frame 2, so LAST = 15 is well past the start-up.
# NGROUPS groups of K images (K = 100, the paper's); group g uses seeds g K + 1 .. g K + K for
# every configuration (0 mutations and each N in NS), so each group's covariances are paired:
# the same initial candidates and temporal history until the first mutation. Per group and N:
# ratio = covariance(N) / covariance(0); reported: each configuration's covariance (mean ±
# 95% t half-width over the groups) and the paired ratio and the reduction 1 - ratio (mean ±
# half-width over the groups, restir stats mean-ci), the paper's "relative reduction" (its
# Table 1: 8-26% for ReSTIR PT scenes).
# Boxes: the paper's (radius COV_RADIUS = 8 px, centre included: Mutations §5 averages Eq. 21
# "over boxes of a given radius centered at each pixel"), and, because the reuse radius scales
# with SIZE and the box does not, also radius COV_RADIUS_SMALL (default: the paper's box/reuse
# ratio 8/20 times RADIUS, at least 1), each with and without the centre (the centre term is
# the pixel's variance, which a mutation leaves unchanged in expectation: Mutations Eq. 17).
# Re-running on a finished OUT_DIR only recomputes the tables (the images are kept).
# Expected run time on 2 idle cores with the defaults: about 3 hours (extrapolated from 32^2:
# 1.3 CPU s per 128^2 frame with 32 candidates; 3 groups x 100 images x 3 configurations x 16
# frames, THREADS = 2). Smoke test (seconds):
#   SIZE=16 LAST=2 K=3 NGROUPS=2 NS=1 CANDIDATES=2 sh scripts/claims_covariance.sh /tmp/cov
set -eu
. "$(dirname "$0")/results/lib.sh"
. "$(dirname "$0")/results/claims_lib.sh"
results_init out/claims-covariance "$@"
defaults SIZE=128 LAST=15 K=100 NGROUPS=3 "NS=1 5" STRATEGY=rv KERNEL=gaussian MCAP=50 MCAP_MODE=absolute \
    CANDIDATES=32 SCENE=scenes/cornell-glossy.scene THREADS=2 COV_RADIUS=8
defaults RADIUS="$(awk -v s="$SIZE" 'BEGIN { r = 20 * s / 1080; printf "%.3g", r < 1 ? 1 : r }')"
MUTATION_OPTS=${MUTATION_OPTS:-} # more mutation options, e.g. "--mutation-sigma 0.1" (a fixed step)
defaults COV_RADIUS_SMALL="$(awk -v r="$RADIUS" 'BEGIN { b = int(r * 8 / 20 + 0.5); print b < 1 ? 1 : b }')"
mkdir -p "$TMP"
F=$(printf %04d "$LAST")
OPTS="--method restir --preset gris-realtime --sequence 0..$LAST --candidates $CANDIDATES --mcap $MCAP --mcap-mode $MCAP_MODE --radius $RADIUS"

# image NAME SEED MUTATION_OPTIONS...: frame LAST of one sequence, kept as TMP/NAME.SEED.pfm
# (an existing file is kept: an interrupted measurement resumes)
image() {
    name=$1 seed=$2; shift 2
    [ -f "$TMP/$name.$seed.pfm" ] && return 0
    # shellcheck disable=SC2086
    "$R" render "$SCENE" $OPTS "$@" --size "${SIZE}x${SIZE}" --threads "$THREADS" --seed "$seed" --quiet --no-png \
        -o "$TMP/run-$name.pfm"
    mv "$TMP/run-$name.$F.pfm" "$TMP/$name.$seed.pfm"
    rm -f "$TMP"/run-"$name".*.pfm
}
# covariance NAME GROUP RADIUS [--exclude-center]: Eq. 21 over the K images of the group
covariance() {
    files="" i=1
    while [ "$i" -le "$K" ]; do files="$files $TMP/$1.$(($2 * K + i)).pfm"; i=$((i + 1)); done
    # shellcheck disable=SC2086
    "$R" compare --covariance $files --radius "$3" ${4:-} | awk '/covariance/ { print $NF }'
}
BOXES="$COV_RADIUS:centre $COV_RADIUS:no-centre"
[ "$COV_RADIUS_SMALL" != "$COV_RADIUS" ] && BOXES="$BOXES $COV_RADIUS_SMALL:centre $COV_RADIUS_SMALL:no-centre"
box_file() { echo "$TMP/$1.r${2%%:*}${2#*:}.cov"; } # CONFIG BOX

CONFIGS="n0"
for n in $NS; do CONFIGS="$CONFIGS n$n"; done
for c in $CONFIGS; do for box in $BOXES; do : > "$(box_file "$c" "$box")"; done; done
g=0
while [ "$g" -lt "$NGROUPS" ]; do
    i=1
    while [ "$i" -le "$K" ]; do
        seed=$((g * K + i))
        image n0 "$seed" --mutations 0
        # shellcheck disable=SC2086
        for n in $NS; do image "n$n" "$seed" --mutations "$n" --mutation "$STRATEGY" --mutation-kernel "$KERNEL" $MUTATION_OPTS; done
        i=$((i + 1))
    done
    for c in $CONFIGS; do for box in $BOXES; do
        x=""; [ "${box#*:}" = no-centre ] && x=--exclude-center
        covariance "$c" "$g" "${box%%:*}" $x >> "$(box_file "$c" "$box")"
    done; done
    g=$((g + 1))
done

echo "## Mutations covariance (Eq. 21, r = $COV_RADIUS), $(basename "$SCENE" .scene) ${SIZE}², frame $LAST, $CANDIDATES candidates,"
echo "## cap $MCAP ($MCAP_MODE), radius $RADIUS px, $STRATEGY mutations with the $KERNEL kernel${MUTATION_OPTS:+ ($MUTATION_OPTS)}; $NGROUPS groups of $K paired images"
echo
echo "| box radius | centre | mutations | covariance (mean over groups) | covariance / 0 mutations' (paired per group) | reduction 1 - ratio |"
echo "| --- | --- | --- | --- | --- | --- |"
for box in $BOXES; do
    f0=$(box_file n0 "$box")
    echo "| ${box%%:*} | ${box#*:} | 0 | $(col_ci "$f0") | 1 | 0 |"
    for n in $NS; do
        f=$(box_file "n$n" "$box")
        paste "$f" "$f0" | awk '$2 > 0 { print 1 - $1 / $2 }' > "$f.red"
        echo "| ${box%%:*} | ${box#*:} | $n | $(col_ci "$f") | $(ratio_ci "$f" "$f0") | $(col_ci "$f.red") |"
    done
done
