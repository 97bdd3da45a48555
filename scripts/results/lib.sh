# Helpers shared by the measurement scripts (sourced: scripts/results.sh, tradeoffs.sh,
# results_*.sh, false-alarm.sh, power.sh); sourcing only defines functions. The caller sets
# R (the restir binary), THREADS, OUT, CACHE (reference cache) and SUMMARY (summary.awk) as
# the helpers it uses need them.

# results_init DEFAULT_OUT [OUT_DIR] [BUILD_DIR]: a script's two arguments -> OUT (created),
# R (BUILD_DIR/restir, default build/restir) and TMP (OUT/tmp, created by who needs it).
results_init() { OUT=${2:-$1}; R=${3:-build}/restir; TMP="$OUT/tmp"; mkdir -p "$OUT"; }
# defaults NAME=VALUE...: each NAME keeps its value from the environment, else takes VALUE
# (the knobs a script's header documents).
defaults() { for kv; do eval ": \"\${${kv%%=*}:=\${kv#*=}}\""; done; }

# mean_ci [FORMAT]: the mean and 95% t half-width of the numbers on stdin, "%.4g ± %.2g"
# unless FORMAT says otherwise: `restir stats mean-ci` (stats_mean_ci, docs/cli.md), the one
# implementation of every script. With fewer than two numbers: "—" (the reason on stderr).
mean_ci() { "$R" stats mean-ci ${1:+--format "$1"} || echo "—"; }
# t_table: the 0.975 quantiles of Student's t for 1..1000 degrees of freedom on one line, for
# the awk summaries that compute many intervals at once (awk -v ttable="$(t_table)").
t_table() { "$R" stats t-table; }
# summary [AWK OPTIONS] FILE: summary.awk with the t table
summary() { awk -F, -v ttable="$(t_table)" -f "$SUMMARY" "$@"; }
# json_value FILE SECTION KEY: a scalar of `check --json` output inside the object SECTION.
json_value() {
    awk -v sec="\"$2\"" -v key="\"$3\"" '
        index($0, sec ":") { inside = 1 }
        inside && index($0, key ":") { s = substr($0, index($0, key ":") + length(key) + 1); sub(/^ */, "", s); sub(/[,}].*$/, "", s); print s; exit }' "$1"
}

# metric NAME TEST.pfm REF.pfm [COMPARE_OPTIONS]: one value from `restir compare`
metric() { "$R" compare "$2" "$3" ${4:-} | awk -v m="$1" '$1 == m { print $2 }'; }
# wall seconds of the rendering of the last run (its --stats file)
render_seconds() { grep -o '"render": [0-9.e+-]*' "$1" | tail -n 1 | awk '{ print $2 }'; }
# render SIDE SCENE options...: one render at SIDE x SIDE
render() {
    side=$1; shift
    "$R" render "$@" --size "${side}x${side}" --threads "$THREADS" --quiet --no-png
}
seq_seeds() { i=1; while [ $i -le "$SEEDS" ]; do echo $i; i=$((i + 1)); done; }
calc() { awk "BEGIN { printf \"%.6g\", $1 }"; }

# reference KEY SIDE SCENE METHOD BUDGET [options...] -> prints the path of the reference.
# Two independent halves A and B (PT: sample ranges [0, n/2) and [n/2, n) of seed 9001;
# ReSTIR: frame ranges [0, F/2) and [F/2, F)) merged into REF. Since REF = (A + B) / 2,
# A - REF = (A - B) / 2 has the variance of REF itself, so compare(A, REF) estimates the
# reference's own error in every metric (relMSE exactly in expectation; MAPE for Gaussian
# noise); written to KEY.err as "relmse mape".
reference() {
    key=$1 side=$2 scene=$3 method=$4 budget=$5; shift 5
    ref="$CACHE/$key-${side}-$method$budget-s9001"
    if [ ! -f "$ref.pfm" ] || [ ! -f "$ref.err" ]; then
        half=$((budget / 2))
        if [ "$method" = pt ]; then
            render "$side" "$scene" --method pt --spp $half --seed 9001 "$@" -o "$ref.a.pfm"
            render "$side" "$scene" --method pt --spp $half --sample-offset $half --seed 9001 "$@" -o "$ref.b.pfm"
        else
            render "$side" "$scene" --method restir --frames $half --seed 9001 "$@" -o "$ref.a.pfm"
            render "$side" "$scene" --method restir --frames $half --first-frame $half --seed 9001 "$@" -o "$ref.b.pfm"
        fi
        "$R" merge -o "$ref.tmp.pfm" "$ref.a.pfm" "$ref.b.pfm" --counts $half,$half --no-png --quiet
        echo "$(metric relmse "$ref.a.pfm" "$ref.tmp.pfm") $(metric mape "$ref.a.pfm" "$ref.tmp.pfm")" > "$ref.err"
        mv "$ref.tmp.pfm" "$ref.pfm"
    fi
    echo "$ref"
}
ref_relmse() { awk '{ print $1 }' "$1.err"; }
ref_mape() { awk '{ print $2 }' "$1.err"; }

# summarise RUNS.csv NAME XNAME TITLE XLABEL YLABEL: NAME.csv (means, plotted to NAME.svg) and
# the markdown table NAME.table.md (mean ± 95% interval over seeds).
summarise() {
    runs=$1 name=$2 xname=$3
    summary -v mode=wide -v xname="$xname" "$runs" > "$OUT/$name.csv"
    { summary -v mode=header -v xname="$xname" "$runs"
      summary -v mode=md "$runs"; } > "$OUT/$name.table.md"
    "$R" plot "$OUT/$name.csv" -o "$OUT/$name.svg" --title "$4" --xlabel "$5" --ylabel "$6"
}
# paired_ratio RUNS.csv NUM DEN: markdown rows "| x | mean ± hw |" of NUM/DEN per seed
paired_ratio() { summary -v mode=ratio -v num="$2" -v den="$3" "$1"; }
# drop RUNS.csv SERIES X1 X2: "mean ± hw" of value(X1)/value(X2) per seed
drop() { summary -v mode=drop -v num="$2" -v lo="$3" -v hi="$4" "$1"; }
