# Summaries over seeds of the long-format run tables of scripts/results.sh.
# Input rows (no header): x,series,seed,value. Every number is a mean over seeds with a
# 95% Student-t interval (half-width t_{0.975, n-1} * sd / sqrt(n)); the quantiles come from
# `restir stats t-table` (-v ttable=..., as scripts/results/lib.sh's `summary` passes them), the
# C code's stats_t_quantile.
#   awk -F, -v mode=wide  -f summary.awk RUNS.csv   -> CSV "x,s1,s2,..." of means (for `restir plot`)
#   awk -F, -v mode=md    -f summary.awk RUNS.csv   -> markdown rows "| x | mean ± hw | ... |"
#   awk -F, -v mode=ratio -v num=A -v den=B -f summary.awk RUNS.csv
#        -> markdown rows "| x | mean ± hw |" of the per-seed ratio A/B (paired: same seed,
#           so the run-to-run noise they share cancels; the interval is over the seeds)
#   awk -F, -v mode=drop -v num=S -v lo=X1 -v hi=X2 -f summary.awk RUNS.csv
#        -> "mean ± hw" of the per-seed ratio value(X1)/value(X2) of series S
#   mode=header prints the markdown header "| x | s1 | s2 |" and its rule.
# Header text for the x column: -v xname=...
function tq(df) { # 0.975 quantile of Student's t (the table's last entry beyond it: a bit wide)
    if (df < 1) return 0
    return df <= NT ? T[df] : T[NT]
}
function fmt(v) { return sprintf("%.4g", v) }
function ci(sum, sumsq, n,    m, var) {
    m = sum / n
    if (n < 2) return fmt(m) " (1 seed)"
    var = (sumsq - n * m * m) / (n - 1)
    if (var < 0) var = 0
    return fmt(m) " ± " fmt(tq(n - 1) * sqrt(var / n))
}
BEGIN {
    NT = split(ttable, T, " ")
    if (NT == 0 && (mode == "md" || mode == "ratio" || mode == "drop")) {
        print "summary.awk: no -v ttable (restir stats t-table)" > "/dev/stderr"
        exit 2
    }
    if (xname == "") xname = "x"
}
NF >= 4 && $4 != "" {
    x = $1; s = $2; seed = $3; v = $4 + 0
    if (!(x in xseen)) { xseen[x] = 1; xs[++nx] = x }
    if (!(s in sseen)) { sseen[s] = 1; ss[++ns] = s }
    n[x, s]++; sum[x, s] += v; sq[x, s] += v * v
    val[x, s, seed] = v
    if (!((x, seed) in seedseen)) { seedseen[x, seed] = 1; seeds[x, ++nseed[x]] = seed }
}
END {
    if (mode == "header") {
        line = "| " xname; rule = "|---"
        for (j = 1; j <= ns; ++j) { line = line " | " ss[j]; rule = rule "|---" }
        print line " |"; print rule "|"
    } else if (mode == "wide") {
        line = xname
        for (j = 1; j <= ns; ++j) line = line "," ss[j]
        print line
        for (i = 1; i <= nx; ++i) {
            line = xs[i]
            for (j = 1; j <= ns; ++j) line = line "," (n[xs[i], ss[j]] ? sprintf("%.6g", sum[xs[i], ss[j]] / n[xs[i], ss[j]]) : "")
            print line
        }
    } else if (mode == "md") {
        for (i = 1; i <= nx; ++i) {
            line = "| " xs[i]
            for (j = 1; j <= ns; ++j)
                line = line " | " (n[xs[i], ss[j]] ? ci(sum[xs[i], ss[j]], sq[xs[i], ss[j]], n[xs[i], ss[j]]) : "–")
            print line " |"
        }
    } else if (mode == "ratio") {
        for (i = 1; i <= nx; ++i) {
            x = xs[i]; rs = 0; rq = 0; rn = 0
            for (k = 1; k <= nseed[x]; ++k) {
                sd = seeds[x, k]
                if (((x, num, sd) in val) && ((x, den, sd) in val) && val[x, den, sd] != 0) {
                    r = val[x, num, sd] / val[x, den, sd]; rs += r; rq += r * r; rn++
                }
            }
            print "| " x " | " (rn ? ci(rs, rq, rn) : "–") " |"
        }
    } else if (mode == "drop") {
        rs = 0; rq = 0; rn = 0
        for (k = 1; k <= nseed[lo]; ++k) {
            sd = seeds[lo, k]
            if (((lo, num, sd) in val) && ((hi, num, sd) in val) && val[hi, num, sd] != 0) {
                r = val[lo, num, sd] / val[hi, num, sd]; rs += r; rq += r * r; rn++
            }
        }
        print (rn ? ci(rs, rq, rn) : "–")
    }
}
