#!/bin/sh
# The hostile-case table (issue 27, docs/hostile-cases.md): runs every hostile case (the
# ones issue 27 found and the older ones the CLI rules already handled) through build/restir
# (or $HOSTILE_BIN),
# each in its own empty directory, and prints a Markdown table: the case, the exit status
# (and the expected one), the first line of the message, and the files left behind.
#   sh scripts/hostile.sh            the table on stdout; exit 1 if a status is not the expected one
#                                    or a case with exit 2 left a file
#   make hostile-table               writes docs/hostile-cases.md
#   HOSTILE_TIMES=1 sh scripts/hostile.sh   also each case's milliseconds on stderr
# The test hostile_table_script (make test) runs it and fails on a mismatch. ~10 s.
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
R=${HOSTILE_BIN:-$ROOT/build/restir} # the binary under test (absolute: each case runs in its own directory)
S="$ROOT/scenes"
W=${HOSTILE_DIR:-$ROOT/build/hostile}
rm -rf "$W"
mkdir -p "$W"
W=$(cd "$W" && pwd) # absolute: each case runs in its own directory and copies fixtures from $W
SMALL="$S/cornell.scene --size 16x16 --threads 2 --max-depth 4"
fails=0
n=0

# row NAME EXPECTED SETUP COMMAND [KNOWN]: SETUP runs first (its files are not leftovers),
# then COMMAND (a shell line; $R is the binary) with a 20 s limit; the row is printed. KNOWN
# (e.g. "known: kit") marks files an exit 2 leaves today as a recorded fault, not a failure. The
# message is the first line of stderr (of stdout when stderr is empty), and the last one
# when there are more.
row() {
    name=$1 expected=$2 setup=$3 cmd=$4 known=${5:-}
    n=$((n + 1))
    [ -z "${HOSTILE_TIMES:-}" ] || t0=$(date +%s%N)
    d="$W/case$n"
    mkdir -p "$d"
    (cd "$d" && eval "$setup") >/dev/null 2>&1
    (cd "$d" && find . -mindepth 1 | sort) >"$W/before$n"
    (cd "$d" && eval "timeout 20 $cmd") >"$W/out$n" 2>"$W/err$n" </dev/null
    status=$?
    (cd "$d" && find . -mindepth 1 | sort) >"$W/after$n"
    left=$(comm -13 "$W/before$n" "$W/after$n" | sed 's|^\./||' | while read -r f; do
        case "$f" in
        *.png) if [ -f "$d/$f" ] && [ "$(head -c 4 "$d/$f" | tail -c 3)" != PNG ]; then f="$f (not a PNG)"; fi ;;
        esac
        printf '%s ' "$f"
    done)
    [ -n "$left" ] || left="none"
    grep -v '^pt: [0-9]* spp' "$W/err$n" >"$W/msg$n"
    [ -s "$W/msg$n" ] || cp "$W/out$n" "$W/msg$n"
    msg=$(head -n 1 "$W/msg$n")
    if [ "$(wc -l <"$W/msg$n")" -gt 1 ]; then msg="$msg / $(tail -n 1 "$W/msg$n")"; fi
    msg=$(printf '%s' "$msg" | sed "s|$ROOT/||g; s|$W/case$n/||g; s/|/\\\\|/g" | cut -c1-240)
    mark=""
    if [ "$status" != "$expected" ]; then
        mark=" **expected $expected**"
        fails=$((fails + 1))
    elif [ "$status" = 2 ] && [ "$left" != none ] && [ -n "$known" ]; then
        mark=" ($known)" # a known fault of another helper's command, recorded as it is today
    elif [ "$status" = 2 ] && [ "$left" != none ]; then
        mark=" **exit 2 left files**" # the rule: exit 2 leaves nothing
        fails=$((fails + 1))
    fi
    printf '| %d | %s | %s%s | %s | %s |\n' "$n" "$name" "$status" "$mark" "$msg" "$left"
    [ -z "${HOSTILE_TIMES:-}" ] || echo "$n $((($(date +%s%N) - t0) / 1000000)) ms" >&2
}

