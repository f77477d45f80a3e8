#!/usr/bin/env bash
# `crusher sweep --backend slurm` end to end on a single-node Slurm started here (munged, slurmctld and slurmd with a
# generated slurm.conf in a scratch folder, free ports): a 2-case sweep goes through one job array and its
# sweep.csv equals the local backend's (every column but the wall time); Ctrl-C while the array runs cancels it
# (scancel: no task left in the queue, no node process left), exits 130 and leaves sweep.csv readable. Skipped (exit 77) only when Slurm cannot be
# started as a non-root user; as root a Slurm that does not start fails the test.
source "$(dirname "$0")/ros_env.bash"
crusher="$src/scripts/crusher"
fail() { echo "FAIL: $*"; exit 1; }
cannot_start() {  # why Slurm did not come up
  if [[ $(id -u) != 0 ]]; then echo "SKIP: cannot start Slurm as the non-root user $(id -un): $*"; exit 77; fi
  fail "Slurm did not start as root: $*"
}
for b in munged slurmctld slurmd sbatch squeue; do
  command -v "$b" >/dev/null || cannot_start "$b missing (Debian packages slurm-wlm, munge: crusher setup)"
done
sl=$out/slurm
mkdir -p "$sl/state" "$sl/spool" "$sl/munge"
chmod 700 "$sl/munge"
head -c 1024 /dev/urandom >"$sl/munge/munge.key"
chmod 400 "$sl/munge/munge.key"
munged --foreground --force --socket="$sl/munge/sock" --key-file="$sl/munge/munge.key" \
  --pid-file="$sl/munge/pid" --seed-file="$sl/munge/seed" >"$sl/munge/log" 2>&1 &
pids+=($!)
port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
host=$(hostname -s)
user=$(id -un)
cat >"$sl/slurm.conf" <<EOF
ClusterName=crushertest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(port)
SlurmdPort=$(port)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sl/munge/sock
SlurmUser=$user
SlurmdUser=$user
StateSaveLocation=$sl/state
SlurmdSpoolDir=$sl/spool
SlurmctldPidFile=$sl/slurmctld.pid
SlurmdPidFile=$sl/slurmd.pid
SlurmctldLogFile=$sl/slurmctld.log
SlurmdLogFile=$sl/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=crusher Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$sl/slurm.conf
for _ in $(seq 1 50); do [[ -S $sl/munge/sock ]] && break; sleep 0.1; done
[[ -S $sl/munge/sock ]] || cannot_start "munged: $(tail -n 2 "$sl/munge/log" 2>/dev/null)"
slurmctld -D -c -f "$SLURM_CONF" >"$sl/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$sl/slurmd.out" 2>&1 &
pids+=($!)
up=0
for _ in $(seq 1 60); do
  [[ $(sinfo -h -o %t 2>/dev/null) == idle ]] && { up=1; break; }
  sleep 0.5
done
((up)) || cannot_start "no idle node after 30 s: $(tail -n 3 "$sl"/slurmctld.log "$sl"/slurmd.log 2>/dev/null | tr '\n' ' ')"
sinfo
echo "single-node Slurm up ($host, $(nproc) CPUs)"

