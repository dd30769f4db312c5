#!/usr/bin/env bash
# The photon reference through a real Slurm (issue 42, item 5; docs/cluster.md): a one-node cluster
# on localhost from Debian's packages (munge, slurmctld, slurmd, slurm-client: tools/install-deps.sh),
# started by hand in a temporary folder with its own munge key and slurm.conf (SLURM_CONF), no
# systemd and nothing under /etc or /var. Then, through tools/slurm/submit.sh as a user runs it:
# 1. a 4-task array of shards and the dependent merge: the merged map is the unsharded run's, bit
#    for bit (compare's max_error 0);
# 2. a shard killed mid-run (scancel of array task 2 while it runs; a wrapper holds that task before
#    it starts caustica, so that the cancel always finds it running) leaves no file, Slurm cancels the merge,
#    `caustica merge` names the missing index, and `submit.sh --resubmit I` completes the job with
#    the same map (the same file as in 1, byte for byte);
# 3. a shard of another seed, and one of another scene (submit.sh --resubmit I --seed 2, or
#    --scene sphere_plane, each into a copy of the shards): each merge job fails, naming the seed or
#    the scene, and writes nothing;
# 4. a bench sweep (a tiny bench accuracy, 2 cells: submit.sh --bench, --list-cells counting the
#    cells, an array of --cell auto, bench merge): results.csv equal to one process's but for the
#    timing columns; and the ray-traced camera reference as a 2-task array of rows and its merge
#    (submit.sh --size): the very file an unsharded run writes.
# Every daemon is stopped by the process id this script started (trap on EXIT, failures included),
# and the folder is removed (kept with CAUSTICA_SLURM_KEEP=1). Where Slurm cannot start, the test
# fails and prints the daemons' logs: it is never skipped. Runs as root (CI); as another user, that
# user is SlurmUser (not tried). Two runs side by side do not meet: each has its own ports and socket.
#
# usage: slurm_test.sh CAUSTICA_BINARY SOURCE_DIR
set -euo pipefail
bin=$(realpath "$1")
src=$(realpath "$2")
submit=$src/tools/slurm/submit.sh
start=$SECONDS

dir=$(mktemp -d "${TMPDIR:-/tmp}/caustica-slurm.XXXXXX")
# munged wants its socket's folder and those above it searchable by everyone.
chmod 755 "$dir"
pids=() names=()
export SLURM_CONF=$dir/slurm.conf