KEYS='printf "mesh '"$S"'/cornell.obj\nkeyframe 0 eye 278 273 -800 target 278 273 0 up 0 1 0 fov 39\nkeyframe 10 eye 278 273 -800 target 278 273 0 up 0 -1 0 fov 39\nsize 8 8\n" > up.scene'
EYE='printf "mesh '"$S"'/cornell.obj\ncamera eye 1e39 273 -800 target 278 273 0 up 0 1 0 fov 39\n" > eye.scene'
BIG='printf "v -3e38 -3e38 0\nv 3e38 -3e38 0\nv 0 3e38 0\nf 1 2 3\n" > big.obj; printf "mesh big.obj\ncamera eye 0 0 -10 target 0 0 0 up 0 1 0 fov 39\nmaterial default ke 1 1 1\n" > big.scene'
CKPTS="\$R render $SMALL --spp 1 --quiet --no-png -o a.pfm --checkpoint a.ckpt; \$R render $SMALL --spp 1 --sample-offset 1 --quiet --no-png -o b.pfm --checkpoint b.ckpt"
DUMP="\$R render $SMALL --method restir --sequence 0..1 --dump-dir dump --quiet --no-png -o s.pfm; rm -f s.*"
CORRUPT="$DUMP; head -c 100 dump/frame_0001/initial.resv > t; mv t dump/frame_0001/initial.resv"
NAN="\$R render $SMALL --spp 1 --quiet --no-png -o a.pfm; python3 -c \"import struct;d=open('a.pfm','rb').read();i=d.index(b'\\\\n',d.index(b'\\\\n',3)+1)+1;open('nan.pfm','wb').write(d[:i]+struct.pack('<f',float('nan'))+d[i+4:])\""
RARE="printf 'v -2 0 -2\\nv 2 0 -2\\nv 2 0 2\\nv -2 0 2\\nv -1 3 -1\\nv 1 3 -1\\nv 1 3 1\\nv -1 3 1\\nv -0.01 0.05 -0.01\\nv 0.01 0.05 -0.01\\nv 0.01 0.05 0.01\\nv -0.01 0.05 0.01\\nusemtl floor\\nf 1 4 3\\nf 1 3 2\\nusemtl sky\\nf 5 6 7\\nf 5 7 8\\nusemtl spot\\nf 9 10 11\\nf 9 11 12\\n' > rare.obj; printf 'mesh rare.obj\\ncamera eye 0 1 1 target 0 0 0 up 0 1 0 fov 20\\nsize 48 48\\nmaterial floor type lambert kd 0.7 0.7 0.7\\nmaterial sky type lambert kd 0 0 0 ke 5 5 5\\nmaterial spot type lambert kd 0 0 0 ke 5 5 5\\n' > rare.scene; for k in \$(seq 10 41); do \$R render rare.scene --spp 4 --jitter --pt-strategy nee --seed \$k --threads 2 --quiet --no-png -o n\$k.pfm; done"
RUNS4="for k in 1 2 3 4; do \$R render $SMALL --spp 1 --seed \$k --quiet --no-png -o r\$k.pfm; done"

# The common setups run once into fixture directories; a case's setup copies them (the
# same files, and the script stays well under 15 s).
F="$W/fixtures"
fixture() { mkdir -p "$F/$1" && (cd "$F/$1" && eval "$2") >/dev/null 2>&1; }
fixture runs4 "$RUNS4"
fixture ckpts "$CKPTS"
fixture dump "$DUMP"
fixture nan "$NAN"
RUNS4="cp $F/runs4/* ."
CKPTS="cp $F/ckpts/* ."
DUMP="cp -r $F/dump/* ."
NAN="cp $F/nan/* ."
CORRUPT="$DUMP; head -c 100 dump/frame_0001/initial.resv > t; mv t dump/frame_0001/initial.resv"

