# Helpers of the real-time sequence measurements (sourced by scripts/results_correlation.sh
# and scripts/results_stochastic_disocclusion.sh). The caller defines render() and sets TMP,
# K, F (frame LAST as NNNN) and PRESET.

# sequence_runs NAME [OPTIONS...]: K sequences with seeds 1..K, frame LAST of run k kept as
# TMP/NAME.k.pfm (with STATS=1 also its --stats as TMP/NAME.k.json); files already there are
# kept, so an interrupted measurement resumes.
sequence_runs() {
    name=$1; shift
    k=1
    while [ "$k" -le "$K" ]; do
        if [ ! -f "$TMP/$name.$k.pfm" ]; then
            if [ "${STATS:-0}" = 1 ]; then
                render $PRESET "$@" --seed "$k" -o "$TMP/run-$name.pfm" --stats "$TMP/$name.$k.json"
            else
                render $PRESET "$@" --seed "$k" -o "$TMP/run-$name.pfm"
            fi
            mv "$TMP/run-$name.$F.pfm" "$TMP/$name.$k.pfm"
            rm -f "$TMP"/run-"$name".*.pfm
        fi
        k=$((k + 1))
    done
}

# runs NAME [N]: the paths of the first N (default K) kept frames of NAME.
runs() { k=1; while [ "$k" -le "${2:-$K}" ]; do printf "%s " "$TMP/$1.$k.pfm"; k=$((k + 1)); done; }
