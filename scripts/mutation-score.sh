#!/bin/sh
# Mutation score: applies each planted bug of tests/mutants/*.patch to a scratch copy of
# the tree (HEAD plus uncommitted changes), builds it, runs `make test` and records
# whether the suite catches the bug, by which tests, and with what margin (|z| of the
# failing statistic, or "exact" for a deterministic assertion; tests/test.h
# test_margin). Prints a markdown table and the score; exit status 1 if any mutant
# survives, does not apply or does not build, 2 if the unmutated tree is not green.
# Margins are written \|z\| in the table (a markdown-escaped |z|).
#
#   sh scripts/mutation-score.sh [--quick] [--long] [--seed N] [--keep] [NAME ...]
#     --quick   first run only the tests the patch's "# expected catch:" header names (those
#               of `make test`, matched against the test registry); a mutant they catch is
#               caught by `make test`, one they miss gets the whole suite as before. Minutes
#               instead of about 2 hours for the whole set; the survivors are exact either way.
#     --long    run `make test-long` on the survivors of `make test` (slow)
#     --seed N  the suite's seed (default: the suite's own, 1)
#     --keep    keep the scratch directory
#     NAME      only these mutants, in this order (file names without .patch)
# Environment: MUTANT_SCRATCH (scratch directory, default /tmp/restir-mutants.PID),
# MUTANT_OUT (logs and the table, default out/mutants), MUTANT_TIMEOUT (seconds per
# suite run, default 1200), MAKE_JOBS (default 2).
# Not part of CI: about 2 minutes per mutant on 2 cores.
set -u

long=0
keep=0
quick=0
seed=
only=
while [ $# -gt 0 ]; do
    case "$1" in
    --long) long=1 ;;
    --quick) quick=1 ;;
    --keep) keep=1 ;;
    --seed)
        [ $# -ge 2 ] || { echo "mutation-score: --seed needs a number" >&2; exit 2; }
        seed=$2
        shift
        ;;
    -*) echo "mutation-score: unknown option $1" >&2; exit 2 ;;
    *) only="$only $1" ;;
    esac
    shift
done

root=$(git rev-parse --show-toplevel 2>/dev/null) || { echo "mutation-score: not in a git tree" >&2; exit 2; }
cd "$root" || exit 2
scratch=${MUTANT_SCRATCH:-/tmp/restir-mutants.$$}
out=${MUTANT_OUT:-$root/out/mutants}
timeout_s=${MUTANT_TIMEOUT:-1200}
jobs=${MAKE_JOBS:-2}
seedarg=
[ -n "$seed" ] && seedarg="SEED=$seed"

