#!/bin/sh
# make fuzz: runs the libFuzzer harnesses of tests/fuzz/ one after the other (the
# machine is shared: one job, under nice), RUNS executions each, and prints one line
# per target: executions, coverage (cov = edges, ft = features), corpus, time, findings.
#
#   sh scripts/fuzz.sh BUILD OUT RUNS TARGET[:RUNS]...
#   FUZZ_SECONDS=600 sh scripts/fuzz.sh BUILD OUT -1 TARGET...   (a time slice per target)
#
# BUILD is build/fuzz (ASan + UBSan, make fuzz) or build/fuzz-ubsan (UBSan only,
# make fuzz FUZZ_SAN=undefined: several times faster; replay its corpus under
# ASan + UBSan afterwards, docs/fuzzing.md).
#
# The working corpus OUT/corpus/TARGET starts from the committed inputs of
# tests/data/fuzz/TARGET plus the small files of ../shared/data with the right
# extension; it grows across runs (not committed). A crash, leak or timeout is written
# as OUT/crash/TARGET-*; fix it and copy the input to tests/data/fuzz/TARGET/crash-*
# so that `make test` replays it (docs/fuzzing.md).
set -u
build=$1 out=$2 runs=$3
shift 3
shared=../shared/data
mkdir -p "$out/crash"

seed_corpus() { # target corpus-dir
    cp tests/data/fuzz/"$1"/* "$2"/ 2>/dev/null
    case $1 in
    obj | mtl | pfm)
        [ -d "$shared" ] && find "$shared" -type f -name "*.$1" -size -70k -exec cp {} "$2"/ \; 2>/dev/null ;;
    exr | png) # the image corpus (tests/data/images), small files only
        find tests/data/images -type f -name "*.$1" -size -8k -exec cp {} "$2"/ \; 2>/dev/null ;;
    esac
}

max_len() {
    case $1 in
    pfm) echo 4096 ;; # headers are where the parsing is; large images: make test-data
    cli) echo 1024 ;;
    dump) echo 4096 ;;
    exr | png) echo 8192 ;; # the corpus files are 0.3-6 KB
    inflate) echo 4096 ;;
    *) echo 16384 ;;
    esac
}

printf '%-6s %12s %8s %8s %14s %8s %s\n' target executions cov ft corpus seconds findings
for t in "$@"; do
    target_runs=$runs
    case $t in *:*) target_runs=${t#*:} t=${t%%:*} ;; esac
    corpus=$out/corpus/$t
    mkdir -p "$corpus"
    [ -n "$(ls -A "$corpus")" ] || seed_corpus "$t" "$corpus"
    dict=
    [ -f tests/fuzz/$t.dict ] && dict=-dict=tests/fuzz/$t.dict
    start=$(date +%s)
    # -close_fd_mask=3: the readers' messages (expected) would drown the log.
    nice -n 10 "$build/fuzz_$t" "$corpus" $dict -runs="$target_runs" -max_len="$(max_len "$t")" -timeout=10 ${FUZZ_SECONDS:+-max_total_time=$FUZZ_SECONDS} \
        -rss_limit_mb=2048 -close_fd_mask=3 -print_final_stats=1 -artifact_prefix="$out/crash/$t-" \
        > "$out/$t.log" 2>&1
    status=$?
    seconds=$(($(date +%s) - start))
    done_line=$(grep -E '^#[0-9]+[[:space:]].*cov: ' "$out/$t.log" | tail -1)
    execs=$(grep '^stat::number_of_executed_units' "$out/$t.log" | awk '{print $2}')
    cov=$(echo "$done_line" | sed -n 's/.*cov: \([0-9]*\).*/\1/p')
    ft=$(echo "$done_line" | sed -n 's/.*ft: \([0-9]*\).*/\1/p')
    corp=$(echo "$done_line" | sed -n 's/.*corp: \([^ ]*\).*/\1/p')
    findings=$(ls "$out/crash" | grep -c "^$t-")
    [ $status -eq 0 ] || findings="$findings (exit $status, see $out/$t.log)"
    printf '%-6s %12s %8s %8s %14s %8s %s\n' "$t" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$seconds" "$findings"
done