logs() {  # the daemons' logs (their stdout where they logged nothing else) and the jobs' output
  local f
  for f in "$dir"/munged.log "$dir"/slurmctld.log "$dir"/slurmd.log "$dir"/*.stdout "$dir"/*.shards/*.out "$dir"/sweep/cells/*.out; do
    [ -s "$f" ] || continue
    case $f in *d.stdout) [ -s "${f%.stdout}.log" ] && continue ;; esac
    echo "---- ${f#"$dir"/} (last 40 lines) ----"
    tail -n 40 "$f"
  done
}
fail() {
  echo "FAIL: $*" >&2
  logs >&2
  exit 1
}
cleanup() {
  local rc=$? p i
  trap - EXIT
  # The jobs first (their slurmstepd processes belong to this cluster), then the daemons by pid.
  if [ -f "$dir/slurm.conf" ] && [ ${#pids[@]} -gt 1 ]; then
    timeout 5 scancel --quiet --user "$(id -un)" > /dev/null 2>&1 || true
    for i in $(seq 50); do
      [ -z "$(timeout 2 squeue -h -o %i 2> /dev/null)" ] && break
      sleep 0.1
    done
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill -TERM "${pids[i]}" 2> /dev/null || true; done
  for p in "${pids[@]}"; do
    for i in $(seq 50); do kill -0 "$p" 2> /dev/null || break; sleep 0.1; done
    if kill -0 "$p" 2> /dev/null; then kill -KILL "$p" 2> /dev/null || true; fi
    wait "$p" 2> /dev/null || true
  done
  if [ -n "${CAUSTICA_SLURM_KEEP:-}" ]; then echo "slurm_test: kept $dir" >&2; else rm -rf "$dir"; fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

for tool in munged slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
  command -v "$tool" > /dev/null || [ -x "/usr/sbin/$tool" ] ||
    fail "$tool is not installed: tools/install-deps.sh installs Debian's munge, slurmctld, slurmd and slurm-client"
done
PATH=$PATH:/usr/sbin

# Two free TCP ports on localhost for slurmctld and slurmd (another cluster may be running here).
read -r ctld_port slurmd_port < <(python3 -c '
import socket
ss = [socket.socket() for _ in range(2)]
for s in ss: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in ss))')

# munge: a key of its own and every path in the folder.
mkdir -p "$dir/munge" "$dir/socket" "$dir/state" "$dir/spool" "$dir/run"
chmod 700 "$dir/munge"
chmod 755 "$dir/socket"
head -c 1024 /dev/urandom > "$dir/munge/munge.key"
chmod 400 "$dir/munge/munge.key"
socket=$dir/socket/munge.socket
munged -F --socket="$socket" --key-file="$dir/munge/munge.key" --log-file="$dir/munged.log" \
  --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed" > "$dir/munged.stdout" 2>&1 &
pids+=($!) names+=(munged)

user=$(id -un)
cat > "$SLURM_CONF" <<CONF
ClusterName=caustica-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
MpiDefault=none
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
# Batch jobs scheduled at once rather than up to 3 s later (the default): the test's jobs run for
# a second or less, and the delay was most of its 54 s.
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ReturnToService=2
KillWait=2
MinJobAge=600
InactiveLimit=0
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 RealMemory=1024 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF

wait_for() {  # wait_for SECONDS WHAT COMMAND...: polls COMMAND every 0.2 s
  local limit=$1 what=$2 t0=$SECONDS
  shift 2
  until "$@"; do
    ((SECONDS - t0 < limit)) || fail "$what: not within $limit s"
    sleep 0.2
  done
}
alive() {
  local i
  for i in "${!pids[@]}"; do
    kill -0 "${pids[i]}" 2> /dev/null || fail "${names[i]} (pid ${pids[i]}) exited"
  done
}

munge_up() { alive; test -S "$socket"; }
wait_for 10 "munged did not open its socket $socket" munge_up
slurmctld -D -c -f "$SLURM_CONF" > "$dir/slurmctld.stdout" 2>&1 &
pids+=($!) names+=(slurmctld)
slurmd -D -N localhost -f "$SLURM_CONF" > "$dir/slurmd.stdout" 2>&1 &
pids+=($!) names+=(slurmd)
node_idle() {
  alive
  [ "$(timeout 5 sinfo -h -n localhost -o %t 2> /dev/null)" = idle ]
}
wait_for 30 "the node did not come up idle (sinfo)" node_idle
echo "ok: munged, slurmctld and slurmd up, the node idle ($((SECONDS - start)) s)"

# Job ids of submit.sh's output ("shards: job N", "merge:  job M").
job_of() { sed -n "s/^$1: *job \([0-9]*\) .*/\1/p" "$2"; }
# Whether every job named is out of the queue (done, failed or cancelled).
gone() { [ -z "$(timeout 5 squeue -h -j "$(IFS=,; echo "$*")" -o %i 2> /dev/null)" ]; }
state() { timeout 5 scontrol -o show job "$1" | sed -n 's/.* JobState=\([A-Z_]*\) .*/\1/p' | head -n 1; }
states() { timeout 5 scontrol -o show job "$1" | sed -n 's/.* JobState=\([A-Z_]*\) .*/\1/p' | sort | uniq -c | tr '\n' ' '; }

scene=bunny_plane photons=2e5 map=128
cd "$dir/run"  # submitted from here: the jobs must write nothing here
# A caustica that a shard runs through: where $dir/slow_I exists, task I first waits (so that it
# is still running when the test cancels it), then runs caustica as given.
cat > "$dir/caustica-node" <<NODE
#!/bin/bash
if [ -n "\${SLURM_ARRAY_TASK_ID:-}" ] && [ -e "$dir/slow_\$SLURM_ARRAY_TASK_ID" ]; then
  touch "$dir/started_\$SLURM_ARRAY_TASK_ID"
  sleep 120
fi
exec "$bin" "\$@"
NODE
chmod +x "$dir/caustica-node"
run_submit() { "$submit" --scene "$scene" --photons "$photons" --map-size "$map" --caustica "$dir/caustica-node" "$@"; }

# The unsharded run, beside the cluster's work.
"$bin" reference --scene "$scene" --photons "$photons" --map-size "$map" --out "$dir/whole.exr" > "$dir/whole.stdout" 2>&1 ||
  fail "the unsharded reference exited $?"

# 1. Four shards and the merge.
t0=$SECONDS
run_submit --shards 4 --out "$dir/map.exr" > "$dir/submit1.stdout" 2>&1 || fail "submit.sh exited $?: $(cat "$dir/submit1.stdout")"
shards=$(job_of shards "$dir/submit1.stdout") merge=$(job_of merge "$dir/submit1.stdout")
[ -n "$shards" ] && [ -n "$merge" ] || fail "submit.sh printed no job ids: $(cat "$dir/submit1.stdout")"
wait_for 60 "the array $shards and merge $merge did not finish" gone "$shards" "$merge"
[ "$(state "$merge")" = COMPLETED ] || fail "the merge job $merge ended $(state "$merge") (shards: $(states "$shards"))"
[ -f "$dir/map.exr" ] || fail "the merge job completed and wrote no $dir/map.exr"
"$bin" compare "$dir/map.exr" "$dir/whole.exr" --max-l1 0 > "$dir/compare1.stdout" 2>&1 ||
  fail "the merged map differs from the unsharded run's: $(cat "$dir/compare1.stdout")"
grep -q '"\?max_error"\?[:= ]*0\b' "$dir/compare1.stdout" || grep -q 'max_error 0$' "$dir/compare1.stdout" ||
  fail "the merged map is not the unsharded run's bit for bit: $(cat "$dir/compare1.stdout")"
echo "ok: 4 shards and the merge through Slurm ($((SECONDS - t0)) s), the map the unsharded run's bit for bit"

# 2. A shard killed mid-run: task 2 is cancelled while it runs; the merge can no longer run.
t0=$SECONDS
touch "$dir/slow_2"
run_submit --shards 4 --out "$dir/killed.exr" > "$dir/submit2.stdout" 2>&1 || fail "submit.sh exited $?: $(cat "$dir/submit2.stdout")"
shards=$(job_of shards "$dir/submit2.stdout") merge=$(job_of merge "$dir/submit2.stdout")
wait_for 30 "array task ${shards}_2 did not start" test -e "$dir/started_2"
scancel "${shards}_2" || fail "scancel ${shards}_2 exited $?"
wait_for 60 "the array $shards and merge $merge did not leave the queue after the cancel" gone "$shards" "$merge"
rm -f "$dir/slow_2"
[ "$(state "$merge")" != COMPLETED ] || fail "the merge job $merge ran although shard 2 was cancelled"
[ ! -e "$dir/killed.exr" ] || fail "a map was written although shard 2 was cancelled"
[ ! -e "$dir/killed.shards/shard_2.exr" ] || fail "the cancelled shard left a file"
ls "$dir/killed.shards"/shard_{0,1,3}.exr > /dev/null || fail "the other shards are missing: $(ls -a "$dir/killed.shards")"
if "$bin" merge "$dir/killed.shards"/shard_*.exr --out "$dir/killed.exr" > "$dir/merge2.stdout" 2>&1; then
  fail "merge of 3 of 4 shards succeeded"
fi
grep -q 'shard 2 of 4' "$dir/merge2.stdout" || fail "merge did not name the missing shard 2: $(cat "$dir/merge2.stdout")"
[ ! -e "$dir/killed.exr" ] || fail "the refused merge wrote a map"
echo "ok: a shard cancelled mid-run leaves no file, Slurm cancels the merge, merge names it: $(grep -m1 'shard 2 of 4' "$dir/merge2.stdout")"

# ... and resubmitting that index alone completes the job.
run_submit --shards 4 --out "$dir/killed.exr" --resubmit 2 > "$dir/submit3.stdout" 2>&1 || fail "submit.sh --resubmit exited $?: $(cat "$dir/submit3.stdout")"
shards=$(job_of shards "$dir/submit3.stdout") merge=$(job_of merge "$dir/submit3.stdout")
wait_for 60 "the resubmitted shard $shards and merge $merge did not finish" gone "$shards" "$merge"
[ "$(state "$merge")" = COMPLETED ] || fail "the merge job $merge after the resubmit ended $(state "$merge") (shard: $(states "$shards"))"
"$bin" compare "$dir/killed.exr" "$dir/whole.exr" --max-l1 0 > "$dir/compare3.stdout" 2>&1 ||
  fail "the map after the resubmit differs from the unsharded run's: $(cat "$dir/compare3.stdout")"
cmp -s "$dir/killed.exr" "$dir/map.exr" || fail "the second run's merged file differs from the first's byte for byte"
echo "ok: submit.sh --resubmit 2 completes the job: the same map, the same file byte for byte as the first run's ($((SECONDS - t0)) s for the fault and the resubmit)"

# 3. A shard of another seed among them, and one of another scene: each merge job fails and names
# what differs. Both submitted at once: they run side by side.
t0=$SECONDS
for stray in seed scene; do
  mkdir "$dir/$stray.shards"
  cp "$dir/map.shards"/shard_{0,2,3}.exr "$dir/$stray.shards/"
done
run_submit --shards 4 --out "$dir/seed.exr" --resubmit 1 --seed 2 > "$dir/submit4.stdout" 2>&1 || fail "submit.sh exited $?: $(cat "$dir/submit4.stdout")"
# submit.sh's last --scene wins: the shard traces sphere_plane among bunny_plane's shards.
run_submit --shards 4 --out "$dir/scene.exr" --resubmit 1 --scene sphere_plane > "$dir/submit5.stdout" 2>&1 ||
  fail "submit.sh exited $?: $(cat "$dir/submit5.stdout")"
for stray in seed scene; do
  stdout=$dir/submit$([ $stray = seed ] && echo 4 || echo 5).stdout
  shards=$(job_of shards "$stdout") merge=$(job_of merge "$stdout")
  wait_for 60 "the other $stray's shard $shards and merge $merge did not finish" gone "$shards" "$merge"
  [ -f "$dir/$stray.shards/shard_1.exr" ] || fail "the other $stray's shard ($shards) wrote nothing: $(states "$shards")"
  [ "$(state "$merge")" = FAILED ] || fail "the merge job $merge with a shard of another $stray ended $(state "$merge"), not FAILED"
  [ ! -e "$dir/$stray.exr" ] || fail "the merge with a shard of another $stray wrote a map"
  merge_log=$dir/$stray.shards/caustica-merge-$merge.out
  case $stray in
    seed) pattern='shard_1.exr: seed 2, where' ;;
    scene) pattern='shard_1.exr: scene sphere_plane (identity [0-9a-f]*), where .* has bunny_plane' ;;
  esac
  grep -q "$pattern" "$merge_log" || fail "the failed merge did not name the other $stray: $(cat "$merge_log")"
  echo "ok: a shard of another $stray fails the merge job: $(grep -m1 "$pattern" "$merge_log" | sed 's/^ *//')"
