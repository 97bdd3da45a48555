#!/bin/sh
# make valgrind: the CLI paths of the quick suite under valgrind memcheck (a few minutes;
# not part of make test). Each command must end with its expected exit status and
# without any memcheck error: invalid reads or writes, uses of uninitialised values,
# bad frees, and definitely or indirectly lost memory at exit (--error-exitcode=99).
#   sh scripts/valgrind.sh BUILD/restir [OUT]
set -u
R=$1
OUT=${2:-out/valgrind}
SCENE=tests/data/quad-light.scene
SMALL="--size 8x6 --threads 2 --quiet --no-png"
VG="valgrind --tool=memcheck --error-exitcode=99 --leak-check=full --show-leak-kinds=definite,indirect
    --errors-for-leak-kinds=definite,indirect --quiet"
rm -rf "$OUT"
mkdir -p "$OUT"
failures=0
count=0

# vg NAME EXPECTED-STATUS(ES, a|b) ARGS...: runs `restir ARGS` under memcheck
vg() {
    name=$1 expected=$2
    shift 2
    count=$((count + 1))
    # shellcheck disable=SC2086 # VG is a word list
    $VG "$R" "$@" > "$OUT/$name.log" 2>&1
    status=$?
    case "|$expected|" in
    *"|$status|"*) printf 'ok    %-22s exit %d\n' "$name" "$status" ;;
    *)
        failures=$((failures + 1))
        if [ $status = 99 ]; then
            printf 'FAIL  %-22s memcheck errors (%s)\n' "$name" "$OUT/$name.log"
        else
            printf 'FAIL  %-22s exit %d, expected %s (%s)\n' "$name" "$status" "$expected" "$OUT/$name.log"
        fi ;;
    esac
}

vg render-pt 0 render "$SCENE" --method pt --spp 2 $SMALL -o "$OUT/pt1.pfm" --stats "$OUT/pt1.json"
vg render-pt-seed2 0 render "$SCENE" --method pt --spp 2 --seed 2 $SMALL -o "$OUT/pt2.pfm"
vg render-restir 0 render "$SCENE" --method restir --spatial-passes 1 --neighbors 3 $SMALL -o "$OUT/rs1.pfm"
vg render-restir-seed2 0 render "$SCENE" --method restir --spatial-passes 1 --neighbors 3 --seed 2 $SMALL \
    -o "$OUT/rs2.pfm"
vg render-sequence-dump 0 render "$SCENE" --method restir --sequence 0..1 --spatial-passes 1 $SMALL \
    --dump-dir "$OUT/dumpA" -o "$OUT/seqA.pfm"
vg render-sequence-again 0 render "$SCENE" --method restir --sequence 0..1 --spatial-passes 1 $SMALL \
    --dump-dir "$OUT/dumpB" -o "$OUT/seqB.pfm"
vg info 0 info "$SCENE"
vg compare 0 compare "$OUT/pt1.pfm" "$OUT/rs1.pfm" --error-map "$OUT/map.png"
vg check 0\|1 check --a "$OUT/pt1.pfm" "$OUT/pt2.pfm" --b "$OUT/rs1.pfm" "$OUT/rs2.pfm" --block 2
vg merge 0 merge -o "$OUT/merged.pfm" "$OUT/pt1.pfm" "$OUT/pt2.pfm" --counts 2,2 --no-png --quiet
vg inspect 0 inspect "$SCENE" --pixel 3,3 --size 8x6
vg vectors-check 0 vectors --check tests/vectors/wrs.jsonl tests/vectors/mis.jsonl tests/vectors/shift.jsonl
vg diff-dump 0 diff-dump "$OUT/dumpA" "$OUT/dumpB"
# Bad input: a message and exit 2, and no leak on the error paths.
printf 'v 0 0 0\nv 1 0 0\nf 1 2 7\n' > "$OUT/bad.obj"
vg bad-obj 2 render "$OUT/bad.obj" $SMALL -o "$OUT/bad.pfm"
printf 'PF\n4 4\n-1\n' > "$OUT/short.pfm"
vg bad-pfm 2 compare "$OUT/short.pfm" "$OUT/pt1.pfm"
vg bad-option 2 render "$SCENE" --spp many
vg missing-scene 2 render "$OUT/absent.scene" $SMALL

echo "valgrind: $((count - failures)) passed, $failures failed (logs in $OUT)"
[ $failures = 0 ]