case "$out" in /*) ;; *) out="$root/$out" ;; esac
mkdir -p "$out" || exit 2
rm -rf "$scratch"
mkdir -p "$scratch/base" || exit 2
[ "$keep" = 1 ] || trap 'rm -rf "$scratch"' EXIT INT TERM

# The tree as it is now: tracked files (with uncommitted edits) and untracked ones not ignored.
git ls-files -z --cached --others --exclude-standard |
    xargs -0 sh -c 'for f; do [ -f "$f" ] && printf "%s\0" "$f"; done' sh |
    tar --null -T - -cf - | tar -xf - -C "$scratch/base" || exit 2

say() { printf '%s\n' "$*" >&2; }

# Tests read ../shared/data relative to the tree (make test-data, the long suite): the
# scratch copies see the same directory.
[ -d "$root/../shared" ] && ln -s "$(cd "$root/../shared" && pwd)" "$scratch/shared"

# Runs the suite (make test or test-long) in directory $1; margins go to $2, log to $3.
# Prints the outcome: survived / caught / crashed / timeout.
run_suite() {
    dir=$1 margins=$2 log=$3 target=$4
    rm -f "$margins"
    (cd "$dir" && RESTIR_TEST_MARGIN_FILE="$margins" timeout "$timeout_s" nice -n 10 make -j"$jobs" $seedarg "$target") >"$log" 2>&1
    status=$?
    if [ $status = 0 ]; then echo survived
    elif [ $status = 124 ]; then echo timeout
    elif grep -q '^[0-9]* passed, [0-9]* failed$' "$log"; then echo caught
    else echo crashed
    fi
}

# The tests of `make test` (not TEST_LONG) that a patch's "# expected catch:" header names.
named_catchers() { # PATCH REGISTRY
    sed -n '/^# expected catch:/,/^diff --git/p' "$1" | grep '^#' | tr -c 'A-Za-z0-9_\n' ' ' | tr ' ' '\n' |
        grep -x -F -f "$(registry_names "$2")" | sort -u | tr '\n' ' '
}
registry_names() { # REGISTRY -> a file of the short tests' names
    f="$scratch/short-tests.txt"
    [ -f "$f" ] || sed -n 's/^X(\([A-Za-z0-9_]*\), 0)$/\1/p' "$1" > "$f"
    echo "$f"
}

say "mutation-score: building the unmutated tree in $scratch/base"
if ! (cd "$scratch/base" && nice -n 10 make -j"$jobs" build/restir build/tests/run) >"$out/base-build.log" 2>&1; then
    say "mutation-score: the unmutated tree does not build ($out/base-build.log)"
    exit 2
fi
base=$(run_suite "$scratch/base" "$scratch/base/margins.txt" "$out/base-test.log" test)
if [ "$base" != survived ]; then
    say "mutation-score: the unmutated tree is not green ($out/base-test.log)"
    exit 2
fi
if [ "$long" = 1 ]; then
    base=$(run_suite "$scratch/base" "$scratch/base/margins.txt" "$out/base-test-long.log" test-long)
    if [ "$base" != survived ]; then
        say "mutation-score: the unmutated tree fails make test-long ($out/base-test-long.log)"
        exit 2
    fi
fi

table="$out/table.md"
{
    echo "| mutant | outcome | catching tests (margin) | best margin |"
    echo "| --- | --- | --- | --- |"
} >"$table"
total=0
caught=0
bad=0
# Every mutant in name order, or the named ones in the order given.
patches=
if [ -n "$only" ]; then
    for name in $only; do patches="$patches tests/mutants/$name.patch"; done
else
    patches=$(ls tests/mutants/*.patch)
fi
for patch in $patches; do
    name=$(basename "$patch" .patch)
    total=$((total + 1))
    dir="$scratch/mutant"
    rm -rf "$dir"
    cp -a "$scratch/base" "$dir"
    rm -f "$dir/margins.txt"
    log="$out/$name.log"
    tests=""
    margin=""
    say "mutation-score: $name"
    if [ ! -f "$patch" ]; then
        outcome="no such mutant"
    elif ! (cd "$dir" && git apply -p1 "$root/$patch") >"$log" 2>&1; then
        outcome="does not apply"
    elif ! (cd "$dir" && nice -n 10 make -j"$jobs" build/restir build/tests/run) >>"$log" 2>&1; then
        outcome="does not build"
    else
        outcome=survived
        named=
        [ "$quick" = 1 ] && named=$(named_catchers "$root/$patch" "$scratch/base/build/test_registry.h")
        if [ -n "$named" ]; then
            outcome=$(T="$named" run_suite "$dir" "$dir/margins.txt" "$log.named" test)
            [ "$outcome" = survived ] || outcome="$outcome (named tests)"
        fi
        [ "$outcome" = survived ] && outcome=$(run_suite "$dir" "$dir/margins.txt" "$log.test" test)
        if [ "$outcome" = survived ] && [ "$long" = 1 ]; then
            outcome=$(run_suite "$dir" "$dir/margins.txt" "$log.test-long" test-long)
            [ "$outcome" = survived ] || outcome="$outcome (test-long only)"
        fi
        if [ -s "$dir/margins.txt" ]; then
            tests=$(awk '{ printf "%s%s (%s)", (NR > 1 ? ", " : ""), $1, ($2 == "exact" ? "exact" : "\\|z\\| " $3) }' "$dir/margins.txt")
            margin=$(awk '$2 == "exact" { e = 1 } $2 == "z" && $3 + 0 > z + 0 { z = $3 }
                          END { if (e) print "exact"; else if (z != "") printf "\\|z\\| %s", z }' "$dir/margins.txt")
        fi
    fi
    case "$outcome" in
    caught*|crashed*|timeout*) caught=$((caught + 1)) ;;
    *) bad=$((bad + 1)) ;;
    esac
    [ -n "$margin" ] || margin="-"
    [ -n "$tests" ] || tests="-"
    echo "| $name | $outcome | $tests | $margin |" >>"$table"
    say "  $outcome: $tests"
done

cat "$table"
echo
echo "mutation score: $caught of $total caught"
[ "$bad" = 0 ] || exit 1
exit 0