done
echo "ok: ($((SECONDS - t0)) s for the other seed and scene)"

# 4. A bench sweep as an array of cells and the camera reference as an array of rows, submitted
# at once; the one-process runs beside them.
t0=$SECONDS
sweep="--scenes sphere_plane --graphs caustics_adaptive,refraction_deferred --grids 64 --reference-photons 1e5 --caustic-size 64 --size 64x36 --frames 1"
"$submit" --bench accuracy --sweep "$sweep" --out "$dir/sweep" --caustica "$bin" > "$dir/submit6.stdout" 2>&1 ||
  fail "submit.sh --bench exited $?: $(cat "$dir/submit6.stdout")"
grep -q 'array 0-1 of 2 cells' "$dir/submit6.stdout" || fail "submit.sh --bench did not count 2 cells: $(cat "$dir/submit6.stdout")"
"$submit" --scene "$scene" --size 64x36 --shards 2 --out "$dir/camera.exr" --caustica "$bin" > "$dir/submit7.stdout" 2>&1 ||
  fail "submit.sh --size exited $?: $(cat "$dir/submit7.stdout")"
# Three lights' point light: its map by shards (--light), and the picture lit by a map of it by rows
# (--caustics 2=MAP), each against one process's file.
lights="$src/scenes/three_lights.json"
"$bin" reference --scene "$lights" --light 2 --photons 20000 --map-size 32 --out "$dir/light2_whole.exr" > "$dir/light2_whole.stdout" 2>&1 ||
  fail "the one-process map of light 2 exited $?: $(cat "$dir/light2_whole.stdout")"
