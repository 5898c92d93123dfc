#!/usr/bin/env bash
# houle farm on a real Slurm cluster of one node: munged, slurmctld and slurmd started here as root
# with their own key, config, ports, state and logs in a temporary folder, talking over 127.0.0.1
# only, and stopped at the end whatever happens. A 24-frame render in array tasks of 5 frames must be
# byte-identical to one houle render; one task killed mid-way (SIGKILL) leaves frames missing, which
# the final check job reports, and the resubmitted array renders only those, leaving no partial file;
# a raw target's parts are joined by the final job. Prints the time of each step.
# Usage: test_farm_slurm.sh <houle binary> <source dir>. Exit 77 (skipped) only where Slurm cannot be
# installed: not root, or apt-get failed.
set -uo pipefail
houle=$(realpath "$1") src=$(realpath "$2")
t_start=$SECONDS
deadline=$((SECONDS + 150))  # ctest's TIMEOUT for this test is 170 s

skip() { echo "farm_slurm: SKIPPED: $*"; exit 77; }
need=(munged slurmctld slurmd sbatch squeue scancel sinfo)
missing() { for p in "${need[@]}"; do command -v "$p" >/dev/null || return 0; done; return 1; }
if missing; then
  [ "$(id -u)" -eq 0 ] || skip "Slurm is not installed and installing it needs root (scripts/setup --slurm)"
  "$src/scripts/setup" --slurm >/dev/null 2>&1 || skip "Slurm is not installed and scripts/setup --slurm failed"
  missing && skip "scripts/setup --slurm did not install ${need[*]}"
fi
[ "$(id -u)" -eq 0 ] || skip "the test starts slurmd, which runs jobs as their user, and needs root"

