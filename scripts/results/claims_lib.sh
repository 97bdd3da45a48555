# Helpers of the issue-28 claim scripts (scripts/claims_*.sh), sourced after lib.sh. The
# caller sets R, OUT, TMP and SCENE-independent knobs; nothing here renders by itself.

# cpu_sequence PREFIX LAST SCENE OPTIONS...: one real-time sequence 0..LAST with --threads 1
# (CPU time is then the run's cost whatever the machine's load); keeps frame LAST as
# PREFIX.pfm, the --stats as PREFIX.json, and prints the process CPU seconds (user + system).
cpu_sequence() {
    prefix=$1 last=$2 scene=$3; shift 3
    cpu_run "$prefix" "$R" render "$scene" --method restir --sequence "0..$last" "$@" \
        --threads 1 --quiet --no-png -o "$prefix.run.pfm" --stats "$prefix.json" >/dev/null
    mv "$prefix.run.$(printf %04d "$last").pfm" "$prefix.pfm"
    rm -f "$prefix".run.*.pfm
    cpu_seconds "$prefix"
}

# cpu_run PREFIX COMMAND...: runs COMMAND, its CPU time (user, system) kept in PREFIX.time;
# fails as the command fails. cpu_seconds PREFIX: that time as user + system seconds.
cpu_run() { prefix=$1; shift; /usr/bin/time -f "%U %S" -o "$prefix.time" "$@"; }
cpu_seconds() { awk '{ printf "%.3f\n", $1 + $2 }' "$1.time"; }

# need WHAT VALUE: VALUE, or stop the script if it is empty (a metric whose command failed
# inside a pipeline or a substitution would otherwise enter the tables as a blank)
need() { [ -n "$2" ] || { echo "${0##*/}: no value for $1" >&2; exit 1; }; echo "$2"; }

# metric_of TEST REF NAME: one value of `restir compare` (relmse, mape, ...)
metric_of() { "$R" compare "$1" "$2" | awk -v k="$3" '$1 == k { print $2 }'; }

# masked_nmse RUN REF MASK LO,HI: the run's nmse (sum (run - ref)^2 / sum ref^2, luminance)
# over the pixels whose MASK luminance lies in [LO, HI] (`compare --bias` of the run with a
# copy of itself: K = 2 identical runs, so the mean is this run's value; a copy, because
# compare refuses the same file twice as two inputs)
masked_nmse() {
    cp "$1" "$1.dup.pfm"
    "$R" compare --bias "$1" "$1.dup.pfm" --ref "$2" --block 1 --mask "$3" --mask-range "$4" |
        awk '$1 == "nmse" { print $2 }'
    rm -f "$1.dup.pfm"
}

# ratio_ci NUM_FILE DEN_FILE: the per-line ratios num/den (paired: line k of both files is
# seed k) as "mean ± 95% t half-width" (restir stats mean-ci)
ratio_ci() { paste "$1" "$2" | awk '$2 > 0 { print $1 / $2 }' | mean_ci; }

# col_ci FILE: "mean ± half-width" of the numbers in FILE
col_ci() { mean_ci < "$1"; }