"$submit" --scene "$lights" --light 2 --photons 20000 --map-size 32 --shards 2 --out "$dir/light2.exr" --caustica "$bin" > "$dir/submit_light.stdout" 2>&1 ||
  fail "submit.sh --light exited $?: $(cat "$dir/submit_light.stdout")"
"$submit" --scene "$lights" --size 32x18 --caustics "2=$dir/light2_whole.exr" --shards 2 --out "$dir/lit2.exr" --caustica "$bin" > "$dir/submit_lit.stdout" 2>&1 ||
  fail "submit.sh --caustics exited $?: $(cat "$dir/submit_lit.stdout")"
"$bin" reference --scene "$lights" --size 32x18 --caustics "2=$dir/light2_whole.exr" --out "$dir/lit2_whole.exr" > "$dir/lit2_whole.stdout" 2>&1 ||
  fail "the one-process picture lit by light 2's map exited $?: $(cat "$dir/lit2_whole.stdout")"
# shellcheck disable=SC2086  # the sweep's options are words
"$bin" bench accuracy $sweep --out "$dir/sweep_whole" > "$dir/sweep_whole.stdout" 2>&1 || fail "the one-process sweep exited $?"
"$bin" reference --scene "$scene" --size 64x36 --out "$dir/camera_whole.exr" > "$dir/camera_whole.stdout" 2>&1 ||
  fail "the unsharded camera reference exited $?"
