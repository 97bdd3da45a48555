#!/bin/sh
# make test-data: every OBJ under the shared data directory through `restir info`,
# checked against tests/data-expectations.txt (path, loads|rejected, part of the error).
# A file expected to load must exit 0; a rejected one must exit 2 with its one-line
# "file:line: what" error. Prints one line per file and ends with "N passed, N failed".
# Usage: sh tests/test-data.sh BUILD/restir DATA_DIR
BIN=$1
DATA=$2
TABLE=tests/data-expectations.txt
if [ ! -d "$DATA" ]; then
    echo "test-data: $DATA is absent; skipped"
    exit 0
fi
if [ ! -x "$BIN" ]; then
    echo "test-data: $BIN is not built" >&2
    exit 2
fi
list=$(mktemp) || exit 2
trap 'rm -f "$list"' EXIT
find "$DATA" -name '*.obj' | LC_ALL=C sort >"$list"
passed=0
failed=0
while IFS= read -r file; do
    rel=${file#"$DATA"/}
    kind=$(awk -F '\t' -v p="$rel" '$1 == p { print $2; exit }' "$TABLE")
    text=$(awk -F '\t' -v p="$rel" '$1 == p { print $3; exit }' "$TABLE")
    out=$("$BIN" info "$file" 2>&1)
    status=$?
    verdict=FAIL
    case $kind in
    loads) [ $status -eq 0 ] && verdict=ok ;;
    rejected)
        if [ $status -eq 2 ] && [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] &&
            printf '%s\n' "$out" | grep -F -q -- "$file:" &&
            printf '%s\n' "$out" | grep -F -q -- "$text"; then
            verdict=ok
        fi
        ;;
    *) out="not in $TABLE" ;;
    esac
    if [ $verdict = ok ]; then
        passed=$((passed + 1))
        echo "ok   $rel ($kind)"
    else
        failed=$((failed + 1))
        echo "FAIL $rel: expected ${kind:-an entry}, exit $status: $(printf '%s\n' "$out" | head -1)"
    fi
done <"$list"
echo "$passed passed, $failed failed"
[ $failed -eq 0 ]