# The folder holds munge's socket: munged wants it reachable by all and writable only by us.
d=$(mktemp -d /tmp/houle-slurm.XXXXXX)
chmod 755 "$d"
mkdir -p "$d/munge" "$d/state" "$d/spool" "$d/work"
chmod 755 "$d/munge"
pids=()  # the daemons, in the order they stop: slurmd, slurmctld, munged
watchdog=
# alive <pid>: running, not a zombie waiting for us.
alive() { local s; s=$(ps -o stat= -p "$1" 2>/dev/null); [ -n "$s" ] && [ "${s:0:1}" != Z ]; }
stop_cluster() {
  trap '' INT TERM
  [ -n "$watchdog" ] && kill "$watchdog" 2>/dev/null
  # Our own controller: every job in it is ours. Cancel, give the steps a moment, stop the daemons.
  if [ ${#pids[@]} -gt 1 ]; then
    scancel --user=root >/dev/null 2>&1
    for _ in $(seq 50); do squeue -h 2>/dev/null | grep -q . || break; sleep 0.1; done
  fi
  for p in "${pids[@]}"; do
    kill "$p" 2>/dev/null
    for _ in $(seq 50); do alive "$p" || break; sleep 0.1; done
    kill -KILL "$p" 2>/dev/null
    wait "$p" 2>/dev/null
  done
  rm -rf "$d"
}
trap stop_cluster EXIT
trap 'exit 130' INT TERM
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); printf 'FAIL %s\n' "$*"; }
die() { bad "$@"; for f in "$d"/*.log; do echo "--- $f"; tail -n 15 "$f"; done; echo "farm_slurm: ${pass} passed, ${fail} failed"; exit 1; }
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

# munge: its own key, socket, pid, log and seed.
dd if=/dev/urandom of="$d/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$d/munge/munge.key"
munged -F --key-file="$d/munge/munge.key" --socket="$d/munge/munge.socket" --pid-file="$d/munge/munged.pid" \
  --log-file="$d/munged.log" --seed-file="$d/munge/seed" 2>"$d/munged.out.log" &
pids=($!)
until [ -S "$d/munge/munge.socket" ]; do
  kill -0 "${pids[0]}" 2>/dev/null || die "munged did not start"
  sleep 0.1
done

# Two free ports on 127.0.0.1 for slurmctld and slurmd.
read -r port_ctld port_slurmd < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
node=$(hostname -s)
cpus=$(nproc)
cat >"$d/slurm.conf" <<EOF
ClusterName=houlefarm
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port_ctld
SlurmdPort=$port_slurmd
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$d/munge/munge.socket
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/slurmctld.log
SlurmdLogFile=$d/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
MailProg=/bin/true
SchedulerType=sched/builtin
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=farm Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$d/slurm.conf
t0=$(now)
slurmctld -D -f "$SLURM_CONF" >"$d/slurmctld.out.log" 2>&1 &
pids=($! "${pids[@]}")
slurmd -D -N "$node" -f "$SLURM_CONF" >"$d/slurmd.out.log" 2>&1 &
pids=($! "${pids[@]}")
# Should this script be killed without its EXIT trap (SIGKILL at a ctest timeout), the daemons go too.
( while kill -0 $$ 2>/dev/null; do sleep 1; done; kill "${pids[@]}" 2>/dev/null ) &
watchdog=$!
until [ "$(sinfo -h -N -o %t 2>/dev/null)" = idle ]; do
  [ $SECONDS -lt $deadline ] || die "the node did not come up: sinfo says '$(sinfo -h -N -o %t 2>&1)'"
  for p in "${pids[@]}"; do alive "$p" || die "a Slurm daemon exited"; done
  sleep 0.2
done
echo "farm_slurm: one-node cluster ($node, $cpus CPUs, ports $port_ctld/$port_slurmd on 127.0.0.1) up in $(since "$t0") s"

# wait_jobs <ids...>: until the controller runs or queues none of them.
wait_jobs() {
  while squeue -h -j "$(IFS=,; echo "$*")" 2>/dev/null | grep -q .; do
    [ $SECONDS -lt $deadline ] || die "jobs $* still queued or running at the deadline: $(squeue 2>&1)"
    sleep 0.2
  done
}
# submitted <output of houle farm slurm --submit>: the array job's id and the check job's id.
array_id() { sed -nE 's/^houle farm: submitted array job ([0-9]+):.*/\1/p' <<<"$1"; }
check_id() { sed -nE 's/^houle farm: submitted the final check, job ([0-9]+),.*/\1/p' <<<"$1"; }
written() { cat "$@" 2>/dev/null | sed -nE 's/^houle render: ([0-9]+) frames written.*/\1/p' | awk '{ s += $1 } END { print s + 0 }'; }

cd "$d/work" || die "no work folder"
mkdir frames ref
# Film quality at 320x180: about half a second a frame on one thread, so a task killed after its
# first frame still has four to go.
scene=$src/scenes/paper_plate3.toml
opts=(--size 320x180 --quality film)
t0=$(now)
"$houle" render "$scene" --frames 0:23 "${opts[@]}" --out 'ref/%04d.png' --quiet || die "the reference render failed"
echo "farm_slurm: reference, houle render of frames 0:23 on 2 threads: $(since "$t0") s"
farm=("$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --out 'frames/%04d.png' "${opts[@]}" --threads 1
      --sbatch "--time=5 --cpus-per-task=1")

# First submission; task 2 (frames 10:14) is killed as soon as its first frame is there.
t0=$(now)
out=$("${farm[@]}" --submit 2>&1) || die "houle farm slurm --submit: $out"
job=$(array_id "$out") check=$(check_id "$out")
[ -n "$job" ] && [ -n "$check" ] || die "no job ids in: $out"
until [ -e frames/0010.png ]; do
  [ $SECONDS -lt $deadline ] || die "frame 10 never came: $(cat houle-farm-"$job"_2.out 2>&1)"
  sleep 0.05
done
scancel --signal=KILL --full "${job}_2" || bad "scancel of task 2 failed"
wait_jobs "$job" "$check"
echo "farm_slurm: array of 5 tasks (task 2 killed) and the final check: $(since "$t0") s"
done_before=$(ls frames | grep -cE '^[0-9]{4}\.png$')
missing_before=$((24 - done_before))
first_missing=$(for n in $(seq 10 14); do [ -e "frames/$(printf %04d "$n").png" ] || { echo "$n"; break; }; done)
if [ -n "$first_missing" ] && [ "$first_missing" -gt 10 ] && [ "$missing_before" -eq $((15 - first_missing)) ]; then
  ok
else
  die "task 2 was not killed mid-way, or other frames are missing: $(ls frames | tr '\n' ' ')"
fi
want=$([ "$first_missing" -eq 14 ] && echo 14 || echo "$first_missing:14")
status_log=houle-farm-${job}_status.out
if grep -qx "houle farm status: $done_before of 24 frames complete in frames/%04d.png; missing $missing_before: $want" "$status_log" &&
   grep -q 'array tasks to run again: 2 ' "$status_log"; then
  ok
else
  bad "the final check after the kill said:"; cat "$status_log"
fi
# As if the kill had come mid-write: a temporary file beside the first missing frame.
echo partial >"frames/$(printf %04d "$first_missing").png.tmp99999"
stat -c '%n %i %Y' frames/*.png >before.txt
sleep 1  # a rewritten frame would get a new mtime

# Resubmission: the same command; only the missing frames are rendered.
t0=$(now)
out=$("${farm[@]}" --submit 2>&1) || die "resubmission: $out"
job2=$(array_id "$out") check2=$(check_id "$out")
wait_jobs "$job2" "$check2"
echo "farm_slurm: resubmitted array and the final check: $(since "$t0") s"
rendered=$(written houle-farm-"$job2"_[0-4].out)
[ "$rendered" -eq "$missing_before" ] && ok || bad "resubmission rendered $rendered frames, want the $missing_before missing"
skipped=$(grep -l 'already complete in' houle-farm-"$job2"_[0-4].out | wc -l)
[ "$skipped" -eq 4 ] && ok || bad "resubmission: $skipped tasks found their chunk complete, want 4"
stat -c '%n %i %Y' frames/*.png | grep -Fxf before.txt | cmp -s - before.txt && ok || bad "resubmission rewrote complete frames"
grep -q 'removed 1 temporary file that a stopped run left' houle-farm-"$job2"_2.out && ok || bad "task 2 did not remove the temporary file"
leftover=$(ls frames | grep -vE '^[0-9]{4}\.png$')
[ -z "$leftover" ] && ok || bad "files other than frames left: $leftover"
grep -q 'status: frames 0:23 complete (24 frames in frames/%04d.png)' "houle-farm-${job2}_status.out" && ok ||
  bad "the final check after the resubmission said: $(cat "houle-farm-${job2}_status.out")"
identical=0
for n in $(seq -f %04g 0 23); do cmp -s "ref/$n.png" "frames/$n.png" && identical=$((identical + 1)); done
[ "$identical" -eq 24 ] && ok || bad "$identical of 24 frames byte-identical to the single render"

# Raw: each task writes its part, the final job joins them in order.
t0=$(now)
"$houle" render "$scene" --frames 0:23 --size 96x54 --quality draft --raw ref.rgb --quiet || die "reference raw render"
out=$("$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --raw clip.rgb --size 96x54 --quality draft --threads 1 \
  --script raw.sbatch --submit 2>&1) || die "raw submission: $out"
job3=$(array_id "$out") check3=$(check_id "$out")
wait_jobs "$job3" "$check3"
echo "farm_slurm: raw target, array and the joining job: $(since "$t0") s"
grep -q 'joined 5 parts (frames 0:23) into clip.rgb' "raw-${job3}_status.out" && ok ||
  bad "the raw final check said: $(cat "raw-${job3}_status.out")"
cmp -s ref.rgb clip.rgb && ok || bad "the joined raw file differs from one render"
ls clip.rgb.* >/dev/null 2>&1 && bad "parts left after the join: $(ls clip.rgb.*)"

echo "farm_slurm: figures: 24 frames in 5 tasks of up to 5; task 2 killed after $((first_missing - 10)) of its 5 frames;" \
  "$missing_before frames missing, $rendered rendered on resubmission, $identical/24 byte-identical; total $((SECONDS - t_start)) s"
echo "farm_slurm: ${pass} passed, ${fail} failed"
[ "$fail" -eq 0 ]