cells=$(job_of cells "$dir/submit6.stdout") sweep_merge=$(job_of merge "$dir/submit6.stdout")
shards=$(job_of shards "$dir/submit7.stdout") merge=$(job_of merge "$dir/submit7.stdout")
light_shards=$(job_of shards "$dir/submit_light.stdout") light_merge=$(job_of merge "$dir/submit_light.stdout")
lit_shards=$(job_of shards "$dir/submit_lit.stdout") lit_merge=$(job_of merge "$dir/submit_lit.stdout")
wait_for 90 "the cells $cells, the camera's shards $shards and their merges did not finish" gone "$cells" "$sweep_merge" "$shards" "$merge" \
  "$light_shards" "$light_merge" "$lit_shards" "$lit_merge"
[ "$(state "$sweep_merge")" = COMPLETED ] || fail "the bench merge job $sweep_merge ended $(state "$sweep_merge") (cells: $(states "$cells")): $(tail -n 20 "$dir"/sweep/cells/*.out)"
no_timings() { cut -d, -f1-5,8- "$1"; }  # results.csv without method_ms and frame_ms
[ "$(head -n 1 "$dir/sweep/results.csv" | cut -d, -f6,7)" = method_ms,frame_ms ] || fail "results.csv's columns moved: $(head -n 1 "$dir/sweep/results.csv")"
[ "$(wc -l < "$dir/sweep/results.csv")" -eq 5 ] || fail "the merged results.csv has not 4 rows: $(cat "$dir/sweep/results.csv")"
diff <(no_timings "$dir/sweep/results.csv") <(no_timings "$dir/sweep_whole/results.csv") > "$dir/sweep.diff" ||
  fail "the sweep's merged results differ from one process's: $(cat "$dir/sweep.diff")"