echo "| # | case | exit | message (first line) | left behind |"
echo "| --- | --- | --- | --- | --- |"
echo "| | **issue 27** | | | |"
row "keyframes whose interpolated up passes through zero (frame 5)" 2 "$KEYS" "\$R render up.scene --frame 5 --spp 1 -o up.pfm"
row "camera eye 1e39" 2 "$EYE" "\$R render eye.scene --spp 1 -o eye.pfm"
row "vertices at +-3e38" 2 "$BIG" "\$R render big.scene --spp 1 -o big.pfm"
row "--eye 1e39,0,0 on the command line" 2 "" "\$R render $SMALL --eye 1e39,0,0 --spp 1 -o x.pfm"
row "--stats equal to -o" 2 "" "\$R render $SMALL --spp 1 -o a.pfm --stats a.pfm"
row "--checkpoint equal to the PNG preview (another spelling)" 2 "" "\$R render $SMALL --spp 1 -o a.pfm --checkpoint ./a.png"
row "merge -o a.ckpt a.ckpt b.ckpt" 2 "$CKPTS" "\$R merge -o a.ckpt a.ckpt b.ckpt"
row "--sample-offset with --resume" 2 "$CKPTS" "\$R render $SMALL --spp 4 --resume a.ckpt --sample-offset 100 -o c.pfm"
row "--resume of another seed (the message shows the checkpoint's fields)" 2 "$CKPTS" "\$R render $SMALL --seed 5 --spp 4 --resume a.ckpt -o c.pfm"
row "--dump-stages initial,bogus" 2 "" "\$R render $SMALL --method restir --sequence 0..1 --dump-dir dump --dump-stages initial,bogus -o s.pfm"
row "--from-dump with a corrupt frame 1" 2 "$CORRUPT" "\$R render $SMALL --method restir --sequence 0..1 --from-dump dump --from-stage initial -o f.pfm"
row "vectors --check, a negative RNG input" 2 "printf '{\"fn\": \"rng_u\", \"case\": \"x\", \"in\": [1, 0, 0, -1, 1, 0], \"out\": [1, 0.5]}\n' > neg.jsonl" "\$R vectors --check neg.jsonl"
row "vectors --check, an empty file" 2 ": > empty.jsonl" "\$R vectors --check empty.jsonl"
row "vectors --check, a wrong input count" 2 "printf '{\"fn\": \"rng_u\", \"case\": \"x\", \"in\": [1, 0, 0, 1, 1], \"out\": [1, 0.5]}\n' > cnt.jsonl" "\$R vectors --check cnt.jsonl"
row "vectors --check, a pick's random number -1e10" 2 "printf '{\"fn\": \"stochastic_pairwise_weights\", \"case\": \"x\", \"in\": [1, 1, 1, 1, 1, 0.5, 2, 1, 0.3, 3, 0.9, 0.35, 0.45, 0.5, -1e10], \"out\": [0]}\n' > u.jsonl" "\$R vectors --check u.jsonl"
row "mesh /dev/urandom" 2 "printf 'mesh /dev/urandom\n' > u.scene" "\$R info u.scene"
row "manifest with frames.last = 2e9 (diff-dump)" 2 "$DUMP; sed -i 's/\"last\": 1/\"last\": 2000000000/' dump/manifest.json" "\$R diff-dump dump dump"
row "replay temporal without frame 0's final file" 2 "$DUMP; rm dump/frame_0000/temporal.resv" "\$R replay dump --frame 1 --stage temporal --dump-dir out"
row "inspect --from-dump of a manifest without command_line" 2 "$DUMP; sed -i '/command_line/d' dump/manifest.json" "\$R inspect --from-dump dump --frame 1 --stage temporal --pixel 3,3"
row "inspect --from-dump --stage initial" 2 "$DUMP" "\$R inspect --from-dump dump --frame 1 --stage initial --pixel 3,3"
row "--history-from-dump at the dump's first frame" 2 "$DUMP" "\$R render $SMALL --method restir --sequence 0..1 --from-dump dump --from-stage initial --history-from-dump -o h.pfm"
row "diagnose with a B that holds no stage file" 2 "$DUMP; mkdir b; cp dump/manifest.json b/" "\$R diagnose dump b"
row "merge --counts with a NaN pixel" 2 "$NAN" "\$R merge -o m.pfm a.pfm nan.pfm --counts 1,1"
row "merge --counts 1,inf" 2 "$NAN" "\$R merge -o m.pfm a.pfm nan.pfm --counts 1,inf"
row "SIGTERM during a complete aov render" 143 "" "timeout --preserve-status -s TERM 0.2 \$R render $S/cornell.scene --method aov --aov depth --size 2048x2048 --threads 1 --no-png -o aov.pfm"
row "--runs 2 (the message names the files written)" 0 "" "\$R render $SMALL --spp 1 --runs 2 --no-png -o r.pfm"
row "help --help" 0 "" "\$R help --help"
row "vectors -o outside the repository" 0 "" "\$R vectors -o v"
row "check --z-map OUT.png" 0 "$RUNS4" "\$R check --a r1.pfm r2.pfm --b r3.pfm r4.pfm --z-map z.png --quiet"
row "check --z-map naming an input" 2 "$RUNS4" "\$R check --a r1.pfm r2.pfm --b r3.pfm r4.pfm --z-map r1.pfm --quiet"
row "check on heavy-tailed runs (NEE only under a rare close light, K = 16)" 3 "$RARE" "\$R check --a \$(ls n*.pfm | head -16) --b \$(ls n*.pfm | tail -16) --quiet"
row "check --json naming a file of --a-moments" 2 "\$R render $SMALL --spp 1 --runs 2 --quiet --no-png -o m.pfm" "\$R check --a-moments m --b-moments m --json m.moments.json"
row "compare --bias --level 2" 2 "$RUNS4" "\$R compare --bias r1.pfm r2.pfm --ref r3.pfm --level 2"
row "SIGINT during the first offline ReSTIR frame (nothing complete)" 130 "" "timeout --preserve-status -s INT 0.3 \$R render $S/cornell.scene --size 160x160 --method restir --preset gris-offline --threads 2 --quiet -o x.pfm"
echo "| | **earlier rules (docs/cli.md)** | | | |"
row "--threads 0" 2 "" "\$R render $SMALL --threads 0 -o x.pfm"
row "--size 100000x100000" 2 "" "\$R render $SMALL --size 100000x100000 -o x.pfm"
row "-o x.png" 2 "" "\$R render $SMALL -o x.png"
row "-o into a missing directory two levels deep" 2 "" "\$R render $SMALL --spp 1 -o no/such/x.pfm"
row "--stats naming a directory" 2 "mkdir d" "\$R render $SMALL --spp 1 -o x.pfm --stats d"
row "--spp with --method restir" 2 "" "\$R render $SMALL --method restir --spp 4 -o x.pfm"
row "--checkpoint with offline restir" 2 "" "\$R render $SMALL --method restir --checkpoint c.ckpt -o x.pfm"
row "--runs 1" 2 "" "\$R render $SMALL --runs 1 -o x.pfm"
row "--no-png=1 (a flag given a value)" 2 "" "\$R render $SMALL --no-png=1 -o x.pfm"
row "OBJ face index 100000000" 2 "printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 100000000\n' > i.obj" "\$R info i.obj"
row "a 5 MB line" 2 "yes v | tr -d '\\n' | head -c 5000000 > long.obj" "\$R info long.obj"
row "a coordinate 1e39 in an OBJ" 2 "printf 'v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n' > f.obj" "\$R info f.obj"
row "a scene without mesh" 2 "printf 'size 8 8\n' > n.scene" "\$R info n.scene"
row "a scene without emitters, --method pt" 2 "printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > t.obj" "\$R render t.obj --spp 1 -o t.pfm"
row "unknown command" 2 "" "\$R frobnicate"
row "check with a truncated PFM" 2 "$RUNS4; head -c 100 r1.pfm > cut.pfm" "\$R check --a cut.pfm r2.pfm --b r3.pfm r4.pfm"
row "merge images without --counts" 2 "$NAN" "\$R merge -o m.pfm a.pfm nan.pfm"
row "--png into a directory that cannot be created" 2 "" "\$R render $SMALL --spp 1 -o x.pfm --png no/such/x.png"
row "SIGINT during pt (partial image and checkpoint kept)" 130 "" "timeout --preserve-status -s INT 0.5 \$R render $SMALL --spp 100000000 --quiet --no-png --checkpoint c.ckpt -o x.pfm"
row "SIGTERM during offline restir (the mean of the frames so far)" 143 "" "timeout --preserve-status -s TERM 0.5 \$R render $SMALL --method restir --frames 100000000 --quiet --no-png -o x.pfm"
echo "| | **the audit beyond the list: compare, check, plot, generate, stats, merge, vectors, help** | | | |"
FULL='ln -s /dev/full full' # a link: a regression would replace the link, never the device
# DISK N COMMAND: COMMAND with files limited to N blocks of 512 bytes and SIGXFSZ ignored,
# so a write beyond fails with EFBIG: a full disk without root or a small file system.
printf '#!/bin/sh\ntrap "" XFSZ\nulimit -f "$1"\nshift\nexec "$@"\n' > "$W/disk.sh"
DISK="sh $W/disk.sh 1"
CSV='printf "x,y\n1,2\n2,4\n" > d.csv'
row "compare --error-map naming TEST (was: TEST overwritten, exit 0)" 2 "$RUNS4" "\$R compare r1.pfm r2.pfm --error-map r1.pfm"
row "compare --json and --error-map one file (was: exit 0)" 2 "$RUNS4" "\$R compare r1.pfm r2.pfm --json e.out --error-map ./e.out"
row "compare --json to a link to /dev/full (was, as root: /dev/full replaced by a file)" 2 "$RUNS4; $FULL" "\$R compare r1.pfm r2.pfm --json full"
row "compare --error-map into /dev" 2 "$RUNS4" "\$R compare r1.pfm r2.pfm --error-map /dev/restir-map.png"
row "compare --error-map below a regular file (checked before work)" 2 "$RUNS4" "\$R compare r1.pfm r2.pfm --error-map r1.pfm/m.png"
row "compare --error-map on a full disk" 2 "$RUNS4" "$DISK \$R compare r1.pfm r2.pfm --error-map m.png"
row "compare, its table to a full stdout (was: exit 0)" 2 "$RUNS4" "\$R compare r1.pfm r2.pfm > /dev/full"
row "compare --metric without --error-map (was: ignored, exit 0)" 2 "$RUNS4" "\$R compare r1.pfm r2.pfm --metric mse"
row "compare a 0x0 PFM" 2 "printf 'PF\n0 0\n-1.0\n' > z.pfm" "\$R compare z.pfm z.pfm"
row "compare a NaN pixel" 2 "$NAN" "\$R compare nan.pfm a.pfm"
row "compare --covariance with one run twice (was: exit 0)" 2 "$RUNS4" "\$R compare --covariance r1.pfm ./r1.pfm r2.pfm"
row "compare --covariance --map naming a run (was: the run overwritten)" 2 "$RUNS4" "\$R compare --covariance r1.pfm r2.pfm --map r2.pfm"
row "compare --bias --json naming --ref" 2 "$RUNS4" "\$R compare --bias r1.pfm r2.pfm --ref r3.pfm --json r3.pfm"
row "compare --bias with one run twice" 2 "$RUNS4" "\$R compare --bias r1.pfm r1.pfm --ref r3.pfm"
ZERO="python3 -c \"import struct;[open('z%d.pfm'%k,'wb').write(b'PF\\\\n16 16\\\\n-1.0\\\\n'+bytes(3072)) for k in (1,2,3)]\""
row "compare --bias against a black reference (was: 'rel_bias -nan', -nan in the JSON, exit 0)" 2 "$ZERO" "\$R compare --bias z1.pfm z2.pfm --ref z3.pfm --json b.json"
row "compare --bias with a NaN run (was: 'rel_bias nan', exit 0)" 2 "$NAN; cp a.pfm b.pfm" "\$R compare --bias nan.pfm a.pfm --ref b.pfm"
row "compare --bias --mask with a NaN pixel (was: exit 0)" 2 "$RUNS4; $NAN" "\$R compare --bias r1.pfm r2.pfm --ref r3.pfm --mask nan.pfm"
row "compare --bias --mask-range without --mask (was: ignored, exit 0)" 2 "$RUNS4" "\$R compare --bias r1.pfm r2.pfm --ref r3.pfm --mask-range 1e300,inf"
row "check with a file on both sides (was: exit 0)" 2 "$RUNS4" "\$R check --a r1.pfm r2.pfm --b r3.pfm ./r1.pfm"
row "check --ref with a NaN pixel (was: SIGFPE, exit 136)" 2 "$RUNS4; $NAN" "\$R check --a r1.pfm r2.pfm --ref nan.pfm"
row "check --json to a link to /dev/full" 2 "$RUNS4; $FULL" "\$R check --a r1.pfm r2.pfm --b r3.pfm r4.pfm --json full"
row "check --json below a regular file (checked before work)" 2 "$RUNS4" "\$R check --a r1.pfm r2.pfm --b r3.pfm r4.pfm --json r1.pfm/c.json"
row "check --z-map on a full disk" 2 "$RUNS4" "$DISK \$R check --a r1.pfm r2.pfm --b r3.pfm r4.pfm --z-map z.pfm --quiet"
row "check, the verdict to a full stdout (was: exit 0)" 2 "$RUNS4" "\$R check --a r1.pfm r2.pfm --b r3.pfm r4.pfm --quiet > /dev/full"
row "plot -o naming DATA.csv (was: the data overwritten, exit 0)" 2 "$CSV" "\$R plot d.csv -o d.csv"
row "plot --linear of y from -1e308 to 1e308 (was: NaN coordinates in the SVG, exit 0)" 2 "printf 'x,y\n1,1e308\n2,-1e308\n' > b.csv" "\$R plot b.csv -o b.svg --linear"
row "plot --linear of y 1e308 .. 1.7e308 (was: hung)" 2 "printf 'x,y\n1,1e308\n2,1.7e308\n' > b.csv" "\$R plot b.csv -o b.svg --linear"
row "plot --linear of a span below the values' rounding (was: hung)" 2 "printf 'x,y\n1,1e300\n2,1.0000000000000002e300\n' > b.csv" "\$R plot b.csv -o b.svg --linear"
row "plot of a header without rows" 2 "printf 'x,y\n' > h.csv" "\$R plot h.csv -o h.svg"
row "plot on a full disk" 2 "$CSV" "$DISK \$R plot d.csv -o d.svg --title \$(head -c 600 /dev/zero | tr '\\0' t)"
row "generate -o a.scene (was: OBJ text in a .scene file, exit 0)" 2 "" "\$R generate ajar -o a.scene"
row "generate on a full disk (was: the MTL left behind)" 2 "" "$DISK \$R generate ajar -o g.obj"
row "generate sphere --subdivisions 8192 (was: accepted: 805M triangles, about 50 GB by extrapolation)" 2 "" "\$R generate sphere --subdivisions 8192 -o s.obj"
row "generate -o into /dev" 2 "" "\$R generate ajar -o /dev/restir-g.obj"
row "SIGTERM during generate (was: a 98 MB OUT.obj.tmp.PID left)" 143 "" "timeout --preserve-status -s TERM 0.5 \$R generate sphere --subdivisions 600 -o s.obj"
row "generate --progress sometimes" 2 "" "\$R generate sphere --progress sometimes -o s.obj"
# bench: the JSON goes to b.json; the message's last line is b.json's last entry
BENCH_INT() { # SIGNAL SECONDS ARGS: bench ARGS > b.json, signalled; b.json's last entry on stderr
    echo "timeout --preserve-status -s $1 $2 \$R bench $3 > b.json; s=\$?; tail -n 2 b.json | head -n 1 >&2; exit \$s"
}
row "SIGINT 0.3 s into bench restir (was: waited for the 6 s step, then a closed array that looked complete)" 130 "" "$(BENCH_INT INT 0.3 "restir $S/cornell.scene --threads 2")"
row "SIGTERM 0.3 s into bench animation (the shipped scenes, then the 270k-triangle sphere)" 143 "ln -s $S scenes" "$(BENCH_INT TERM 0.3 "animation --generated 150 --threads 2")"
row "SIGINT 0.3 s into bench pairing-sigma (was: 120 s, no step boundary)" 130 "" "$(BENCH_INT INT 0.3 pairing-sigma)"
row "stats mean-ci of one 8.9 kB line 1..2000 (was: numbers split at 4096 bytes, mean 998.1)" 0 "seq 1 2000 | tr '\\n' ' ' > l.txt" "\$R stats mean-ci l.txt --format '%.6g +- %.3g'"
row "stats mean-ci of 1e308 1e308 -1e308 (was: 'inf +- -nan', exit 0)" 2 "echo 1e308 1e308 -1e308 > b.txt" "\$R stats mean-ci b.txt"
row "stats mean-ci of a directory" 2 "mkdir d" "\$R stats mean-ci d"
row "stats mean-ci of one number" 2 "echo 5 > one.txt" "\$R stats mean-ci one.txt"
row "stats t-table to a full stdout (was: exit 0)" 2 "" "\$R stats t-table > /dev/full"
row "help to a full stdout (was: exit 0)" 2 "" "\$R help > /dev/full"
row "merge of one image twice (was: exit 0, its samples counted twice)" 2 "\$R render $SMALL --spp 1 --quiet --no-png -o a.pfm" "\$R merge -o m.pfm a.pfm ./a.pfm --counts 1,1"
row "merge of images with --checkpoint-out (was: ignored, exit 0)" 2 "$CKPTS" "\$R merge -o m.pfm a.pfm b.pfm --counts 1,1 --checkpoint-out m.ckpt"
row "merge of checkpoints with --counts (was: ignored, exit 0)" 2 "$CKPTS" "\$R merge -o m.pfm a.ckpt b.ckpt --counts 1,1"
row "merge -o to a link to /dev/full" 2 "$CKPTS; $FULL" "\$R merge -o full a.ckpt b.ckpt --no-png"
row "merge of an empty checkpoint (was: 'all checkpoints or all images')" 2 "$CKPTS; : > e.ckpt" "\$R merge -o m.pfm e.ckpt b.ckpt"
row "merge on a full disk" 2 "$CKPTS" "$DISK \$R merge -o m.pfm a.ckpt b.ckpt --checkpoint-out m.ckpt"
row "vectors -o on a full disk (was: 2 of 13 files left)" 2 "" "sh $W/disk.sh 20 \$R vectors -o v"
row "vectors -o naming a regular file" 2 ": > f" "\$R vectors -o f"
row "info to a full stdout (was: exit 0)" 2 "" "\$R info $S/cornell.scene > /dev/full"
row "info --up 0,0,0" 2 "" "\$R info $S/cornell.scene --up 0,0,0"
row "camera fov 0 in a scene file" 2 "printf 'mesh $S/cornell.obj\ncamera eye 0 0 0 target 0 0 1 up 0 1 0 fov 0\n' > c.scene" "\$R info c.scene"
row "camera eye = target in a scene file" 2 "printf 'mesh $S/cornell.obj\ncamera eye 1 2 3 target 1 2 3 up 0 1 0 fov 40\n' > c.scene" "\$R info c.scene"
row "animate with a zero rotation axis" 2 "printf 'mesh $S/ajar-swing.obj\nanimate door 0 rotate 0 0 0 30\n' > a.scene" "\$R info a.scene"
row "a scene whose triangles are all degenerate" 2 "printf 'v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n' > deg.obj" "\$R info deg.obj"
echo "| | **the audit beyond the list: render's option combinations and outputs** | | | |"
SEQ="$SMALL --method restir --sequence 0..1 --quiet"
row "--runs 2 with --checkpoint (was: the last run's state, exit 0)" 2 "" "\$R render $SMALL --spp 1 --runs 2 --checkpoint q.ckpt -o r.pfm"
row "--runs 2 with --resume (was: 'a different seed' after run 1)" 2 "$CKPTS" "\$R render $SMALL --spp 1 --runs 2 --resume a.ckpt -o r.pfm"
row "--runs 2 --png naming PREFIX.moments.json (was: one overwrote the other)" 2 "" "\$R render $SMALL --spp 1 --runs 2 -o r.pfm --png r.moments.json"
row "--runs 2 --stats naming PREFIX.blocks.bin" 2 "" "\$R render $SMALL --spp 1 --runs 2 -o r.pfm --stats r.blocks.bin"
row "--sequence with --checkpoint naming a frame (was: exit 0)" 2 "" "\$R render $SEQ -o s.pfm --checkpoint ./s.0000.pfm"
row "--sequence with --stats naming a frame's PNG (was: exit 0)" 2 "" "\$R render $SEQ -o s.pfm --stats s.0001.png"
row "--sequence 0..1 --runs 2 --stats naming frame 1's variance" 2 "" "\$R render $SEQ --runs 2 -o s.pfm --stats s.0001.var.pfm"
row "--stats naming the dump's manifest.json (was: exit 0)" 2 "" "\$R render $SEQ -o s.pfm --dump-dir d --stats d/manifest.json"
row "-o inside a frame directory of --dump-dir" 2 "mkdir -p d/frame_0000" "\$R render $SEQ -o d/frame_0000/s.pfm --dump-dir d"
row "--dump-dir overlapping --from-dump (was: the stages read are overwritten)" 2 "$DUMP" "\$R render $SEQ --from-dump dump --from-stage initial --dump-dir dump/../dump -o f.pfm"
row "--sequence with --checkpoint (frames and the checkpoint)" 0 "" "\$R render $SEQ -o s.pfm --checkpoint q.ckpt"
row "--sequence with --png (was: ignored, the file never written, exit 0)" 2 "" "\$R render $SEQ -o s.pfm --png p.png"
row "--sequence with --frames 5 (was: ignored, exit 0)" 2 "" "\$R render $SEQ -o s.pfm --frames 5"
row "--sequence with --frame 3 (was: ignored, exit 0)" 2 "" "\$R render $SEQ -o s.pfm --frame 3"
row "--runs 2 with --progressive 1 (was: ignored, exit 0)" 2 "" "\$R render $SMALL --spp 4 --runs 2 --progressive 1 -o r.pfm"
row "--sequence 5..2" 2 "" "\$R render $SMALL --method restir --sequence 5..2 -o s.pfm"
row "--sequence 0..100000000" 2 "" "\$R render $SMALL --method restir --sequence 0..100000000 -o s.pfm"
row "--size 0x0" 2 "" "\$R render $SMALL --size 0x0 -o x.pfm"
row "--size 8192x8193" 2 "" "\$R render $SMALL --size 8192x8193 -o x.pfm"
row "--threads -1" 2 "" "\$R render $SMALL --threads -1 -o x.pfm"
row "--threads 1000" 2 "" "\$R render $SMALL --threads 1000 -o x.pfm"
row "--spp 0" 2 "" "\$R render $SMALL --spp 0 -o x.pfm"
row "pt --time-limit 1e-9: no pass complete (was: a black image of 0 spp, exit 0)" 2 "" "\$R render $SMALL --spp 1 --time-limit 1e-9 -o x.pfm --checkpoint x.ckpt"
row "pt --runs 2 --time-limit 1e-9 (was: mean and variance of two black images, exit 0)" 2 "" "\$R render $SMALL --spp 1 --runs 2 --time-limit 1e-9 -o r.pfm"
row "-o to a link to /dev/full" 2 "$FULL" "\$R render $SMALL --spp 1 --no-png -o full"
row "-o on a full disk" 2 "" "$DISK \$R render $SMALL --spp 1 -o x.pfm"
row "--stats into /dev" 2 "" "\$R render $SMALL --spp 1 -o x.pfm --stats /dev/restir-stats.json"
echo "| | **inspect, replay, diff-dump, diagnose** | | | |"
row "replay --dump-dir into the dump it replays (refused by render's dump checks)" 2 "$DUMP" "\$R replay dump --frame 1 --stage temporal --dump-dir dump"
row "diff-dump --images into dump A (was: exit 0, images written among A's stage files)" 2 "$DUMP; cp -r dump d2" "\$R diff-dump dump d2 --images dump > /dev/null"
row "diff-dump, its table to a full stdout" 2 "$DUMP; cp -r dump d2" "\$R diff-dump dump d2 > /dev/full"
row "diff-dump --images on a full disk (exit 2 keeps the images written so far and says so)" 2 "$DUMP; cp -r dump d2" "$DISK \$R diff-dump dump d2 --images im > /dev/null" "kept, named on stderr"
row "replay --dump-dir on a full disk" 2 "$DUMP" "$DISK \$R replay dump --frame 1 --stage temporal --dump-dir out"
row "diff-dump --images naming a link to /dev/null" 2 "$DUMP; cp -r dump d2; ln -s /dev/null nl" "\$R diff-dump dump d2 --images nl"
echo
echo "$n cases, $fails with an unexpected exit status (or files left by an exit 2)."
[ "$fails" = 0 ]
