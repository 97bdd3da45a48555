#!/bin/sh
# Runs every command of README.md's code blocks marked ```sh tested (test readme_commands_run),
# from the repository root, small: build/restir -> the tested binary, out/ -> a scratch
# directory, --size above 64 pixels -> 32 x 24, --spp and --sample-offset divided by 1024
# (at least 1 spp), `make run` -> scripts/demo.sh with tiny sizes, `make test` skipped (it
# is the suite running this). Prints each command; exit 1 at the first that fails.
#
# usage: tests/readme_commands.sh README.md RESTIR_BIN SCRATCH_DIR
readme=$1
bin=$2
tmp=$3
mkdir -p "$tmp" || exit 2
rm -rf "$tmp/out"
# the tested blocks, continuation lines joined, comments and blank lines dropped
awk '/^```sh tested/ { inblock = 1; next }
     /^```/ { inblock = 0; next }
     inblock {
         sub(/[ \t]*#.*$/, "")
         if ($0 ~ /\\$/) { sub(/\\$/, ""); line = line $0; next }
         line = line $0
         if (line ~ /[^ \t]/) print line
         line = ""
     }' "$readme" > "$tmp/commands.txt" || exit 2
[ -s "$tmp/commands.txt" ] || { echo "readme: no tested command in $readme"; exit 1; }

shrink() {
    awk -v bin="$bin" -v out="$tmp/out/" '{
        n = split($0, w, /[ \t]+/); s = ""
        for (i = 1; i <= n; ++i) {
            t = w[i]
            if (t == "") continue
            if (t == "build/restir") t = bin
            gsub(/^out\//, out, t)
            if ((w[i-1] == "--spp" || w[i-1] == "--sample-offset") && t ~ /^[0-9]+$/) {
                t = int(t / 1024); if (w[i-1] == "--spp" && t < 1) t = 1
            }
            if (w[i-1] == "--size" && split(t, d, "x") == 2 && (d[1] > 64 || d[2] > 64)) t = "32x24"
            s = s (s == "" ? "" : " ") t
        }
        print s
    }'
}

status=0
while IFS= read -r cmd; do
    case "$cmd" in
    "make test"*) echo "skip: $cmd (the suite itself)"; continue ;;
    "make run"*) run="DEMO_SIZE=32x24 DEMO_SECONDS=0.5 DEMO_RUNS=4 DEMO_CHECK_SPP=4 DEMO_REF_SPP=64 DEMO_REF_FRAMES=4 sh scripts/demo.sh $tmp/out $bin" ;;
    make*) echo "readme: no rule to run '$cmd' in the test"; status=1; continue ;;
    *) run=$(printf '%s\n' "$cmd" | shrink) ;;
    esac
    echo "run: $run"
    if ! sh -c "$run" > "$tmp/last.txt" 2>&1; then
        cat "$tmp/last.txt"
        echo "readme: FAILED: $cmd"
        exit 1
    fi
done < "$tmp/commands.txt"
exit $status