printf 'base: %s\nrun: {duration_s: 3.0, settle_s: 1.5}\n' "$src/launch_free_configs/gyp1200_400rpm.yaml" >"$out/base.yaml"
args=("$out/base.yaml" --vary mbd.drive.speed_rpm=400,600 --no-plots)
CRUSHER_NO_BUILD=1 CRUSHER_SWEEP_POLL_S=0.5 bash "$crusher" sweep "${args[@]}" --backend slurm --partition crusher \
  --time 10:00 --cpus-per-case 1 --out "$out/slurm_sweep" >"$out/slurm.log" 2>&1 ||
  { cat "$out/slurm.log"; cat "$out"/slurm_sweep/slurm/*.out 2>/dev/null; tail -n 20 "$sl/slurmctld.log"; fail "the slurm sweep failed"; }
cat "$out/slurm.log"
grep -q "slurm job array [0-9]*: 2 tasks" "$out/slurm.log" || fail "no job array submitted"
grep -q "^#SBATCH --array=0-1" "$out"/slurm_sweep/slurm/array-*.sh || fail "the batch script is not a 2-task array"
grep -q "^#SBATCH --partition=crusher" "$out"/slurm_sweep/slurm/array-*.sh || fail "--partition not passed"
CRUSHER_NO_BUILD=1 bash "$crusher" sweep "${args[@]}" --out "$out/local_sweep" >"$out/local.log" 2>&1 ||
  { cat "$out/local.log"; fail "the local sweep failed"; }
/usr/bin/python3 - "$out/slurm_sweep/sweep.csv" "$out/local_sweep/sweep.csv" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(p))) for p in sys.argv[1:])
assert len(a) == 2 and all(r["status"] == "ok" for r in a), a
for ra, rb in zip(a, b):
    ra.pop("wall_s"); rb.pop("wall_s")
    assert ra == rb, (ra, rb)
print("the slurm sweep's rows equal the local sweep's")
PY

# Ctrl-C while the array runs: the array is cancelled, nothing of it keeps running, sweep.csv stays readable.
printf 'base: %s\nrun: {duration_s: 1200.0, settle_s: 1.5}\n' "$src/launch_free_configs/gyp1200_400rpm.yaml" >"$out/long.yaml"
set -m  # the sweep in a process group of its own, as in a terminal (SIGINT not ignored as in a background job)
CRUSHER_NO_BUILD=1 CRUSHER_SWEEP_POLL_S=0.5 bash "$crusher" sweep "$out/long.yaml" --vary mbd.drive.speed_rpm=400,500 \
  --no-plots --backend slurm --partition crusher --time 10:00 --cpus-per-case 1 --out "$out/cancelled" >"$out/cancel.log" 2>&1 &
sweep_pid=$!
set +m
pids+=("$sweep_pid")
for _ in $(seq 1 120); do
  grep -q "slurm job array" "$out/cancel.log" && [[ -n $(squeue -h -t R 2>/dev/null) ]] && break
  sleep 0.5
done
[[ -n $(squeue -h -t R) ]] || { cat "$out/cancel.log"; fail "the long array never ran"; }
sleep 2
kill -INT -- -"$sweep_pid"
for _ in $(seq 1 60); do kill -0 "$sweep_pid" 2>/dev/null || break; sleep 0.5; done
if kill -0 "$sweep_pid" 2>/dev/null; then
  kill -KILL -- -"$sweep_pid"; scancel --user="$user" 2>/dev/null
  cat "$out/cancel.log"; fail "the slurm sweep did not stop within 30 s of Ctrl-C"
fi
rc=0
wait "$sweep_pid" || rc=$?
cat "$out/cancel.log"
((rc == 130)) || fail "Ctrl-C on the slurm sweep exited $rc, not 130"
grep -q "cancelled slurm job" "$out/cancel.log" || fail "the array was not cancelled"
for _ in $(seq 1 40); do [[ -z $(squeue -h 2>/dev/null) ]] && break; sleep 0.5; done
[[ -z $(squeue -h) ]] || { left=$(squeue -h); scancel --user="$user"; fail "tasks left in the queue after Ctrl-C: $left"; }
for _ in $(seq 1 40); do pgrep -f "$out/cancelled/cases" >/dev/null || break; sleep 0.5; done
! pgrep -af "$out/cancelled/cases" || fail "processes of the cancelled cases still run"
/usr/bin/python3 -c "import csv,sys; r=list(csv.DictReader(open(sys.argv[1]))); assert len(r) == 2, r" "$out/cancelled/sweep.csv" ||
  fail "sweep.csv is not readable after Ctrl-C"
echo "Ctrl-C cancelled the slurm array (exit 130), sweep.csv readable"

# A coupled case on MPI ranks (issue 25): --ranks 2 submits each case as 2 tasks; its `crusher run --ranks 2` starts
# dem_node with mpirun inside the task's allocation.
/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/coupled.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=0.08, settle_s=0.04, tf_hz=20)
c["run"].pop("coupled", None)
c["dem"]["feed"].update(max_fed_kg=3.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
CRUSHER_NO_BUILD=1 CRUSHER_SWEEP_POLL_S=0.5 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
  bash "$crusher" sweep "$out/coupled.yaml" --vary dem.feed.max_fed_kg=3.0 --load dem --ranks 2 --no-plots \
  --backend slurm --partition crusher --time 10:00 --cpus-per-case 1 --out "$out/ranks_sweep" >"$out/ranks.log" 2>&1 ||
  { cat "$out/ranks.log"; cat "$out"/ranks_sweep/slurm/*.out 2>/dev/null; fail "the coupled slurm sweep on 2 ranks failed"; }
grep -q "^#SBATCH --ntasks=2" "$out"/ranks_sweep/slurm/array-*.sh || fail "--ranks 2 is not 2 tasks per case"
grep -q "the charge on 2 MPI ranks" "$out"/ranks_sweep/slurm/*.out "$out"/ranks_sweep/cases/*/*.log 2>/dev/null ||
  grep -rq "on 2 MPI ranks" "$out/ranks_sweep" || fail "the case's dem_node did not run on 2 ranks"
/usr/bin/python3 -c "import csv,sys; r=list(csv.DictReader(open(sys.argv[1]))); assert len(r) == 1 and r[0]['status'] == 'ok', r" \
  "$out/ranks_sweep/sweep.csv" || fail "the coupled case on 2 ranks has no result"
echo "coupled case on 2 MPI ranks through slurm: ok"
echo "slurm sweep check passed"
