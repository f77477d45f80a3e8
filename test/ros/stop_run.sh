#!/usr/bin/env bash
# A coupled `crusher run` stopped from outside says so and exits non-zero, within seconds, never hanging:
#  A: SIGTERM to the wrapper mid-run: exit 143, summary.json "stopped" names the signal;
#  B: dem_node frozen (SIGSTOP) before its first answer, then SIGINT to the wrapper: exit 130 (signals are honoured
#     while mbd_node waits for step 0, and a stopped node does not hold the wrapper);
#  C: an XML-RPC shutdown of mbd_node (rosnode kill): non-zero, "shut the node down from outside";
#  D: dem_node frozen mid-run: mbd_node times out (coupling.timeout_s 3 s), the wrapper ends the frozen node.
# Before: A and C exited 0 with a normal summary, B waited first_timeout_s, D waited forever.
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot
/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=30.0, settle_s=0.1, tf_hz=20)
c["dem"]["feed"].update(max_fed_kg=2.0)
c["coupling"].update(timeout_s=3.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
node_pid() { pgrep -f "inertia_crusher/$1 .*_out:=$out/$2" | head -n 1; }
start_run() {  # NAME: a run in the background (SIGINT not ignored, as in a terminal); run_pid
  /usr/bin/python3 -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); os.execv(sys.argv[1], sys.argv[1:])' \
    "$src/scripts/crusher" run "$out/case.yaml" --out "$out/$1" >"$out/$1.log" 2>&1 &
  run_pid=$!
  pids+=($run_pid)
}
wait_for() {  # NAME what: until the run's file exists
  for _ in $(seq 1 600); do [[ -e $2 ]] && return 0; sleep 0.1; done
  tail -n 20 "$out/$1.log"; echo "FAIL: $1: no $2"; exit 1
}
end_of() {  # NAME EXPECTED-RC MESSAGE: the run ends within 30 s with that status and message
  local t0=$SECONDS rc=0
  timeout 30 tail --pid="$run_pid" -f /dev/null || { tail -n 20 "$out/$1.log"; echo "FAIL: $1: still running after 30 s"; exit 1; }
  wait "$run_pid" || rc=$?
  echo "$1: exit $rc after $((SECONDS - t0)) s: $(grep -o "$3.*" "$out/$1.log" | head -n 1)"
  [[ $2 == nonzero && $rc != 0 || $rc == "$2" ]] || { tail -n 20 "$out/$1.log"; echo "FAIL: $1: exit $rc, expected $2"; exit 1; }
  grep -q "$3" "$out/$1.log" || { tail -n 20 "$out/$1.log"; echo "FAIL: $1: no '$3'"; exit 1; }
}
mid_run() {  # NAME: until the run's coupled steps are under way (its master's URI from the wrapper's log)
  for _ in $(seq 1 300); do grep -q "ROS master: " "$out/$1.log" && break; sleep 0.1; done
  export ROS_MASTER_URI=$(grep -o "ROS master: .*" "$out/$1.log" | cut -d' ' -f3) ROS_IP=127.0.0.1
  timeout 120 rostopic echo -n 1 /crusher/geometry_wrench/step >/dev/null || { tail -n 20 "$out/$1.log"; echo "FAIL: $1: no step"; exit 1; }
}

start_run A
mid_run A
kill -TERM "$run_pid"
end_of A 143 "stopped by SIGTERM"
grep -q '"stopped": "stopped by a signal (SIGTERM)' "$out/A/summary.json" || { cat "$out/A/summary.json"; echo "FAIL: A: summary.json does not say it was stopped"; exit 1; }

start_run B
for _ in $(seq 1 200); do p=$(node_pid dem_node B) && [[ -n $p ]] && break; sleep 0.05; done
kill -STOP "$p"
sleep 3
kill -INT "$run_pid"
end_of B 130 "stopped by SIGINT"

start_run C
mid_run C
rosnode kill /mbd_node >/dev/null
end_of C nonzero "shut the node down from outside"
grep -q '"stopped": "ROS shut the node down' "$out/C/summary.json" || { cat "$out/C/summary.json"; echo "FAIL: C: summary.json does not say it was stopped"; exit 1; }

start_run D
mid_run D
kill -STOP "$(node_pid dem_node D)"
end_of D 1 "no answer from the DEM node"
echo "stops from outside: passed"
