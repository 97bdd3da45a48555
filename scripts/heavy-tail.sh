#!/bin/sh
# check on a heavy-tailed estimator (issue 27; docs/statistics.md "When check cannot
# judge"): the path tracer with NEE only (--pt-strategy nee) under a tiny light 0.05 above
# a floor (selected by power with probability ~1e-4, so a rare sample carries a geometry
# term up to 1/h^2: a near-zero light pdf where the contribution is large), and the same
# path tracer with MIS (well-behaved: BSDF sampling covers the tiny light). Both are
# unbiased, so every "different" is a false alarm. SETS independent sets of K runs per
# estimator; pairs of sets are checked: NEE vs NEE, NEE vs MIS, MIS vs MIS. Prints one
# Markdown row per comparison: how often the verdict was consistent, different,
# inconclusive, and what the tests alone said.
#   sh scripts/heavy-tail.sh [OUT_DIR] [BUILD_DIR]     (SETS=20, K=16, SIZE=64, SPP=4)
set -eu
OUT=${1:-out/heavy-tail}
R=${2:-build}/restir
SETS=${SETS:-20}
K=${K:-16}
SIZE=${SIZE:-64}
SPP=${SPP:-4}
mkdir -p "$OUT"
cat > "$OUT/rare.obj" <<'EOF'
v -2 0 -2
v 2 0 -2
v 2 0 2
v -2 0 2
v -1 3 -1
v 1 3 -1
v 1 3 1
v -1 3 1
v -0.01 0.05 -0.01
v 0.01 0.05 -0.01
v 0.01 0.05 0.01
v -0.01 0.05 0.01
usemtl floor
f 1 4 3
f 1 3 2
usemtl sky
f 5 6 7
f 5 7 8
usemtl spot
f 9 10 11
f 9 11 12
EOF
cat > "$OUT/rare.scene" <<EOF
mesh rare.obj
camera eye 0 1 1 target 0 0 0 up 0 1 0 fov 20
size $SIZE $SIZE
material floor type lambert kd 0.7 0.7 0.7
material sky type lambert kd 0 0 0 ke 5 5 5
material spot type lambert kd 0 0 0 ke 5 5 5
EOF
# set STRATEGY S: K runs of set S (seeds 1000 S + k), their file list on stdout
set_files() {
    list=""
    k=0
    while [ "$k" -lt "$K" ]; do
        f="$OUT/$1-$2-$k.pfm"
        if [ ! -f "$f" ]; then
            if [ "$1" = nee ]; then st="--pt-strategy nee"; else st=""; fi
            # shellcheck disable=SC2086
            "$R" render "$OUT/rare.scene" --spp "$SPP" --jitter $st --seed $((1000 * $2 + k)) --threads 1 --quiet \
                --no-png -o "$f"
        fi
        list="$list $f"
        k=$((k + 1))
    done
    echo "$list"
}
echo "| comparison (K = $K per side, $SETS pairs) | consistent | different | inconclusive | the tests alone: different | median tail index A, B |"
echo "| --- | --- | --- | --- | --- | --- |"
for pair in "nee nee" "nee mis" "mis mis"; do
    set -- $pair
    c=0 d=0 i=0 td=0 s=0
    : > "$OUT/tails.txt"
    while [ "$s" -lt "$SETS" ]; do
        a=$(set_files "$1" $((2 * s)))
        b=$(set_files "$2" $((2 * s + 1)))
        status=0
        # shellcheck disable=SC2086
        "$R" check --a $a --b $b --quiet --json "$OUT/check.json" > /dev/null 2>&1 || status=$?
        case $status in
        0) c=$((c + 1)) ;;
        1) d=$((d + 1)) ;;
        3) i=$((i + 1)) ;;
        *) echo "check failed with status $status" >&2; exit 2 ;;
        esac
        grep -q '"tests_say": "different"' "$OUT/check.json" && td=$((td + 1))
        awk '/"a": \{"measured"/ { sub(/.*"tail_index": /, ""); sub(/,.*/, ""); a = $0 }
             /"b": \{"measured"/ { sub(/.*"tail_index": /, ""); sub(/,.*/, ""); print a, $0 }' "$OUT/check.json" >> "$OUT/tails.txt"
        s=$((s + 1))
    done
    med=$(sort -g -k1,1 "$OUT/tails.txt" | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
    medb=$(sort -g -k2,2 "$OUT/tails.txt" | awk '{ b[NR] = $2 } END { print b[int((NR + 1) / 2)] }')
    printf "| %s vs %s | %d | %d | %d | %d | %.2f, %.2f |\n" "$(echo "$1" | tr a-z A-Z)" "$(echo "$2" | tr a-z A-Z)" "$c" "$d" "$i" "$td" "$med" "$medb"
done