echo "ok: bench accuracy as an array of 2 cells and bench merge: results.csv one process's but for the timing columns"
[ "$(state "$merge")" = COMPLETED ] || fail "the camera's merge job $merge ended $(state "$merge") (shards: $(states "$shards"))"
cmp -s "$dir/camera.exr" "$dir/camera_whole.exr" || fail "the merged camera image differs from the unsharded run's file"
ls "$dir/camera.shards"/shard_{0,1}.exr > /dev/null || fail "the camera's shards are missing: $(ls -a "$dir/camera.shards")"
echo "ok: the camera reference as 2 shards of rows and the merge: the unsharded run's file byte for byte ($((SECONDS - t0)) s for the sweep and the camera)"
[ "$(state "$light_merge")" = COMPLETED ] || fail "light 2's merge job $light_merge ended $(state "$light_merge") (shards: $(states "$light_shards"))"
"$bin" compare "$dir/light2.exr" "$dir/light2_whole.exr" --max-l1 0 > "$dir/compare6.stdout" 2>&1 ||
  fail "light 2's merged map differs from one process's: $(cat "$dir/compare6.stdout")"
[ "$(state "$lit_merge")" = COMPLETED ] || fail "the lit picture's merge job $lit_merge ended $(state "$lit_merge") (shards: $(states "$lit_shards"))"
cmp -s "$dir/lit2.exr" "$dir/lit2_whole.exr" || fail "the merged picture lit by light 2's map differs from the unsharded run's file"
echo "ok: a light's map by shards (--light 2) and a picture lit by it by rows (--caustics 2=MAP): one process's, bit for bit"

# The jobs wrote only beside their shards, nothing in the folder they were submitted from.
[ -z "$(ls -A "$dir/run")" ] || fail "the jobs wrote into the folder they were submitted from: $(ls -A "$dir/run")"

# Timing (not part of the test; docs/cluster.md): CAUSTICA_SLURM_TIME_PHOTONS=N times one process
# (before and after) against 4 shards through this cluster and their merge, the same N photons on the bunny at 512^2,
# each shard given CAUSTICA_SLURM_TIME_CPUS cores (default 2: one shard at a time on this node).
if [ -n "${CAUSTICA_SLURM_TIME_PHOTONS:-}" ]; then
  n=$CAUSTICA_SLURM_TIME_PHOTONS cpus=${CAUSTICA_SLURM_TIME_CPUS:-2}
  now() { date +%s.%N; }
  t0=$(now)
  "$bin" reference --scene "$scene" --photons "$n" --out "$dir/time_whole.exr" > "$dir/time_whole.stdout" 2>&1 || fail "reference exited $?"
  t1=$(now)
  "$submit" --scene "$scene" --photons "$n" --shards 4 --cpus "$cpus" --caustica "$bin" --out "$dir/time_map.exr" > "$dir/submit9.stdout" 2>&1 || fail "submit.sh exited $?"
  shards=$(job_of shards "$dir/submit9.stdout") merge=$(job_of merge "$dir/submit9.stdout")
  wait_for 600 "the timed array $shards and merge $merge did not finish" gone "$shards" "$merge"
  t2=$(now)
  [ "$(state "$merge")" = COMPLETED ] || fail "the timed merge job $merge ended $(state "$merge")"
  # One process again after the shards: on a machine others share, the load moves during a run;
  # the shards are compared with the mean of the runs before and after them.
  "$bin" reference --scene "$scene" --photons "$n" --out "$dir/time_whole2.exr" > "$dir/time_whole2.stdout" 2>&1 || fail "reference exited $?"
  t3=$(now)
  "$bin" compare "$dir/time_map.exr" "$dir/time_whole.exr" --max-l1 0 > "$dir/compare5.stdout" 2>&1 || fail "the timed maps differ: $(cat "$dir/compare5.stdout")"
  grep -h -E '^(shard [0-9]|photons [0-9]+ in|merged)' "$dir/time_whole.stdout" "$dir"/time_map.shards/*.out "$dir/time_whole2.stdout" || true
  awk -v a="$t0" -v b="$t1" -v c="$t2" -v d="$t3" -v n="$n" -v k="$cpus" 'BEGIN {
    printf "timing: %s photons: one process %.2f s before and %.2f s after 4 shards through Slurm (%d cores each) and the merge, %.2f s (%.2fx their mean); the maps equal\n", n, b - a, d - c, k, c - b, (c - b) / ((b - a + d - c) / 2) }'
fi

echo "slurm_test: passed in $((SECONDS - start)) s"
