#!/bin/sh
# `make test-cluster`: runs the GNU parallel and Slurm job-array recipes of
# docs/reference-renders.md as written there (the blocks fenced "```sh cluster-..."), scaled
# down by substitution: 64 jobs -> 4, -j 8 -> -j 2, 8 CPUs per task -> 1, the scene at
# --size 48x48 (each job keeps its 1024 samples, a few seconds of work, so that a job can be
# interrupted while it renders). Checks:
#   1. parallel: the 4 jobs and the merge exit 0;
#   2. Slurm (a one-node cluster of its own: munged, slurmctld and slurmd on 127.0.0.1,
#      configured in a temporary directory, stopped and removed on exit, also on failure):
#      the job array runs; task 0 receives SIGTERM while rendering (scancel -b, the signal
#      `#SBATCH --signal=B:TERM@120` sends) and Slurm records ExitCode=143:0, state FAILED,
#      with a checkpoint of fewer than 1024 samples; resubmitting index 0 resumes and
#      completes it; resubmitting a complete index (1) leaves its checkpoint unchanged;
#      beside it, one task too long for `--time=3` gets the script's own
#      `--signal=B:TERM@120` before the limit: ExitCode=143:0 and a checkpoint;
#   3. the two merged images (parallel, Slurm with the resumed task) are byte-identical,
#      and each agrees with one run over samples 0..4095 to at most one float ulp per
#      value (docs/reference-renders.md, "How exact is a merge"); how many values differ
#      is printed.
# Needs root (slurmd starts jobs as their user) and Debian's parallel, slurm-wlm and munge;
# without them it says what is missing and exits 2. Exit 1: a check failed.
#
# usage: scripts/test-cluster.sh [RESTIR]   (default build/restir; run from the repository root)
BIN=${1:-build/restir}
DOC=docs/reference-renders.md
SIZE=48x48
START=$(date +%s)

say() { printf 'test-cluster: %s\n' "$*"; }
fail() { say "FAILED: $*"; exit 1; }

# ---- what the machine must have ----
missing=""
for tool in parallel munged munge slurmctld slurmd sbatch squeue scontrol scancel sinfo; do
    command -v "$tool" > /dev/null 2>&1 || missing="$missing $tool"
done
if [ -z "$missing" ] && ! parallel --version 2> /dev/null | grep -q "GNU parallel"; then
    missing=" parallel(GNU; this 'parallel' is another program, e.g. moreutils')"
fi
if [ -n "$missing" ]; then
    say "missing:$missing (Debian: apt-get install parallel slurm-wlm munge); nothing was run"
    exit 2
