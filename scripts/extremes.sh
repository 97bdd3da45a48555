#!/bin/sh
# The extremes table of docs/precision.md (issue 16): runs the extremes suite
# (tests/test_extremes.c, the long form) in the double and the float build for SEEDS seeds,
# with RESTIR_EXTREMES_TABLE collecting one row per case, method, build and seed, and
# writes the table (markdown) to OUT_DIR/table.md; with UPDATE_DOCS=1 it also replaces the
# part of docs/precision.md between the "extremes-table" markers. TABLE_ONLY=1 rebuilds the
# table from OUT_DIR/rows.tsv without running anything.
#   make extremes-table   (or: sh scripts/extremes.sh [OUT_DIR])
# Columns: non-finite pixels + samples summed over all seeds; the relative bias
# (mean - reference) / reference as the range over seeds; the largest |t| = |bias| / se
# over seeds (se from the R runs of one seed: t has R - 1 degrees of freedom, so with R = 4
# a |t| of 5.8 is a two-sided p of 0.01); the pooled z = sum of the seeds' biases over the
# root of the sum of their se^2 (all seeds together); float - double: the relative
# difference of the two builds' means at the same seed (the same addressed random numbers),
# the largest |value| over seeds.
set -eu
OUT=${1:-out/extremes}
SEEDS=${SEEDS:-1 2 3 4 5}
mkdir -p "$OUT"
ROWS="$OUT/rows.tsv"
# TABLE_ONLY=1: only rebuild the table from an existing OUT_DIR/rows.tsv.
if [ "${TABLE_ONLY:-0}" != 1 ]; then
    : > "$ROWS"
    make -j2 build/tests/run build/restir >/dev/null
    make -j2 PRECISION=float build/float/tests/run build/float/restir >/dev/null
    for seed in $SEEDS; do
        for b in build build/float; do
            RESTIR_EXTREMES_TABLE="$ROWS" nice -n 10 "$b/tests/run" --long --seed "$seed" extremes_ \
                >"$OUT/log-$(echo "$b" | tr / -)-$seed.txt" 2>&1 ||
                { echo "extremes suite failed: $b seed $seed (see $OUT)" >&2; exit 1; }
        done
    done
else
    SEEDS=$(cut -f4 "$ROWS" | sort -un | tr '\n' ' ')
fi
awk -F '\t' '
function abs(x) { return x < 0 ? -x : x }
{
    key = $1 "\t" $2
    if (!(key in seen)) { seen[key] = 1; order[++n] = key }
    bk = key "\t" $3
    rel = ($5 - $7) / $7
    z = $6 > 0 ? abs($5 - $7) / $6 : 0
    nf[bk] += $8
    runs[key] = $9
    bsum[bk] += $5 - $7
    vsum[bk] += $6 * $6
    if (!(bk in lo) || rel < lo[bk]) lo[bk] = rel
    if (!(bk in hi) || rel > hi[bk]) hi[bk] = rel
    if (!(bk in zmax) || z > zmax[bk]) zmax[bk] = z
    mean[bk "\t" $4] = $5
    seeds[key "\t" $4] = 1
}
END {
    print "| case | method | runs | NaN/Inf (double, float) | rel. bias, double (range over seeds) | max \\|t\\| | pooled z | rel. bias, float | max \\|t\\| | pooled z | float − double (max \\|rel.\\|, paired) |"
    print "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    for (i = 1; i <= n; ++i) {
        key = order[i]; split(key, kk, "\t")
        d = key "\tdouble"; f = key "\tfloat"
        fd = 0
        for (sk in seeds) {
            split(sk, ss, "\t")
            if (ss[1] "\t" ss[2] != key) continue
            md = mean[d "\t" ss[3]]; mf = mean[f "\t" ss[3]]
            if (md != "" && mf != "" && md != 0 && abs((mf - md) / md) > fd) fd = abs((mf - md) / md)
        }
        zd = vsum[d] > 0 ? bsum[d] / sqrt(vsum[d]) : 0
        zf = vsum[f] > 0 ? bsum[f] / sqrt(vsum[f]) : 0
        printf "| %s | %s | %s | %d, %d | %.1e … %.1e | %.1f | %.1f | %.1e … %.1e | %.1f | %.1f | %.1e |\n", kk[1], kk[2], runs[key], nf[d], nf[f], lo[d], hi[d], zmax[d], zd, lo[f], hi[f], zmax[f], zf, fd
    }
}' "$ROWS" > "$OUT/table.md"
echo "seeds: $SEEDS" >> "$OUT/table.md"
cat "$OUT/table.md"
if [ "${UPDATE_DOCS:-0}" = 1 ]; then
    awk -v table="$OUT/table.md" '
        /<!-- extremes-table begin -->/ { print; while ((getline line < table) > 0) print line; skip = 1; next }
        /<!-- extremes-table end -->/ { skip = 0 }
        !skip { print }' docs/precision.md > "$OUT/precision.md"
    mv "$OUT/precision.md" docs/precision.md
fi
