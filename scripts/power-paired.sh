#!/bin/sh
# The power table of the paired stage tests (docs/statistics.md, "Evidence without blind
# spots", issue 26): runs the tests named power_* (tests/test_power_*.c) for each seed and
# prints one row per paired comparison: seed, name, K, the detectable relative bias per
# channel (80 % power at alpha = 1e-4, from the bench's own standard errors) and the z of
# each channel. The numbers come from the bench's log line (tests/bench.c, RESTIR_BENCH_LOG).
#   sh scripts/power-paired.sh [BUILD_DIR]
# Environment: SEEDS ("1 2 3"), LONG (1: the TEST_LONG variants too), FILTER (the test name
# filters, default "power_light_ris power_mutate power_stochastic power_temporal").
set -eu
BUILD=${1:-build}
SEEDS=${SEEDS:-"1 2 3"}
FILTER=${FILTER:-"power_light_ris power_mutate power_stochastic power_temporal"}
RUN="$BUILD/tests/run"
[ -x "$RUN" ] || { echo "power-paired.sh: $RUN not built (make $RUN)" >&2; exit 2; }
LOG=$(mktemp "${TMPDIR:-/tmp}/power-paired.XXXXXX")
trap 'rm -f "$LOG"' EXIT INT TERM
echo "| seed | comparison | K | detectable R / G / B | z R / G / B |"
echo "| --- | --- | --- | --- | --- |"
for seed in $SEEDS; do
    : > "$LOG"
    status=0
    RESTIR_BENCH_LOG="$LOG" "$RUN" ${LONG:+--long} --seed "$seed" $FILTER > /dev/null 2>&1 || status=$?
    # bench NAME: K n | R A a B b rel r% z z detectable d% | G ... | B ...
    awk -v seed="$seed" -F' [|] ' '{
        name = $1; sub(/^bench /, "", name); k = name; sub(/.*: K /, "", k); sub(/: K [0-9]+$/, "", name)
        det = ""; z = ""
        for (c = 2; c <= 4; ++c) {
            n = split($c, f, " ")
            for (i = 1; i <= n; ++i) {
                if (f[i] == "z") z = z (c > 2 ? " / " : "") f[i + 1]
                if (f[i] == "detectable") det = det (c > 2 ? " / " : "") f[i + 1]
            }
        }
        printf "| %s | %s | %s | %s | %s |\n", seed, name, k, det, z
    }' "$LOG"
    [ "$status" -eq 0 ] || echo "| $seed | (a test failed: exit $status) | | | |"
done