fi
[ "$(id -u)" = 0 ] || { say "needs root (slurmd starts jobs as their user); nothing was run"; exit 2; }
[ -x "$BIN" ] || { say "no restir binary at $BIN (make build/restir)"; exit 2; }
[ -f "$DOC" ] || { say "run from the repository root ($DOC not found)"; exit 2; }
case "$BIN" in /*) ABS_BIN=$BIN ;; *) ABS_BIN=$(pwd)/$BIN ;; esac

TMP=$(mktemp -d /tmp/restir-cluster.XXXXXX) || exit 2
chmod 755 "$TMP" # munged wants its socket's directories searchable by all
CTLD_PID=""
SLURMD_PID=""
cleanup() {
    if [ -n "$SLURMD_PID" ]; then
        jobs_left=$(squeue -h -o %A 2> /dev/null | sort -u)
        [ -z "$jobs_left" ] || scancel --full $jobs_left 2> /dev/null
        sleep 1
    fi
    for pid in $SLURMD_PID $CTLD_PID; do kill "$pid" 2> /dev/null; done
    for pid in $SLURMD_PID $CTLD_PID; do wait "$pid" 2> /dev/null; done
    [ -f "$TMP/munge/munged.pid" ] && kill "$(cat "$TMP/munge/munged.pid")" 2> /dev/null
    sleep 1
    rm -rf "$TMP"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP

# ---- the recipes, scaled down ----
# block NAME: the lines of the fenced block "```sh NAME" of the document
block() { awk -v name="$1" '$0 == "```sh " name { on = 1; next } /^```/ { on = 0 } on' "$DOC"; }
shrink() {
    sed -e 's/seq 0 63/seq 0 3/' -e 's/--array=0-63/--array=0-3/' -e 's/-j 8 /-j 2 /' \
        -e 's/--cpus-per-task=8/--cpus-per-task=1/' -e "s#scenes/cornell.scene#scenes/cornell.scene --size $SIZE#"
}
# Each recipe must still have what the substitutions expect, or the test would run it unscaled.
for want in "cluster-parallel:seq 0 63" "cluster-parallel:-j 8 " "cluster-slurm:--array=0-63" \
    "cluster-slurm:--cpus-per-task=8" "cluster-slurm:--signal=B:TERM@" "cluster-slurm:SPP=1024" \
    "cluster-slurm-submit:^sbatch reference.sbatch" "cluster-slurm-merge:restir merge"; do
    block "${want%%:*}" | grep -q -e "${want#*:}" || fail "$DOC: block '${want%%:*}' no longer contains '${want#*:}'"
done

mkdir -p "$TMP/bin" "$TMP/par" "$TMP/slurm" "$TMP/munge" "$TMP/ctl/state" "$TMP/ctl/spool" "$TMP/parallel-home"
# `restir` on the PATH: a wrapper that logs its arguments (to see that a resubmitted task
# resumes) and then is replaced by the real program (exec: signals reach restir itself).
printf '#!/bin/sh\necho "$*" >> "%s/invocations.log"\nexec "%s" "$@"\n' "$TMP" "$ABS_BIN" > "$TMP/bin/restir"
chmod +x "$TMP/bin/restir"
ln -s "$(pwd)/scenes" "$TMP/par/scenes"
ln -s "$(pwd)/scenes" "$TMP/slurm/scenes"
touch "$TMP/parallel-home/will-cite"
PATH=$TMP/bin:$PATH
PARALLEL_HOME=$TMP/parallel-home
export PATH PARALLEL_HOME
block cluster-parallel | shrink > "$TMP/par/recipe.sh"
block cluster-slurm | shrink > "$TMP/slurm/reference.sbatch"
block cluster-slurm-submit | sed "s/^sbatch /sbatch --parsable /" > "$TMP/slurm/submit.sh"
block cluster-slurm-merge | shrink > "$TMP/slurm/merge.sh"

# ---- 1. GNU parallel ----
say "GNU parallel: 4 jobs of 1024 spp at $SIZE, -j 2, then merge"
(cd "$TMP/par" && sh -e recipe.sh > log.txt 2>&1) || { cat "$TMP/par/log.txt"; fail "the parallel recipe"; }
[ -f "$TMP/par/out/cornell-ref.pfm" ] && [ -f "$TMP/par/out/cornell-ref.ckpt" ] || fail "parallel: no merged image"
T_PAR=$(date +%s)

# ---- 2. a one-node Slurm cluster ----
dd if=/dev/urandom of="$TMP/munge/munge.key" bs=128 count=1 2> /dev/null
chmod 700 "$TMP/munge"
chmod 600 "$TMP/munge/munge.key"
chmod 755 "$TMP/munge" # the socket's directory must be searchable; the key stays 0600
munged --key-file="$TMP/munge/munge.key" --socket="$TMP/munge/munge.sock" --pid-file="$TMP/munge/munged.pid" \
    --log-file="$TMP/munge/munged.log" --seed-file="$TMP/munge/munged.seed" ||
    { cat "$TMP/munge/munged.log"; fail "munged did not start"; }
HOST=$(hostname -s)
PORT=$((20000 + ($$ % 5000) * 2))
cat > "$TMP/ctl/slurm.conf" << EOF
ClusterName=restirtest
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
AuthType=auth/munge
AuthInfo=socket=$TMP/munge/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$TMP/ctl/state
SlurmdSpoolDir=$TMP/ctl/spool
SlurmctldPidFile=$TMP/ctl/slurmctld.pid
SlurmdPidFile=$TMP/ctl/slurmd.pid
SlurmctldLogFile=$TMP/ctl/slurmctld.log
SlurmdLogFile=$TMP/ctl/slurmd.log
PlugStackConfig=$TMP/ctl/plugstack.conf
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
KillWait=10
MinJobAge=3600
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
: > "$TMP/ctl/plugstack.conf"
SLURM_CONF=$TMP/ctl/slurm.conf
export SLURM_CONF
slurmctld -D -f "$SLURM_CONF" > "$TMP/ctl/slurmctld.out" 2>&1 &
CTLD_PID=$!
slurmd -D -f "$SLURM_CONF" > "$TMP/ctl/slurmd.out" 2>&1 &
SLURMD_PID=$!
slurm_logs() { tail -n 20 "$TMP/ctl/slurmctld.log" "$TMP/ctl/slurmd.log" "$TMP/ctl/"*.out 2> /dev/null; }
i=0
until [ "$(sinfo -h -o %T 2> /dev/null)" = idle ]; do
    i=$((i + 1))
    [ $i -le 60 ] || { slurm_logs; fail "the Slurm node did not become idle in 60 s"; }
    sleep 1
done
say "Slurm ($(sinfo -V)) up: node $HOST, $(nproc) CPUs, port $PORT"

# job_field JOB KEY: KEY=value of `scontrol show job`
job_field() { scontrol show job "$1" 2> /dev/null | tr ' ' '\n' | sed -n "s/^$2=//p" | head -n 1; }
# wait_done JOB: until no task of JOB is pending or running (at most 10 minutes)
wait_done() {
    i=0
    while squeue -h -j "$1" -t PENDING,RUNNING,COMPLETING 2> /dev/null | grep -q .; do
        i=$((i + 1))
        [ $i -le 600 ] || { slurm_logs; fail "job $1 still running after 10 minutes"; }
        sleep 1
    done
}
# ckpt_range FILE: "first-sample spp" of a path-tracer checkpoint (docs/path-tracer.md)
ckpt_range() { od -An -tu4 -j24 -N8 "$1" | awk '{ print $1, $2 }'; }

# The real time limit, beside the array: the same script with a task far too long for
# `--time=3` (minutes), so that the recipe's own `#SBATCH --signal=B:TERM@120` line must
# deliver SIGTERM about two minutes before the limit (Slurm checks every 30-60 s).
mkdir -p "$TMP/limit/parts"
ln -s "$(pwd)/scenes" "$TMP/limit/scenes"
sed 's/^SPP=1024$/SPP=1000000/' "$TMP/slurm/reference.sbatch" > "$TMP/limit/reference.sbatch"
LIMIT_JOB=$(cd "$TMP/limit" && sbatch --parsable --array=0 --time=3 reference.sbatch) || fail "sbatch --time=3"
LIMIT_START=$(date +%s)
say "Slurm: job $LIMIT_JOB: one task with --time=3 (minutes) and the recipe's --signal=B:TERM@120"

cd "$TMP/slurm" || fail "cd"
JOB=$(sh -e submit.sh) || { slurm_logs; fail "the submit recipe"; }
say "Slurm: job array $JOB (tasks 0-3, 1024 spp each); SIGTERM to task 0 while it renders"
i=0
until [ "$(squeue -h -j "${JOB}_0" -o %T 2> /dev/null)" = RUNNING ]; do
    i=$((i + 1))
    [ $i -le 300 ] || { slurm_logs; fail "task 0 never started"; }
    sleep 0.2
done
# scancel's status is not the signal's fate (it may report an error for a task the signal
# just ended, or the batch step may not exist yet): send, then look whether the task ended.
sleep 1
i=0
while [ "$(squeue -h -j "${JOB}_0" -o %T 2> /dev/null)" = RUNNING ]; do
    i=$((i + 1))
    [ $i -le 20 ] || { cat scancel.err; fail "task 0 still runs after 20 times scancel -b --signal=TERM ${JOB}_0"; }
    scancel -b --signal=TERM "${JOB}_0" 2>> scancel.err
    sleep 1
done
wait_done "$JOB"
for t in 0 1 2 3; do say "  task $t: $(job_field "${JOB}_$t" JobState), ExitCode=$(job_field "${JOB}_$t" ExitCode)"; done
[ "$(job_field "${JOB}_0" ExitCode)" = 143:0 ] || { cat "slurm-${JOB}_0.out"; fail "task 0: ExitCode is not 143:0"; }
[ "$(job_field "${JOB}_0" JobState)" = FAILED ] || fail "task 0: a task stopped by SIGTERM must not be COMPLETED"
for t in 1 2 3; do
    [ "$(job_field "${JOB}_$t" ExitCode)" = 0:0 ] || { cat "slurm-${JOB}_$t.out"; fail "task $t failed"; }
done
[ -f parts/part0.ckpt ] || fail "task 0 left no checkpoint"
set -- $(ckpt_range parts/part0.ckpt)
say "  task 0's checkpoint: samples $1.., $2 of 1024 spp"
[ "$1" = 0 ] && [ "$2" -lt 1024 ] || fail "task 0 was not interrupted while rendering (checkpoint: $2 spp); try again on a less loaded machine"

cp parts/part1.ckpt part1.before
: > "$TMP/invocations.log"
RESUB=$(sbatch --parsable --array=0,1 reference.sbatch) || fail "resubmitting tasks 0 and 1"
wait_done "$RESUB"
say "  resubmitted 0 and 1 ($RESUB): task 0 $(job_field "${RESUB}_0" JobState) ExitCode=$(job_field "${RESUB}_0" ExitCode), task 1 $(job_field "${RESUB}_1" JobState) ExitCode=$(job_field "${RESUB}_1" ExitCode)"
for t in 0 1; do
    [ "$(job_field "${RESUB}_$t" ExitCode)" = 0:0 ] || { cat "slurm-${RESUB}_$t.out"; fail "resubmitted task $t failed"; }
done
for t in 0 1; do
    grep -q -e "--resume parts/part$t.ckpt" "$TMP/invocations.log" ||
        { cat "$TMP/invocations.log"; fail "resubmitted task $t did not run with --resume parts/part$t.ckpt"; }
done
say "  both resubmitted tasks ran with --resume (their checkpoints existed)"
[ "$(ckpt_range parts/part0.ckpt)" = "0 1024" ] || fail "resumed task 0: checkpoint holds $(ckpt_range parts/part0.ckpt)"
cmp -s part1.before parts/part1.ckpt || fail "resubmitting the complete task 1 changed its checkpoint"
sh -e merge.sh > merge.log 2>&1 || { cat merge.log; fail "the Slurm merge recipe"; }
wait_done "$LIMIT_JOB"
LIMIT_END=$(date +%s)
say "  time-limit task: $(job_field "${LIMIT_JOB}_0" JobState), ExitCode=$(job_field "${LIMIT_JOB}_0" ExitCode), RunTime=$(job_field "${LIMIT_JOB}_0" RunTime), checkpoint $(ckpt_range "$TMP/limit/parts/part0.ckpt" 2> /dev/null | awk '{ print $2 }') spp"
[ "$(job_field "${LIMIT_JOB}_0" ExitCode)" = 143:0 ] ||
    { cat "$TMP/limit/slurm-${LIMIT_JOB}_0.out"; fail "time-limit task: ExitCode is not 143:0 (the --signal line did not reach restir)"; }
[ -f "$TMP/limit/parts/part0.ckpt" ] || fail "time-limit task: no checkpoint"
[ $((LIMIT_END - LIMIT_START)) -lt 180 ] || fail "time-limit task: ran into the limit itself (no early signal)"
T_SLURM=$(date +%s)

# ---- 3. the merged images against one run ----
cd "$TMP" || fail "cd"
(cd slurm && restir render scenes/cornell.scene --size $SIZE --method pt --seed 1 --max-depth 10 --threads 2 \
    --quiet --no-png --spp 4096 -o ../single.pfm) || fail "the single run"
cmp -s par/out/cornell-ref.pfm slurm/out/cornell-ref.pfm || fail "the parallel and Slurm merges differ"
say "parallel merge = Slurm merge (with a resumed task): byte-identical"
# the float values of a PFM, as unsigned integers (their bits), one a line
pfm_bits() { od -An -v -tu4 -w4 -j "$(head -n 3 "$1" | wc -c)" "$1"; }
[ "$(head -n 3 single.pfm)" = "$(head -n 3 par/out/cornell-ref.pfm)" ] || fail "single run and merge: different headers"
pfm_bits single.pfm > single.bits
pfm_bits par/out/cornell-ref.pfm > merged.bits
# For non-negative floats the difference of the bit patterns is the distance in ulps.
summary=$(paste single.bits merged.bits | awk '{ d = $1 - $2; if (d < 0) d = -d; if (d) n++; if (d > m) m = d }
    END { printf "%d %d %d", NR, n, m }')
set -- $summary
if [ "$2" = 0 ]; then
    say "merge vs one run of 4096 spp: byte-identical ($1 values)"
else
    say "merge vs one run of 4096 spp: $2 of $1 values differ, by at most $3 ulp"
fi
[ "$3" -le 1 ] || fail "the merge differs from one run by $3 ulp (bound: 1)"
END=$(date +%s)
say "passed in $((END - START)) s (parallel $((T_PAR - START)) s, Slurm $((T_SLURM - T_PAR)) s, comparison $((END - T_SLURM)) s)"
